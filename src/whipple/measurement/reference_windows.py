"""Windows files (hand-picked or saved windows) and the comparison of two sets of windows.

A windows file is a CSV with a ``run`` (or ``file``) column naming the run, and either
``start,stop`` (times [s]) or ``start_row,stop_row`` (0-based data rows, the stop row included,
as in the reference windows of the bundled treadmill runs). Lines starting with ``#`` are
comments.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from whipple.atomic import write_text_atomic
from whipple.errors import RunFileError
from whipple.input_files import read_small_file
from whipple.measurement.layouts import other_delimiter
from whipple.measurement.runs import Readable, Run, run_name
from whipple.measurement.windows import Window
from whipple.number_text import parse_integer, parse_number

__all__ = ["read_windows", "write_windows", "WindowMatch", "WindowComparison", "compare_windows"]


def read_windows(path: str | Path | Readable, runs: Sequence[Run] | None = None) -> tuple[Window, ...]:
    """Read a windows file (CSV).

    Columns: ``run`` or ``file`` naming the run (its file name, with or without extension),
    and either ``start,stop`` (times [s]) or ``start_row,stop_row`` (0-based data rows, stop
    row included). Row-based windows need the `runs` to know their sample times; with `runs`
    given, windows of other runs are left out.

    Parameters
    ----------
    path : str, Path or Traversable
        The windows file.
    runs : sequence of Run, optional
        The runs the windows belong to.

    Returns
    -------
    tuple of Window
        The windows, in the file's order.

    Raises
    ------
    RunFileError
        Missing columns, bad numbers, row windows without their run, no windows at all, or
        (with `runs`) no window of any of the runs.
    """
    source = str(path)
    try:
        # A user's file is read up to a size cap (an endless pipe is refused); the bundled one is small.
        data = (read_small_file(path, "windows file", RunFileError) if isinstance(path, str | Path)
                else path.read_bytes())
        text = data.decode("utf-8-sig")
    except OSError as error:
        raise RunFileError(f"cannot read windows file ({error})", source) from None
    except UnicodeDecodeError:
        raise RunFileError("not a UTF-8 text file", source) from None
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    header = next((line for line in lines if line.strip()), "")
    # As run files: a header without commas may be separated by tabs or ';' (and then the
    # times may have a decimal comma).
    delimiter = other_delimiter(header) or ","
    decimal = (lambda cell: cell.replace(",", ".")) if delimiter != "," else (lambda cell: cell)
    try:
        reader = csv.DictReader(lines, delimiter=delimiter)
        fields = set(reader.fieldnames or ())
        if len(fields) < len(reader.fieldnames or ()):  # which of two start columns is meant?
            raise RunFileError("duplicate column names in the header", source)
        rows = list(reader)
    except csv.Error as error:
        raise RunFileError(f"not a readable CSV table ({error})", source) from None
    key = "run" if "run" in fields else "file" if "file" in fields else None
    by_rows = {"start_row", "stop_row"} <= fields
    if key is None or not (by_rows or {"start", "stop"} <= fields):
        raise RunFileError("windows file needs a run (or file) column and start,stop or "
                           "start_row,stop_row columns", source)
    known = {run.name: run for run in runs or ()}
    windows = []
    for number, row in enumerate(rows, 2):
        name = run_name(row[key] or "")
        run = known.get(name)
        if runs is not None and run is None:
            continue
        try:
            if by_rows:
                first, last = _row_number(row["start_row"]), _row_number(row["stop_row"])
            else:
                begin, finish = parse_number(decimal(row["start"] or "")), parse_number(decimal(row["stop"] or ""))
        except ValueError:
            raise RunFileError(f"line {number}: bad start/stop value", source) from None
        if by_rows:
            if run is None:
                raise RunFileError(f"line {number}: row windows need the run {name}", source)
            if not first < last:
                raise RunFileError(f"line {number}: stop_row must be after start_row", source)
            if not 0 <= first < last < run.time.size:
                raise RunFileError(f"line {number}: rows {first}-{last} outside the run (rows 0-{run.time.size - 1})",
                                   source)
            windows.append(Window(name, float(run.time[first]), float(run.time[last]),
                                  first, last + 1, "from windows file"))
            continue
        for value, label in ((begin, "start"), (finish, "stop")):
            if not np.isfinite(value):
                raise RunFileError(f"line {number}: {label} time is {value} (not a finite number of seconds)",
                                   source)
        if not finish > begin:
            raise RunFileError(f"line {number}: stop must be after start", source)
        first, stop = -1, -1
        if run is not None:
            first = int(np.searchsorted(run.time, begin))
            stop = int(np.searchsorted(run.time, finish, side="right"))
        windows.append(Window(name, begin, finish, first, stop, "from windows file"))
    if not rows:
        raise RunFileError("the windows file has no windows", source)
    if not windows:
        named = sorted({run_name(row[key] or "") for row in rows})
        raise RunFileError(f"no window names one of the runs given (it names {_listed(named)}; "
                           f"the runs are {_listed(sorted(known))})", source)
    return tuple(windows)


def _listed(names: Sequence[str], shown: int = 3) -> str:
    """Return a short list of names for an error message."""
    more = f" and {len(names) - shown} more" if len(names) > shown else ""
    return ", ".join(names[:shown]) + more


def _row_number(text: str | None) -> int:
    """Read a data row number: ASCII digits (int() also reads Unicode digits and underscores).

    Raises
    ------
    ValueError
        If `text` is missing (a short line) or not an integer.
    """
    try:
        return parse_integer(text or "")
    except ValueError:
        raise ValueError(f"not a row number: {text!r}") from None


def write_windows(path: str | Path, windows: Sequence[Window]) -> None:
    """Write windows as CSV (run, start, stop [s], start_row, stop_row, reason), atomically.

    Parameters
    ----------
    path : str or Path
        The CSV file to write (which :func:`read_windows` reads back).
    windows : sequence of Window
        The windows.

    Returns
    -------
    None
        The file is written.
    """
    lines = ["run,start,stop,start_row,stop_row,reason"]
    for w in windows:
        reason = w.reason.replace('"', "'")
        lines.append(f'{w.run},{w.start:.6g},{w.stop:.6g},{w.start_index},{w.stop_index - 1},'
                     f'"{reason}"')
    write_text_atomic(path, "\n".join(lines) + "\n")




@dataclass(frozen=True)
class WindowMatch:
    """How one reference window is covered by the found windows.

    Attributes
    ----------
    reference : Window
        The reference window.
    found : Window or None
        The found window overlapping it most, if any overlaps by at least the threshold.
    overlap : float
        Overlap of the two [s] (0 without a match).
    coverage : float
        Overlap as a fraction of the reference window.
    agreement : float
        Overlap as a fraction of the shorter of the two windows.
    """

    reference: Window
    found: Window | None
    overlap: float
    coverage: float
    agreement: float


@dataclass(frozen=True)
class WindowComparison:
    """Found windows against reference windows.

    Attributes
    ----------
    matches : tuple of WindowMatch
        One per reference window, in the reference order.
    extra : tuple of Window
        Found windows that match no reference window.
    """

    matches: tuple[WindowMatch, ...]
    extra: tuple[Window, ...]

    @property
    def matched(self) -> int:
        """Number of reference windows with a match."""
        return sum(match.found is not None for match in self.matches)

    @property
    def unmatched(self) -> tuple[Window, ...]:
        """Reference windows without a match."""
        return tuple(match.reference for match in self.matches if match.found is None)


def compare_windows(
    found: Sequence[Window], reference: Sequence[Window], min_agreement: float = 0.5
) -> WindowComparison:
    """Match found windows to reference windows of the same run.

    A reference window is matched by the found window that overlaps it most, provided the
    overlap is at least `min_agreement` of the shorter of the two (so a found window that
    stops earlier than the reference, or starts later, still matches it when it lies mostly
    inside).

    Parameters
    ----------
    found, reference : sequence of Window
        The two sets (any runs; only windows of the same run are compared).
    min_agreement : float
        Smallest overlap, as a fraction of the shorter window.

    Returns
    -------
    WindowComparison
        Each reference window's match (or none) and the found windows that match no reference.
    """
    matches = []
    used: set[int] = set()
    for ref in reference:
        best, best_overlap = None, 0.0
        for index, window in enumerate(found):
            if window.run != ref.run:
                continue
            overlap = min(ref.stop, window.stop) - max(ref.start, window.start)
            shorter = min(ref.duration, window.duration)
            if overlap > best_overlap and shorter > 0 and overlap >= min_agreement * shorter:
                best, best_overlap = index, overlap
        if best is None:
            matches.append(WindowMatch(ref, None, 0.0, 0.0, 0.0))
            continue
        used.add(best)
        window = found[best]
        matches.append(WindowMatch(
            ref, window, best_overlap, best_overlap / ref.duration if ref.duration else 1.0,
            best_overlap / min(ref.duration, window.duration),
        ))
    extra = tuple(window for index, window in enumerate(found) if index not in used)
    return WindowComparison(tuple(matches), extra)
