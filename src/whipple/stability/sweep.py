"""Design studies: the stability analysis of many parameter sets, in chunks.

A parameter table is a CSV file with a header of benchmark parameter names and one parameter
set per row. Columns that are absent take the value of a base bicycle (so a study can vary
just a few parameters); the base's extensions and controller apply to every row.

Tables of any length are read and analysed in chunks of rows (:data:`CHUNK_ROWS`), so memory
is bounded by the chunk size: :func:`table_chunks` reads a chunk at a time (plain blocks of
numbers with fastnumbers' parser, others with NumPy's; a block a parser refuses is read again
cell by cell for a one-line error naming the line and column), :func:`analyse_chunk`
validates a chunk's sets together, analyses the valid ones with
:mod:`whipple.stability.critical` (from the matrices alone for models of the Whipple form) and
returns the chunk's rows of the results table as text. A chunk is a self-contained task, so
chunks can be analysed on other processes or machines (:mod:`whipple.distributed`) and
written in order.
"""

from __future__ import annotations

import csv
import io
import itertools
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import fastnumbers
import numpy as np
import orjson
from numpy.typing import NDArray

from whipple.errors import InputError
from whipple.input_files import open_binary, text_lines
from whipple.model.assembly import build_linear_model, whipple_form_matrices
from whipple.model.linear import LinearModel
from whipple.model.parameters import PARAMETER_NAMES, Bicycle, validate_rows
from whipple.model.physical_checks import tyre_point_wheel_problem
from whipple.number_text import may_hold_other_numbers, parse_number
from whipple.stability.critical import (
    CriticalSpeeds,
    CriticalSpeedTable,
    critical_speed_table,
    critical_speeds_batch,
    whipple_speed_table,
)

__all__ = ["CHUNK_ROWS", "RESULT_COLUMNS", "ParameterTable", "TableChunk", "MAX_TABLE_ROWS", "MAX_CHUNK_ROWS",
           "table_chunks", "read_parameter_table", "ChunkResult", "SweepTask", "analyse_sets", "float_cells",
           "analyse_chunk", "header_line", "SweepResult", "sweep"]

#: Rows of a parameter table read and analysed together.
CHUNK_ROWS = 10_000
#: Columns the results table adds to the input columns.
RESULT_COLUMNS = ("weave_speed", "capsize_speed", "stable_speed_ranges", "problem")


@dataclass(frozen=True)
class ParameterTable:
    """Columns of a parameter table: name -> values (one per row), and the source file."""

    columns: dict[str, NDArray[np.float64]]
    rows: int
    source: str


@dataclass(frozen=True)
class TableChunk:
    """Consecutive rows of a parameter table.

    Attributes
    ----------
    names : tuple of str
        Column names (benchmark parameters).
    values : ndarray, shape (rows, columns)
        The cells, in the parameters' SI units.
    lines : tuple of str, optional
        The rows as written in the file (without line ends), repeated in the results table;
        without them the cells are written as ``repr`` of the numbers.
    """

    names: tuple[str, ...]
    values: NDArray[np.float64]
    lines: tuple[str, ...] | None = None


def _data_lines(handle: Iterable[str], first: int) -> Iterator[tuple[int, str]]:
    """(line number, line) of the lines that hold data: no comments, no blank lines."""
    for number, line in enumerate(handle, start=first):
        stripped = line.strip()
        if stripped and not stripped.startswith("#") and stripped.strip(",").strip():
            yield number, line


def _csv_rows(lines: list[str], path: Path) -> list[list[str]]:
    """Return the cells of CSV lines; a line the csv module cannot split (a cell too long) is an InputError."""
    try:
        return list(csv.reader(lines))
    except csv.Error as error:
        raise InputError(f"not a readable CSV table ({error})", path) from None


def _parse_cells(lines: list[tuple[int, str]], header: tuple[str, ...], path: Path) -> NDArray[np.float64]:
    """Cells of `lines` one by one: the values, or an InputError naming the first bad cell."""
    values = np.empty((len(lines), len(header)))
    rows = _csv_rows([line for _, line in lines], path)
    for r, ((number, _), row) in enumerate(zip(lines, rows, strict=True)):
        if len(row) != len(header):
            raise InputError(f"line {number}: {len(row)} cells, header has {len(header)}", path)
        for c, cell in enumerate(row):
            try:
                number_value = parse_number(cell)
            except ValueError:
                raise InputError(f"line {number}, column {header[c]}: not a number: {cell.strip()!r}",
                                 path) from None
            if not np.isfinite(number_value):
                raise InputError(f"line {number}, column {header[c]}: not finite: {cell.strip()!r}", path)
            values[r, c] = number_value
    return values


