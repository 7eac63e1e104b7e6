"""Stability analysis of many parameter sets (one per CSV row), for design studies.

Columns are benchmark parameter names; absent ones come from --bicycle (default: the
benchmark), whose extensions and controller apply to every row. The output CSV repeats the
input rows as written and adds ``weave_speed``, ``capsize_speed``, ``stable_speed_ranges`` (as
``low:high`` pairs separated by ``;``) and ``problem`` (why a row was not analysed).

The table is read and analysed in chunks of --chunk rows and the results are written in
order as they come, so tables of millions of rows fit in memory. --workers N analyses the
chunks on a local Dask cluster of N processes, --scheduler ADDRESS on an existing Dask
cluster; the output is the same byte for byte.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from pathlib import Path

from whipple.atomic import atomic_text, check_writable, refuse_input_overwrite
from whipple.cli.arguments import add_rider_argument, bicycle_inputs, integer, speed_range
from whipple.cli.progress import Progress, shown
from whipple.distributed import check_cluster_options, map_ordered
from whipple.errors import InputError
from whipple.input_files import is_regular_file
from whipple.model.parameters import load_bicycle
from whipple.stability.sweep import CHUNK_ROWS, MAX_CHUNK_ROWS, SweepTask, analyse_chunk, header_line, table_chunks


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("table", type=Path, metavar="SETS.csv",
                        help="parameter sets, one per row ('-': standard input)")
    parser.add_argument("--output", "-o", type=Path, required=True, metavar="OUT.csv",
                        help="results table ('-': standard output)")
    parser.add_argument("--bicycle", default="benchmark", metavar="PARAMS",
                        help="bicycle supplying absent columns, extensions and controller (default benchmark)")
    parser.add_argument("--speeds", type=speed_range, default=(0.0, 10.0), metavar="LOW:HIGH",
                        help="speed interval searched, m/s (default 0:10)")
    parser.add_argument("--chunk", type=integer, default=CHUNK_ROWS, metavar="ROWS",
                        help=f"rows read and analysed together (default {CHUNK_ROWS})")
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument("--workers", type=integer, metavar="N",
                         help="analyse chunks on a local Dask cluster of N processes")
    cluster.add_argument("--scheduler", metavar="ADDRESS",
                         help="analyse chunks on an existing Dask cluster (e.g. tcp://host:8786)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar (drawn only on a terminal)")


def _count_lines(path: Path) -> int | None:
    """Count the lines of a regular file (for the progress bar); None for a stream or an unreadable file."""
    if not is_regular_file(path):
        return None
    try:
        with path.open("rb") as handle:
            return sum(block.count(b"\n") for block in iter(lambda: handle.read(1 << 20), b""))
    except OSError:
        return None


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    refuse_input_overwrite(args.output, [args.table, *bicycle_inputs(args)])
    if not 1 <= args.chunk <= MAX_CHUNK_ROWS:
        raise InputError(f"--chunk must be between 1 and {MAX_CHUNK_ROWS}, got {args.chunk}")
    check_cluster_options(args.scheduler, args.workers)
    check_writable(args.output)
    names, chunks = table_chunks(args.table, args.chunk)
    base = load_bicycle(args.bicycle, rider=args.rider)
    tasks: Iterator[SweepTask] = (SweepTask(chunk, base, args.speeds) for chunk in chunks)
    # The lines of the file (a few are the header, comments or blank): the bar's total, roughly.
    total = _count_lines(args.table) if not args.quiet and shown() else None
    rows = skipped = 0
    with (Progress(total, "set", "parameter sets", enabled=not args.quiet) as progress,
          map_ordered(analyse_chunk, tasks, scheduler=args.scheduler, workers=args.workers) as results,
          atomic_text(args.output) as out):
        out.write(header_line(names))
        for result in results:
            out.write(result.text)
            rows, skipped = rows + result.rows, skipped + result.skipped
            progress.update(result.rows)
    print(f"analysed {rows - skipped} of {rows} parameter sets"
          + (f" ({skipped} not physical, see the problem column)" if skipped else "") + f"; wrote {args.output}")
    return 0
