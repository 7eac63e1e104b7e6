"""Find the free-coasting windows of measured runs and fit their weave eigenvalues.

The same measurement as ``whipple diagnose`` (whipple.measurement.measure.measure_runs): for
every run the free-coasting windows are found automatically (or read from --windows); the roll
rate and, where every run measures it, the steer angle are fitted jointly with
c1 + exp(d t)[c2 cos wt + c3 sin wt] sharing one eigenvalue (--signals, --baseline); windows that
no free motion follows nearly as well as the others are set aside (--keep-outliers keeps them);
with --bicycle the steer signal's sign is checked against the model. --method seed-paper fits
the roll rate alone with a constant baseline, as the seed paper does. The speed range of each
window is the linear regression of the speed over it. One line per window: run, window number,
start and stop [s], speed range [m/s], eigenvalue d + i w [1/s] with standard deviations, R^2,
and with --bicycle the model's oscillating mode nearest the measured eigenvalue at the window's
mean speed (divided by the bicycle's speed_scale: measured speed = speed_scale * true speed), or
"no mode near" where the model has no oscillation near it. Stretches the window finder rejected,
windows that cannot be fitted and fits too poor to use (R^2 under 0.5, under 0.75 weave cycle in
all or above the noise, see --min-cycles-above-noise) are listed as skipped, with the reason;
where none is fitted, the command ends with a one-line error saying why (exit code 2).

--bundled adds the measured runs shipped with whipple (a steer-by-wire bicycle on a treadmill;
fit them with --bicycle sbw2024, or --bundled model-matching-on with sbw2024-mm) and compares
the automatic windows with the windows picked by hand for them. --windows FILE fits the file's
windows instead and reports how the automatic windows compare with them; --compare FILE only
compares. FILE may be the word "bundled" for the hand-picked windows of the bundled runs.
--json, --csv and --plot write the results (JSON list of windows; CSV table; PNG figures like
the seed paper's Figures 4, 5, 6).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
from pathlib import Path
from typing import Any

from whipple.atomic import refuse_input_overwrite, write_text_atomic
from whipple.cli.arguments import add_rider_argument
from whipple.cli.measurement_arguments import add_bundled_argument, add_measurement_arguments, measurement_options
from whipple.cli.outputs import check_outputs, save_figure
from whipple.cli.progress import ProgressBars
from whipple.cli.window_comparison import print_comparison
from whipple.errors import InputError
from whipple.measurement.bundled import bundled_reference_windows, bundled_runs
from whipple.measurement.experiment import CSV_COLUMNS
from whipple.measurement.measure import MeasuredRuns, measure_runs, model_modes, unusable_text
from whipple.measurement.plots import fit_figures
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import check_distinct_names, read_run
from whipple.measurement.windows import Window
from whipple.model.parameters import Bicycle, load_bicycle
from whipple.stability.nearest_modes import SHAPE_MATCH

#: Per window, the model's nearest oscillating mode and whether it is near (measure.model_modes).
Modes = list[tuple[complex | None, bool] | None]
#: The word that names the hand-picked windows of the bundled runs in --windows/--compare.
BUNDLED = "bundled"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("runs", nargs="*", metavar="RUN",
                        help="run files (native CSV, a layout's format, or .gz of either)")
    add_bundled_argument(parser, "also fit")
    parser.add_argument("--layout", metavar="NAME-or-FILE",
                        help="layout of the RUN files: a built-in name (sbw-treadmill) or a "
                             "layout TOML file (default: native, or recognised by the header)")
    parser.add_argument("--windows", metavar="FILE",
                        help="fit the windows of FILE (CSV: run,start,stop [s] or "
                             "run,start_row,stop_row) instead of the automatic ones, and "
                             "compare the automatic ones with them; 'bundled': the "
                             "hand-picked windows of the bundled runs")
    parser.add_argument("--compare", metavar="FILE",
                        help="windows file to compare the automatic windows with (they are "
                             "still the ones fitted); 'bundled' as for --windows")
    add_measurement_arguments(parser)
    parser.add_argument("--bicycle", metavar="PARAMS",
                        help="bicycle file or built-in name: list its mode nearest each window's eigenvalue at "
                             "the window's speed, and check the steer signal's sign against it")
    parser.add_argument("--json", metavar="OUT", help="write the windows as a JSON list")
    parser.add_argument("--csv", metavar="OUT", help="write the table as CSV")
    parser.add_argument("--plot", "--plots", dest="plot", metavar="DIR",
                        help="write figures (PNG) into DIR: each run's signals, each fit, and "
                             "the eigenvalues against speed")


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    if not args.runs and not args.bundled:
        raise InputError("no runs: name run files, or use --bundled for the runs shipped with whipple")
    options = measurement_options(args)
    inputs = [*args.runs, *(f for f in (args.windows, args.compare, args.bicycle, args.rider, args.layout)
                            if f and f != BUNDLED)]
    check_outputs({"--json": args.json, "--csv": args.csv}, inputs, {"--plot": args.plot})

    runs = [read_run(path, layout=args.layout) for path in args.runs]
    if args.bundled:
        runs += [read_run(entry) for entry in bundled_runs(args.bundled)]
    check_distinct_names(runs)

    def windows_file(value: str | None) -> tuple[Window, ...] | None:
        if value is None:
            return None
        return read_windows(bundled_reference_windows() if value == BUNDLED else value, runs)

    chosen = windows_file(args.windows)
    reference = windows_file(args.compare) if args.compare else chosen
    reference_name = args.compare or args.windows
    if reference is None and args.bundled:
        reference, reference_name = windows_file(BUNDLED), BUNDLED
    if reference_name == BUNDLED:
        reference_name = "the hand-picked windows of the bundled runs"
    if args.rider and not args.bicycle:
        raise InputError("--rider needs --bicycle (the bicycle the rider sits on)")
    bicycle = load_bicycle(args.bicycle, rider=args.rider) if args.bicycle else None

    with ProgressBars() as progress:
        measured = measure_runs(runs, options, windows=chosen, bicycle=bicycle, progress=progress)
    modes: Modes = model_modes(measured.windows, bicycle) if bicycle is not None else [None] * len(measured.windows)
    _print_table(measured, modes)
    if reference is not None:
        print_comparison(reference_name, reference, measured, options.fit_options(measured.signals))
    _write_outputs(args, measured, modes, bicycle, inputs)
    if not any(m.fit is not None for m in measured.windows):  # the table and the outputs say why
        raise InputError("no window fitted{}{}".format(*unusable_text(measured.windows)))
    return 0


def _model_text(mode: tuple[complex | None, bool] | None) -> str:
    """Return the model column: the nearest oscillating mode, marked "far" where it is not near the measurement."""
    if mode is None:
        return ""
    value, near = mode
    return "no oscillation" if value is None else _complex(value) + ("" if near else " far")


def _pair(value: complex | None) -> list[float] | None:
    return None if value is None else [value.real, value.imag]


def _complex(value: complex | None) -> str:
    return "" if value is None else f"{value.real:+.2f}{value.imag:+.2f}i"


def _time(seconds: float) -> str:
    # Clock times (seconds since 1970: 1.7e9) keep their hundredths; a mistyped window file may
    # hold any number.
    return f"{seconds:7.2f}" if abs(seconds) < 1e12 else f"{seconds:7.2g}"


def _print_table(measured: MeasuredRuns, modes: Modes) -> None:
    width = max(len("run"), *(len(r.run.name) for r in measured))
    print(f"{measured.describe()} (method {measured.options.method})")
    for run_ in measured:
        fitted = len(run_.fitted)
        origin = "from the windows file" if run_.from_file else "found automatically"
        print(f"{run_.run.name}: {fitted} window(s) fitted, {len(run_) - fitted} skipped "
              f"({origin}); roll-rate noise {run_.noise:.3g} rad/s, dominant frequency "
              f"{run_.frequency:.2f} Hz")
        for warning in run_.run.warnings:
            print(f"  note: {warning}")
    print()
    print(f"{'run':<{width}}  {'#':>3}  {'start':>7}  {'stop':>7}  {'speed [m/s]':<11}  "
          f"{'eigenvalue d + iw [1/s] (± 1 std)':<31}  {'R^2':>5}  {'model [1/s]':<17}  notes")
    for m, mode in zip(measured.windows, modes, strict=True):
        w = m.window
        speed = f"{m.speed.low:.2f}-{m.speed.high:.2f}" if m.speed else ""
        model = _model_text(mode)
        head = f"{m.run.name:<{width}}  {m.number:>3}  {_time(w.start)}  {_time(w.stop)}  {speed:<11}  "
        if m.fit is None:
            print(f"{head}{'skipped':<31}  {'':>5}  {model:<17}  {m.rejected}")
            continue
        d_std, w_std = m.fit.eigenvalue_std
        value = f"{m.fit.damping:+.2f}±{d_std:.2f} {m.fit.frequency:+.2f}±{w_std:.2f}i"
        notes = f"not used: {m.quality}; {m.notes}" if m.quality else m.notes
        print(f"{head}{value:<31}  {m.fit.r_squared:5.3f}  {model:<17}  {notes}")
    if any(mode is not None and not mode[1] for mode in modes):
        print("model: the model's oscillating mode nearest the measured eigenvalue; 'far': more than "
              f"{100 * SHAPE_MATCH:.0f}% of |eigenvalue| from it, so the window describes no mode of this model; "
              "'no oscillation': the model has no oscillating mode at that speed")


def _write_outputs(args: argparse.Namespace, measured: MeasuredRuns, modes: Modes,
                   bicycle: Bicycle | None, inputs: list[str]) -> None:
    windows = measured.windows
    if args.json:
        entries: list[dict[str, Any]] = [
            {**m.to_dict(), "model_eigenvalue": _pair(mode[0] if mode else None),
             "model_mode_near": mode[1] if mode else None} for m, mode in zip(windows, modes, strict=True)]
        write_text_atomic(args.json, json.dumps(entries, indent=1, allow_nan=False) + "\n")
        print(f"wrote {args.json}")
    if args.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow([*CSV_COLUMNS[:-2], "model_damping", "model_frequency", "model_near", *CSV_COLUMNS[-2:]])
        for m, mode in zip(windows, modes, strict=True):
            model, near = mode if mode else (None, False)
            row = m.csv_row()
            cells = ["", "", ""] if model is None else [f"{model.real:.6g}", f"{model.imag:.6g}", str(near).lower()]
            writer.writerow([*row[:-2], *cells, *row[-2:]])
        write_text_atomic(args.csv, buffer.getvalue())
        print(f"wrote {args.csv}")
    if args.plot:
        count = 0
        for name, figure in fit_figures(measured, bicycle):
            target = Path(args.plot) / name
            refuse_input_overwrite(target, inputs)
            save_figure(figure, target, dpi=100)
            count += 1
        print(f"wrote {count} figure(s) into {args.plot}")
