"""Hidden-effect rates of the diagnosis, per bicycle and trial family.

For every bicycle of the trials (benchmark, kooijman2008, BicycleParameters' Browser, and for
controller effects the controlled sbw2024 and two riderless bicycles given its kind of
controller, ``kooijman2008_sbw`` and ``browser_sbw``) and every trial family it supports
(tests/hidden_effects.py), over many seeds: simulate runs with the effect hidden at a random
realistic size and position, diagnose them blind, and count the outcomes:

- right: the verdict ``named`` with the expected cause (no effect: ``none``; a truth outside
  every candidate: ``none`` or ``ambiguous``);
- ambiguous (truth): an ``ambiguous`` verdict whose family, or leading pair of causes, holds
  the expected cause (a pair is never named);
- said none: the verdict ``none`` where an effect was hidden;
- wrong confident: the verdict ``named`` with another cause;
- warned: of the wrong confident, how many carry the dispersion caveat (s^2 > 2);
- covered: the leading cause is the expected one and its interval (value +/- 2 std) covers
  the true values.

Run: ``python benchmarks/bench_diagnosis.py [--seeds 17] [--workers 2 | --scheduler ADDRESS]
[--bicycles ...] [--families ...] [--trials FILE] [--log FILE] [--compare C] [--size-scale S] [--occam laplace]
[--no-rigid-loads] [--cycles-above-noise C] [--fixed-point-start model] [--signals roll_rate] [--twin]
[--conditions ground+faults] [--sample-rate 500] [--noise-scale 3] [--speeds 2.5 4 6]``;
``--seeds`` is per bicycle and family; ``--trials`` runs only the listed trials among those;
``--sample-rate`` samples every run at another rate than the simulator's 100 Hz (the effects,
their sizes and the field conditions drawn stay those of the trials at 100 Hz; write each rate
to its own log); ``--noise-scale`` multiplies every sensor's noise per sample (a cheaper
instrument; the effects and field conditions drawn stay the same); ``--speeds`` gives every
bicycle's trials these speeds instead of their own (fewer speeds than the trials': fewer
windows, and a jackknife over fewer speed groups);
``--size-scale`` multiplies every hidden effect's size (effects smaller or larger than the
ranges the rates were measured on; write each scale to its own log); ``--families two_effects``
hides two different effects together (run only when asked; its outcomes are counted apart:
named one of the two is right, named a third cause wrong); ``--combine-dispersion D`` is an
experiment: pairs of causes are tried when the best single cause leaves a dispersion above D
(the package's rule: 2; 0 tries them always); ``--one-speed-lead 0`` leaves out the rule that a
lead one speed's windows carry is no name (``VerdictRules.one_speed_lead``; the rates before
it); ``--occam laplace`` is another: the evidence's
Occam factor by the Laplace approximation within each cause's bounds
(``DiagnosisOptions.occam``); ``--cycles-above-noise C`` leaves out the windows
holding fewer than C weave cycles above the noise (``FitOptions.min_cycles_above_noise``; the
package's 0.75 by default, 0: the rates before that check); ``--no-rigid-loads`` leaves the
payloads' rigid-load form out of the candidates (``DiagnosisOptions.rigid_loads``, in by
default); ``--fixed-point-start model``
another: the fitting bias' fixed point starts from each model's weave
(``DiagnosisOptions.fixed_point_start``); ``--signals`` the signals fitted jointly in
every window (``whipple diagnose --signals``; by default as ``whipple diagnose`` fits the trials'
runs, the roll rate with the steer angle; ``roll_rate``: alone, as the rates before 2026-11-29,
latest); ``--compare fitting-function`` compares each window's eigenvalue through the fitting
function (the default until 2026-12-01), ``--compare eigenvalues`` directly; by default models
are compared with the windows' samples (``DiagnosisOptions.comparison``). Every trial is
diagnosed by :func:`whipple.diagnose` with the options these flags build. The
trials run on a local Dask cluster of N worker processes, or on an existing Dask cluster
(:func:`whipple.distributed.map_ordered`; the workers of an existing cluster need this
repository's ``tests`` folder on their path, for ``hidden_effects``). ``--from-log FILE [FILE ...]``
tabulates logs together (e.g. of a run cut short: trials run seed by seed across every case), with
``--replace-from FILE [FILE ...]`` the trials of other logs in place of its own (a later log's over
an earlier's). ``--twin`` also
diagnoses each trial's windows without noise (``hidden_effects.noise_free_twin``) and logs that
outcome ninth; the column "given" then counts as right, besides the right names, the
ambiguous verdicts with the truth among the contenders whose noise-free twin is ambiguous with
the truth among them too: windows of those speeds and uncertainties cannot single out the
truth however lucky the noise.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from hidden_effects import (  # noqa: E402
    BICYCLES,
    CONDITIONS,
    CONTROLLED_BICYCLES,
    EXPECTED,
    TWO,
    FieldConditions,
    families,
    field_conditions,
    given_data,
    hidden_bicycle,
    hidden_causes,
    measurement_options,
    run_trial,
    trial_bicycle,
    trial_rng,
)

from whipple.cli.measurement_arguments import signal_names  # noqa: E402
from whipple.diagnosis.fitting import COMPARISONS  # noqa: E402
from whipple.diagnosis.options import OCCAM_CHARGES, DiagnosisOptions, PairRules  # noqa: E402
from whipple.distributed import map_ordered  # noqa: E402
from whipple.errors import InputError  # noqa: E402
from whipple.measurement.experiment import MIN_CYCLES_ABOVE_NOISE  # noqa: E402

OUTCOMES = ("right", "ambiguous_truth", "none", "wrong")


Arguments = tuple[str, str, int, float, bool, DiagnosisOptions, FieldConditions, tuple[float, ...] | None]


def _trial(arguments: Arguments) -> tuple:
    bicycle, family, seed, scale, twin, options, conditions, speeds = arguments
    try:
        trial = run_trial(family, seed, bicycle, speeds=speeds, scale=scale, twin=twin, options=options,
                          conditions=conditions)
    except InputError as error:  # e.g. an effect so large that too few windows were usable
        return (bicycle, family, seed, "error", error.problem, "error", False, float("nan"))
    outcome = trial.outcome
    if family == "none" and outcome == "right":
        outcome = "said_none"  # the right answer here, kept apart from "said none" to an effect
    row = (bicycle, family, seed, trial.diagnosis.verdict, trial.diagnosis.cause, outcome, trial.covers(),
           max(trial.diagnosis.scale, trial.diagnosis.shape_scale))
    return (*row, trial.twin_outcome) if twin else row


def _reclassified(r: tuple) -> tuple:
    """A logged result under the current verdict rules (logs of earlier code).

    * A verdict ``named`` for a pair of causes ("A + B"): ``ambiguous`` since a leading pair is
      never named outright (the rule changes nothing else, so the rest of the trial stands; the
      outcome is right for a truth outside the candidates, ambiguous (truth) if the pair holds
      the expected cause, otherwise ambiguous: the rivals are not logged).
    * An ambiguous verdict led by a pair holding the expected cause: ambiguous (truth) (logs
      written before pairs were split in ``Trial.contenders``).
    """
    expected = EXPECTED.get(r[1])
    parts = r[4].split(" + ")
    if r[3] == "named" and len(parts) == 2:
        outcome = "right" if expected is None else "ambiguous_truth" if expected in parts else "ambiguous"
        return (r[0], r[1], r[2], "ambiguous", r[4], outcome, *r[6:])
    if r[5] == "ambiguous" and r[3] == "ambiguous" and expected in parts:
        return (*r[:5], "ambiguous_truth", *r[6:])
    return r


def _given_data(r: tuple) -> str:
    """A logged result's outcome as :func:`hidden_effects.given_data` counts it (the twin's
    outcome is logged ninth, with ``--twin``)."""
    return given_data(r[5], r[8] if len(r) > 8 else None)


def _row(label: str, rows: list, width: int = 28) -> str:
    n = len(rows)
    count = {outcome: sum(r[5] == outcome for r in rows) for outcome in (*OUTCOMES, "said_none", "ambiguous")}
    right = count["right"] + count["said_none"]
    given = sum(_given_data(r) in ("right", "said_none") for r in rows)
    none = count["none"] + count["said_none"]
    covered = sum(r[6] for r in rows)
    others: dict[str, int] = {}
    for r in rows:
        if r[5] not in ("right", "said_none"):
            key = f"{r[3]}:{r[4]}"
            others[key] = others.get(key, 0) + 1
    shown = ", ".join(f"{k} x{v}" for k, v in sorted(others.items(), key=lambda kv: -kv[1])[:4])
    # A wrong name with the report's caveat that even the best model leaves residuals well
    # above their stated uncertainties (dispersion above 2).
    warned = sum(r[5] == "wrong" and r[7] > 2.0 for r in rows)
    return (f"{label:<{width}}{n:>6}{right / n:>7.0%}{given / n:>7.0%}{count['ambiguous_truth'] / n:>8.0%}"
            f"{none / n:>7.0%}"
            f"{count['wrong'] / n:>7.0%}{warned:>7}{covered / n:>9.0%}  {shown}")


def _order(results: list, case: tuple[str, str]) -> int:
    """Cases in the order they first ran (bicycle by bicycle as given, then family)."""
    bicycles = list(dict.fromkeys(r[0] for r in results))
    families_seen = list(dict.fromkeys(r[1] for r in results))
    return bicycles.index(case[0]) * 100 + families_seen.index(case[1])


def _lowest_rate(results: list, outcomes: tuple[str, ...]) -> tuple[float, str]:
    """The lowest share of trials with one of `outcomes` over the families, and that family."""
    if not results:
        return float("nan"), "-"
    return min((sum(r[5] in outcomes for r in results if r[1] == family) / sum(r[1] == family for r in results),
                family) for family in dict.fromkeys(r[1] for r in results))


def _print_two_effects(rows: list) -> None:
    """Outcomes of the two-effect family, with each wrong confident name's two true effects."""
    bases = {name: trial_bicycle(name) for name in dict.fromkeys(r[0] for r in rows)}
    expected = {tuple(r[:3]): set(hidden_causes(hidden_bicycle(bases[r[0]], TWO, trial_rng(TWO, r[2]))[1]))
                for r in rows}
    count = {outcome: sum(r[5] == outcome for r in rows) for outcome in ("right", "ambiguous_truth", "ambiguous",
                                                                          "none", "wrong", "error")}
    both = sum(r[5] == "ambiguous_truth" and len(expected[tuple(r[:3])]) == 2
               and expected[tuple(r[:3])] <= set(r[4].split(" + ")) for r in rows)
    print(f"\ntwo effects together ({len(rows)} trials): named one of them {count['right']}; ambiguous with one of "
          f"them among the contenders {count['ambiguous_truth']} (led by the pair of both: {both}); ambiguous "
          f"otherwise {count['ambiguous']}; none {count['none']}; no usable windows {count['error']}; wrong "
          f"confident {count['wrong']} ({count['wrong'] / len(rows):.1%})")
    for r in rows:
        if r[5] == "wrong":
            print(f"  wrong: {r[0]} seed {r[2]}: hidden {' + '.join(sorted(expected[tuple(r[:3])]))} "
                  f"(and any outside the candidates), named {r[4]}")


