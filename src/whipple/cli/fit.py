"""Find the free-coasting windows of measured runs and fit their weave eigenvalues.

For every run the free-coasting windows are found automatically (or read from --windows), the
roll rate (or the --signals, jointly) is fitted with c1 + exp(d t)[c2 cos wt + c3 sin wt] by
separable least squares, and the speed range of each window is the linear regression of the
speed over it. One line per window: run, window number, start and stop [s], speed range
[m/s], eigenvalue d + i w [1/s] with standard deviations, R^2, and with --bicycle the model's
weave eigenvalue at the window's mean speed (divided by the bicycle's speed_scale: measured
speed = speed_scale * true speed). Stretches the window finder rejected and windows that
cannot be fitted are listed as skipped, with the reason.

--bundled adds the measured runs shipped with whipple (a steer-by-wire bicycle on a treadmill;
fit them with --bicycle sbw2024) and compares the automatic windows with the windows picked
by hand for them. --windows FILE fits the file's windows instead and reports how the
automatic windows compare with them; --compare FILE only compares. FILE may be the word
"bundled" for the hand-picked windows of the bundled runs. --json, --csv and --plot write the
results (JSON list of windows; CSV table; PNG figures like the seed paper's Figures 4, 5, 6).
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from whipple.runs import Run
    from whipple.speedometer import SpeedRange
    from whipple.weavefit import WeaveFit
    from whipple.windows import Window, WindowSearch

HELP = "find free-coasting windows in measured runs and fit their weave eigenvalues"

#: The word that names the hand-picked windows of the bundled runs in --windows/--compare.
BUNDLED = "bundled"

CSV_COLUMNS = ("run", "window", "start", "stop", "speed_low", "speed_high", "speed_mean",
               "damping", "damping_std", "frequency", "frequency_std", "r_squared", "samples",
               "model_damping", "model_frequency", "skipped", "notes")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("runs", nargs="*", metavar="RUN",
                        help="run files (native CSV, a layout's format, or .gz of either)")
    parser.add_argument("--bundled", action="store_true",
                        help="also fit the measured runs shipped with whipple (steer-by-wire "
                             "bicycle on a treadmill, 5 belt speeds; model: --bicycle sbw2024)")
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
    parser.add_argument("--signals", default="roll_rate", metavar="NAME[,NAME...]",
                        help="signals fitted jointly, sharing one eigenvalue (default roll_rate)")
    # The choices of whipple.weavefit (BASELINES, NOISE_MODELS), spelled out here so that the
    # parser does not import SciPy.
    parser.add_argument("--baseline", choices=("constant", "linear", "quadratic"),
                        default="constant",
                        help="non-oscillating part of the fitted function: the seed paper's "
                             "constant c1 (default), or a polynomial in time that also absorbs "
                             "a slow capsize-mode drift")
    parser.add_argument("--noise", choices=("auto", "white", "correlated"), default="auto",
                        help="covariance of the eigenvalue: white residuals, Newey-West for "
                             "autocorrelated ones, or Newey-West when the residual's lag-1 "
                             "autocorrelation is significant (default auto)")
    parser.add_argument("--bicycle", metavar="PARAMS",
                        help="bicycle file or built-in name: list its model weave eigenvalue "
                             "at each window's speed")
    parser.add_argument("--json", metavar="OUT", help="write the windows as a JSON list")
    parser.add_argument("--csv", metavar="OUT", help="write the table as CSV")
    parser.add_argument("--plot", "--plots", dest="plot", metavar="DIR",
                        help="write figures (PNG) into DIR: each run's signals, each fit, and "
                             "the eigenvalues against speed")


@dataclass(frozen=True)
class _Fitting:
    """How windows are fitted: the signals, the covariance estimate, the baseline."""

    signals: tuple[str, ...]
    noise: str
    baseline: str


@dataclass
class _Entry:
    """One line of the table: a fitted window, or a skipped one with the reason."""

    run: Run
    window: Window
    number: int = 0
    speed: SpeedRange | None = None
    fit: WeaveFit | None = None
    skipped: str | None = None
    model: complex | None = None
    baseline: str = "constant"


def run(args: argparse.Namespace) -> int:
    from whipple.bundled import bundled_reference_windows, bundled_runs
    from whipple.errors import InputError, RunFileError
    from whipple.reference_windows import read_windows
    from whipple.runs import read_run
    from whipple.windows import find_windows

    if not args.runs and not args.bundled:
        raise InputError("no runs: name run files, or use --bundled for the runs shipped "
                         "with whipple")
    signals = tuple(name.strip() for name in args.signals.split(",") if name.strip())
    if not signals:
        raise InputError("--signals names no signal")
    inputs = [*args.runs, *(f for f in (args.windows, args.compare, args.bicycle, args.layout)
                            if f and f != BUNDLED)]
    _check_outputs(args, inputs)

    runs = [read_run(path, layout=args.layout) for path in args.runs]
    if args.bundled:
        runs += [read_run(entry) for entry in bundled_runs()]
    names = [r.name for r in runs]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise InputError(f"two runs are named {twice[0]} (windows and figures go by run name)")
    for run_ in runs:
        missing = [name for name in signals if name not in run_.signals]
        if missing:
            raise RunFileError(f"no {', '.join(missing)} signal to fit", run_.source)

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
    bicycle = None
    if args.bicycle:
        from whipple.parameters import load_bicycle

        bicycle = load_bicycle(args.bicycle)

    fitting = _Fitting(signals, args.noise, args.baseline)
    searches = {run_.name: find_windows(run_) for run_ in runs}
    entries: list[_Entry] = []
    for run_ in runs:
        search = searches[run_.name]
        if chosen is not None:
            windows = [w for w in chosen if w.run == run_.name]
            rejected: list[Window] = []
        else:
            windows, rejected = list(search.windows), list(search.rejected)
        none = ("no window of this run in the windows file" if chosen is not None
                else "no free-coasting window found")
        entries += _analyse(run_, windows, rejected, fitting, none)
    if bicycle is not None:
        _add_model(entries, bicycle)

    _print_table(runs, searches, entries, chosen is not None)
    if reference is not None:
        _print_comparison(reference_name, reference, searches, entries, fitting)
    _write_outputs(args, runs, searches, entries, bicycle, inputs)
    return 0


def _check_outputs(args: argparse.Namespace, inputs: list[str]) -> None:
    """Refuse outputs that would replace an input, or a plot folder that is a file."""
    from whipple.atomic import refuse_input_overwrite
    from whipple.errors import InputError

    for output in (args.json, args.csv):
        if output is not None:
            refuse_input_overwrite(output, inputs)
            if Path(output).is_dir():
                raise InputError("output is a folder", output)
    if args.plot is not None and Path(args.plot).exists() and not Path(args.plot).is_dir():
        raise InputError("--plot needs a folder; this is a file", args.plot)


def _analyse(run_: Run, windows: list[Window], rejected: list[Window], fitting: _Fitting,
             none: str) -> list[_Entry]:
    """Fit each window of a run; rejected stretches and failed fits become skipped entries.

    A run without any window gets one skipped entry spanning it, with the reason `none`.
    """
    from whipple.errors import RunFileError
    from whipple.speedometer import speed_regression
    from whipple.weavefit import NoOscillationError, fit_window

    speed = run_.speed()
    entries = []
    first, last = float(run_.time[0]), float(run_.time[-1])
    for window in windows:
        entry = _Entry(run_, window, baseline=fitting.baseline)
        if window.start >= last or window.stop <= first:
            entry.skipped = f"window outside the run ({first:.2f}-{last:.2f} s)"
            entries.append(entry)
            continue
        try:
            entry.speed = speed_regression(run_.time, speed, window.start, window.stop)
            entry.fit = fit_window(run_, window, fitting.signals, fitting.noise, fitting.baseline)
        except (NoOscillationError, RunFileError) as error:
            entry.skipped = error.problem
        entries.append(entry)
    for window in rejected:
        entry = _Entry(run_, window, skipped=window.reason.removeprefix("rejected: "))
        try:
            entry.speed = speed_regression(run_.time, speed, window.start, window.stop)
        except RunFileError:
            pass
        entries.append(entry)
    if not windows and not rejected:
        from whipple.windows import Window

        whole = Window(run_.name, float(run_.time[0]), float(run_.time[-1]), 0, run_.time.size,
                       "the whole run")
        entries.append(_Entry(run_, whole, skipped=none,
                              speed=speed_regression(run_.time, speed, whole.start, whole.stop)))
    entries.sort(key=lambda entry: entry.window.start)
    for number, entry in enumerate(entries, 1):
        entry.number = number
    return entries


def _add_model(entries: list[_Entry], bicycle: Any) -> None:
    """The model's weave eigenvalue at each window's mean speed, in one vectorised call."""
    import numpy as np

    from whipple.model import linear_model
    from whipple.stability import weave_eigenvalue

    timed = [entry for entry in entries if entry.speed is not None]
    if not timed:
        return
    scale = float(bicycle.extensions.speed_scale)
    measured = np.array([entry.speed.mean for entry in timed if entry.speed is not None])
    values = weave_eigenvalue(linear_model(bicycle), measured / scale)
    for entry, value in zip(timed, values, strict=True):
        entry.model = None if np.isnan(value) else complex(value)


def _notes(entry: _Entry) -> str:
    return "; ".join((entry.window.reason, *entry.window.notes))


def _print_table(runs: list[Run], searches: dict[str, WindowSearch], entries: list[_Entry],
                 from_file: bool) -> None:
    width = max(len("run"), *(len(r.name) for r in runs))
    for run_ in runs:
        search = searches[run_.name]
        mine = [entry for entry in entries if entry.run is run_]
        fitted = sum(entry.fit is not None for entry in mine)
        origin = "from the windows file" if from_file else "found automatically"
        print(f"{run_.name}: {fitted} window(s) fitted, {len(mine) - fitted} skipped "
              f"({origin}); roll-rate noise {search.noise:.3g} rad/s, dominant frequency "
              f"{search.frequency:.2f} Hz")
        for warning in run_.warnings:
            print(f"  note: {warning}")
    print()
    print(f"{'run':<{width}}  {'#':>3}  {'start':>7}  {'stop':>7}  {'speed [m/s]':<11}  "
          f"{'eigenvalue d + iw [1/s] (± 1 std)':<31}  {'R^2':>5}  {'model [1/s]':<13}  notes")
    for entry in entries:
        w = entry.window
        speed = (f"{entry.speed.low:.2f}-{entry.speed.high:.2f}" if entry.speed else "")
        model = "" if entry.model is None else _complex(entry.model)
        head = f"{entry.run.name:<{width}}  {entry.number:>3}  {w.start:7.2f}  {w.stop:7.2f}  {speed:<11}  "
        if entry.fit is None:
            print(f"{head}{'skipped':<31}  {'':>5}  {model:<13}  {entry.skipped}")
            continue
        fit = entry.fit
        d_std, w_std = fit.eigenvalue_std
        value = f"{fit.damping:+.2f}±{d_std:.2f} {fit.frequency:+.2f}±{w_std:.2f}i"
        print(f"{head}{value:<31}  {fit.r_squared:5.3f}  {model:<13}  {_notes(entry)}")


def _complex(value: complex) -> str:
    return f"{value.real:+.2f}{value.imag:+.2f}i"


def _print_comparison(name: str, reference: tuple[Window, ...], searches: dict[str, WindowSearch],
                      entries: list[_Entry], fitting: _Fitting) -> None:
    """How the automatic windows match the reference ones, and the eigenvalues of both."""
    import numpy as np

    from whipple.errors import InputError
    from whipple.reference_windows import compare_windows
    from whipple.weavefit import fit_window

    compared = {w.run for w in reference}
    found = [w for run_name, search in searches.items() if run_name in compared
             for w in search.windows]
    comparison = compare_windows(found, reference)
    print()
    if not reference:
        print(f"windows of {name}: none for these runs")
        return
    coverage = np.mean([m.coverage for m in comparison.matches if m.found is not None] or [0.0])
    print(f"automatic windows vs {name}: {comparison.matched} of {len(comparison.matches)} "
          f"matched (an automatic window overlaps at least half of the shorter of the two; "
          f"mean coverage of the matched ones {100 * coverage:.0f}%); {len(comparison.extra)} "
          f"automatic window(s) in no reference window")
    for missed in comparison.unmatched:
        print(f"  unmatched: {missed.run} {missed.start:.2f}-{missed.stop:.2f} s")
    runs = {entry.run.name: entry.run for entry in entries}
    differences = []
    for match in comparison.matches:
        if match.found is None:
            continue
        try:
            pair = [fit_window(runs[match.reference.run], w, fitting.signals, fitting.noise,
                               fitting.baseline).eigenvalue
                    for w in (match.found, match.reference)]
        except InputError:
            continue
        differences.append(pair[0] - pair[1])
    if differences:
        delta = np.array(differences)
        print(f"  eigenvalue on the automatic minus on the reference window, over "
              f"{delta.size} matched pair(s): median |Δd| {np.median(np.abs(delta.real)):.2f} 1/s, "
              f"median |Δw| {np.median(np.abs(delta.imag)):.2f} rad/s")


def _pair(value: complex | None) -> list[float] | None:
    return None if value is None else [float(value.real), float(value.imag)]


def _json_entry(entry: _Entry) -> dict[str, Any]:
    fit, speed = entry.fit, entry.speed
    return {
        "run": entry.run.name,
        "start": entry.window.start,
        "stop": entry.window.stop,
        "speed": None if speed is None else [speed.low, speed.high],
        "speed_mean": None if speed is None else speed.mean,
        "eigenvalue": None if fit is None else _pair(fit.eigenvalue),
        "eigenvalue_std": None if fit is None else list(fit.eigenvalue_std),
        "r_squared": None if fit is None else fit.r_squared,
        "model_eigenvalue": _pair(entry.model),
        "skipped": entry.skipped,
        # Beyond the listed fields: what the diagnosis needs, and where the window came from.
        "eigenvalue_covariance": None if fit is None else fit.covariance.tolist(),
        "samples": None if fit is None else fit.n_samples,
        "signals": None if fit is None else list(fit.signal_names),
        "noise_model": None if fit is None else fit.noise_model,
        "baseline": None if fit is None else entry.baseline,
        "notes": _notes(entry),
        "window": entry.number,
        "source": entry.run.source,
    }


def _csv_row(entry: _Entry) -> list[object]:
    fit, speed, model = entry.fit, entry.speed, entry.model
    values: list[object] = [entry.run.name, entry.number, entry.window.start, entry.window.stop]
    values += [speed.low, speed.high, speed.mean] if speed else [None] * 3
    values += ([fit.damping, fit.eigenvalue_std[0], fit.frequency, fit.eigenvalue_std[1],
                fit.r_squared, fit.n_samples] if fit else [None] * 6)
    values += [model.real, model.imag] if model is not None else [None] * 2
    values += [entry.skipped, _notes(entry)]
    return [("" if v is None else f"{v:.6g}" if isinstance(v, float) else v) for v in values]


def _write_outputs(args: argparse.Namespace, runs: list[Run], searches: dict[str, WindowSearch],
                   entries: list[_Entry], bicycle: Any, inputs: list[str]) -> None:
    import csv
    import io
    import json

    from whipple.atomic import write_text_atomic
    from whipple.errors import InputError

    try:
        if args.json:
            text = json.dumps([_json_entry(entry) for entry in entries], indent=1, allow_nan=False)
            write_text_atomic(args.json, text + "\n")
            print(f"wrote {args.json}")
        if args.csv:
            buffer = io.StringIO()
            writer = csv.writer(buffer, lineterminator="\n")
            writer.writerow(CSV_COLUMNS)
            writer.writerows(_csv_row(entry) for entry in entries)
            write_text_atomic(args.csv, buffer.getvalue())
            print(f"wrote {args.csv}")
        if args.plot:
            count = _write_plots(Path(args.plot), runs, searches, entries, bicycle, inputs)
            print(f"wrote {count} figure(s) into {args.plot}")
    except OSError as error:
        raise InputError(f"cannot write output ({error.strerror or error})",
                         getattr(error, "filename", None)) from None


def _write_plots(folder: Path, runs: list[Run], searches: dict[str, WindowSearch],
                 entries: list[_Entry], bicycle: Any, inputs: list[str]) -> int:
    import numpy as np

    from whipple.atomic import atomic_path, refuse_input_overwrite
    from whipple.plotting_runs import plot_measured_eigenvalues, plot_run, plot_weave_fit

    def save(name: str, figure: Any) -> None:
        target = folder / name
        refuse_input_overwrite(target, inputs)
        with atomic_path(target) as temporary:
            figure.savefig(temporary, dpi=100)

    count = 0
    for run_ in runs:
        mine = [entry for entry in entries if entry.run is run_]
        fitted = [entry for entry in mine if entry.fit is not None]
        unfitted = [entry.window for entry in mine if entry.fit is None]
        rejected = [w for w in unfitted if w.reason.startswith("rejected")]
        failed = [w for w in unfitted if not w.reason.startswith("rejected")
                  and w.reason != "the whole run"]
        save(f"{run_.name}_run.png",
             plot_run(run_, [e.window for e in fitted], rejected=rejected, skipped=failed,
                      numbers=[e.number for e in fitted]))
        count += 1
        for entry in fitted:
            assert entry.fit is not None
            save(f"{run_.name}_window{entry.number:02d}_{entry.window.start:.2f}s.png",
                 plot_weave_fit(entry.fit, run_, entry.speed,
                                title=f"{run_.name}, window {entry.number}"))
            count += 1
    fitted = [entry for entry in entries if entry.fit is not None and entry.speed is not None]
    model = critical = None
    scale = 1.0
    title = "measured weave eigenvalues"
    if bicycle is not None:
        from whipple.critical import critical_speeds
        from whipple.model import linear_model
        from whipple.stability import eigen_analysis

        scale = float(bicycle.extensions.speed_scale)
        top = max([10.0, *(1.1 * e.speed.high / scale for e in fitted if e.speed is not None)])
        linear = linear_model(bicycle)
        model = eigen_analysis(linear, np.linspace(0.0, top, 1001))
        critical = critical_speeds(linear, 0.0, top)
        title = f"measured weave eigenvalues and the model of {bicycle.name or 'the bicycle'}"
    if fitted:
        save("eigenvalues.png", plot_measured_eigenvalues(
            [e.speed for e in fitted if e.speed is not None],
            [e.fit for e in fitted if e.fit is not None], model, critical, scale, title))
        count += 1
    return count
