"""Layouts: small TOML files that describe how a foreign run file maps onto the run-file spec.

Users describe their data instead of converting it. A layout file looks like this (every key
is optional except ``[columns]``)::

    name = "my-logger"
    description = "Lab logger, 200 Hz, degrees"
    delimiter = ","             # one character, or "whitespace"
    header = true               # the first non-comment line names the columns
    names = ["a", "b"]          # the column names when header = false
    comment = "#"               # lines starting with this are skipped ("# key: value" is metadata)
    sample_rate = 200.0         # Hz, needed when no column maps to "time"
    detect = "t_ms;gyro_x;"     # a file whose first line starts with this uses the layout
    ignore = ["checksum"]       # file columns dropped without a warning

    [columns]                   # file column -> run-file column (roll_rate, steer_angle, ...)
    gyro_x = "roll_rate"
    t_ms = "time"

    [scale]                     # run-file column -> factor that gives SI units (and signs)
    roll_rate = 0.017453292519943295   # deg/s -> rad/s; use a negative factor to flip a sign
    time = 0.001

    [extra]                     # file column -> name of an extra signal, kept as is (scaled if
    acc_y = "lateral_acceleration"     # [scale] names it)

    [speed]                     # where the forward speed comes from (default: what the file has)
    source = "column"           # "column": a column maps to speed; "speedometer": a column maps
                                # to speedometer; "constant": the value below
    value = 4.2                 # m/s, for source = "constant"
    wheel_radius = 0.35         # m, for source = "speedometer"
    pulses_per_revolution = 20

    [metadata]                  # extra metadata for every run read with this layout
    bicycle = "my-bicycle"

Built-in layouts live in ``whipple/data/layouts/<name>.toml``.

A layout is checked when it is loaded, so that a mistake in it is reported against the layout
file rather than against the run read with it: two file columns mapped to one signal, a
``[scale]`` key the layout does not map or a factor that is zero or not finite, and a sample
rate, speed value, wheel radius or pulse count that is not a finite positive number are
refused.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from whipple.errors import RunFileError
from whipple.input_files import read_small_file
from whipple.number_text import parse_number

#: Columns of the run-file spec, with their SI units.
SPEC_COLUMNS = {
    "time": "s",
    "roll_rate": "rad/s",
    "yaw_rate": "rad/s",
    "steer_angle": "rad",
    "steer_rate": "rad/s",
    "roll_angle": "rad",
    "speed": "m/s",
    "speedometer": "V",
    "steer_torque": "N m",
    "battery": "V",
}

SPEED_SOURCES = ("column", "speedometer", "constant")

#: Characters that cannot separate the cells of a table: line ends, and the characters of numbers.
_NOT_DELIMITERS = frozenset("\r\n0123456789.+-eE")
#: Top-level keys of a layout file.
_KEYS = frozenset({"name", "description", "delimiter", "header", "names", "comment", "sample_rate",
                   "detect", "ignore", "columns", "scale", "extra", "speed", "metadata"})

#: Keys of the ``[speed]`` table that hold a positive number.
_SPEED_NUMBERS = ("value", "wheel_radius", "pulses_per_revolution")

#: Metadata keys the reader turns into positive numbers (see ``runs._metadata_number``): checked
#: in a layout's ``[metadata]`` so that a bad value there is blamed on the layout, not the run.
_NUMERIC_METADATA = ("sample_rate", "wheel_radius", "pulses_per_revolution", "speed")

#: Builds the ``bad layout file: ...`` error of the layout being parsed.
Failure = Callable[[str], RunFileError]


@dataclass(frozen=True)
class RunLayout:
    """How to read a run file whose layout is not the native one.

    Attributes
    ----------
    name : str
        Name of the layout (the built-in name or the file stem).
    columns : dict of str to str
        File column -> run-file spec column.
    scale : dict of str to float
        Output column -> factor applied to the file values (to SI units and spec signs).
    extra : dict of str to str
        File column -> name of an extra signal to keep.
    ignore : tuple of str
        File columns dropped silently.
    delimiter : str or None
        Field separator; None means any whitespace.
    header : bool
        Whether the first non-comment line holds the column names.
    names : tuple of str
        Column names when there is no header line.
    comment : str
        Comment prefix.
    sample_rate : float or None
        Sample rate [Hz] when the file has no time column.
    detect : str
        Prefix of a file's first line that identifies this layout ("" = never auto-detected).
    speed : dict
        Speed source (see the module docstring).
    metadata : dict of str to str
        Metadata added to every run.
    """

    name: str
    columns: dict[str, str]
    scale: dict[str, float] = field(default_factory=dict)
    extra: dict[str, str] = field(default_factory=dict)
    ignore: tuple[str, ...] = ()
    delimiter: str | None = ","
    header: bool = True
    names: tuple[str, ...] = ()
    comment: str = "#"
    sample_rate: float | None = None
    detect: str = ""
    speed: dict[str, Any] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)
    description: str = ""

    def column_map(self, names: list[str]) -> dict[str, str]:
        """File column -> run-file column, for a file whose columns are `names`.

        The ``[columns]`` and ``[extra]`` entries; and a file column literally named ``time``
        is the time when no entry maps a column to it (nor names it in ``extra`` or ``ignore``):
        a layout need not say that ``time`` means time.
        """
        wanted = {name: self.columns[name] for name in names if name in self.columns}
        wanted.update({name: self.extra[name] for name in names if name in self.extra})
        if ("time" in names and "time" not in wanted and "time" not in self.ignore
                and "time" not in self.columns.values()):
            wanted["time"] = "time"
        return wanted


def other_delimiter(header: str) -> str | None:
    """Return the tab or ``;`` that separates a header line without commas, if it holds one.

    Spreadsheets in locales with a decimal comma write ``;`` between cells, and many loggers tabs;
    run files and windows files with the spec's column names are read so without a layout.
    """
    if "," in header:
        return None
    return next((delimiter for delimiter in ("\t", ";") if delimiter in header), None)


def builtin_layouts() -> tuple[str, ...]:
    """Names of the layouts shipped with whipple."""
    folder = resources.files("whipple.data").joinpath("layouts")
    return tuple(sorted(entry.name[:-5] for entry in folder.iterdir() if entry.name.endswith(".toml")))


def load_layout(layout: str | Path) -> RunLayout:
    """Load a layout by built-in name or from a TOML file.

    Parameters
    ----------
    layout : str or Path
        A built-in name (see :func:`builtin_layouts`) or the path of a layout file.

    Raises
    ------
    RunFileError
        If the file cannot be read or does not describe a valid layout.
    """
    if isinstance(layout, str) and layout in builtin_layouts():
        entry = resources.files("whipple.data").joinpath("layouts", f"{layout}.toml")
        return parse_layout(entry.read_text(encoding="utf-8"), layout, f"layout {layout}")
    path = Path(layout)
    data = read_small_file(path, "layout file", _layout_error)
    try:
        text = data.decode("utf-8-sig")  # tolerate a byte-order mark, as bicycle files do
    except UnicodeDecodeError:
        raise RunFileError("bad layout file: not a text file (invalid UTF-8)", path) from None
    return parse_layout(text, path.stem, path)


def _layout_error(problem: str, source: str) -> RunFileError:
    """Return the error of a layout file that cannot be read (a mistyped built-in name?) or is no text."""
    if problem.startswith("cannot read"):
        return RunFileError(f"{problem.replace('file:', 'layout file:')}; built-in layouts: "
                            f"{', '.join(builtin_layouts())}", source)
    return RunFileError(f"bad layout file: {problem}", source)


def parse_layout(text: str, name: str, source: str | Path) -> RunLayout:
    """Parse the TOML text of a layout; errors name `source`.

    Raises
    ------
    RunFileError
        ``bad layout file: ...`` for invalid TOML, unknown keys, and values of the wrong type
        or out of range (see the module docstring for what each key takes).
    """
    def fail(problem: str) -> RunFileError:
        return RunFileError(f"bad layout file: {problem}", source)

    data = _toml(text, fail)
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise fail(f"unknown key(s) {', '.join(unknown)}")
    columns = _string_table(data.get("columns", {}), "columns", fail)
    extra = _string_table(data.get("extra", {}), "extra", fail)
    _check_columns(columns, extra, fail)
    delimiter = data.get("delimiter", ",")
    if not isinstance(delimiter, str) or not (len(delimiter) == 1 or delimiter == "whitespace"):
        raise fail("delimiter must be one character or \"whitespace\"")
    if delimiter in _NOT_DELIMITERS:
        raise fail(f"delimiter {delimiter!r} cannot separate numbers (a line end, or a character of numbers)")
    header = data.get("header", True)
    if not isinstance(header, bool):
        raise fail(f"header must be true or false, got {_shown(header)}")
    names = _string_list(data.get("names", []), "names", fail)
    _check_names(header, names, columns, extra, fail)
    sample_rate = data.get("sample_rate")
    if sample_rate is not None:
        sample_rate = _positive(sample_rate, "sample_rate", "a positive number [Hz]", fail)
    return RunLayout(
        name=_string(data, "name", name, fail),
        columns=columns,
        # A file column named "time" is the time without an entry (RunLayout.column_map).
        scale=_scale(data.get("scale", {}), {"time", *columns.values(), *extra.values()}, fail),
        extra=extra,
        ignore=tuple(_string_list(data.get("ignore", []), "ignore", fail)),
        delimiter=None if delimiter == "whitespace" else delimiter,
        header=header,
        names=tuple(names),
        comment=_string(data, "comment", "#", fail),
        sample_rate=sample_rate,
        detect=_string(data, "detect", "", fail),
        speed=_speed(data.get("speed", {}), fail),
        metadata=_metadata(data.get("metadata", {}), fail),
        description=_string(data, "description", "", fail),
    )


def detect_layout(first_line: str) -> RunLayout | None:
    """Return the built-in layout whose ``detect`` prefix starts `first_line`, if any."""
    for name in builtin_layouts():
        layout = load_layout(name)
        if layout.detect and first_line.strip().startswith(layout.detect):
            return layout
    return None


def _toml(text: str, fail: Failure) -> dict[str, Any]:
    """Parse the TOML text of a layout."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise fail(str(error)) from None
    except ValueError:
        # An integer of more than 4300 digits, which Python refuses to convert: tomllib lets
        # that ValueError through instead of a TOMLDecodeError.
        raise fail("an integer with too many digits to read") from None


