"""The ``whipple`` command line: a thin layer over the library.

``whipple --help`` prints :data:`DESCRIPTION`; ``whipple --version`` the installed version (from
the package's metadata).

Each subcommand lives in its own module ``whipple.cli.<name>`` exposing ``add_arguments(parser)``
and ``run(args) -> int``; its one-line help is in :data:`COMMANDS`. Only the module of the
command being run is imported, so that a quick command (``whipple sweep`` on a table, say)
does not pay for loading SciPy, CasADi and matplotlib it never uses.

Library errors caused by bad input (:class:`whipple.errors.InputError`) become a one-line
message and exit code 2; failed analyses (:class:`whipple.errors.AnalysisError`) exit with 1;
an output that cannot be written (a read-only folder, a path that is a folder) is bad input.
SIGTERM and SIGHUP end a command as Ctrl-C does: temporary files are removed, outputs keep
their old content, and the exit code is 128 + the signal's number. When an output option names
standard output (``-``), the command's messages go to standard error.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import signal
import sys
import warnings
from collections.abc import Iterator, Sequence
from types import FrameType

from whipple.atomic import is_standard_output, messages_to_standard_error
from whipple.errors import AnalysisError, InputError

#: Subcommands in order of appearance in ``whipple --help``, with their one-line help.
COMMANDS = {
    "check": "validate a bicycle, print its matrices and stable speed range",
    "stability": "eigenvalues versus speed: figure and table",
    "sweep": "critical speeds and stable ranges of many parameter sets (CSV)",
    "verify": "compare the generated equations with published matrices",
    "regenerate": "re-derive the equations and rewrite (or --check) the generated code",
    "fit": "find free-coasting windows in measured runs and fit their weave eigenvalues",
    "simulate": "simulate realistic measured runs (push, coast, catch, sensor noise) as run files",
    "diagnose": "find what the model gets wrong on measured runs and which cause explains it",
    "evaluate": "score models on measured runs: weave eigenvalue error and samples' residual, per speed",
}


#: What ``whipple --help`` says the tool does, above the list of commands.
DESCRIPTION = """\
The linearized Whipple bicycle, derived from first principles and confronted with measured data.

  check a bicycle      whipple check benchmark            (matrices, weave and capsize speeds)
  stability            whipple stability sbw2024 --plot eig.png
  many bicycles        whipple sweep table.csv --output speeds.csv --workers 2
  measured runs        whipple fit --bundled --bicycle sbw2024
  what is wrong, why   whipple diagnose --bundled --bicycle sbw2024 --report out/
  score models         whipple evaluate runs/*.csv --bicycle a.toml --bicycle b.toml

A bicycle is a TOML file, a BicycleParameters <Name>Benchmark.txt, or a built-in name
(benchmark, kooijman2008, sbw2024, sbw2024-mm). `whipple COMMAND --help` lists a command's options.
"""

#: Options whose value may be ``-`` for standard output.
OUTPUT_OPTIONS = ("csv", "json", "output", "save_model", "plot")
#: Signals that end a command cleanly (as Ctrl-C does).
ENDING_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors exit with code 2 and a single line.

    A value that starts with a minus sign and a digit (``--speeds -1:5``) is a value, not an
    option: its own check then says what is wrong with it.
    """

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-\.?[0-9]")

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")


class Terminated(BaseException):
    """SIGTERM or SIGHUP arrived: the command unwinds (removing temporary files) and exits."""

    def __init__(self, number: int) -> None:
        super().__init__(number)
        self.number = number


def _terminate(number: int, frame: FrameType | None) -> None:
    # One signal is enough: a second one must not interrupt the cleanup the first one started.
    for other in ENDING_SIGNALS:
        signal.signal(other, signal.SIG_IGN)
    raise Terminated(number)


@contextlib.contextmanager
def _ending_signals_raise() -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP raise :class:`Terminated` (main thread only)."""
    try:
        previous = {number: signal.signal(number, _terminate) for number in ENDING_SIGNALS}
    except ValueError:  # not the main thread: signals stay as they are
        previous = {}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def _version() -> str:
    """Return the installed package's version (its metadata, as pip installed it)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("whipple")
    except PackageNotFoundError:  # run from a source tree that was never installed
        return "unknown (not installed)"


def _requested(argv: Sequence[str]) -> str | None:
    """Return the subcommand named in `argv` (its first word that is one), if any."""
    return next((word for word in argv if word in COMMANDS), None)


def _input_files(args: argparse.Namespace) -> list[str]:
    """Return the files named on the command line that exist and are not outputs, in order."""
    named: list[str] = []
    for option, value in vars(args).items():
        if option in OUTPUT_OPTIONS or callable(value):
            continue
        for item in value if isinstance(value, list | tuple) else [value]:
            if isinstance(item, str | os.PathLike) and os.path.isfile(item) and os.fspath(item) not in named:
                named.append(os.fspath(item))
    return named


def build_parser(argv: Sequence[str] = ()) -> argparse.ArgumentParser:
    """Return the parser; the arguments of the subcommand named in `argv` are filled in."""
    parser = _Parser(prog="whipple", description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter,
                     epilog="Documentation: the docs/ folder of the source (build it with docs/build).")
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    subparsers = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    chosen = _requested(argv)
    for name, text in COMMANDS.items():
        if name != chosen:
            subparsers.add_parser(name, help=text)
            continue
        module = importlib.import_module(f"whipple.cli.{name}")
        sub = subparsers.add_parser(name, help=text, description=module.__doc__)
        module.add_arguments(sub)
        sub.set_defaults(run=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``whipple`` console script."""
    arguments = list(sys.argv[1:] if argv is None else argv)
    args = build_parser(arguments).parse_args(arguments)
    to_standard_output = any(isinstance(value, str | os.PathLike) and is_standard_output(value)
                             for value in (getattr(args, name, None) for name in OUTPUT_OPTIONS))
    messages = messages_to_standard_error() if to_standard_output else contextlib.nullcontext()
    try:
        with _ending_signals_raise(), messages, warnings.catch_warnings():
            # numpy's RuntimeWarnings (overflow, invalid value) would print lines of library
            # source before the one-line error that the checks of the results give.
            warnings.simplefilter("ignore", RuntimeWarning)
            return int(args.run(args))
    except Terminated as ended:
        print(f"whipple {args.command}: ended by {signal.Signals(ended.number).name}", file=sys.stderr)
        return 128 + ended.number
    except InputError as error:
        print(f"whipple {args.command}: error: {error}", file=sys.stderr)
        return 2
    except AnalysisError as error:
        print(f"whipple {args.command}: analysis failed: {error}", file=sys.stderr)
        return 1
    except (ArithmeticError, ValueError) as error:
        # numpy.linalg.LinAlgError (a ValueError) and overflow: matrices with infinite or NaN
        # entries, from values far beyond any bicycle's that no check anticipated. Matched by
        # name so that `whipple --help` need not import numpy.
        if isinstance(error, ValueError) and type(error).__name__ != "LinAlgError":
            raise
        inputs = ", ".join(_input_files(args)) or "the input"
        print(f"whipple {args.command}: analysis failed: the numbers overflow ({error}); a value far out of "
              f"range in {inputs}?", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"whipple {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader (e.g. `head`) closed the pipe: stop quietly, as other command line tools do.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141
    except OSError as error:
        # Outputs go through whipple.atomic (an OutputError naming the file); this is the net
        # for anything else the system refuses, still one line and no traceback.
        where = f"{error.filename}: " if error.filename else ""
        print(f"whipple {args.command}: error: {where}{error.strerror or error}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
