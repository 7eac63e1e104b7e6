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
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from whipple.atomic import atomic_path, refuse_input_overwrite
from whipple.cli.arguments import add_rider_argument, bicycle_inputs, integer, speed_range
from whipple.distributed import check_cluster_options, map_ordered
from whipple.errors import InputError
from whipple.model.parameters import load_bicycle
from whipple.stability.sweep import CHUNK_ROWS, SweepTask, analyse_chunk, header_line, table_chunks


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("table", type=Path, metavar="SETS.csv", help="parameter sets, one per row")
    parser.add_argument("--output", "-o", type=Path, required=True, metavar="OUT.csv", help="results table")
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
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _count_rows(path: Path) -> int | None:
    """Count the data lines of the table (for the progress bar); None if it cannot be read."""
    try:
        with path.open("rb") as handle:
            return sum(1 for line in handle if line.strip() and not line.lstrip().startswith(b"#")) - 1
    except OSError:
        return None


class _Progress:
    """Sets done, total and rate on one line of stderr (tqdm would double the start-up time)."""

    def __init__(self, total: int | None, shown: bool) -> None:
        self.total, self.shown, self.done = total, shown, 0
        self.start = self.last = time.perf_counter()

    def update(self, rows: int) -> None:
        self.done += rows
        now = time.perf_counter()
        if self.shown and (now - self.last > 0.5 or self.done == self.total):
            self.last = now
            of = f" of {self.total}" if self.total else ""
            rate = self.done / max(now - self.start, 1e-9)
            print(f"\r{self.done}{of} parameter sets, {rate:.0f}/s", end="", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.shown and self.done:
            print(file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    refuse_input_overwrite(args.output, [args.table, *bicycle_inputs(args)])
    if args.chunk < 1:
        raise InputError(f"--chunk must be at least 1, got {args.chunk}")
    check_cluster_options(args.scheduler, args.workers)
    names, chunks = table_chunks(args.table, args.chunk)
    base = load_bicycle(args.bicycle, rider=args.rider)
    tasks: Iterator[SweepTask] = (SweepTask(chunk, base, args.speeds) for chunk in chunks)
    total = _count_rows(args.table) if not args.quiet else None
    rows = skipped = 0
    progress = _Progress(total, not args.quiet and (total or 0) >= 200)
    with (map_ordered(analyse_chunk, tasks, scheduler=args.scheduler, workers=args.workers) as results,
          atomic_path(args.output) as temporary, temporary.open("w", encoding="utf-8", newline="") as out):
        out.write(header_line(names))
        for result in results:
            out.write(result.text)
            rows, skipped = rows + result.rows, skipped + result.skipped
            progress.update(result.rows)
    progress.close()
    print(f"analysed {rows - skipped} of {rows} parameter sets"
          + (f" ({skipped} not physical, see the problem column)" if skipped else "") + f"; wrote {args.output}")
    return 0
