"""Diagnose what the model gets wrong on measured runs, name the cause, extend, measure the gain.

Every free-coasting window of the runs is fitted (the same measurement as ``whipple fit``); each
candidate cause (steer damping, Coulomb steer friction, steer inertia rigid or reflected, speed
scale, rear or front payload, tyre compliance, the controller's gain, delay or lag, a wrong parameter) is fitted to
all windows jointly and compared by its evidence; the chosen cause's extended model is tested on
held-out speeds (with --gain-by-cause, every candidate too, and a choice by prediction). The
bicycle file carries the controller, if any. --workers N runs the held-out speeds' diagnoses on a
local Dask cluster of N processes, --scheduler ADDRESS on an existing one; the results are those
of the serial run. The library does the same in one call: whipple.diagnose(runs, bicycle, options).
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path

from whipple.atomic import write_text_atomic
from whipple.cli.arguments import add_rider_argument, bicycle_inputs, integer, number
from whipple.cli.measurement_arguments import (
    add_bundled_argument,
    add_measurement_arguments,
    measurement_options,
    print_run_notes,
)
from whipple.cli.outputs import check_outputs, save_figure
from whipple.cli.progress import ProgressBars
from whipple.diagnosis.estimate_text import estimate_text
from whipple.diagnosis.fitting import COMPARISONS
from whipple.diagnosis.gain_text import cause_gain_sentences, gain_sentences
from whipple.diagnosis.markdown import report_markdown
from whipple.diagnosis.options import OCCAM_CHARGES, DiagnosisOptions
from whipple.diagnosis.pipeline import diagnose
from whipple.diagnosis.plots import report_figures
from whipple.diagnosis.priors import shift_sentence
from whipple.diagnosis.report import DiagnosisReport
from whipple.distributed import check_cluster_options
from whipple.errors import InputError
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import MIN_CYCLES, MIN_WINDOWS, SHORT_WINDOW_CYCLES
from whipple.measurement.experiment_file import Experiment, group_model_file, read_experiment
from whipple.model.fleet import Model
from whipple.model.parameters import Bicycle, load_bicycle, write_bicycle_toml


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("runs", nargs="*", type=Path, metavar="RUNS", help="run files")
    add_bundled_argument(parser, "use")
    parser.add_argument("--bicycle", metavar="PARAMS", help="bicycle file or built-in name")
    parser.add_argument("--experiment", metavar="FILE",
                        help="an experiment file of several groups (one bicycle under several controllers; "
                             "'bundled': both bundled experiments), instead of RUNS and --bicycle")
    parser.add_argument("--layout", default=None, help="layout of the run files (name or TOML file)")
    parser.add_argument("--windows", type=Path, default=None, metavar="FILE",
                        help="windows file instead of automatic windows")
    parser.add_argument("--json", type=Path, default=None, metavar="OUT", help="write the diagnosis JSON")
    parser.add_argument("--report", type=Path, default=None, metavar="DIR", help="write report.md and figures")
    parser.add_argument("--save-model", type=Path, default=None, metavar="FILE",
                        help="write the extended model as a bicycle file (with --experiment: a folder, one "
                             "<group>.toml per group)")
    parser.add_argument("--no-parameters", action="store_true",
                        help="do not consider a wrong benchmark parameter as a cause")
    add_measurement_arguments(parser)
    parser.add_argument("--compare", choices=COMPARISONS, default="samples",
                        help="how each model is compared with the windows: samples (default), its free response "
                             "fitted to every window's samples; fitting-function, its weave eigenvalue plus the bias "
                             "the window's fit shows on the model's own response; eigenvalues, its weave eigenvalue "
                             "directly (see docs/diagnosis.md)")
    parser.add_argument("--gain-by-cause", nargs="?", const="singles", choices=("singles", "pairs"), default=None,
                        help="also give every candidate's held-out gain, each refitted on every fold without a "
                             "choice (pairs: also every pair of physical causes; slow, see docs/diagnosis.md)")
    parser.add_argument("--evidence", choices=OCCAM_CHARGES, default=DiagnosisOptions.occam,
                        help="how the evidence charges a cause's fitted values: bic (default), ln(n)/2 per value; "
                             "prior, the marginal likelihood under each value's physical or measured prior, with "
                             "the calibration of every measured parameter as a candidate (for a bicycle whose "
                             "measurement uncertainty is stated; slower); laplace, the share of its bounds a fit "
                             "leaves open")
    parser.add_argument("--prediction-shortlist", type=integer, metavar="N",
                        default=DiagnosisOptions.prediction_shortlist,
                        help="where no candidate explains the data, choose the model offered among the base model "
                             "and the N best-supported physically consistent candidates by how well each predicts "
                             "the speeds left out in turn (default "
                             f"{DiagnosisOptions.prediction_shortlist}; 0: always the best-supported consistent one)")
    parser.add_argument("--prediction-standard-errors", type=number, metavar="K",
                        default=DiagnosisOptions.prediction_standard_errors,
                        help="that choice's rule: offer the simplest candidate whose mean squared error on the "
                             "left-out speeds is within K standard errors of the best predictor's (default "
                             f"{DiagnosisOptions.prediction_standard_errors:g}; 0: the best predictor)")
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument("--workers", type=integer, metavar="N",
                         help="diagnose the held-out speeds on a local Dask cluster of N processes")
    cluster.add_argument("--scheduler", metavar="ADDRESS",
                         help="diagnose the held-out speeds on an existing Dask cluster (e.g. tcp://host:8786)")


def options_of(args: argparse.Namespace) -> DiagnosisOptions:
    """Return the diagnosis options of the command's flags."""
    return DiagnosisOptions(measurement=measurement_options(args), comparison=args.compare,
                            parameters=not args.no_parameters, gain_by_cause=args.gain_by_cause,
                            occam=args.evidence, prediction_shortlist=args.prediction_shortlist,
                            prediction_standard_errors=args.prediction_standard_errors)


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    check_cluster_options(args.scheduler, args.workers)
    experiment = _experiment(args)
    sources: list = [*args.runs, *(bundled_runs(args.bundled) if args.bundled else [])]
    if not sources and experiment is None:
        raise InputError("no run files given (name files, use --bundled, or --experiment FILE)")
    if experiment is None and args.bicycle is None:
        raise InputError("--bicycle is needed (a bicycle file or a built-in name), or --experiment FILE")
    inputs = [s for s in sources if isinstance(s, Path)] + bicycle_inputs(args)
    inputs += [path for path in (args.windows, args.layout) if path is not None]
    inputs += list(experiment.inputs()) if experiment is not None else []
    if experiment is None and args.save_model is not None and Path(args.save_model).suffix.lower() == ".txt":
        raise InputError("--save-model writes TOML; a .txt file would be read back as BicycleParameters text "
                         "(use .toml)", args.save_model)
    report_file = args.report / "report.md" if args.report is not None else None
    models = ({"--save-model": args.save_model} if experiment is None else
              {f"--save-model's {name}.toml": group_model_file(args.save_model, name)
               for name in (group.name for group in experiment.groups)} if args.save_model is not None else {})
    check_outputs({"--json": args.json, **models, "--report's report.md": report_file}, inputs,
                  {"--report": args.report, **({"--save-model": args.save_model}
                                               if experiment is not None and args.save_model is not None else {})})
    options = options_of(args)
    with ProgressBars() as progress:
        if experiment is not None:
            report = diagnose(experiment, options=options, progress=progress, workers=args.workers,
                              scheduler=args.scheduler)
        else:
            report = diagnose(sources, load_bicycle(args.bicycle, rider=args.rider), options, layout=args.layout,
                              windows=args.windows, progress=progress, workers=args.workers, scheduler=args.scheduler)
    data = report.to_dict()
    _print_report(report, data)
    if args.json is not None:
        write_text_atomic(args.json, json.dumps(data, indent=2) + "\n")
        print(f"wrote {args.json}")
    if args.report is not None:
        figures = {}
        for key, figure in report_figures(report).items():
            figures[key] = f"{key}.png"
            save_figure(figure, args.report / figures[key], dpi=120)
        command = "whipple " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if sys.argv[1:] else ""
        write_text_atomic(args.report / "report.md", report_markdown(report, figures, command))
        print(f"wrote {args.report / 'report.md'}")
    if args.save_model is not None:
        for path, bicycle in saved_models(report.extended, args.save_model):
            write_bicycle_toml(bicycle, path)
            print(f"wrote {path}")
    return 0


