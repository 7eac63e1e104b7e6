"""Score models on measured runs: the weave eigenvalue's error and the samples' residual, per speed and overall.

Every free-coasting window of the runs is measured once (the same measurement as ``whipple fit``
and ``whipple diagnose``) and each model is scored on the usable ones: the RMS and the median of
|measured - predicted| weave eigenvalue [1/s] (the model's mode nearest the measured eigenvalue at
the window's speed, as the held-out gain of ``whipple diagnose`` scores its models), and the
chi-square per sample of the model's free response fitted to each window's samples (1: only the
noise left). Per speed group and over all windows.

Runs: RUN files (or --bundled) scored against each --bicycle; they are measured against the first
one (its controller and mode shape check the steer signal's sign). Or --experiment FILE (or the word
"bundled"): each group's runs measured against the group's own bicycle, which is scored first
(labelled "experiment"), and with --models DIR the models DIR/<group>.toml (one bicycle file per
group, e.g. the extended models of a diagnosis), labelled DIR. --json and --csv write the scores.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
from pathlib import Path

from whipple.atomic import write_text_atomic
from whipple.cli.measurement_arguments import (
    add_bundled_argument,
    add_measurement_arguments,
    measurement_options,
    print_run_notes,
)
from whipple.cli.outputs import check_outputs
from whipple.cli.progress import ProgressBars
from whipple.diagnosis.evaluation import Evaluation, evaluate, evaluate_experiment
from whipple.errors import InputError
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment_file import BUNDLED, read_experiment, read_group_models
from whipple.measurement.measure import MeasurementOptions, measure_runs
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle

#: Columns of the --csv table (one row per scope, group, speed and model).
CSV_COLUMNS = ("scope", "group", "model", "speed", "speed_low", "speed_high", "windows", "rms", "median",
               "chi2_per_sample", "samples")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    parser.add_argument("runs", nargs="*", metavar="RUN", help="run files (with --bicycle)")
    add_bundled_argument(parser, "also score on")
    parser.add_argument("--bicycle", action="append", default=[], metavar="PARAMS",
                        help="a model to score: bicycle file or built-in name (repeat for several; the runs are "
                             "measured against the first)")
    parser.add_argument("--layout", metavar="NAME-or-FILE", help="layout of the RUN files (name or TOML file)")
    parser.add_argument("--windows", metavar="FILE", help="windows file fitted instead of the automatic windows")
    parser.add_argument("--experiment", metavar="FILE",
                        help="an experiment file (groups of runs, each with its bicycle; 'bundled': both bundled "
                             "experiments) instead of RUN files and --bicycle")
    parser.add_argument("--models", action="append", default=[], metavar="DIR",
                        help="with --experiment: also score the models DIR/<group>.toml (repeat for several)")
    add_measurement_arguments(parser)
    parser.add_argument("--no-samples", action="store_true",
                        help="score the weave eigenvalues alone, not the samples' residual (faster)")
    parser.add_argument("--json", metavar="OUT", help="write the scores as JSON")
    parser.add_argument("--csv", metavar="OUT", help="write the table as CSV")


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    options = measurement_options(args)
    if args.experiment is not None:
        given = [flag for flag, value in (("RUN files", args.runs), ("--bundled", args.bundled),
                                          ("--bicycle", args.bicycle), ("--layout", args.layout),
                                          ("--windows", args.windows)) if value]
        if given:
            raise InputError(f"--experiment names the runs and their bicycles; {', '.join(given)} cannot be "
                             "given with it")
        experiment = read_experiment(args.experiment)
        # The models read are <folder>/<group>.toml: inputs as much as the experiment's files.
        inputs = [*experiment.inputs(), *args.models,
                  *(Path(folder) / f"{group.name}.toml" for folder in args.models for group in experiment.groups)]
        check_outputs({"--json": args.json, "--csv": args.csv}, inputs)
        model_sets = {"experiment": experiment.bicycles()}
        for folder in args.models:
            if folder in model_sets:
                raise InputError(f"--models {folder} given twice, or named as the experiment's own bicycles are "
                                 f"(write ./{folder})")
            model_sets[folder] = read_group_models(folder, experiment)
        with ProgressBars() as progress:
            result = evaluate_experiment(experiment, model_sets, options, samples=not args.no_samples,
                                         progress=progress)
        where = "the bundled experiments" if args.experiment == BUNDLED else str(experiment.source)
        print(f"{where}: groups {', '.join(g.name for g in experiment.groups)}; each measured against its own bicycle")
    else:
        result = _evaluate_runs(args, options)
    _print(result)
    _write(args, result)
    return 0


def _evaluate_runs(args: argparse.Namespace, options: MeasurementOptions) -> Evaluation:
    """Measure the RUN files (and bundled runs) against the first --bicycle and score every --bicycle."""
    if args.models:
        raise InputError("--models gives one model per group of an --experiment; score runs with --bicycle")
    if not args.runs and not args.bundled:
        raise InputError("no runs: name run files, use --bundled, or give an --experiment")
    if not args.bicycle:
        raise InputError("no model to score: give --bicycle (repeat it for several)")
    twice = sorted({name for name in args.bicycle if args.bicycle.count(name) > 1})
    if twice:
        raise InputError(f"--bicycle {twice[0]} given twice")
    inputs = [*args.runs, *args.bicycle, *(path for path in (args.layout, args.windows) if path)]
    check_outputs({"--json": args.json, "--csv": args.csv}, inputs)
    models = {name: load_bicycle(name) for name in args.bicycle}
    runs = [read_run(path, layout=args.layout) for path in args.runs]
    runs += [read_run(entry) for entry in (bundled_runs(args.bundled) if args.bundled else [])]
    windows = read_windows(args.windows, runs) if args.windows else None
    with ProgressBars() as progress:
        measured = measure_runs(runs, options, windows=windows, bicycle=next(iter(models.values())),
                                progress=progress)
    print(f"{len(runs)} runs; {measured.describe()}; measured against {args.bicycle[0]}")
    print_run_notes(measured)
    return evaluate(measured, models, samples=not args.no_samples)


def _cells(row: dict) -> list[str]:
    """Return a row's cells for the table and the CSV file."""
    low, high = row["speed_range"]
    chi2 = "" if row["chi2_per_sample"] is None else f"{row['chi2_per_sample']:.4g}"
    return [row["scope"], row["group"] or "", row["model"], f"{row['speed']:.3f}", f"{low:.3f}", f"{high:.3f}",
            str(row["windows"]), f"{row['rms']:.4g}", f"{row['median']:.4g}", chi2, str(row["samples"])]