def _parse_block(lines: list[tuple[int, str]], header: tuple[str, ...], path: Path) -> NDArray[np.float64]:
    """Cells of `lines` with NumPy's parser; anything it refuses is read again cell by cell."""
    if any(may_hold_other_numbers(line) for _, line in lines):
        return _parse_cells(lines, header, path)
    try:
        values = np.loadtxt([line for _, line in lines], delimiter=",", dtype=float, ndmin=2,
                            comments=None, quotechar='"')
    except ValueError:
        return _parse_cells(lines, header, path)
    if values.shape != (len(lines), len(header)) or not np.all(np.isfinite(values)):
        return _parse_cells(lines, header, path)
    return values


def _plain_block(lines: list[str], columns: int) -> NDArray[np.float64] | None:
    """Return the cells of lines that are all plain rows of finite numbers; None for anything else.

    Nearly every table is such a block (no comments, blank lines or quotes), and reading the
    numbers is most of the cost of a sweep's row: fastnumbers' parser (the fast_float algorithm,
    correctly rounded, so the values are those of ``float``) reads them several times faster
    than NumPy's or Python's. A block that is not plain (or a cell it refuses: quoted, ``1_0``)
    is read by the general path, which also names a bad cell.
    """
    if set(map(str.count, lines, itertools.repeat(","))) != {columns - 1}:
        return None
    joined = ",".join(lines)
    if may_hold_other_numbers(joined):
        return None
    values = fastnumbers.try_array(joined.split(","), dtype=float, on_fail=np.nan)
    if not np.all(np.isfinite(values)):
        return None
    return values.reshape(len(lines), columns)


#: Most rows of a parameter table: a sweep of them writes about 10 GB and takes hours; an
#: endless input (a pipe that never closes) is refused when it passes this many.
MAX_TABLE_ROWS = 100_000_000
#: Most rows analysed together (``--chunk``): measured 0.38 GB peak for 250,000 rows of two
#: columns (0.9 GB for 10^6), against 0.13 GB for the default chunk.
MAX_CHUNK_ROWS = 250_000


def _row_blocks(blocks: Iterable[list[str]], rows: int) -> Iterator[list[str]]:
    """Regroup blocks of lines into blocks of `rows` lines (the last block fewer)."""
    pending: list[str] = []
    for block in blocks:
        pending.extend(block)
        start = 0
        while len(pending) - start >= rows:
            yield pending[start:start + rows]
            start += rows
        del pending[:start]
    if pending:
        yield pending


def _header(lines: Iterator[list[str]], path: Path) -> tuple[tuple[str, ...], int, list[str]]:
    """Return the column names, the number of the line holding them and the rest of its block."""
    number = 0
    for block in lines:
        for k, line in enumerate(block):
            stripped = line.strip()
            if not stripped or stripped.startswith("#") or not stripped.strip(","):
                continue
            header = tuple(cell.strip() for cell in _csv_rows([line], path)[0])
            unknown = [name for name in header if name not in PARAMETER_NAMES]
            if unknown:
                raise InputError(f"unknown column(s) {', '.join(unknown)}; columns must be benchmark parameter "
                                 "names", path)
            repeated = sorted({name for name in header if header.count(name) > 1})
            if repeated:
                raise InputError(f"repeated column(s) {', '.join(repeated)}", path)
            return header, number + k + 1, block[k + 1:]
        number += len(block)
    raise InputError("empty parameter table", path)