def _shown(value: Any) -> str:
    """Return `value` for a one-line message: its repr, shortened if long (a huge integer)."""
    text = repr(value)
    if len(text) <= 40:
        return text
    if isinstance(value, int):
        return f"an integer of {len(text.lstrip('-'))} digits"
    return f"{text[:20]}... ({len(text)} characters)"


def _finite(value: Any) -> float | None:
    """Return `value` as a float if it is a finite TOML number (not a boolean), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    try:
        number = float(value)
    except OverflowError:  # an integer beyond the largest float
        return None
    return number if math.isfinite(number) else None


def _positive(value: Any, key: str, rule: str, fail: Failure) -> float:
    """Return `value` as a float if it is a finite positive number, else fail naming `key`."""
    number = _finite(value)
    if number is None or number <= 0:
        raise fail(f"{key} must be {rule}, got {_shown(value)}")
    return number


def _check_columns(columns: dict[str, str], extra: dict[str, str], fail: Failure) -> None:
    """Refuse a ``[columns]`` and ``[extra]`` mapping in which one signal would hide another."""
    if not columns:
        raise fail("[columns] must map at least one file column")
    for target in columns.values():
        if target not in SPEC_COLUMNS:
            raise fail(f"[columns] target {target!r} is not a run-file column ({', '.join(SPEC_COLUMNS)})")
    if "roll_rate" not in columns.values():
        raise fail("no column maps to roll_rate")
    # The reader keeps one array per signal name: a second file column mapped to the same name
    # would silently replace the first.
    seen: dict[str, str] = {}
    for table, mapping in (("[columns]", columns), ("[extra]", extra)):
        for column, target in mapping.items():
            if target in seen:
                raise fail(f"{table} maps file column {column!r} to {target!r}, which file column "
                           f"{seen[target]!r} already gives")
            seen[target] = column
    both = sorted(set(columns) & set(extra))
    if both:
        raise fail(f"file column {both[0]!r} is in both [columns] and [extra]")


def _check_names(header: bool, names: list[str], columns: dict[str, str], extra: dict[str, str],
                 fail: Failure) -> None:
    """Without a header line, `names` are the file's columns: they must hold every mapped one."""
    if header:
        return
    if not names:
        raise fail("a layout without header line needs names = [...]")
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise fail(f"names lists {twice[0]!r} twice")
    for column in (*columns, *extra):
        if column not in names:
            raise fail(f"file column {column!r} of [columns]/[extra] is not in names")


