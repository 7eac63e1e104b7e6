"""Measured (or simulated) runs: reading run files into plain :class:`Run` objects.

The native format is the CSV of the run-file spec (``# key: value`` metadata lines, a header
line, SI units, Meijaard et al. 2007 signs). Other layouts are read through a layout file
(:mod:`whipple.measurement.layouts`); the logs of the steer-by-wire treadmill bicycle are recognised
by their header line. Files ending in ``.gz`` are decompressed transparently.
"""

from __future__ import annotations

import gzip
import re
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError, RunFileError
from whipple.measurement.layouts import SPEC_COLUMNS, RunLayout, detect_layout, load_layout
from whipple.measurement.speedometer import speedometer_speed
from whipple.number_text import may_hold_other_numbers, parse_number
from whipple.simulation.simulator import SimulatedRun

#: Runs shorter than this [s] are refused: they cannot hold a weave cycle (at most about 3 Hz at
#: riding speeds, 1 Hz and less below 4 m/s). Whether a longer run holds one, the fit of its
#: windows says (a cut segment of a published data set often holds just one cycle or two).
MIN_DURATION = 1.0


class Readable(Protocol):
    """A file-like location: a Path or an importlib.resources Traversable."""

    @property
    def name(self) -> str:
        """File name."""

    def read_bytes(self) -> bytes:
        """Whole content."""


@dataclass(frozen=True)
class Run:
    """One measured or simulated run.

    Attributes
    ----------
    name : str
        Name of the run (the file name without ``.gz`` and extension).
    source : str
        Path of the file it was read from.
    time : ndarray, shape (n,)
        Sample times [s], strictly increasing.
    signals : dict of str to ndarray, each shape (n,)
        Signals by run-file column name (``roll_rate`` [rad/s], ``steer_angle`` [rad], ...),
        in SI units; layouts may add extra signals under their own names.
    metadata : dict of str to str
        The file's ``# key: value`` lines and the layout's metadata.
    sample_rate : float
        Sample rate [Hz] (the median one when a time column is given).
    warnings : tuple of str
        What was ignored while reading (unknown columns, gaps: empty, NaN or non-numeric
        cells, negative speeds); never printed by the library.
    """

    name: str
    source: str
    time: NDArray[np.float64]
    signals: dict[str, NDArray[np.float64]]
    metadata: dict[str, str]
    sample_rate: float
    warnings: tuple[str, ...] = field(default=())

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.time[-1] - self.time[0])

    def speed(self) -> NDArray[np.float64]:
        """Forward speed at every sample [m/s].

        From the ``speed`` column, else from the ``speedometer`` signal (with the
        ``wheel_radius`` and ``pulses_per_revolution`` metadata), else the constant ``speed``
        metadata.
        """
        if "speed" in self.signals:
            return self.signals["speed"]
        if "speedometer" in self.signals:
            radius = _metadata_number(self.metadata, "wheel_radius", self.source)
            pulses = _metadata_number(self.metadata, "pulses_per_revolution", self.source)
            signal = self.signals["speedometer"]
            speed = np.full(self.time.shape, np.nan)
            # Each stretch between gaps on its own: crossings are not counted across a gap.
            for first, stop in contiguous(np.isfinite(signal)):
                try:
                    staircase = speedometer_speed(self.time[first:stop], signal[first:stop], radius, pulses,
                                                  source=self.source)
                except RunFileError:
                    if first == 0 and stop == signal.size:
                        raise
                    continue  # too short a stretch to hold two crossings: no speed there
                speed[first:stop] = staircase.sampled(self.time[first:stop])
            return speed
        return np.full(self.time.shape, _metadata_number(self.metadata, "speed", self.source))