def table_chunks(path: str | Path, rows: int = CHUNK_ROWS, max_lines: int = MAX_TABLE_ROWS
                 ) -> tuple[tuple[str, ...], Iterator[TableChunk]]:
    """Read the header of a parameter table now and its rows lazily, `rows` at a time.

    Every cell must be a finite number. Lines starting with ``#`` and blank lines are ignored.
    ``-`` reads standard input. The file is read in blocks (a line longer than
    :data:`whipple.input_files.MAX_LINE_CHARACTERS`, binary data and more than
    `max_lines` lines (:data:`MAX_TABLE_ROWS`) are refused when met), so memory is bounded by
    `rows`.

    Returns
    -------
    names : tuple of str
        The columns (benchmark parameter names).
    chunks : iterator of TableChunk
        The rows in order, at most `rows` per chunk; reading it raises InputError at the first
        bad line.

    Raises
    ------
    InputError
        Unreadable file, unknown or repeated column, empty table, no rows, `rows` beyond
        :data:`MAX_CHUNK_ROWS`, and (while iterating) a line with the wrong number of cells or a
        non-numeric or non-finite cell, named by line number and column, binary data, a line
        too long, too many lines.
    """
    path = Path(path)
    if not 1 <= rows <= MAX_CHUNK_ROWS:
        raise InputError(f"a chunk must hold 1 to {MAX_CHUNK_ROWS:,} rows, got {rows}")
    try:
        handle = open_binary(path)
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", path) from None
    lines = text_lines(handle, str(path), InputError)

    def counted() -> Iterator[list[str]]:
        total = 0
        for block in lines:
            total += len(block)
            if total > max_lines:
                raise InputError(f"more than {max_lines:,} lines: too long a parameter table (split it)", path)
            yield block

    stream = counted()

    def blocks(first_line: int, rest: list[str]) -> Iterator[TableChunk]:
        """Chunks of at most `rows` lines of the file, from line `first_line` on."""
        for block in _row_blocks(itertools.chain([rest], stream), rows):
            values = _plain_block(block, len(header))
            if values is not None:
                yield TableChunk(header, values, tuple(block))
            elif data := list(_data_lines(block, first_line)):
                yield TableChunk(header, _parse_block(data, header, path), tuple(line for _, line in data))
            first_line += len(block)

    try:
        # The header is the first data line; the lines before it are comments or blank.
        header, header_line_number, rest = _header(stream, path)
        chunks = blocks(header_line_number + 1, rest)
        first = next(chunks, None)
        if first is None:
            raise InputError("no parameter sets (only a header)", path)
    except BaseException:
        handle.close()
        raise

    def all_chunks() -> Iterator[TableChunk]:
        with handle:
            yield first
            yield from chunks

    return header, all_chunks()


def read_parameter_table(path: str | Path) -> ParameterTable:
    """Read a whole CSV of parameter sets; every cell must be a finite number.

    Parameters
    ----------
    path : str or Path
        The CSV file: a header of benchmark parameter names, one parameter set per row.

    Returns
    -------
    ParameterTable
        The columns by name, as arrays of floats.

    Raises
    ------
    InputError
        As :func:`table_chunks`.
    """
    header, chunks = table_chunks(path)
    values = np.concatenate([chunk.values for chunk in chunks])
    return ParameterTable({name: values[:, c] for c, name in enumerate(header)}, values.shape[0], str(path))


@dataclass(frozen=True)
class ChunkResult:
    """The analysis of one chunk: its rows of the results table, and counts.

    Attributes
    ----------
    text : str
        CSV lines (no header) with the input cells and :data:`RESULT_COLUMNS`.
    rows, skipped : int
        Rows in the chunk, and rows not analysed (not physical; see the problem column).
    """

    text: str
    rows: int
    skipped: int


@dataclass(frozen=True)
class SweepTask:
    """Everything one chunk's analysis needs (picklable, for other processes or machines).

    Attributes
    ----------
    chunk : TableChunk
        The parameter sets.
    base : Bicycle
        Supplies absent parameters, the extensions and the controller.
    speed_range : tuple of float
        Speed interval searched [m/s].
    """

    chunk: TableChunk
    base: Bicycle
    speed_range: tuple[float, float]


def _with_point_wheels(problems: tuple[str, ...], parameters: dict[str, float | NDArray[np.float64]]
                       ) -> tuple[str, ...]:
    """Add the problem of rows whose point wheels the base's tyre model cannot hold."""
    zero = {name: np.broadcast_to(np.asarray(parameters[name]) == 0, (len(problems),)) for name in ("rR", "rF")}
    result = list(problems)
    for row in np.flatnonzero(zero["rR"] | zero["rF"]).tolist():
        text = tyre_point_wheel_problem([name for name in ("rR", "rF") if zero[name][row]])
        result[row] = f"{result[row]}; {text}" if result[row] else text
    return tuple(result)


