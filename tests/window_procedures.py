"""Simulated procedures of real experiments, and how the window finder fares on their coasts.

Used by tests/test_real_procedures.py (a fast subset and the slow rate) and
benchmarks/bench_window_finder.py (the rate over bicycles, speeds, procedures and seeds; its
docstring describes the procedures and what is counted).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.linalg import expm

from whipple.errors import InputError
from whipple.measurement.experiment import measure_run, measure_window
from whipple.measurement.runs import MIN_DURATION, run_from_simulation
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.simulation.procedure import SimulatedRun, cut_run
from whipple.simulation.scenario import RunScenario, Sensors
from whipple.simulation.simulator import simulate_run

BICYCLES = {
    "benchmark": "benchmark",
    "kooijman2008": "kooijman2008",
    "browser": str(Path(__file__).resolve().parent / "data/bicycleparameters/bicycles/BrowserBenchmark.txt"),
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


def scenario(procedure: str, speed: float, seed: int, sample_rate: float = 100.0,
             noise: float = 1.0) -> RunScenario:
    """The scenario of a run of `procedure` ("seed", "sharp" or "growing"; "cut" cuts "sharp" runs).

    `sample_rate` [Hz] and `noise` (a factor on every sensor's noise per sample): field
    conditions other than the default 100 Hz and sensors.
    """
    field = {"sample_rate": sample_rate, "sensors": Sensors().scaled(noise)}
    if procedure == "seed":
        return RunScenario(speed=speed, seed=seed, **field)
    if procedure == "growing":
        return RunScenario(speed=speed, seed=seed, push_duration=0.04, push_roll_rate=0.15, push_signs="random",
                           push_spread=0.4, **field)
    return RunScenario(speed=speed, seed=seed, push_duration=0.04, push_roll_rate=0.8, push_signs="random",
                       push_spread=0.4, coast_spread=0.7, **field)


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
    return [record for record in all_coasts(simulated, eigenvalue, model) if not record["short"]]


def all_coasts(simulated: SimulatedRun, eigenvalue: complex, model) -> list[dict]:
    """As :func:`coasts`, for every coast; ``short`` marks those shorter than a weave cycle.

    The windows of a coast shorter than a cycle can run on past the catch into the held
    bicycle; such coasts are not counted in the rates.
    """
    frequency, fs = eigenvalue.imag, simulated.sample_rate

    def is_short(start: float, stop: float) -> bool:
        return bool((stop - start) * frequency < 2 * np.pi)

    def relative_error(measured_window) -> float:
        return abs(complex(measured_window.fit.damping, measured_window.fit.frequency) - eigenvalue) / abs(eigenvalue)

    run = run_from_simulation(simulated)
    try:
        measured = measure_run(run)
    except InputError as error:
        return [{"fitted": False, "usable": False, "across_catch": 0, "usable_across_catch": 0, "across_push": 0,
                 "hand_mark": [], "catch_shift": [],
                 "errors": [], "errors_across_catch": [], "why": [str(error)], "short": is_short(start, stop)}
                for start, stop in simulated.segments]
    records = []
    caught = set(simulated.catches)
    fitted = [m for m in measured if m.fit is not None]
    for start, stop in simulated.segments:
        inside = [m for m in fitted if start - 0.5 / fs <= m.fit.start < stop]
        # Coasts cut by the record's end have no catch to cross.
        ends_in_catch = any(abs(stop - t) < 1e-6 for t in caught)
        pushed = simulated.time[0] < start - 0.5 / fs
        why = [m.window.reason for m in measured if m.fit is None and m.window.start < stop
               and m.window.stop > start]
        # A window that starts before the push's end and runs on past it is fitted across the push.
        over_push = [m for m in fitted if pushed and m.fit.start < start - 0.5 / fs < m.fit.stop]
        why += [f"fitted across the push: a window from {m.fit.start:.2f} s" for m in over_push]
        across = [m for m in inside if ends_in_catch and m.fit.stop > stop + 1.01 / fs]
        records.append({
            "short": is_short(start, stop),
            "fitted": bool(inside),
            "usable": any(m.usable for m in inside),
            "across_catch": len(across),
            "usable_across_catch": sum(m.usable for m in across),
            "hand_mark": [_hand_mark(simulated, model, stop, m.fit.stop) for m in across],
            "catch_shift": [_catch_shift(run, m, stop) for m in across],
            "across_push": len(over_push),
            "errors": [relative_error(m) for m in inside if m.usable],
            "errors_across_catch": [relative_error(m) for m in across if m.usable],
            "why": why if not inside else [],
        })
    return records


def _catch_shift(run, measured, catch: float) -> float:
    """How far a window's eigenvalue moves when it ends at the catch [standard errors].

    The larger of |d - d_c| / sd(d) and |w - w_c| / sd(w), with d + iw fitted to the window as
    measured and d_c + iw_c to the same window ended at the last sample before the catch (nan
    when that window gives no fit).

    The hand's mark (:func:`_hand_mark`) is sample by sample and holds the hold's own jitter;
    this is what fitting past the catch does to the measurement.
    """
    last = int(np.searchsorted(run.time, catch - 1e-9))
    cut = measure_window(run, replace(measured.window, stop=float(run.time[last - 1]), stop_index=last)).fit
    if cut is None:
        return float("nan")
    fit = measured.fit
    sd = np.sqrt(np.diag(fit.covariance))
    return float(max(abs(fit.damping - cut.damping) / sd[0], abs(fit.frequency - cut.frequency) / sd[1]))


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


@dataclass
class Tally:
    """What the coasts of one bicycle and procedure gave.

    ``count``: coasts holding a weave cycle (``coasts``), with a fitted window (``fitted``), a
    usable one (``usable``), windows fitted across a catch (``across_catch``; those usable:
    ``usable_across_catch``) or a push (``across_push``); ``growing``: the same for
    the coasts of a growing weave; ``errors``: the usable windows' |fitted - model| / |model|;
    ``marks``: the hand's mark on each window fitted across a catch [noise std]; ``shifts``: how
    far each such window's eigenvalue moves when it ends at the catch [standard errors]; ``reasons``:
    the rejected stretches' reasons of the coasts without a window. ``short``: the same counts
    for the coasts shorter than a weave cycle (not in the rates), and ``short_errors`` the
    eigenvalue errors of their usable windows fitted across a catch.
    """

    count: Counter[str] = field(default_factory=Counter)
    growing: Counter[str] = field(default_factory=Counter)
    errors: list[float] = field(default_factory=list)
    marks: list[float] = field(default_factory=list)
    shifts: list[float] = field(default_factory=list)
    reasons: list[str] = field(default_factory=list)
    short: Counter[str] = field(default_factory=Counter)
    short_errors: list[float] = field(default_factory=list)


def procedure_tally(name: str, procedure: str, seeds: Iterable[int], speeds: Iterable[float] = SPEEDS,
                    short: bool = False, sample_rate: float = 100.0, noise: float = 1.0) -> Tally:
    """Simulate and measure the runs of bicycle `name` (a key of BICYCLES) by `procedure`.

    `short`: count the coasts shorter than a weave cycle too (``Tally.short``). `sample_rate`
    [Hz] and `noise`: as :func:`scenario`'s.
    """
    bicycle = load_bicycle(BICYCLES[name])
    model = linear_model(bicycle)
    tally = Tally()
    seeds = list(seeds)
    for speed in growing_speeds(model) if procedure == "growing" else speeds:
        eigenvalue = weave(model, speed)
        if eigenvalue is None or eigenvalue.real > MAX_GROWTH:
            continue
        for seed in seeds:
            simulated = simulate_run(bicycle, scenario(procedure, speed, seed, sample_rate, noise), model)
            for piece in pieces(simulated, procedure, seed):
                records = all_coasts(piece, eigenvalue, model)
                for record in (r for r in records if short and r["short"]):
                    tally.short.update(Counter(coasts=1, fitted=int(record["fitted"]), usable=int(record["usable"]),
                                               across_catch=record["across_catch"],
                                               usable_across_catch=record["usable_across_catch"]))
                    tally.short_errors.extend(record["errors_across_catch"])
                for record in records:
                    if record["short"]:
                        continue
                    counted = Counter(coasts=1, fitted=record["fitted"], usable=record["usable"],
                                      across_catch=record["across_catch"], across_push=record["across_push"],
                                      usable_across_catch=record["usable_across_catch"])
                    tally.count.update(counted)
                    if eigenvalue.real > 0:
                        tally.growing.update(counted)
                    if not record["fitted"]:
                        tally.reasons.extend(record["why"] or ["(nothing listed)"])
                    tally.marks.extend(record["hand_mark"])
                    tally.shifts.extend(record["catch_shift"])
                    tally.errors.extend(record["errors"])
    return tally