def _experiment(args: argparse.Namespace) -> Experiment | None:
    """Return the experiment of ``--experiment``, refusing the options it replaces."""
    if args.experiment is None:
        return None
    given = [flag for flag, value in (("RUNS", args.runs), ("--bundled", args.bundled), ("--bicycle", args.bicycle),
                                      ("--rider", args.rider), ("--layout", args.layout), ("--windows", args.windows))
             if value]
    if given:
        raise InputError(f"--experiment names each group's runs, bicycle, layout and windows: {', '.join(given)} "
                         "cannot be given beside it")
    return read_experiment(args.experiment)


def saved_models(model: Model, target: Path) -> list[tuple[Path, Bicycle]]:
    """Return where ``--save-model`` writes each bicycle: FILE for one bicycle, DIR/<group>.toml for an experiment's."""
    if isinstance(model, Bicycle):
        return [(target, model)]
    return [(group_model_file(target, name), bicycle) for name, bicycle in model.members]


def _print_report(report: DiagnosisReport, data: dict) -> None:
    """Print the report's findings, the headline first."""
    diagnosis, measured = report.diagnosis, report.measured
    runs = len({m.run.name for m in report.measurements})
    how = f"; {measured.describe()}" if measured is not None else ""
    print(f"{len(report.used)} windows used of {len(report.measurements)} ({runs} runs{how})")
    if measured is not None:
        print_run_notes(measured)
    if measured is not None and measured.short:
        print(f"  fewer than {MIN_WINDOWS} windows passed the checks: {measured.short} windows of "
              f"{SHORT_WINDOW_CYCLES:g} to {MIN_CYCLES:g} weave cycles are used, whose eigenvalues are less certain")
    print(f"what the model gets wrong: {report.residual_summary[0]}")
    print(f"verdict: {diagnosis.verdict}" + (f" ({diagnosis.cause})" if diagnosis.verdict != "none" else ""))
    if diagnosis.family:
        print(f"  the data support: {diagnosis.family}")
    for reason in diagnosis.reasons:
        print(f"  why not a confident name: {reason}")
    for name, estimate in data["estimate"].items():
        print(f"  {name} = {estimate_text(estimate)}")
    if data["calibration"]:
        print(f"  the calibration moves: {shift_sentence(data['calibration'])}")
    offered = data["offered"]
    leader_offered = offered is not None and diagnosis.best is not None and offered["cause"] == diagnosis.best.cause
    if report.open_values is not None and leader_offered:
        print(f"  the data leave open: {report.open_values.sentence()}")
    print("ranking: " + ", ".join(f"{cause} {evidence:.1f}" for cause, evidence in diagnosis.ranking()[:5]))
    if diagnosis.verdict != "none" and not leader_offered:
        if offered is None:
            print("model offered: none (the base model)")
        else:
            values = ", ".join(f"{name} = {e['value']:.6g} {e['unit']}" for name, e in offered["values"].items())
            print(f"model offered: {offered['cause']} ({values}; chosen by {offered['chosen_by']})")
            if report.open_values is not None:
                print(f"  the data leave open: {report.open_values.sentence()}")
    for note in report.caveats:
        print(f"caveat: {note}")
    if report.amplitude is not None:
        print(f"linearity: {report.amplitude.summary()}")
    if report.gain is not None:
        g = report.gain
        for speed in g.speeds:
            print(f"held out {speed.speed:.2f} m/s ({speed.windows} windows, {speed.cause} chosen without it): "
                  f"eigenvalue error RMS {speed.base_rms:.2f} -> {speed.extended_rms:.2f} 1/s "
                  f"(cut {100 * speed.cut:+.0f}%), median {speed.base_median:.2f} -> {speed.extended_median:.2f}")
        for sentence in gain_sentences(g):
            print(f"held-out gain: {sentence}")
        if g.time_base is not None:
            print(f"held-out time-domain error (relative rms): base {g.time_base:.3f}, extended {g.time_extended:.3f}")
    for sentence in cause_gain_sentences(report.cause_gains, report.gain, report.prediction_gain,
                                         report.prediction_fit):
        print(f"every candidate held out: {sentence}")