def _valid_sets(chunk: TableChunk, base: Bicycle
                ) -> tuple[tuple[str, ...], list[int], dict[str, float | NDArray[np.float64]] | None]:
    """Validate every row of a chunk; return the problems, the valid rows and their parameters.

    Absent columns take the base's values. The parameters are None when no row is valid.
    """
    count = chunk.values.shape[0]
    # The base's values stay scalars (broadcast): a check of a column the table does not vary
    # then costs nothing per row.
    parameters: dict[str, float | NDArray[np.float64]] = dict(base.parameters)
    parameters.update({name: chunk.values[:, c] for c, name in enumerate(chunk.names)})
    problems = validate_rows(parameters)
    if base.extensions.tyre_compliance is not None:
        problems = _with_point_wheels(problems, parameters)
    if not any(problems):
        return problems, list(range(count)), parameters
    rows = [row for row, problem in enumerate(problems) if not problem]
    if not rows:
        return problems, rows, None
    if len(rows) < count:
        index = np.array(rows)
        parameters = {name: values[index] if isinstance(values, np.ndarray) else values
                      for name, values in parameters.items()}
    return problems, rows, parameters


def _model(parameters: dict[str, float | NDArray[np.float64]], base: Bicycle) -> LinearModel:
    """Return the linear models of valid rows; the base's extensions and controller apply to every row."""
    return build_linear_model(parameters, base.extensions, base.controller)


def _speed_table(parameters: dict[str, float | NDArray[np.float64]], base: Bicycle,
                 speed_range: tuple[float, float]) -> CriticalSpeedTable:
    """Return the critical speeds of valid rows; models of the Whipple form from their matrices alone."""
    matrices = whipple_form_matrices(parameters, base.extensions, base.controller)
    if matrices is None:
        return critical_speed_table(_model(parameters, base), *speed_range)
    return whipple_speed_table(matrices.M, matrices.C1, matrices.K0, matrices.K2, *speed_range)


def analyse_sets(chunk: TableChunk, base: Bicycle, speed_range: tuple[float, float],
                 progress: Callable[[int], None] | None = None
                 ) -> tuple[tuple[str, ...], list[CriticalSpeeds | None]]:
    """Problems (empty if none) and critical speeds (None if not analysed) of each row.

    Parameters
    ----------
    chunk : TableChunk
        The parameter sets.
    base : Bicycle
        Supplies absent parameters, the extensions and the controller.
    speed_range : tuple of float
        Speed interval searched [m/s].
    progress : callable, optional
        Passed on to :func:`~whipple.stability.critical.critical_speeds_batch`.
    """
    problems, rows, parameters = _valid_sets(chunk, base)
    critical: list[CriticalSpeeds | None] = [None] * len(problems)
    if parameters is not None:
        for row, result in zip(rows, critical_speeds_batch(_model(parameters, base), *speed_range,
                                                           progress=progress),
                               strict=True):
            critical[row] = result
    return problems, critical


def float_cells(values: NDArray[np.float64]) -> list[str]:
    """CSV cells of numbers: the shortest text that reads back exactly, empty for NaN.

    The text of ``repr`` (apart from the exponent form of some very small or large numbers),
    written by orjson's float formatter, which is several times faster than ``repr`` and most
    of the cost of writing a results table otherwise.
    """
    if not values.size:
        return []
    return orjson.dumps(values.tolist())[1:-1].decode().replace("null", "").split(",")


