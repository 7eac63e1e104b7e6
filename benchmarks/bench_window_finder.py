"""How many simulated coasts that hold a weave cycle give a fitted window, and whether any is fitted across a catch.

Simulated runs know where each free coasting starts (the push's end) and ends (the catch):
their ``segments``. For four bicycles (benchmark, kooijman2008, the Browser of
BicycleParameters, sbw2024 with its controller), at speeds where the weave oscillates with a
real part up to +1 1/s (growing weave included), runs are simulated with the procedures
below and measured as ``whipple fit`` measures them (window finder, fit, cut before a catch).
A coast counts when it holds at least one weave cycle of the model at its speed (its length
times the weave frequency over 2 pi). It gives a window when a fitted window starts inside
it; that window is fitted across the catch when its fit runs more than one sample past the
catch. A fitted window that starts before a push's end (in the hold before it) and runs on past
it is fitted across the push, and is not the coast's window. For a window fitted across a
catch the hand's mark on its samples is measured: the largest difference, over the samples the
fit holds after the catch, between the true roll rate and the free motion that would have
followed without the hand (the model's state at the catch propagated freely), in standard
deviations of the roll rate's noise. Under 1 the catch came while the motion had sunk into the
noise, and the fit cannot tell it. The mark is taken sample by sample, so it holds the held
bicycle's own jitter (``hold_std``) as well as the hand's pull; what crossing the catch does to
the measurement is printed too: how far the window's eigenvalue moves when the same window ends
at the last sample before the catch, in its fit's standard errors (the larger of the damping's
and the frequency's shifts).

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
coasts without a window. The coasts shorter than a weave cycle are counted apart (not in the
rates): a window starting in one can run on past its catch into the held bicycle, so those
fitted across a catch, the usable ones among them and their eigenvalue errors are printed.

Field conditions: ``--sample-rate`` (Hz, default 100) and ``--noise-scale`` (a factor on every
sensor's noise per sample).

Run: ``python benchmarks/bench_window_finder.py [--seeds 3] [--bicycles ...] [--procedures ...]
[--sample-rate 100] [--noise-scale 1]``
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from window_procedures import BICYCLES, PROCEDURES, SPEEDS, procedure_tally  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--bicycles", nargs="+", default=list(BICYCLES), choices=list(BICYCLES))
    parser.add_argument("--procedures", nargs="+", default=list(PROCEDURES), choices=PROCEDURES)
    parser.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS))
    parser.add_argument("--sample-rate", type=float, default=100.0, help="sample rate of the runs [Hz]")
    parser.add_argument("--noise-scale", type=float, default=1.0,
                        help="factor on every sensor's noise per sample (default sensors: 1)")
    args = parser.parse_args()
    total: Counter[str] = Counter()
    short: Counter[str] = Counter()
    short_errors: list[float] = []
    reasons: Counter[str] = Counter()
    marks: list[float] = []
    shifts: list[float] = []
    for name in args.bicycles:
        for procedure in args.procedures:
            tally = procedure_tally(name, procedure, range(args.seeds), args.speeds, short=True,
                                    sample_rate=args.sample_rate, noise=args.noise_scale)
            count, growing = tally.count, tally.growing
            total.update(count)
            short.update(tally.short)
            short_errors.extend(tally.short_errors)
            marks.extend(tally.marks)
            shifts.extend(tally.shifts)
            reasons.update(_short(why) for why in tally.reasons)
            print(f"{name:13s} {procedure:6s} coasts {count['coasts']:4d}  fitted {count['fitted']:4d} "
                  f"({_rate(count, 'fitted')})  usable {count['usable']:4d} ({_rate(count, 'usable')})  "
                  f"across a catch {count['across_catch']} ({count['usable_across_catch']} usable)  "
                  f"across a push {count['across_push']}  "
                  f"error {_percentiles(tally.errors)}  "
                  f"| growing weave: {growing['coasts']} coasts, {growing['fitted']} fitted "
                  f"| under a cycle: {tally.short['coasts']} coasts, {tally.short['usable']} usable, "
                  f"across a catch {tally.short['across_catch']} ({tally.short['usable_across_catch']} usable, "
                  f"error {_percentiles(tally.short_errors)})", flush=True)
    print(f"\nall: {total['coasts']} coasts holding a weave cycle, {total['fitted']} with a fitted window "
          f"({_rate(total, 'fitted')}), {total['usable']} usable ({_rate(total, 'usable')}); "
          f"fitted across a catch: {total['across_catch']} ({total['usable_across_catch']} of them usable), "
          f"across a push: {total['across_push']}")
    print(f"coasts shorter than a weave cycle (not in the rates): {short['coasts']}, {short['fitted']} with a "
          f"fitted window, {short['usable']} usable; fitted across a catch: {short['across_catch']} "
          f"({short['usable_across_catch']} of them usable"
          + (f"; their eigenvalue errors {', '.join(f'{100 * e:.0f}%' for e in sorted(short_errors))})"
             if short_errors else ")"))
    if marks:
        print(f"the hand's mark on the windows fitted across a catch (noise standard deviations): "
              f"{', '.join(f'{m:.2f}' for m in sorted(marks))}; {sum(m >= 1 for m in marks)} of them at 1 or more")
        print(f"how far their eigenvalue moves when each ends at its catch (its fit's standard errors): "
              f"{', '.join(f'{s:.2f}' for s in sorted(shifts))}")
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
