"""The table of a run file, read as a stream: metadata, column names and the wanted columns.

The file is read in blocks of lines (:func:`whipple.input_files.text_lines`) and every block
is parsed into arrays at once, so that memory holds the numbers of the wanted columns and one
block of text, never the whole file as text. An endless or huge input is refused when it
passes a cap: a line longer than :data:`whipple.input_files.MAX_LINE_CHARACTERS`, more than
:data:`MAX_RUN_SAMPLES` data rows, more than :data:`MAX_RUN_VALUES` numbers kept, or more than
:data:`MAX_RUN_LINES` lines of any kind.
"""

from __future__ import annotations

import gzip
import itertools
import re
import zlib
from dataclasses import dataclass, field, replace
from datetime import datetime
from typing import IO, Any

import fastnumbers
import numpy as np
from numpy.typing import NDArray

from whipple.errors import RunFileError
from whipple.input_files import open_binary, text_lines
from whipple.measurement.layouts import SPEC_COLUMNS, RunLayout, detect_layout, load_layout, other_delimiter
from whipple.measurement.time_stamps import seconds_since
from whipple.measurement.units_row import is_units_row, named_units, unit_factors
from whipple.number_text import may_hold_other_numbers, parse_number

#: Most data rows (samples) of a run file: 27.8 hours at 100 Hz.
MAX_RUN_SAMPLES = 10_000_000
#: Most numbers kept from a run file (480 MB as float64): 10 million samples of 6 columns, fewer
#: of more.
MAX_RUN_VALUES = 60_000_000
#: Most lines of any kind (data, comments, blank lines) of a run file: twice its most rows.
MAX_RUN_LINES = 2 * MAX_RUN_SAMPLES

#: A number written with a decimal comma, and one with a decimal point.
_COMMA_NUMBER = re.compile(r"[-+]?\d+,\d+([eE][-+]?\d+)?")
_POINT_NUMBER = re.compile(r"[-+]?(\d+\.\d*|\.\d+)([eE][-+]?\d+)?")

#: Columns whose cells must be numbers (or empty/NaN, a gap): the ones every analysis reads. A
#: cell of text in another column (a logger's status word, a controller not yet switched on)
#: only leaves a gap in that column.
NUMERIC = ("time", "roll_rate", "speed", "speedometer")


@dataclass
class _Gaps:
    """Gaps found so far in one column: how many, first and last line, whether text was among them."""

    count: int = 0
    first: int = 0
    last: int = 0
    text: bool = False