def _asked_families(bicycle: str, asked: list[str] | None) -> list[str]:
    """The families run on a bicycle: its own (:func:`families`), or those asked for that it supports.

    A family outside the rates of record (``calibration``) runs only when asked for.
    """
    if asked is None:
        return list(families(bicycle))
    own = families(bicycle, two=TWO in asked)
    return [family for family in asked if family in own or (family == "calibration" and bicycle in BICYCLES)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=17, help="seeds per bicycle and family")
    parser.add_argument("--first-seed", type=int, default=0,
                        help="run seeds first..first+seeds-1 (to extend a log: --log appends)")
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument("--workers", type=int, default=2, help="local Dask worker processes")
    cluster.add_argument("--scheduler", help="address of an existing Dask scheduler")
    parser.add_argument("--bicycles", nargs="*", default=[*BICYCLES, *CONTROLLED_BICYCLES])
    parser.add_argument("--families", nargs="*", default=None,
                        help="default: all single-effect families a bicycle supports (two_effects: only when listed)")
    parser.add_argument("--log", type=Path, help="append each trial's result to this JSON-lines file as it ends")
    parser.add_argument("--from-log", type=Path, nargs="+",
                        help="tabulate the trials of these logs (together) instead of running any")
    parser.add_argument("--compare", choices=COMPARISONS, default="samples",
                        help="how models are compared with the windows (diagnose_observations(comparison=...); "
                             "default: with their samples)")
    defaults = DiagnosisOptions()
    parser.add_argument("--combine-dispersion", type=float, default=defaults.pairs.dispersion,
                        help="experiment: the dispersion of the best single cause above which pairs are tried "
                             f"(PairRules.dispersion, {defaults.pairs.dispersion:g}; 0: always)")
    parser.add_argument("--one-speed-lead", type=float, default=defaults.verdict.one_speed_lead,
                        help="the lead a named cause keeps over every rival without any one speed's windows "
                             f"(VerdictRules.one_speed_lead, {defaults.verdict.one_speed_lead:g}; 0: not checked)")
    parser.add_argument("--occam", choices=OCCAM_CHARGES, default=defaults.occam,
                        help="experiment: how the evidence charges fitted values (DiagnosisOptions.occam)")
    parser.add_argument("--rigid-loads", action=argparse.BooleanOptionalAction, default=defaults.rigid_loads,
                        help="the payloads' rigid-load form among the candidates (DiagnosisOptions.rigid_loads; "
                             "--no-rigid-loads: point masses only)")
    parser.add_argument("--cycles-above-noise", type=float, default=MIN_CYCLES_ABOVE_NOISE,
                        help="leave out windows holding fewer weave cycles above the noise "
                             f"(FitOptions.min_cycles_above_noise; default {MIN_CYCLES_ABOVE_NOISE:g}, 0: off)")
    parser.add_argument("--fixed-point-start", choices=("measured", "model"), default=defaults.fixed_point_start,
                        help="experiment: where the fitting bias' fixed point starts "
                             "(DiagnosisOptions.fixed_point_start)")
    parser.add_argument("--signals", type=signal_names, default=None,
                        help="signals fitted jointly in every window (whipple diagnose --signals; default: as whipple "
                             "diagnose chooses, roll_rate,steer_angle for the trials' runs)")
    parser.add_argument("--conditions", choices=CONDITIONS, default="treadmill",
                        help="where the trials' runs are made and the sensors' faults (hidden_effects.CONDITIONS; "
                             "default treadmill, the rates of record)")
    parser.add_argument("--speeds", type=float, nargs="+", default=None,
                        help="the runs' speeds [m/s], one run each, for every bicycle (default: the trials' own, "
                             "hidden_effects.trial_speeds)")
    parser.add_argument("--sample-rate", type=float, default=None,
                        help="every run's sample rate [Hz] (default: the simulator's, 100 Hz, the rates of record)")
    parser.add_argument("--noise-scale", type=float, default=1.0,
                        help="multiply every sensor's noise per sample by this (default 1: the simulator's sensors, "
                             "the rates of record)")
    parser.add_argument("--size-scale", type=float, default=1.0,
                        help="multiply every hidden effect's size by this (tests/hidden_effects.py "
                             "hidden_bicycle: 0.5 halves, 2 doubles the drawn ranges)")
    parser.add_argument("--twin", action="store_true",
                        help="also diagnose each trial's windows without noise (hidden_effects.noise_free_twin): "
                             "whether the data could single out the truth at all")
    parser.add_argument("--replace-from", type=Path, nargs="+",
                        help="with --from-log: take each trial found in these logs (e.g. a --twin rerun, or the "
                             "trials a change touches) from them, a later log's over an earlier's; trials only "
                             "these logs hold are added")
    parser.add_argument("--trials", type=Path,
                        help="run only these trials (JSON lines [bicycle, family, seed], e.g. from changed_windows.py)")
    args = parser.parse_args()
    if args.from_log is not None:
        results = [_reclassified(tuple(json.loads(line)))
                   for log in args.from_log for line in log.read_text().splitlines() if line.strip()]
        print(f"{len(results)} trials from {', '.join(map(str, args.from_log))}")
        for replacement in args.replace_from or ():
            rerun = {tuple(row[:3]): row for line in replacement.read_text().splitlines() if line.strip()
                     for row in [_reclassified(tuple(json.loads(line)))]}
            changed = sum(tuple(r[:3]) in rerun and rerun[tuple(r[:3])][5] != r[5] for r in results)
            known = {tuple(r[:3]) for r in results}
            replaced = sum(key in rerun for key in known)
            results = [rerun.get(tuple(r[:3]), r) for r in results]
            added = [row for key, row in rerun.items() if key not in known]
            results += added
            print(f"{replaced} of them from {replacement} ({changed} with another outcome than before); "
                  f"{len(added)} more trials from it")
    else:
        # Seed by seed across every case, so that a run cut short still covers every case.
        jobs = [(bicycle, family, seed) for seed in range(args.first_seed, args.first_seed + args.seeds)
                for bicycle in args.bicycles
                for family in _asked_families(bicycle, args.families)]
        if args.trials is not None:
            listed = {tuple(json.loads(line)) for line in args.trials.read_text().splitlines() if line.strip()}
            jobs = [job for job in jobs if job in listed]
        options = DiagnosisOptions(
            measurement=measurement_options(args.signals or "auto", args.cycles_above_noise),
            comparison=args.compare, rigid_loads=args.rigid_loads, occam=args.occam,
            fixed_point_start=args.fixed_point_start, pairs=PairRules(dispersion=args.combine_dispersion),
            verdict=replace(defaults.verdict, one_speed_lead=args.one_speed_lead))
        conditions = replace(field_conditions(args.conditions), sample_rate=args.sample_rate,
                             noise_scale=args.noise_scale)
        speeds = None if args.speeds is None else tuple(args.speeds)
        tasks = [(*job, args.size_scale, args.twin, options, conditions, speeds) for job in jobs]
        started = time.perf_counter()
        results = []
        workers = None if args.scheduler else args.workers
        with map_ordered(_trial, tasks, scheduler=args.scheduler, workers=workers) as trials:
            for result in trials:
                results.append(result)
                print(f"\r{len(results)}/{len(jobs)} trials", end="", file=sys.stderr, flush=True)
                if args.log is not None:
                    with args.log.open("a") as log:
                        log.write(json.dumps(result) + "\n")
        print(file=sys.stderr)
        elapsed = time.perf_counter() - started
        where = args.scheduler or f"{args.workers} local workers"
        print(f"{len(jobs)} trials in {elapsed:.0f} s ({where})")
    header = (f"{'bicycle / family':<28}{'seeds':>6}{'right':>7}{'given':>7}{'amb(T)':>8}{'none':>7}{'wrong':>7}"
              f"{'warned':>7}{'covered':>9}  other verdicts")
    print(header)
    cases = sorted(dict.fromkeys((r[0], r[1]) for r in results), key=lambda case: _order(results, case))
    for bicycle, family in cases:
        print(_row(f"{bicycle} / {family}", [r for r in results if (r[0], r[1]) == (bicycle, family)]))
    print("\nAcross bicycles")
    print(header)
    for family in dict.fromkeys(r[1] for r in results):
        print(_row(family, [r for r in results if r[1] == family]))
    two = [r for r in results if r[1] == TWO]
    results = [r for r in results if r[1] != TWO]
    if two:
        _print_two_effects(two)
    if not results:
        return
    named = [r for r in results if r[1] != "none" and EXPECTED[r[1]] is not None]
    wrong = sum(r[5] == "wrong" for r in results)
    worst = _lowest_rate(named, ("right",))
    print(f"\nmust show: each named cause right >= 90%: lowest {worst[0]:.0%} ({worst[1]}); "
          f"wrong confident <= 5%: {wrong} of {len(results)} ({wrong / len(results):.1%}, all families)")
    outside = [r for r in results if r[1] != "none" and EXPECTED[r[1]] is None]
    inside = [r for r in results if r[1] == "none" or EXPECTED[r[1]] is not None]
    wrong_inside = sum(r[5] == "wrong" for r in inside)
    print(f"wrong confident where the truth is a candidate (or no effect): {wrong_inside} of {len(inside)} "
          f"({wrong_inside / max(len(inside), 1):.1%}); where it is none of them: "
          f"{wrong - wrong_inside} of {len(outside)}")
    # Named right, or left open with the truth among the contenders (what the data can tell).
    if any(len(r) > 8 for r in named):
        given = _lowest_rate([(*r[:5], _given_data(r), *r[6:]) for r in named], ("right",))
        twins = sum(len(r) > 8 and r[8] is not None for r in named)
        print(f"right given what the windows can tell (ambiguous counted right where the noise-free twin is "
              f"ambiguous too; {twins} trials with a twin): lowest {given[0]:.0%} ({given[1]})")
    open_or_right = _lowest_rate(named, ("right", "ambiguous_truth"))
    print(f"named right or ambiguous with the truth among the contenders: lowest {open_or_right[0]:.0%} "
          f"({open_or_right[1]})")


if __name__ == "__main__":
    main()
