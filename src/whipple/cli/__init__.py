"""The ``whipple`` command line: a thin layer over the library.

Each subcommand lives in its own module ``whipple.cli.<name>`` exposing ``HELP`` (one line),
``add_arguments(parser)`` and ``run(args) -> int``. Library errors caused by bad input
(:class:`whipple.errors.InputError`) become a one-line message and exit code 2; failed
analyses (:class:`whipple.errors.AnalysisError`) exit with 1.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import sys
from collections.abc import Sequence

from whipple.errors import AnalysisError, InputError

# Order of appearance in ``whipple --help``.
COMMANDS = (
    "check",
    "stability",
    "sweep",
    "verify",
    "regenerate",
    "fit",
    "simulate",
    "diagnose",
)


class _Parser(argparse.ArgumentParser):
    """Argument parser whose usage errors exit with code 2 and a single line."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """Assemble the parser from the subcommand modules that are installed."""
    parser = _Parser(prog="whipple", description=__doc__.splitlines()[0])
    subparsers = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMANDS:
        module_name = f"whipple.cli.{name}"
        if importlib.util.find_spec(module_name) is None:
            continue
        module = importlib.import_module(module_name)
        sub = subparsers.add_parser(name, help=module.HELP, description=module.__doc__)
        module.add_arguments(sub)
        sub.set_defaults(run=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``whipple`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args))
    except InputError as error:
        print(f"whipple {args.command}: error: {error}", file=sys.stderr)
        return 2
    except AnalysisError as error:
        print(f"whipple {args.command}: analysis failed: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"whipple {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader (e.g. `head`) closed the pipe: stop quietly, as other command line tools do.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
