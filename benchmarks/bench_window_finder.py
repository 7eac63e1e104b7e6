"""How many simulated coasts that hold a weave cycle give a fitted window, and whether any is fitted across a catch.

Simulated runs know where each free coasting starts (the push's end) and ends (the catch):
their ``segments``. For four bicycles (benchmark, kooijman2008, the Browser of
BicycleParameters, sbw2024 with its controller), at speeds where the weave oscillates with a
real part up to +1 1/s (growing weave included), runs are simulated with the procedures
below and measured as ``whipple fit`` measures them (window finder, fit, cut before a catch).
A coast counts when it holds at least one weave cycle of the model at its speed (its length
times the weave frequency over 2 pi). It gives a window when a fitted window starts inside
it; that window is fitted across the catch when its fit runs more than one sample past the
catch, and across the push when it starts before the push's end. For a window fitted across a
catch the hand's mark on its samples is measured: the largest difference, over the samples the
fit holds after the catch, between the true roll rate and the free motion that would have
followed without the hand (the model's state at the catch propagated freely), in standard
deviations of the roll rate's noise. Under 1 the catch came while the motion had sunk into the
noise, and the fit cannot tell it.

Procedures (``whipple.simulation``):

* ``seed``: the seed paper's, as ``RunScenario`` has it by default: held upright, a push of
  0.1 s from rest, alternating, a catch after 5 s or at the roll limits, held, pushed again.
* ``sharp``: pushes from rest of 0.04 s, of either sign at random, their sizes spread by
  +-40 % around a larger roll rate (0.8 rad/s), coasts caught by hand after 1.5-5 s.
* ``growing``: at the speeds where the weave grows at +0.25, +0.5, +0.75 and +1 1/s (below the
  weave speed), small pushes from rest (0.15 rad/s, either sign, sizes spread by +-40 %): the
  weave grows out of them until the bicycle is caught at the roll or roll-rate limit.
* ``cut``: the ``sharp`` runs cut into segments (``procedure.cut_run``), one per coast, from
  0-0.3 s after the push's end to 0.2 s before or 0.3 s after the catch: segments that start
  after their push, as published data sets hold them (segments shorter than 1 s are not
  written, the reader refuses them).

Printed: per bicycle and procedure, coasts holding a cycle, those with a fitted window
(and a usable one, passing the quality checks), windows fitted across a catch or a push, and
the median and 90th percentile of the usable windows' eigenvalue error relative to the model's
weave, |fitted - model| / |model|; the overall rate; and the rejected stretches' reasons of the
coasts without a window.

Run: ``python benchmarks/bench_window_finder.py [--seeds 3] [--bicycles ...] [--procedures ...]``
"""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np
from scipy.linalg import expm

from whipple.errors import InputError
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import MIN_DURATION, run_from_simulation
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.procedure import SimulatedRun, cut_run
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

BICYCLES = {
    "benchmark": "benchmark",
    "kooijman2008": "kooijman2008",
    "browser": str(Path(__file__).resolve().parents[1] / "tests/data/bicycleparameters/bicycles/BrowserBenchmark.txt"),
    "sbw2024": "sbw2024",
}
PROCEDURES = ("seed", "sharp", "growing", "cut")
#: Real parts of the weave [1/s] of the "growing" procedure's speeds.
GROWTH_RATES = (0.25, 0.5, 0.75, 1.0)
#: Speeds tried [m/s]; those where the weave does not oscillate or grows faster than
#: ``MAX_GROWTH`` are left out.
SPEEDS = (2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 6.0, 7.0)
#: Largest real part of the weave [1/s] of the runs.
MAX_GROWTH = 1.0


def weave(model, speed: float) -> complex | None:
    """The model's oscillating eigenvalue of largest real part at `speed` [m/s] [1/s], or None."""
    eigenvalues = np.linalg.eigvals(model.state_matrix(speed))
    oscillating = eigenvalues[eigenvalues.imag > 1e-6]
    return complex(oscillating[np.argmax(oscillating.real)]) if oscillating.size else None