def _quoted(cell: str) -> str:
    """Write one CSV cell as the csv module does (quoted only if it must be)."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="").writerow([cell])
    return buffer.getvalue()


def analyse_chunk(task: SweepTask) -> ChunkResult:
    """Analyse one chunk of a table and format its rows of the results table.

    The input row is repeated as written (or as ``repr`` of the numbers, which read back
    exactly), then the weave and capsize speeds [m/s], the stable speed ranges as ``low:high``
    pairs [m/s] separated by ``;``, and the problem of a row that was not analysed. The speeds
    come from :func:`~whipple.stability.critical.critical_speed_table` (the same solver as
    :func:`analyse_sets`, without a result object per row), or for models of the Whipple form
    from :func:`~whipple.stability.critical.whipple_speed_table` (the same numbers from the
    matrices alone).
    """
    problems, valid, parameters = _valid_sets(task.chunk, task.base)
    count = len(problems)
    weave_cells, capsize_cells, ranges = [""] * count, [""] * count, [""] * count
    if parameters is not None:
        table = _speed_table(parameters, task.base, task.speed_range)
        weave_cells, capsize_cells = float_cells(table.weave_speed), float_cells(table.capsize_speed)
        ranges = _range_cells(table, len(valid))
        if len(valid) < count:  # rows not analysed have empty cells
            weave_cells, capsize_cells, ranges = (_scattered(cells, valid, count)
                                                  for cells in (weave_cells, capsize_cells, ranges))
    rows = task.chunk.lines
    if rows is None:
        cells, width = float_cells(task.chunk.values.ravel()), task.chunk.values.shape[1]
        rows = tuple(",".join(cells[start:start + width]) for start in range(0, len(cells), width))
    problem_cells = [_quoted(problem) if problem else "" for problem in problems]
    text = "".join([f"{inputs},{weave},{capsize},{pairs},{problem}\n" for inputs, weave, capsize, pairs, problem
                    in zip(rows, weave_cells, capsize_cells, ranges, problem_cells, strict=True)])
    return ChunkResult(text, count, count - len(valid))


def _range_cells(table: CriticalSpeedTable, count: int) -> list[str]:
    """Return the stable ranges of each of `count` models as ``low:high`` pairs separated by ``;``."""
    pairs = np.array(list(map(":".join, zip(float_cells(table.range_low), float_cells(table.range_high),
                                            strict=True))), dtype=object)
    cells = np.full(count, "", dtype=object)
    # Most models have one range: placed at once; a model's further ranges (in increasing
    # speed, as the table lists them) are appended one by one.
    further = np.zeros(pairs.size, dtype=bool)
    further[1:] = table.range_model[1:] == table.range_model[:-1]
    cells[table.range_model[~further]] = pairs[~further]
    for model, pair in zip(table.range_model[further].tolist(), pairs[further].tolist(), strict=True):
        cells[model] = f"{cells[model]};{pair}"
    return cells.tolist()


def _scattered(cells: list[str], rows: list[int], count: int) -> list[str]:
    """`count` cells: ``cells[k]`` at ``rows[k]``, empty elsewhere."""
    full = [""] * count
    for row, cell in zip(rows, cells, strict=True):
        full[row] = cell
    return full


def header_line(names: tuple[str, ...]) -> str:
    """Return the header line of the results table of a table with columns `names`."""
    return ",".join(names + RESULT_COLUMNS) + "\n"


@dataclass(frozen=True)
class SweepResult:
    """Per row: validity (with the problems), and the critical speeds of the valid rows."""

    valid: NDArray[np.bool_]
    problems: tuple[str, ...]
    critical: tuple[CriticalSpeeds | None, ...]


def sweep(table: ParameterTable, base: Bicycle, speed_range: tuple[float, float] = (0.0, 10.0),
          progress: Callable[[int], None] | None = None) -> SweepResult:
    """Critical speeds and stable ranges of every row of a table read whole (vectorised over rows).

    Parameters
    ----------
    table : ParameterTable
        The parameter sets.
    base : Bicycle
        Supplies absent parameters, the extensions and the controller.
    speed_range : tuple of float
        Speed interval searched [m/s].
    progress : callable, optional
        Called with the number of valid sets analysed so far.

    Returns
    -------
    SweepResult
        Per row: whether it was analysed, the problem if not, and its critical speeds
        (:class:`~whipple.stability.critical.CriticalSpeeds`).
    """
    names = tuple(table.columns)
    values = np.stack([table.columns[name] for name in names], axis=-1).reshape(table.rows, len(names))
    problems, critical = analyse_sets(TableChunk(names, values), base, speed_range, progress)
    valid = np.array([result is not None for result in critical], dtype=bool)
    return SweepResult(valid, problems, tuple(critical))
