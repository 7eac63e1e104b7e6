"""Which hidden-effect trials a change of the window finder touches (to rerun only those).

A trial's diagnosis depends on its runs only through the windows found in them (the fits of
unchanged windows are unchanged), so after a change of ``whipple.measurement.windows`` only the
trials with some other window need to run again; the rest of an earlier log stands.

Run: ``python benchmarks/changed_windows.py OLD_WINDOWS.py [--seeds 50] [--first-seed 0]
[--workers 2] [--conditions ground+faults] > trials.jsonl``, where OLD_WINDOWS.py is the earlier
``src/whipple/measurement/windows.py`` (e.g. ``git show REV:src/whipple/measurement/windows.py``).
Prints one JSON line ``[bicycle, family, seed]`` per touched trial, for
``bench_diagnosis.py --trials``; on stderr the count and the touched speeds.

A change elsewhere in the measurement (the cut before a catch in ``measure_window``, say) is
compared on the windows as the trials' diagnosis measures them: ``--dump FILE`` writes every
trial's measured windows (first and last sample, and whether usable) to FILE, run once with the
earlier code and once with the current (``PYTHONPATH=OLD_TREE/src`` for the earlier), and
``--compare OLD NEW`` prints the trials whose windows differ, as above.

``--set-aside`` (instead of OLD_WINDOWS.py) lists the trials in which
``whipple.measurement.free_motion.set_aside_outlying`` sets some window aside (the trials that
rule touches, run as ``hidden_effects.run_trial`` measures them). ``--cycles-above-noise C`` lists the trials that the
window check ``FitOptions(min_cycles_above_noise=C)`` touches, measured without it: those with a
usable window holding fewer than C weave cycles above the noise. ``--bicycles`` chooses the
bicycles (default: those of ``bench_diagnosis.py``, the uncontrolled ones, sbw2024 and its
controlled variants; before 2026-12-07 the variants were left out, and so were their trials
from the lists of touched trials).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from hidden_effects import BICYCLES, CONDITIONS, CONTROLLED_BICYCLES, families, trial_options, trial_runs  # noqa: E402

from whipple.measurement import windows as current  # noqa: E402
from whipple.measurement.experiment import FitOptions, diagnosis_signals, measure_run  # noqa: E402
from whipple.measurement.free_motion import set_aside_outlying  # noqa: E402


def _load(path: str):
    spec = importlib.util.spec_from_file_location("earlier_windows", path)
    module = importlib.util.module_from_spec(spec)
    # Dataclasses look their module up while they are built.
    sys.modules["earlier_windows"] = module
    spec.loader.exec_module(module)
    return module


def _touched(job: tuple[str, str, str, int, str]) -> tuple[str, str, int, list[float]]:
    """The speeds [m/s] of a trial whose runs the two finders cut differently."""
    old_path, bicycle, family, seed, conditions = job
    earlier = _load(old_path)
    _, _, runs = trial_runs(family, seed, bicycle, conditions=conditions)
    speeds = []
    for run in runs:
        # The samples measure_run lets a window use.
        valid = np.isfinite(run.speed()) & np.logical_and.reduce(
            [np.isfinite(run.signals[name]) for name in FitOptions().signals])
        before = [(w.start_index, w.stop_index) for w in earlier.find_windows(run, valid=valid).windows]
        after = [(w.start_index, w.stop_index) for w in current.find_windows(run, valid=valid).windows]
        if before != after:
            speeds.append(float(np.median(run.speed())))
    return bicycle, family, seed, speeds


def _short_above_noise(job: tuple[float, str, str, int, str]) -> tuple[str, str, int, list[float]]:
    """The speeds [m/s] of a trial's runs with a usable window of fewer than the given cycles above the noise."""
    minimum, bicycle, family, seed, conditions = job
    base, _, runs = trial_runs(family, seed, bicycle, conditions=conditions)
    return bicycle, family, seed, [
        float(np.median(run.speed())) for run in runs
        if any(m.skipped is None and m.fit is not None and m.fit.cycles_above_noise < minimum
               for m in measure_run(run, None, trial_options(base, min_cycles_above_noise=0.0)))]