def _scale(value: Any, mapped: set[str], fail: Failure) -> dict[str, float]:
    """Return the ``[scale]`` table: a finite non-zero factor for signals the layout maps."""
    table = _table(value, "scale", fail)
    scale = {}
    for key, factor in table.items():
        if key not in mapped:
            raise fail(f"[scale] names {key!r}, which is no column this layout maps "
                       f"({', '.join(sorted(mapped))})")
        number = _finite(factor)
        if number is None or number == 0:
            raise fail(f"[scale] must map column names to finite non-zero numbers, got {key!r} = {_shown(factor)}")
        scale[key] = number
    return scale


def _speed(value: Any, fail: Failure) -> dict[str, Any]:
    """Return the ``[speed]`` table, its numbers checked (they become the run's metadata)."""
    speed = _table(value, "speed", fail)
    unknown = sorted(set(speed) - {"source", *_SPEED_NUMBERS})
    if unknown:
        raise fail(f"unknown key(s) in [speed]: {', '.join(unknown)}")
    source = speed.get("source", "column")
    if not isinstance(source, str) or source not in SPEED_SOURCES:
        raise fail(f"[speed] source must be one of {', '.join(SPEED_SOURCES)}")
    if source == "constant" and "value" not in speed:
        raise fail("[speed] source = \"constant\" needs value")
    for key in _SPEED_NUMBERS:
        if key in speed:
            _positive(speed[key], f"[speed] {key}", "a positive number", fail)
    return dict(speed)


