"""Find the free-coasting windows of measured runs and fit their weave eigenvalues.

For every run the free-coasting windows are found automatically (or read from --windows), the
roll rate (or the --signals, jointly) is fitted with c1 + exp(d t)[c2 cos wt + c3 sin wt], and
the speed range over each window is the linear regression of the speed. One line per window:
run, start and stop [s], speed range [m/s], eigenvalue d + i w [1/s] with standard deviations,
R^2 and the window's notes. With --bicycle, the model's weave eigenvalue at the window's mean
speed is listed too. --compare reports how the automatic windows match a reference windows
file; --csv writes the table; --plots writes seed-style figures (run overview, each fit).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

HELP = "find free-coasting windows in measured runs and fit their weave eigenvalues"

COLUMNS = ("run", "start", "stop", "speed_low", "speed_high", "speed_mean", "damping",
           "damping_std", "frequency", "frequency_std", "r_squared", "samples",
           "model_damping", "model_frequency", "notes")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("runs", nargs="+", metavar="RUN",
                        help="run files (native CSV, a layout's format, or .gz of either)")
    parser.add_argument("--layout", metavar="NAME-or-FILE",
                        help="layout of the run files (default: native, or recognised)")
    parser.add_argument("--windows", metavar="FILE",
                        help="windows file (run,start,stop or run,start_row,stop_row) to use "
                             "instead of finding windows automatically")
    parser.add_argument("--compare", metavar="FILE",
                        help="reference windows file to compare the automatic windows with")
    parser.add_argument("--signals", default="roll_rate", metavar="NAME[,NAME...]",
                        help="signals fitted jointly (default roll_rate)")
    parser.add_argument("--bicycle", metavar="PARAMS",
                        help="bicycle whose model weave eigenvalue is listed for comparison")
    parser.add_argument("--csv", metavar="FILE", help="write the table as CSV")
    parser.add_argument("--plots", metavar="DIR", help="write figures (PNG) into DIR")


def run(args: argparse.Namespace) -> int:
    from whipple.atomic import atomic_path, refuse_input_overwrite, write_text_atomic
    from whipple.errors import InputError
    from whipple.reference_windows import compare_windows, read_windows
    from whipple.runs import read_run
    from whipple.speedometer import speed_regression
    from whipple.weavefit import NoOscillationError, fit_window
    from whipple.windows import Window, find_windows

    inputs = [*args.runs, *(f for f in (args.windows, args.compare, args.bicycle) if f)]
    signals = tuple(name.strip() for name in args.signals.split(",") if name.strip())
    if not signals:
        raise InputError("--signals names no signal")
    runs = [read_run(path, layout=args.layout) for path in args.runs]
    chosen = read_windows(args.windows, runs) if args.windows else None
    model_weave = _model_hook(args.bicycle)

    rows: list[dict[str, object]] = []
    found_all: list[Window] = []
    for run_ in runs:
        search = find_windows(run_)
        found_all.extend(search.windows)
        windows = ([w for w in chosen if w.run == run_.name] if chosen is not None
                   else list(search.windows))
        speed = run_.speed()
        print(f"{run_.name}: {len(windows)} window(s); noise {search.noise:.3g}, weave band "
              f"{search.frequency:.2f} Hz")
        for warning in run_.warnings:
            print(f"  note: {warning}")
        figures = []
        for window in windows:
            speeds = speed_regression(run_.time, speed, window.start, window.stop)
            row: dict[str, object] = {
                "run": run_.name, "start": window.start, "stop": window.stop,
                "speed_low": speeds.low, "speed_high": speeds.high, "speed_mean": speeds.mean,
                "notes": "; ".join((window.reason, *window.notes)),
            }
            try:
                fit = fit_window(run_, window, signals)
            except NoOscillationError as error:
                row["notes"] = f"no oscillation: {error.problem}"
            else:
                row.update(damping=fit.damping, damping_std=fit.eigenvalue_std[0],
                           frequency=fit.frequency, frequency_std=fit.eigenvalue_std[1],
                           r_squared=fit.r_squared, samples=fit.n_samples)
                if args.plots:
                    figures.append((window, fit, speeds))
            if model_weave is not None:
                eigenvalue = complex(model_weave([speeds.mean])[0])
                row.update(model_damping=eigenvalue.real, model_frequency=eigenvalue.imag)
            rows.append(row)
            print("  " + _line(row))
        if args.plots:
            _write_plots(Path(args.plots), run_, search, windows, figures, inputs, atomic_path,
                         refuse_input_overwrite)

    if args.compare:
        comparison = compare_windows(found_all, read_windows(args.compare, runs))
        print(f"reference windows matched: {comparison.matched} of {len(comparison.matches)}; "
              f"automatic windows not in the reference: {len(comparison.extra)}")
        for missed in comparison.unmatched:
            print(f"  unmatched reference: {missed.run} {missed.start:.2f}-{missed.stop:.2f} s")
    if args.csv:
        refuse_input_overwrite(args.csv, inputs)
        lines = [",".join(COLUMNS)]
        for row in rows:
            lines.append(",".join(_csv_cell(row.get(column)) for column in COLUMNS))
        write_text_atomic(args.csv, "\n".join(lines) + "\n")
    return 0


def _model_hook(bicycle: str | None):
    """The model's weave eigenvalue as a function of speed, or None without --bicycle.

    OPTIONAL HOOK: uses whipple.model.linear_model and whipple.stability.weave_eigenvalue.
    """
    if bicycle is None:
        return None
    from whipple.model import linear_model
    from whipple.parameters import load_bicycle
    from whipple.stability import weave_eigenvalue

    model = linear_model(load_bicycle(bicycle))
    return lambda speeds: weave_eigenvalue(model, speeds)


def _line(row: dict[str, object]) -> str:
    text = (f"{row['start']:8.2f}-{row['stop']:<8.2f} s  v {row['speed_low']:.2f}-"
            f"{row['speed_high']:.2f} m/s")
    if "damping" in row:
        text += (f"  lambda {row['damping']:+.2f}±{row['damping_std']:.2f} "
                 f"{row['frequency']:+.2f}±{row['frequency_std']:.2f}i 1/s  "
                 f"R2 {row['r_squared']:.3f}")
    if "model_damping" in row and not math.isnan(float(str(row["model_damping"]))):
        text += f"  model {row['model_damping']:+.2f}{row['model_frequency']:+.2f}i"
    return f"{text}  [{row['notes']}]"


def _csv_cell(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    text = str(value)
    return f'"{text}"' if ("," in text or '"' in text) else text


def _write_plots(folder, run_, search, windows, fits, inputs, atomic_path, refuse) -> None:
    from whipple.plotting_runs import plot_run, plot_weave_fit

    figures = [(f"{run_.name}_run.png", plot_run(run_, windows, rejected=search.rejected))]
    for index, (window, fit, speeds) in enumerate(fits, 1):
        figures.append((f"{run_.name}_window{index:02d}_{window.start:.2f}s.png",
                        plot_weave_fit(fit, run_, speeds)))
    for name, figure in figures:
        target = folder / name
        refuse(target, inputs)
        with atomic_path(target) as temporary:
            figure.savefig(temporary, dpi=120)