def _set_aside(job: tuple[None, str, str, int, str]) -> tuple[str, str, int, list[float]]:
    """The speeds [m/s] of a trial's windows that no one free motion follows (set aside)."""
    _, bicycle, family, seed, conditions = job
    base, _, runs = trial_runs(family, seed, bicycle, conditions=conditions)
    options = trial_options(base, signals=diagnosis_signals(runs))
    measured = [m for run in runs for m in measure_run(run, None, options)]
    return bicycle, family, seed, [m.speed.mean for m, kept in zip(measured, set_aside_outlying(measured), strict=True)
                                   if m.usable and not kept.usable]


def _measured(job: tuple[None, str, str, int, str]) -> tuple[str, str, int, list[list]]:
    """A trial's windows as its diagnosis measures them: [speed, first, last, usable] per fitted window."""
    _, bicycle, family, seed, conditions = job
    base, _, runs = trial_runs(family, seed, bicycle, conditions=conditions)
    options = trial_options(base, signals=diagnosis_signals(runs))
    return bicycle, family, seed, [
        [round(float(np.median(run.speed())), 6), m.fit.start, m.fit.stop, bool(m.usable)]
        for run in runs for m in measure_run(run, None, options) if m.fit is not None]


def _compare(old: str, new: str) -> None:
    """Print the trials whose measured windows differ between two ``--dump`` files."""
    def read(path: str) -> dict[tuple, list]:
        with open(path) as lines:
            return {tuple(entry[:3]): entry[3] for entry in map(json.loads, lines)}

    before, after = read(old), read(new)
    touched = 0
    for key in sorted(set(before) & set(after), key=lambda k: (k[2], k[0], k[1])):
        if before[key] != after[key]:
            touched += 1
            print(json.dumps(list(key)), flush=True)
            speeds = sorted({w[0] for w in {tuple(w) for w in before[key]} ^ {tuple(w) for w in after[key]}})
            print(f"{' '.join(map(str, key))}: {speeds}", file=sys.stderr)
    print(f"{touched} of {len(set(before) & set(after))} trials touched", file=sys.stderr)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old_windows", nargs="?", help="the earlier windows.py")
    parser.add_argument("--cycles-above-noise", type=float,
                        help="instead: the trials with a window of fewer weave cycles above the noise")
    parser.add_argument("--set-aside", action="store_true",
                        help="instead: the trials with a window that free_motion.set_aside_outlying sets aside")
    parser.add_argument("--bicycles", nargs="*", default=[*BICYCLES, *CONTROLLED_BICYCLES],
                        help="default: those of bench_diagnosis.py, the controlled variants included")
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--conditions", choices=list(CONDITIONS), default="treadmill",
                        help="where the trials' runs are made (as bench_diagnosis.py --conditions)")
    parser.add_argument("--dump", help="instead: write every trial's measured windows to this file")
    parser.add_argument("--compare", nargs=2, metavar=("OLD", "NEW"),
                        help="instead: the trials whose windows differ between two --dump files")
    args = parser.parse_args()
    if args.compare:
        _compare(*args.compare)
        return
    if sum([args.old_windows is not None, args.cycles_above_noise is not None, args.set_aside,
            args.dump is not None]) != 1:
        parser.error("give one of OLD_WINDOWS.py, --cycles-above-noise, --set-aside, --dump and --compare")
    first = args.cycles_above_noise if args.cycles_above_noise is not None else args.old_windows
    jobs = [(first, bicycle, family, seed, args.conditions)
            for seed in range(args.first_seed, args.first_seed + args.seeds)
            for bicycle in args.bicycles for family in families(bicycle)]
    if args.dump:
        with ProcessPoolExecutor(args.workers) as pool, open(args.dump, "w") as out:
            for entry in pool.map(_measured, jobs, chunksize=4):
                out.write(json.dumps(list(entry)) + "\n")
        return
    touched = 0
    check = (_set_aside if args.set_aside else _touched if args.cycles_above_noise is None else _short_above_noise)
    with ProcessPoolExecutor(args.workers) as pool:
        for bicycle, family, seed, speeds in pool.map(check, jobs, chunksize=4):
            if speeds:
                touched += 1
                print(json.dumps([bicycle, family, seed]), flush=True)
                print(f"{bicycle} {family} {seed}: {speeds}", file=sys.stderr)
    print(f"{touched} of {len(jobs)} trials touched", file=sys.stderr)


if __name__ == "__main__":
    main()
