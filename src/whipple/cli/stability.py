"""Eigenvalues versus speed of a bicycle: figure (like the seed paper's Figure 6) and table.

Real parts are drawn solid and imaginary parts dashed, modes labelled, critical speeds marked
and the stable band shaded. The CSV table lists every eigenvalue with its mode at each speed.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
from pathlib import Path

import numpy as np

from whipple.atomic import write_text_atomic
from whipple.cli.arguments import add_rider_argument, bicycle_inputs, integer, speed_range
from whipple.cli.outputs import check_outputs, figure_format, save_figure
from whipple.cli.progress import Progress
from whipple.errors import InputError
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.stability.critical import critical_speeds
from whipple.stability.eigen import eigen_analysis, eigenvalue_table
from whipple.stability.plots import plot_eigenvalues

#: Most speeds in the table and figure: a 10 MB table; more is refused rather than swapped.
MAX_POINTS = 100_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("bicycle", metavar="PARAMS", help="bicycle file or built-in name")
    parser.add_argument("--speeds", type=speed_range, default=(0.0, 10.0), metavar="LOW:HIGH",
                        help="speed interval, m/s (default 0:10)")
    parser.add_argument("--points", type=integer, default=1001,
                        help=f"speeds in the table and figure (default 1001, at most {MAX_POINTS})")
    parser.add_argument("--plot", type=Path, metavar="FILE.png",
                        help="write the figure (format from the suffix: png, pdf, svg, ...; png without one; '-': "
                             "PNG on standard output)")
    parser.add_argument("--csv", type=Path, metavar="FILE.csv",
                        help="write the eigenvalue table ('-': standard output)")
    parser.add_argument("--json", action="store_true", help="print critical speeds and ranges as JSON")


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    if not 2 <= args.points <= MAX_POINTS:
        raise InputError(f"--points must be between 2 and {MAX_POINTS}, got {args.points}")
    check_outputs({"--plot": args.plot, "--csv": args.csv}, bicycle_inputs(args))
    if args.plot is not None:
        figure_format(args.plot)
    bicycle = load_bicycle(args.bicycle, rider=args.rider)
    model = linear_model(bicycle)
    low, high = args.speeds
    steps = 2 + (args.csv is not None) + (args.plot is not None)
    with Progress(steps, "step", "stability") as progress:
        result = eigen_analysis(model, np.linspace(low, high, args.points), vectors=False)
        progress.finished("eigenvalues")
        critical = critical_speeds(model, low, high)
        progress.finished("critical speeds")
        if args.csv is not None:
            header, rows = eigenvalue_table(result)
            buffer = io.StringIO()
            writer = csv.writer(buffer, lineterminator="\n")
            writer.writerow(header)
            writer.writerows(rows)
            write_text_atomic(args.csv, buffer.getvalue())
            progress.finished("table")
        if args.plot is not None:
            figure = plot_eigenvalues(result, critical, title=bicycle.name or str(args.bicycle))
            save_figure(figure, args.plot, dpi=150)
            progress.finished("figure")
    if args.json:
        print(json.dumps({"bicycle": bicycle.name, **critical.to_dict()}, indent=2))
    else:
        print(f"bicycle: {bicycle.name or args.bicycle}")
        for line in critical.summary():
            print(line)
        for output in (args.plot, args.csv):
            if output is not None:
                print(f"wrote {output}")
    return 0
