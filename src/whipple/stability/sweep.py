"""Design studies: the stability analysis of many parameter sets at once.

A parameter table is a CSV file with a header of benchmark parameter names and one parameter
set per row. Columns that are absent take the value of a base bicycle (so a study can vary
just a few parameters); the base's extensions and controller apply to every row.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError
from whipple.model.assembly import build_linear_model
from whipple.model.parameters import PARAMETER_NAMES, Bicycle, validate
from whipple.stability.critical import CriticalSpeeds, critical_speeds_batch


@dataclass(frozen=True)
class ParameterTable:
    """Columns of a parameter table: name -> values (one per row), and the source file."""

    columns: dict[str, NDArray[np.float64]]
    rows: int
    source: str


def read_parameter_table(path: str | Path) -> ParameterTable:
    """Read a CSV of parameter sets; every cell must be a finite number.

    Raises
    ------
    InputError
        Unknown or repeated column, empty table, a non-numeric or non-finite cell (named by
        row and column).
    """
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            lines = [row for row in csv.reader(line for line in handle if not line.lstrip().startswith("#"))]
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror}", path) from None
    except UnicodeDecodeError:
        raise InputError("not a text (UTF-8) file", path) from None
    lines = [row for row in lines if any(cell.strip() for cell in row)]
    if not lines:
        raise InputError("empty parameter table", path)
    header = [cell.strip() for cell in lines[0]]
    unknown = [name for name in header if name not in PARAMETER_NAMES]
    if unknown:
        raise InputError(f"unknown column(s) {', '.join(unknown)}; columns must be benchmark parameter names", path)
    repeated = sorted({name for name in header if header.count(name) > 1})
    if repeated:
        raise InputError(f"repeated column(s) {', '.join(repeated)}", path)
    body = lines[1:]
    if not body:
        raise InputError("no parameter sets (only a header)", path)
    values = np.empty((len(body), len(header)))
    for r, row in enumerate(body, start=2):
        if len(row) != len(header):
            raise InputError(f"line {r}: {len(row)} cells, header has {len(header)}", path)
        for c, cell in enumerate(row):
            try:
                number = float(cell)
            except ValueError:
                raise InputError(f"line {r}, column {header[c]}: not a number: {cell.strip()!r}", path) from None
            if not np.isfinite(number):
                raise InputError(f"line {r}, column {header[c]}: not finite: {cell.strip()!r}", path)
            values[r - 2, c] = number
    return ParameterTable({name: values[:, c] for c, name in enumerate(header)}, len(body), str(path))


@dataclass(frozen=True)
class SweepResult:
    """Per row: validity (with the problems), and the critical speeds of the valid rows."""

    valid: NDArray[np.bool_]
    problems: tuple[str, ...]
    critical: tuple[CriticalSpeeds | None, ...]


def sweep(table: ParameterTable, base: Bicycle, speed_range: tuple[float, float] = (0.0, 10.0),
          progress: Callable[[int], None] | None = None) -> SweepResult:
    """Critical speeds and stable ranges of every row (vectorised over rows)."""
    parameters = {name: np.full(table.rows, value) for name, value in base.parameters.items()}
    parameters.update(table.columns)
    valid = np.ones(table.rows, dtype=bool)
    problems = [""] * table.rows
    for row in range(table.rows):  # cheap scalar checks give each row its own message
        report = validate({name: values[row] for name, values in parameters.items()})
        if report.problems:
            valid[row] = False
            problems[row] = "; ".join(report.problems)
    critical: list[CriticalSpeeds | None] = [None] * table.rows
    rows = np.flatnonzero(valid)
    if rows.size:
        model = build_linear_model({name: values[rows] for name, values in parameters.items()},
                                   base.extensions, base.controller)
        results = critical_speeds_batch(model, *speed_range, progress=progress)
        for row, result in zip(rows.tolist(), results, strict=True):
            critical[row] = result
    return SweepResult(valid, tuple(problems), tuple(critical))
