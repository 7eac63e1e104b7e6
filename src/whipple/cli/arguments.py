"""Argument types shared by several subcommands (speeds in m/s)."""

from __future__ import annotations

import argparse
import math

from whipple.number_text import parse_integer, parse_number


def number(text: str) -> float:
    """Read a number written as ASCII decimal text (:func:`whipple.number_text.parse_number`)."""
    try:
        return parse_number(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def integer(text: str) -> int:
    """Read an integer written in ASCII digits."""
    try:
        return parse_integer(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None


def speed_range(text: str) -> tuple[float, float]:
    """``LOW:HIGH`` in m/s, with 0 <= LOW < HIGH."""
    try:
        low_text, high_text = text.split(":")
        low, high = parse_number(low_text), parse_number(high_text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected LOW:HIGH in m/s, got {text!r}") from None
    if not (math.isfinite(low) and math.isfinite(high) and 0 <= low < high):
        raise argparse.ArgumentTypeError(f"need 0 <= LOW < HIGH (finite), got {text!r}")
    return low, high


def speed_list(text: str) -> list[float]:
    """``V1,V2,...`` in m/s (at least one)."""
    items = text.split(",")
    if text.strip() and not all(item.strip() for item in items):
        raise argparse.ArgumentTypeError(f"an empty item in {text!r}")
    try:
        speeds = [parse_number(item) for item in items if item.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected speeds like 2,3.5,5 (m/s), got {text!r}") from None
    if not speeds:
        raise argparse.ArgumentTypeError("no speeds given")
    twice = sorted({speed for speed in speeds if speeds.count(speed) > 1})
    if twice:
        raise argparse.ArgumentTypeError(f"speed {twice[0]:g} given twice")
    return speeds


def bicycle_inputs(args: argparse.Namespace) -> list[str]:
    """Return the bicycle file and the rider file a command reads (outputs must not replace them)."""
    return [path for path in (args.bicycle, args.rider) if path]


def add_rider_argument(parser: argparse.ArgumentParser) -> None:
    """``--rider FILE``: a rigid rider joined to the bicycle's rear frame."""
    parser.add_argument("--rider", metavar="FILE",
                        help="BicycleParameters rider file (<Rider><Bicycle>Benchmark.txt): the rider's body, "
                             "joined to the rear frame as a rigid rider")