def growing_speeds(model) -> list[float]:
    """The speeds [m/s] below the weave speed at which the weave's real part is each of GROWTH_RATES."""
    grid = np.arange(0.3, 10.0, 0.02)
    real = np.array([w.real if (w := weave(model, v)) is not None else np.nan for v in grid])
    speeds = []
    for rate in GROWTH_RATES:
        # The fastest speed at which the real part falls through `rate`: the growing weave just
        # below the weave speed, not another mode at walking pace.
        falls = np.flatnonzero((real[:-1] >= rate) & (real[1:] < rate))
        if falls.size:
            k = falls[-1]
            speeds.append(float(grid[k] + (grid[k + 1] - grid[k]) * (real[k] - rate) / (real[k] - real[k + 1])))
    return speeds


def scenario(procedure: str, speed: float, seed: int) -> RunScenario:
    """The scenario of a run of `procedure` ("seed", "sharp" or "growing"; "cut" cuts "sharp" runs)."""
    if procedure == "seed":
        return RunScenario(speed=speed, seed=seed)
    if procedure == "growing":
        return RunScenario(speed=speed, seed=seed, push_duration=0.04, push_roll_rate=0.15, push_signs="random",
                           push_spread=0.4)
    return RunScenario(speed=speed, seed=seed, push_duration=0.04, push_roll_rate=0.8, push_signs="random",
                       push_spread=0.4, coast_spread=0.7)


def pieces(simulated: SimulatedRun, procedure: str, seed: int) -> list[SimulatedRun]:
    """The runs measured: the whole run, or for "cut" one segment around each coast."""
    if procedure != "cut":
        return [simulated]
    rng = np.random.default_rng([seed, 1])
    cuts = []
    for start, stop in simulated.segments:
        first, last = start + rng.uniform(0.0, 0.3), stop + rng.uniform(-0.2, 0.3)
        if last - first >= MIN_DURATION:
            cuts.append(cut_run(simulated, first, last))
    return cuts


def coasts(simulated: SimulatedRun, eigenvalue: complex, model) -> list[dict]:
    """Measure a run; one record per coast holding a weave cycle (`eigenvalue`: the model's weave [1/s])."""
    frequency, fs = eigenvalue.imag, simulated.sample_rate
    try:
        measured = measure_run(run_from_simulation(simulated))
    except InputError as error:
        return [{"fitted": False, "usable": False, "across_catch": 0, "across_push": 0, "hand_mark": [],
                 "errors": [], "why": [str(error)]}
                for start, stop in simulated.segments if (stop - start) * frequency >= 2 * np.pi]
    records = []
    caught = set(simulated.catches)
    for start, stop in simulated.segments:
        if (stop - start) * frequency < 2 * np.pi:
            continue
        inside = [m for m in measured if m.fit is not None and start - 0.5 / fs <= m.fit.start < stop]
        # Coasts cut by the record's end have no catch to cross.
        ends_in_catch = any(abs(stop - t) < 1e-6 for t in caught)
        pushed = simulated.time[0] < start - 0.5 / fs
        why = [m.window.reason for m in measured if m.fit is None and m.window.start < stop
               and m.window.stop > start]
        across = [m for m in inside if ends_in_catch and m.fit.stop > stop + 1.01 / fs]
        records.append({
            "fitted": bool(inside),
            "usable": any(m.usable for m in inside),
            "across_catch": len(across),
            "hand_mark": [_hand_mark(simulated, model, stop, m.fit.stop) for m in across],
            "across_push": sum(pushed and m.fit.start < start - 0.5 / fs for m in inside),
            "errors": [abs(complex(m.fit.damping, m.fit.frequency) - eigenvalue) / abs(eigenvalue)
                       for m in inside if m.usable],
            "why": why if not inside else [],
        })
    return records