def _metadata(value: Any, fail: Failure) -> dict[str, str]:
    """Return the ``[metadata]`` table as strings, checking the values read as numbers."""
    table = _table(value, "metadata", fail)
    metadata = {}
    for key, entry in table.items():
        if isinstance(entry, dict | list):
            raise fail(f"[metadata] {key!r} must be a string or a number")
        metadata[key] = str(entry)
    for key in _NUMERIC_METADATA:
        if key in table:
            entry = table[key]
            number = _text_number(entry) if isinstance(entry, str) else _finite(entry)
            if number is None or number <= 0:
                raise fail(f"[metadata] {key} must be a positive number, got {_shown(entry)}")
    return metadata


def _text_number(text: str) -> float | None:
    """Return `text` as a finite number, or None (see :func:`parse_number`)."""
    try:
        number = parse_number(text)
    except ValueError:
        return None
    return number if math.isfinite(number) else None


def _string(data: dict[str, Any], key: str, default: str, fail: Failure) -> str:
    """Return ``data[key]`` (or `default`), which must be a string."""
    value = data.get(key, default)
    if not isinstance(value, str):
        raise fail(f"{key} must be a string, got {_shown(value)}")
    return value


def _string_list(value: Any, key: str, fail: Failure) -> list[str]:
    """Return a list of strings (a lone string is refused: ``ignore = "x"`` is no list)."""
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise fail(f"{key} must be a list of strings, got {_shown(value)}")
    return list(value)


def _table(value: Any, key: str, fail: Failure) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise fail(f"[{key}] must be a table")
    return value


def _string_table(value: Any, key: str, fail: Failure) -> dict[str, str]:
    table = _table(value, key, fail)
    if not all(isinstance(v, str) for v in table.values()):
        raise fail(f"[{key}] values must be strings")
    return {str(k): str(v) for k, v in table.items()}
