"""The options of the one weave measurement that ``whipple fit`` and ``whipple diagnose`` share.

Both commands take the same flags and build the same
:class:`~whipple.measurement.measure.MeasurementOptions` from them, so that a window gets the
same eigenvalue from either (:func:`whipple.measurement.measure.measure_runs`).
"""

from __future__ import annotations

import argparse

from whipple.cli.arguments import number
from whipple.errors import InputError
from whipple.measurement.bundled import BUNDLED_EXPERIMENTS, DEFAULT_EXPERIMENT
from whipple.measurement.experiment import MIN_CYCLES_ABOVE_NOISE
from whipple.measurement.measure import METHODS, MeasuredRuns, MeasurementOptions


def add_measurement_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the measurement's flags: ``--method``, ``--signals``, ``--baseline``, ``--noise``, ``--settle``, ...."""
    group = parser.add_argument_group("measurement (the same for whipple fit and whipple diagnose)")
    group.add_argument("--method", choices=METHODS, default="whipple",
                       help="whipple (default): the signals and baseline below, windows that are no one free "
                            "motion set aside, the steer signal's sign checked against the model; seed-paper: "
                            "the seed paper's plain fit, c1 + exp(d t)[c2 cos wt + c3 sin wt] of the roll rate, "
                            "nothing set aside")
    group.add_argument("--signals", default=None, metavar="NAME[,NAME...]",
                       help="signals fitted jointly, sharing one eigenvalue (default auto: roll_rate,steer_angle "
                            "where every run measures the steer angle wherever it measures the roll rate, "
                            "roll_rate otherwise; the first signal is the mode shape's reference)")
    group.add_argument("--baseline", default=None, choices=("auto", "constant", "linear", "quadratic"),
                       help="non-oscillating part of the window fits (default auto: quadratic, following the "
                            "capsize mode, in windows of two weave cycles or more; constant otherwise)")
    group.add_argument("--noise", choices=("auto", "white", "correlated"), default="auto",
                       help="covariance of the eigenvalue: white residuals, Newey-West for autocorrelated ones, "
                            "or Newey-West when the residual's lag-1 autocorrelation is significant (default auto)")
    group.add_argument("--settle", type=number, default=0.0, metavar="SECONDS",
                       help="leave the first SECONDS of every window out of the fits (default 0, as in the seed "
                            "paper); e.g. 0.3 for a bicycle whose castering mode is slow at the measured speeds")
    group.add_argument("--min-cycles-above-noise", type=number, default=MIN_CYCLES_ABOVE_NOISE, metavar="CYCLES",
                       help="leave out windows holding fewer weave cycles than this while the oscillation stands "
                            "above the noise (default %(default)s; 0: no such check, as in the seed paper)")
    group.add_argument("--keep-outliers", action="store_true",
                       help="use every window that passes the window checks, also those that no free response "
                            "of a linear model follows nearly as well as the others (by default set aside as "
                            "holding a catch or a push)")


def add_bundled_argument(parser: argparse.ArgumentParser, verb: str) -> None:
    """``--bundled [EXPERIMENT]``: the measured runs shipped with whipple, one of its two experiments."""
    experiments = ", ".join(f"{name} (model: --bicycle {bicycle})"
                            for name, (_, bicycle) in BUNDLED_EXPERIMENTS.items())
    parser.add_argument("--bundled", nargs="?", const=DEFAULT_EXPERIMENT, default=None,
                        choices=tuple(BUNDLED_EXPERIMENTS), metavar="EXPERIMENT",
                        help=f"{verb} the measured runs shipped with whipple: a steer-by-wire bicycle on a treadmill "
                             f"at 5 belt speeds, in one of two experiments: {experiments}; default "
                             f"{DEFAULT_EXPERIMENT}. Name run files before it, not after")


def signal_names(text: str) -> tuple[str, ...]:
    """Return the run-file signal names of a ``--signals`` value (comma-separated)."""
    names = tuple(name.strip() for name in text.split(",") if name.strip())
    if not names:
        raise InputError("--signals names no signal")
    return names


def measurement_options(args: argparse.Namespace) -> MeasurementOptions:
    """Return the measurement options of the command's flags."""
    if args.method == "seed-paper":
        given = [flag for flag, value in (("--signals", args.signals), ("--baseline", args.baseline),
                                          ("--keep-outliers", args.keep_outliers or None)) if value is not None]
        if given:
            raise InputError(f"--method seed-paper fits the roll rate with a constant baseline and sets nothing "
                             f"aside; {', '.join(given)} cannot change that (leave it out, or use --method whipple)")
        seed = MeasurementOptions.seed_paper()
        return MeasurementOptions(**{**vars(seed), "noise": args.noise, "settle": args.settle,
                                     "min_cycles_above_noise": args.min_cycles_above_noise})
    signals = "auto" if args.signals in (None, "auto") else signal_names(args.signals)
    return MeasurementOptions(signals=signals, baseline=args.baseline or "auto", noise=args.noise,
                              settle=args.settle, min_cycles_above_noise=args.min_cycles_above_noise,
                              set_aside=not args.keep_outliers)


def print_run_notes(measured: MeasuredRuns) -> None:
    """Print what reading each run noted (gaps filled, units converted, ...), one ``note (run):`` line each."""
    for name, notes in measured.run_notes.items():
        for note in notes:
            print(f"  note ({name}): {note}")