def _hand_mark(simulated: SimulatedRun, model, catch: float, stop: float) -> float:
    """Largest |true - free| roll rate from the catch to `stop` [s], in roll-rate noise units."""
    time = simulated.time
    first, last = int(np.searchsorted(time, catch - 1e-9)), int(np.searchsorted(time, stop + 1e-9))
    dt = float(time[1] - time[0])
    step = expm(model.state_matrix(float(simulated.speed[first])) * dt)
    state, free = simulated.states[first].copy(), []
    for _ in range(first, last):
        free.append(state[simulated.state_names.index("roll_rate")])
        state = step @ state
    difference = simulated.state("roll_rate")[first:last] - np.array(free)
    return float(np.max(np.abs(difference)) / simulated.scenario.sensors.roll_rate.noise)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--bicycles", nargs="+", default=list(BICYCLES), choices=list(BICYCLES))
    parser.add_argument("--procedures", nargs="+", default=list(PROCEDURES), choices=PROCEDURES)
    parser.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS))
    args = parser.parse_args()
    total: Counter[str] = Counter()
    reasons: Counter[str] = Counter()
    marks: list[float] = []
    for name in args.bicycles:
        bicycle = load_bicycle(BICYCLES[name])
        model = linear_model(bicycle)
        for procedure in args.procedures:
            count: Counter[str] = Counter()
            growing: Counter[str] = Counter()
            errors: list[float] = []
            for speed in growing_speeds(model) if procedure == "growing" else args.speeds:
                eigenvalue = weave(model, speed)
                if eigenvalue is None or eigenvalue.real > MAX_GROWTH:
                    continue
                for seed in range(args.seeds):
                    simulated = simulate_run(bicycle, scenario(procedure, speed, seed), model)
                    for piece in pieces(simulated, procedure, seed):
                        for record in coasts(piece, eigenvalue, model):
                            tally = Counter(coasts=1, fitted=record["fitted"], usable=record["usable"],
                                            across_catch=record["across_catch"], across_push=record["across_push"])
                            count.update(tally)
                            if eigenvalue.real > 0:
                                growing.update(tally)
                            reasons.update(_short(why) for why in record["why"] or ["(nothing listed)"]
                                           if not record["fitted"])
                            marks.extend(record["hand_mark"])
                            errors.extend(record["errors"])
            total.update(count)
            print(f"{name:13s} {procedure:6s} coasts {count['coasts']:4d}  fitted {count['fitted']:4d} "
                  f"({_rate(count, 'fitted')})  usable {count['usable']:4d} ({_rate(count, 'usable')})  "
                  f"across a catch {count['across_catch']}  across a push {count['across_push']}  "
                  f"error {_percentiles(errors)}  "
                  f"| growing weave: {growing['coasts']} coasts, {growing['fitted']} fitted", flush=True)
    print(f"\nall: {total['coasts']} coasts holding a weave cycle, {total['fitted']} with a fitted window "
          f"({_rate(total, 'fitted')}), {total['usable']} usable ({_rate(total, 'usable')}); "
          f"fitted across a catch: {total['across_catch']}, across a push: {total['across_push']}")
    if marks:
        print(f"the hand's mark on the windows fitted across a catch (noise standard deviations): "
              f"{', '.join(f'{m:.2f}' for m in sorted(marks))}; {sum(m >= 1 for m in marks)} of them at 1 or more")
    if reasons:
        print("why the coasts without a window gave none (the rejected stretches' reasons):")
        for reason, n in reasons.most_common(12):
            print(f"  {n:4d}  {reason}")


def _percentiles(errors: list[float]) -> str:
    return f"{100 * np.median(errors):.1f}%/{100 * np.quantile(errors, 0.9):.1f}%" if errors else "-"


def _rate(count: Counter[str], key: str) -> str:
    return f"{100 * count[key] / count['coasts']:.0f}%" if count["coasts"] else "-"


def _short(reason: str) -> str:
    """A reason without its times, to count alike reasons together."""
    return " ".join("#" if any(c.isdigit() for c in word) else word for word in reason.split())


if __name__ == "__main__":
    main()
