"""Validate a bicycle (a parameter file or a built-in name), print its matrices and stability.

Prints the validation result, the matrices M, C1, K0 (with gravity), K2 (and D when steer
damping is present), the weave and capsize speeds, the stable speed ranges found by root
finding in --speeds, and the eigenvalues at a few speeds. --json prints one JSON object with
``matrices``, ``weave_speed``, ``capsize_speed``, ``stable_speed_ranges`` and more.
"""

from __future__ import annotations

import argparse
import json

from whipple.cli.arguments import add_rider_argument, speed_range
from whipple.errors import InputError
from whipple.model.parameters import load_bicycle
from whipple.stability.report import analyse_bicycle


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("bicycle", metavar="PARAMS",
                        help="bicycle file (.toml or BicycleParameters *Benchmark.txt) or built-in name")
    parser.add_argument("--speeds", type=speed_range, default=(0.0, 10.0), metavar="LOW:HIGH",
                        help="speed interval searched for critical speeds, m/s (default 0:10)")
    parser.add_argument("--json", action="store_true", help="print a JSON object instead of text")


def _matrix_lines(name: str, matrix) -> list[str]:
    rows = [f"[{matrix[i][0]:>14.8f} {matrix[i][1]:>14.8f} ]" for i in range(2)]
    return [f"  {name:<3}= {rows[0]}", f"        {rows[1]}"]


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    bicycle = load_bicycle(args.bicycle, rider=args.rider)
    try:
        report = analyse_bicycle(bicycle, speed_range=args.speeds)
    except InputError as error:
        raise InputError(error.problem, args.bicycle) from None
    if args.json:
        print(json.dumps(report.to_dict(), indent=2))
        return 0
    print(f"bicycle: {bicycle.name or args.bicycle} ({bicycle.source or args.bicycle})")
    print("validation: ok" if not report.warnings else "validation: ok, with warnings")
    for warning in report.warnings:
        print(f"  warning: {warning}")
    print("matrices (M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = f, q = [roll, steer], K0 with g):")
    for name, matrix in report.matrices.items():
        print("\n".join(_matrix_lines(name, matrix)))
    for line in report.summary_lines():
        print(line)
    return 0