def contiguous(valid: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Return the ``(first, stop)`` index ranges of the stretches where `valid` holds."""
    edges = np.diff(np.concatenate(([0], valid.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(), np.flatnonzero(edges == -1).tolist(), strict=True))


def run_from_simulation(simulated: SimulatedRun) -> Run:
    """Return the measured part of a simulated run, as if read from its run file.

    Parameters
    ----------
    simulated : SimulatedRun
        A run from :func:`whipple.simulation.simulator.simulate_run`.
    """
    return Run(name=simulated.name, source=f"<simulated {simulated.name}>", time=simulated.time,
               signals=dict(simulated.signals), metadata=dict(simulated.metadata),
               sample_rate=simulated.sample_rate)


def check_distinct_names(runs: Sequence[Run]) -> None:
    """Refuse runs sharing a name: windows files, tables and figures name a run by it."""
    names = [run.name for run in runs]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        files = " and ".join([str(run.source) for run in runs if run.name == twice[0]][:2])
        raise InputError(f"two runs are named {twice[0]} ({files}; windows and figures go by run name)")


def read_run(
    path: str | Path | Readable,
    layout: str | Path | RunLayout | None = None,
    min_duration: float = MIN_DURATION,
) -> Run:
    """Read a run file.

    Parameters
    ----------
    path : str, Path or Traversable
        The run file (native CSV, or a layout's format); ``.gz`` files are decompressed.
    layout : str, Path or RunLayout, optional
        A built-in layout name, a layout file, or a layout. By default the native format,
        unless the first line identifies a built-in layout (e.g. the sbw-treadmill logs).
    min_duration : float
        Shortest acceptable run [s].

    Raises
    ------
    RunFileError
        If the file cannot be read, misses roll_rate, time or speed information, holds text or
        infinite values in the time, roll_rate, speed or speedometer columns, has
        non-increasing times or is too short, or gives a metadata key twice. Empty and NaN
        cells are gaps (NaN), noted in the run's warnings; text in other columns too. Numbers
        are ASCII decimal text (:func:`whipple.number_text.parse_number`).
    """
    source = str(path)
    lines = _read_lines(Path(path) if isinstance(path, str | Path) else path, source)
    # Line numbers and text of the non-blank lines, kept apart: a tuple per line would cost
    # more memory than the text of a long run.
    numbers = np.flatnonzero([bool(line.strip()) for line in lines]) + 1
    content = [lines[number - 1] for number in numbers]
    del lines
    if not content:
        raise RunFileError("empty file", source)
    if layout is None:
        chosen = detect_layout(content[0])
    elif isinstance(layout, RunLayout):
        chosen = layout
    else:
        chosen = load_layout(layout)
    native = chosen is None
    active = chosen or RunLayout(name="native", columns={name: name for name in SPEC_COLUMNS})

    own, row_numbers, rows = _split_comments(numbers, content, active.comment, source)
    del content
    metadata = {**active.metadata, **own}
    if active.header:
        if not rows:
            raise RunFileError("no header line", source)
        header_line = rows[0]
        row_numbers, rows = row_numbers[1:], rows[1:]
        names = [name.strip() for name in header_line.split(active.delimiter)]
    else:
        names = list(active.names)
    if len(set(names)) != len(names):
        raise RunFileError("duplicate column names in the header", source)
    if not rows:
        raise RunFileError("no data rows", source)

    wanted = active.column_map(names)
    unknown = [n for n in names if n not in wanted and n not in active.ignore]
    warnings = [f"ignored unknown column(s): {', '.join(unknown)}"] if unknown else []
    missing = [n for n in active.columns if n not in names and not native]
    if missing:
        warnings.append(f"layout column(s) not in the file: {', '.join(missing)}")
    if "roll_rate" not in wanted.values():
        raise RunFileError("missing roll_rate column", source)

    signals, notes = _parse_columns(row_numbers, rows, names, wanted, active.delimiter, source)
    del rows
    warnings += notes
    for name, factor in active.scale.items():
        if name in signals:
            signals[name] = signals[name] * factor
    if "time" in signals and np.isnan(signals["time"]).any():
        # A sample without a time cannot be placed: drop the row (the jump is a gap).
        keep = ~np.isnan(signals["time"])
        signals = {name: values[keep] for name, values in signals.items()}
        warnings.append(f"{int((~keep).sum())} row(s) without a time value dropped")
    for name in ("roll_rate", "speed", "speedometer"):
        if name in signals and np.isnan(signals[name]).all():
            raise RunFileError(f"column {name} has no values (every cell empty or NaN)", source)
    time, sample_rate = _time_base(signals, metadata, active, len(signals["roll_rate"]), source)
    if time[-1] - time[0] < min_duration:
        raise RunFileError(
            f"run too short ({time[-1] - time[0]:.3g} s; at least {min_duration:g} s needed)", source
        )
    _check_speed_source(signals, metadata, active, source)
    speed = signals.get("speed")
    if speed is not None and np.nanmin(speed, initial=0.0) < 0:
        warnings.append(f"speed is negative in {int(np.sum(speed < 0))} sample(s): the model's forward speed is "
                        "positive, so no window there is fitted (flip the speed's sign with a layout's [scale] "
                        "if that is its convention)")
    for values in signals.values():
        values.flags.writeable = False
    time.flags.writeable = False
    return Run(
        name=run_name(getattr(path, "name", source)),
        source=source,
        time=time,
        signals=signals,
        metadata=metadata,
        sample_rate=sample_rate,
        warnings=tuple(warnings),
    )


def _split_comments(
    numbers: NDArray[np.intp], content: list[str], comment: str, source: str
) -> tuple[dict[str, str], NDArray[np.intp], list[str]]:
    """Split numbered lines into the metadata before the first row and the other rows.

    A ``<comment> key: value`` line before the header (or first data row) is metadata; any
    other comment line is skipped. A key given twice is refused: which of the two values is
    meant cannot be told, and taking the last would silently change the run (a second
    ``sample_rate`` rescales its time).

    Returns
    -------
    metadata : dict of str to str
    row_numbers : ndarray of int
        The line number of each row.
    rows : list of str
        The rows (the header line first, if any), stripped.
    """
    metadata: dict[str, str] = {}
    lines: dict[str, int] = {}
    rows: list[str] = []
    kept = np.zeros(len(content), dtype=bool)
    for position, line in enumerate(content):
        stripped = line.strip()
        if comment and stripped.startswith(comment):
            key, colon, value = stripped[len(comment):].partition(":")
            key = key.strip()
            if colon and not rows:
                number = int(numbers[position])
                if key in lines:
                    raise RunFileError(f"line {number}: metadata '{key}' given twice (first on line "
                                       f"{lines[key]})", source)
                lines[key] = number
                metadata[key] = value.strip()
            continue
        rows.append(stripped)
        kept[position] = True
    return metadata, numbers[kept], rows


def _read_lines(path: Path | Readable, source: str) -> list[str]:
    try:
        data = path.read_bytes()
    except OSError as error:
        raise RunFileError(f"cannot read file ({error.strerror or error})", source) from None
    if data[:2] == b"\x1f\x8b":
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError, zlib.error) as error:
            raise RunFileError(f"corrupt gzip data ({error})", source) from None
    try:
        return data.decode("utf-8-sig").splitlines()
    except UnicodeDecodeError:
        raise RunFileError("not a text file (invalid UTF-8)", source) from None


#: Columns whose cells must be numbers (or empty/NaN, a gap): the ones every analysis reads. A
#: cell of text in another column (a logger's status word, a controller not yet switched on)
#: only leaves a gap in that column.
_NUMERIC = ("time", "roll_rate", "speed", "speedometer")


def _parse_columns(
    row_numbers: NDArray[np.intp],
    rows: list[str],
    names: list[str],
    wanted: dict[str, str],
    delimiter: str | None,
    source: str,
) -> tuple[dict[str, NDArray[np.float64]], list[str]]:
    """Return the wanted columns as float arrays (NaN for gaps) and notes on their gaps.

    Empty and NaN cells are gaps (NaN) in any column; text is refused in the columns every
    analysis reads (:data:`_NUMERIC`), infinities too, and is a gap elsewhere. The rows are
    split ``_ROW_BLOCK`` at a time, so that the cells of a long run never all exist at once.
    """
    columns = {column: names.index(column) for column in wanted}
    values = {column: np.empty(len(rows)) for column in wanted}
    text = {column: np.zeros(len(rows), dtype=bool) for column in wanted}
    for first in range(0, len(rows), _ROW_BLOCK):
        table = [line.split(delimiter) for line in rows[first:first + _ROW_BLOCK]]
        for offset, fields in enumerate(table):
            if len(fields) != len(names):
                raise RunFileError(f"line {row_numbers[first + offset]} has {len(fields)} fields, the header has "
                                   f"{len(names)}", source)
        for column, j in columns.items():
            cells = [fields[j] for fields in table]
            block = slice(first, first + len(cells))
            values[column][block], text[column][block] = _numbers(cells)
            _refuse_bad_cells(column, wanted[column], values[column][block], text[column][block], cells,
                              row_numbers[block], source)
    signals: dict[str, NDArray[np.float64]] = {}
    notes: list[str] = []
    for column, target in wanted.items():
        column_values = values[column]
        column_values[np.isinf(column_values)] = np.nan
        gaps = np.isnan(column_values)
        if gaps.any():
            lines = [row_numbers[i] for i in np.flatnonzero(gaps)[[0, -1]]]
            kind = "empty, NaN or non-numeric" if text[column].any() else "empty or NaN"
            notes.append(f"column '{column}': {int(gaps.sum())} {kind} cell(s) (lines {lines[0]}-{lines[1]}), "
                         "read as gaps")
        signals[target] = column_values
    return signals, notes


#: Rows split into cells at a time while reading (about 100 MB of Python strings for 5 columns).
_ROW_BLOCK = 1 << 16


def _refuse_bad_cells(column: str, target: str, values: NDArray[np.float64], text: NDArray[np.bool_],
                      cells: list[str], row_numbers: NDArray[np.intp], source: str) -> None:
    """Refuse text and infinities in a column every analysis reads (:data:`_NUMERIC`)."""
    if target not in _NUMERIC:
        return
    if text.any():
        bad = int(np.argmax(text))
        raise RunFileError(f"line {row_numbers[bad]}, column '{column}': non-numeric value '{cells[bad].strip()}'",
                           source)
    infinite = np.isinf(values)
    if infinite.any():
        bad = int(np.argmax(infinite))
        raise RunFileError(f"line {row_numbers[bad]}, column '{column}': {cells[bad].strip()} value", source)


def _numbers(cells: list[str]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Cells as floats, NaN where empty or not a number; and where they held text."""
    joined = "".join(cells)
    # numpy converts as float() does, which also reads Unicode digits and underscores: a
    # column that may hold any goes cell by cell through parse_number.
    if not may_hold_other_numbers(joined):
        try:
            return np.array(cells, dtype=float), np.zeros(len(cells), dtype=bool)
        except ValueError:
            pass
    return _lenient(cells)


def _lenient(cells: list[str]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Cells as floats, NaN where empty or not a number; and where they held text."""
    values = np.full(len(cells), np.nan)
    text = np.zeros(len(cells), dtype=bool)
    for i, cell in enumerate(cells):
        cell = cell.strip()
        if not cell:
            continue
        try:
            values[i] = parse_number(cell)
        except ValueError:
            text[i] = True
    return values, text


def _time_base(
    signals: dict[str, NDArray[np.float64]],
    metadata: dict[str, str],
    layout: RunLayout,
    n: int,
    source: str,
) -> tuple[NDArray[np.float64], float]:
    if "time" in signals:
        time = signals.pop("time")
        steps = np.diff(time)
        if steps.size and not (steps > 0).all():
            bad = int(np.argmin(steps > 0)) + 1
            raise RunFileError(
                f"time is not strictly increasing at data row {bad} (t = {time[bad]:g} s)", source
            )
        if "sample_rate" in metadata:
            _metadata_number(metadata, "sample_rate", source)  # the time column rules; a bad value is still an error
        rate = float(1.0 / np.median(steps)) if steps.size else 0.0
        _check_sample_rate(rate, "from the time column; in ms or us instead of s?", source)
        return time, rate
    if "sample_rate" in metadata:
        rate = _metadata_number(metadata, "sample_rate", source)
    elif layout.sample_rate is not None:
        rate = layout.sample_rate
    else:
        raise RunFileError("no time column and no sample_rate", source)
    _check_sample_rate(rate, "from sample_rate", source)
    return np.arange(n) / rate, rate


#: Lowest sample rate [Hz] of a run: a weave of 0.5-3 Hz needs several samples per period.
MIN_SAMPLE_RATE = 10.0


def _check_sample_rate(rate: float, origin: str, source: str) -> None:
    if not rate >= MIN_SAMPLE_RATE:
        raise RunFileError(f"sample rate {rate:.3g} Hz ({origin}) is below {MIN_SAMPLE_RATE:g} Hz: too slow to "
                           "resolve the weave", source)


def _check_speed_source(
    signals: dict[str, NDArray[np.float64]],
    metadata: dict[str, str],
    layout: RunLayout,
    source: str,
) -> None:
    settings = layout.speed
    if settings.get("source") == "constant":
        if "value" not in settings:
            raise RunFileError("bad layout file: [speed] source = \"constant\" needs value", source)
        metadata.setdefault("speed", str(settings["value"]))
    for key in ("wheel_radius", "pulses_per_revolution"):
        if key in settings:
            metadata.setdefault(key, str(settings[key]))
    if "speed" in signals:
        return
    if "speedometer" in signals:
        for key in ("wheel_radius", "pulses_per_revolution"):
            _metadata_number(metadata, key, source)
        return
    if "speed" in metadata:
        _metadata_number(metadata, "speed", source)
        return
    raise RunFileError(
        "missing speed information: needs a speed column, a speedometer column with "
        "wheel_radius and pulses_per_revolution, or speed metadata", source
    )


def _metadata_number(metadata: dict[str, str], key: str, source: str) -> float:
    if key not in metadata:
        raise RunFileError(f"missing metadata '{key}'", source)
    try:
        value = parse_number(metadata[key])
    except ValueError:
        raise RunFileError(f"metadata '{key}' is not a number: '{metadata[key]}'", source) from None
    if not np.isfinite(value) or value <= 0:
        raise RunFileError(f"metadata '{key}' must be positive, got {metadata[key]}", source)
    return value


def run_name(file_name: str) -> str:
    """Return the name of the run in a file: its name without folder, ``.gz`` and extension.

    Only a short alphabetic extension is removed (``.csv``, ``.log``), so names with dots in
    them (``..._12.6kph``) survive.
    """
    name = Path(file_name.strip()).name
    if name.endswith(".gz"):
        name = name[:-3]
    return re.sub(r"\.[A-Za-z]{1,4}$", "", name)
