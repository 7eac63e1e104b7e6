"""Stability analysis of many parameter sets (one per CSV row), for design studies.

Columns are benchmark parameter names; absent ones come from --bicycle (default: the
benchmark), whose extensions and controller apply to every row. The output CSV repeats the
input columns and adds ``weave_speed``, ``capsize_speed``, ``stable_speed_ranges`` (as
``low:high`` pairs separated by ``;``) and ``problem`` (why a row was not analysed).
"""

from __future__ import annotations

import argparse
import csv
import io
import sys
from pathlib import Path

from tqdm import tqdm

from whipple.atomic import refuse_input_overwrite, write_text_atomic
from whipple.cli.arguments import speed_range
from whipple.model.parameters import load_bicycle
from whipple.stability.sweep import read_parameter_table, sweep


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    parser.add_argument("table", type=Path, metavar="SETS.csv", help="parameter sets, one per row")
    parser.add_argument("--output", "-o", type=Path, required=True, metavar="OUT.csv", help="results table")
    parser.add_argument("--bicycle", default="benchmark", metavar="PARAMS",
                        help="bicycle supplying absent columns, extensions and controller (default benchmark)")
    parser.add_argument("--speeds", type=speed_range, default=(0.0, 10.0), metavar="LOW:HIGH",
                        help="speed interval searched, m/s (default 0:10)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _format(value: float | None) -> str:
    return "" if value is None else repr(float(value))


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    refuse_input_overwrite(args.output, [args.table, args.bicycle])
    table = read_parameter_table(args.table)
    base = load_bicycle(args.bicycle)
    with tqdm(total=table.rows, unit="set", disable=args.quiet or table.rows < 200, file=sys.stderr) as bar:
        result = sweep(table, base, args.speeds, progress=lambda done: bar.update(done - bar.n))
        bar.update(table.rows - bar.n)  # rows skipped as non-physical count as done
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    names = list(table.columns)
    writer.writerow(names + ["weave_speed", "capsize_speed", "stable_speed_ranges", "problem"])
    for row in range(table.rows):
        critical = result.critical[row]
        cells = [repr(float(table.columns[name][row])) for name in names]
        if critical is None:
            writer.writerow(cells + ["", "", "", result.problems[row]])
        else:
            ranges = ";".join(f"{low!r}:{high!r}" for low, high in critical.stable_speed_ranges)
            writer.writerow(cells + [_format(critical.weave_speed), _format(critical.capsize_speed), ranges, ""])
    write_text_atomic(args.output, buffer.getvalue())
    skipped = int((~result.valid).sum())
    print(f"analysed {table.rows - skipped} of {table.rows} parameter sets"
          + (f" ({skipped} not physical, see the problem column)" if skipped else "") + f"; wrote {args.output}")
    return 0