def _print(result: Evaluation) -> None:
    """Print one line per speed group, group and model, the models of one speed together."""
    rows = result.rows()
    width = max(len("group"), *(len(row["group"] or "") for row in rows))
    model_width = max(len("model"), *map(len, result.models))

    def group_cell(text: str) -> str:  # runs given without an experiment file: no group column
        return f"{text:<{width}}  " if result.groups[0].name is not None else ""

    for group in result.groups:
        name = f"group {group.name}: " if group.name is not None else ""
        print(f"{name}{len(group.runs)} runs, {group.windows} usable windows")
    print()
    print(f"{group_cell('group')}{'speed [m/s]':<11}  {'windows':>7}  {'model':<{model_width}}  "
          f"{'RMS [1/s]':>9}  {'median [1/s]':>12}  {'chi2/sample':>11}")
    for row in rows:
        speed = f"{row['speed']:.2f}" if row["scope"] == "speed" else "all"
        chi2 = "-" if row["chi2_per_sample"] is None else f"{row['chi2_per_sample']:.3g}"
        print(f"{group_cell(row['group'] or 'all')}{speed:<11}  {row['windows']:>7}  {row['model']:<{model_width}}  "
              f"{row['rms']:>9.3f}  {row['median']:>12.3f}  {chi2:>11}")
    print("RMS, median: of |measured - predicted| weave eigenvalue over the windows (the model's mode nearest the "
          "measured one); chi2/sample: the model's free response fitted to each window's samples (1: only noise)")


def _write(args: argparse.Namespace, result: Evaluation) -> None:
    if args.json:
        write_text_atomic(args.json, json.dumps(result.to_dict(), indent=1, allow_nan=False) + "\n")
        print(f"wrote {args.json}")
    if args.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(CSV_COLUMNS)
        writer.writerows(_cells(row) for row in result.rows())
        write_text_atomic(Path(args.csv), buffer.getvalue())
        print(f"wrote {args.csv}")