@dataclass
class RunTable:
    """What a run file holds, before any check of its values.

    Attributes
    ----------
    layout : RunLayout
        The layout the file was read with (the native one when none applies).
    native : bool
        Whether it is the native format.
    metadata : dict of str to str
        The layout's metadata updated by the file's ``# key: value`` lines.
    names : list of str
        The file's column names.
    signals : dict of str to ndarray
        The wanted columns by run-file name (NaN for gaps), unscaled.
    notes : list of str
        What was ignored (unknown columns, gaps) or converted.
    units : dict of str to float
        Factors to SI units of run-file columns whose unit the header (after a column's name) or
        a row of units under it gives in other units (:mod:`whipple.measurement.units_row`);
        not yet applied.
    """

    layout: RunLayout
    native: bool
    metadata: dict[str, str] = field(default_factory=dict)
    names: list[str] = field(default_factory=list)
    signals: dict[str, NDArray[np.float64]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    units: dict[str, float] = field(default_factory=dict)


class _Gzip:
    """A gzip stream whose failures are a one-line RunFileError naming the file."""

    def __init__(self, handle: IO[bytes], source: str) -> None:
        self.stream = gzip.GzipFile(fileobj=handle)
        self.source = source

    def read(self, size: int) -> bytes:
        try:
            return self.stream.read(size)
        except (OSError, EOFError, zlib.error) as error:
            raise RunFileError(f"corrupt gzip data ({error})", self.source) from None


def read_run_table(path: Any, layout: str | Any | None, source: str, max_samples: int = MAX_RUN_SAMPLES) -> RunTable:
    """Read the metadata, header and wanted columns of a run file (``.gz`` decompressed on the fly).

    Parameters
    ----------
    path : path or Traversable
        The run file.
    layout : str, path, RunLayout or None
        As for :func:`whipple.measurement.runs.read_run`.
    source : str
        Name of the file in messages.
    max_samples : int
        Most data rows read (at most :data:`MAX_RUN_VALUES` numbers are kept whatever it is).

    Raises
    ------
    RunFileError
        Unreadable, not text, a line too long, too many rows or lines, empty, no header or data
        rows, duplicate column names, no roll_rate column, a metadata key given twice, a row
        with the wrong number of fields, text or an infinity in a column every analysis reads.
    """
    try:
        handle = open_binary(path)
    except OSError as error:
        raise RunFileError(f"cannot read file ({error.strerror or error})", source) from None
    with handle:
        stream: Any = handle
        head = handle.peek(2)[:2] if hasattr(handle, "peek") else b""
        if head == b"\x1f\x8b":
            stream = _Gzip(handle, source)
        return _Reader(layout, source, max_samples).read(text_lines(stream, source, _run_file_error))


def _run_file_error(problem: str, source: str) -> RunFileError:
    return RunFileError(problem, source)


class _Reader:
    """The state of one file's reading: before the first row, at the header, in the data."""

    def __init__(self, layout: str | Any | None, source: str, max_samples: int) -> None:
        self.layout_argument, self.source, self.max_samples = layout, source, max_samples
        self.table: RunTable | None = None
        self.comment = "#"
        self.metadata_lines: dict[str, int] = {}
        self.metadata: dict[str, str] = {}
        self.wanted: dict[str, str] = {}
        self.columns: dict[str, list[NDArray[np.float64]]] = {}
        self.gaps: dict[str, _Gaps] = {}
        self.rows = 0
        self.row_limit = max_samples
        self.header_done = False
        self.units_row_possible = False
        self.decimal_comma_possible = False
        self.decimal_comma = False
        self.clock_origin: datetime | None = None
        # The last row read, if it had too few fields: left out if no row follows it.
        self.cut_short: tuple[int, int] | None = None

    def read(self, blocks: Any) -> RunTable:
        number = 0
        for block in blocks:
            self._block(block, number)
            number += len(block)
            if number > 2 * self.max_samples:
                raise RunFileError(f"more than {2 * self.max_samples:,} lines: too long for a run file", self.source)
        if self.table is None:
            raise RunFileError("empty file", self.source)
        if not self.header_done and self.table.layout.header:
            raise RunFileError("no header line", self.source)
        if self.cut_short is not None:
            number, fields = self.cut_short
            self.table.notes.append(f"the last line ({number}) has {fields} of the header's {len(self.table.names)} "
                                    "fields (a file cut short?): left out")
        if self.rows == 0:
            raise RunFileError("no data rows", self.source)
        table = self.table
        table.metadata = {**table.layout.metadata, **self.metadata}
        for column, pieces in self.columns.items():
            target = self.wanted[column]
            table.signals[target] = np.concatenate(pieces)
            pieces.clear()
            gaps = self.gaps[column]
            if gaps.count:
                kind = "empty, NaN or non-numeric" if gaps.text else "empty or NaN"
                table.notes.append(f"column '{column}': {gaps.count} {kind} cell(s) (lines {gaps.first}-"
                                   f"{gaps.last}), read as gaps")
        return table

    def _choose_layout(self, first_line: str) -> None:
        layout = self.layout_argument
        if layout is None:
            chosen = detect_layout(first_line)
        elif isinstance(layout, RunLayout):
            chosen = layout
        else:
            chosen = load_layout(layout)
        native = chosen is None
        active = chosen or RunLayout(name="native", columns={name: name for name in SPEC_COLUMNS})
        self.table = RunTable(active, native)
        self.comment = active.comment

    def _block(self, block: list[str], offset: int) -> None:
        """Take one block of lines (`offset` lines came before it)."""
        start = 0
        if not self.header_done:
            found = self._preamble(block, offset)
            if found is None:
                return
            start = found
        chars = self._blanks()
        rows = [row.strip(chars) for row in (block[start:] if start else block)]
        comment = self.comment
        numbers: range | list[int] = range(offset + start + 1, offset + len(block) + 1)
        # Nearly every block is rows only: no blank line, no comment, and no loop over its lines.
        if not all(rows) or (comment and comment in "".join(rows)):
            kept = [(number, row) for number, row in zip(numbers, rows, strict=True)
                    if row and not (comment and row.startswith(comment))]
            numbers, rows = [number for number, _ in kept], [row for _, row in kept]
        if rows:
            self._data(numbers, rows)

    def _preamble(self, block: list[str], offset: int) -> int | None:
        """Read metadata lines and the header; return where the data rows start, or None if not yet."""
        for k, line in enumerate(block):
            stripped = line.strip()
            if not stripped:
                continue
            if self.table is None:
                self._choose_layout(stripped)
            assert self.table is not None
            comment = self.comment
            if comment and stripped.startswith(comment):
                key, colon, value = stripped[len(comment):].partition(":")
                key = key.strip()
                if colon:
                    if key in self.metadata_lines:
                        raise RunFileError(f"line {offset + k + 1}: metadata '{key}' given twice (first on line "
                                           f"{self.metadata_lines[key]})", self.source)
                    self.metadata_lines[key] = offset + k + 1
                    self.metadata[key] = value.strip()
                continue
            if self.table.native and "," not in stripped:
                self._sniff_delimiter(stripped)
            layout = self.table.layout
            if layout.header:
                header = line.strip(self._blanks())
                self._set_names([_unquoted(name) for name in header.split(layout.delimiter)], offset + k + 1)
                self.header_done = True
                self.units_row_possible = True
                return k + 1
            self._set_names(list(layout.names))
            self.header_done = True
            return k
        return None

    def _blanks(self) -> str | None:
        """Return the characters stripped from a line's ends: blanks, but not a delimiter that is one (a tab).

        A tab-separated row whose first or last cell is empty starts or ends with a tab; stripped
        of it, the row would lose that cell. None: every blank.
        """
        delimiter = self.table.layout.delimiter if self.table is not None else None
        if delimiter is None or not delimiter.isspace():
            return None
        return "".join(c for c in " \t\r\n\x0b\x0c" if c != delimiter)

    def _sniff_delimiter(self, header: str) -> None:
        """Take a native header without commas as separated by the tab, ``;`` or blanks it has.

        Spreadsheets in locales with a decimal comma write ``;`` between cells, and many loggers
        and MATLAB write tabs or spaces; the column names are the spec's all the same. Their
        cells are then read with a decimal comma too (:meth:`_data`).
        """
        assert self.table is not None
        delimiter = other_delimiter(header)
        if delimiter is None and len(header.split()) > 1:
            delimiter = ""
        if delimiter is None:
            return
        self.table.layout = replace(self.table.layout, delimiter=delimiter or None)
        shown = {"\t": "tabs", ";": "';'", "": "blanks"}[delimiter]
        self.table.notes.append(f"columns separated by {shown}")
        self.decimal_comma_possible = True

    def _set_names(self, names: list[str], line: int = 0) -> None:
        assert self.table is not None
        table, layout = self.table, self.table.layout
        if table.native:
            names, units, renamed = named_units(names)
            if renamed:
                table.notes.append(f"column names read as the run-file spec's: {', '.join(renamed)}")
            self._take_units(units, line, set(), "the header")
        if len(set(names)) != len(names):
            raise RunFileError("duplicate column names in the header", self.source)
        table.names = names
        wanted = layout.column_map(names)
        unknown = [n for n in names if n not in wanted and n not in layout.ignore]
        if unknown:
            table.notes.append(f"ignored unknown column(s): {', '.join(name or '(unnamed)' for name in unknown)}")
        missing = [n for n in layout.columns if n not in names and not table.native]
        if missing:
            table.notes.append(f"layout column(s) not in the file: {', '.join(missing)}")
        if "roll_rate" not in wanted.values():
            hint = _delimiter_hint(names, layout.delimiter) or _name_hint(names)
            raise RunFileError(f"missing roll_rate column{hint}", self.source)
        self.wanted = wanted
        self.columns = {name: [] for name in wanted}
        self.gaps = {name: _Gaps() for name in wanted}
        self.row_limit = min(self.max_samples, MAX_RUN_VALUES // len(wanted))

    def _data(self, numbers: range | list[int], rows: list[str]) -> None:
        """Parse data rows (stripped, with their line numbers) into the wanted columns."""
        assert self.table is not None
        joined = "".join(rows)
        if '"' in joined:
            # Quoted cells (spreadsheet and R exports): numbers never hold a quote.
            rows = [row.replace('"', "") for row in rows]
            joined = joined.replace('"', "")
        if self.decimal_comma_possible:
            # Numbers with a comma and none with a point, in cells not separated by commas: a
            # decimal comma (a cell of dates and times may hold a point all the same).
            cells = [cell.strip() for row in rows[:100] for cell in row.split(self.table.layout.delimiter)]
            comma = any(_COMMA_NUMBER.fullmatch(cell) for cell in cells)
            point = any(_POINT_NUMBER.fullmatch(cell) for cell in cells)
            if comma or point:
                self.decimal_comma_possible = False
                self.decimal_comma = comma and not point
            if self.decimal_comma:
                self.table.notes.append("decimal commas read as points")
        if self.decimal_comma:
            rows = [row.replace(",", ".") for row in rows]
            joined = joined.replace(",", ".")
        if self.units_row_possible:
            self.units_row_possible = False
            if self._units_row(numbers[0], rows[0]):
                numbers, rows = numbers[1:], rows[1:]
                joined = "".join(rows)
                if not rows:
                    return
        if self.cut_short is not None:
            # Rows follow it: not the file's last line, so a row with the wrong number of fields.
            number, fields = self.cut_short
            width = len(self.table.names)
            raise RunFileError(f"line {number} has {fields} fields, the header has {width}", self.source)
        last = rows[-1].split(self.table.layout.delimiter)
        if len(last) < len(self.table.names):
            # A logger that stopped mid-line (power lost) leaves its last line short.
            self.cut_short = (int(numbers[-1]), len(last))
            numbers, rows = numbers[:-1], rows[:-1]
            if not rows:
                return
        self.rows += len(rows)
        if self.rows > self.row_limit:
            raise RunFileError(f"more than {self.row_limit:,} data rows: too long a run (whipple reads at most "
                               f"{MAX_RUN_VALUES:,} numbers of a run, here {len(self.wanted)} a row)", self.source)
        names = self.table.names
        width = len(names)
        cells = _cells(rows, numbers, width, self.table.layout.delimiter, self.source)
        plain = not may_hold_other_numbers(joined)
        # All cells at once (reading one column's cells from the list would cost more than
        # reading every column), then the wanted columns.
        table = _numbers(cells, plain).reshape(len(rows), width)
        for column, target in self.wanted.items():
            j = names.index(column)
            values = table[:, j].copy()
            text = _text_cells(values, cells, j, width)
            if target == "time" and text.any() and not np.isfinite(values).any():
                # A column of text only: dates and times (a number among them is no stamp).
                stamped = seconds_since(cells[j::width], self.clock_origin)
                if stamped is not None:
                    values, text, origin = stamped
                    if self.clock_origin is None:
                        self.table.notes.append(f"time read from dates and times, 0 s at {origin.isoformat(' ')}")
                    self.clock_origin = origin
            if target in NUMERIC and text.any():
                bad = int(np.argmax(text))
                raise RunFileError(f"line {numbers[bad]}, column '{column}': non-numeric value "
                                   f"'{cells[bad * width + j].strip()}'", self.source)
            infinite = np.isinf(values)
            if infinite.any():
                if target in NUMERIC:
                    bad = int(np.argmax(infinite))
                    cell = cells[bad * width + j].strip()
                    # An overflowing number (1e999) is read as inf: say so rather than echo it.
                    what = f"{cell} value" if "inf" in cell.lower() else f"value {cell} is too large (infinite)"
                    raise RunFileError(f"line {numbers[bad]}, column '{column}': {what}", self.source)
                values[infinite] = np.nan
            gap_rows = np.flatnonzero(np.isnan(values))
            if gap_rows.size:
                gaps = self.gaps[column]
                gaps.first = gaps.first or numbers[int(gap_rows[0])]
                gaps.last = numbers[int(gap_rows[-1])]
                gaps.count += int(gap_rows.size)
                gaps.text = gaps.text or bool(text.any())
            self.columns[column].append(values)

    def _units_row(self, number: int, row: str) -> bool:
        """Read the row under the header if it is a row of units (no number in it); say whether it was."""
        assert self.table is not None
        cells = row.split(self.table.layout.delimiter)
        if len(cells) != len(self.table.names) or not is_units_row(cells):
            return False
        units = {self.wanted[name]: cell for name, cell in zip(self.table.names, cells, strict=True)
                 if name in self.wanted}
        self._take_units(units, number, set(self.table.layout.scale), "the row of units under the header")
        return True

    def _take_units(self, units: dict[str, str], line: int, scaled: set[str], where: str) -> None:
        """Keep the factors to SI of the units `where` gives on `line` (:func:`~.units_row.unit_factors`), noted."""
        assert self.table is not None
        factors, notes = unit_factors(units, line, scaled, self.source, where)
        self.table.units.update(factors)
        self.table.notes.extend(notes)


def _unquoted(name: str) -> str:
    """Return a header cell without surrounding blanks and one pair of quotes around it."""
    name = name.strip()
    if len(name) >= 2 and name[0] == name[-1] and name[0] in "\"'":
        return name[1:-1].strip()
    return name


def _name_hint(names: list[str]) -> str:
    """Name the header's column that looks like the roll rate (another case, a unit), or list the header."""
    near = [name for name in names if re.sub(r"[\s_]*[\[(].*$", "", name).strip().lower() == "roll_rate"]
    if near:
        return (f" (the header has {near[0][:60]!r}: the exact name is roll_rate, in rad/s; a layout's [columns] "
                "maps another name and its [scale] another unit)")
    shown = ", ".join(repr(name[:30]) for name in names[:8]) + (" ..." if len(names) > 8 else "")
    return f" (the header has {shown}; a layout's [columns] maps another name)"


def _delimiter_hint(names: list[str], delimiter: str | None) -> str:
    """Say so when a one-column header looks separated by another delimiter (``;``, a tab)."""
    other = next((d for d in ";\t|" if d != delimiter and len(names) == 1 and d in names[0]), None)
    if other is None:
        return ""
    shown = "a tab" if other == "\t" else repr(other)
    return (f" (the header is one column {names[0][:60]!r}: separated by {shown}, not {delimiter!r}? "
            "a layout file can name its delimiter)")


def _cells(rows: list[str], numbers: range | list[int], width: int, delimiter: str | None, source: str) -> list[str]:
    """Return the cells of rows, row after row; a row with the wrong number of fields is refused."""
    if delimiter is not None and set(map(str.count, rows, itertools.repeat(delimiter))) == {width - 1}:
        return delimiter.join(rows).split(delimiter)
    split = [row.split(delimiter) for row in rows]
    for number, fields in zip(numbers, split, strict=True):
        if len(fields) != width:
            raise RunFileError(f"line {number} has {len(fields)} fields, the header has {width}", source)
    return list(itertools.chain.from_iterable(split))


def _numbers(cells: list[str], plain: bool) -> NDArray[np.float64]:
    """Cells as floats, NaN where empty or not a number (see :func:`_text_cells` for which held text).

    `plain` says the cells hold no characters Python's float reads and
    :func:`whipple.number_text.parse_number` refuses (other scripts' digits, underscores): then
    fastnumbers' parser (correctly rounded, as ``float``) reads them; otherwise each cell goes
    through parse_number.
    """
    if plain:
        return fastnumbers.try_array(cells, dtype=float, on_fail=np.nan, on_overflow=np.inf)
    values = np.full(len(cells), np.nan)
    for i, cell in enumerate(cells):
        try:
            values[i] = parse_number(cell)
        except ValueError:
            pass
    return values


def _text_cells(values: NDArray[np.float64], cells: list[str], column: int, width: int) -> NDArray[np.bool_]:
    """Where the NaN `values` of one column came from text, not from an empty or NaN cell."""
    text = np.zeros(values.shape, dtype=bool)
    for row in np.flatnonzero(np.isnan(values)).tolist():
        cell = cells[row * width + column].strip()
        if not cell:
            continue
        try:
            parse_number(cell)
        except ValueError:
            text[row] = True
    return text
