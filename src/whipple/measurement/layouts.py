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
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from whipple.errors import RunFileError

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
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as error:
        known = ", ".join(builtin_layouts())
        raise RunFileError(
            f"cannot read layout file ({error.strerror or error}); built-in layouts: {known}", path
        ) from None
    return parse_layout(text, path.stem, path)


def parse_layout(text: str, name: str, source: str | Path) -> RunLayout:
    """Parse the TOML text of a layout; errors name `source`."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise RunFileError(f"bad layout file: {error}", source) from None

    def fail(problem: str) -> RunFileError:
        return RunFileError(f"bad layout file: {problem}", source)

    known = {"name", "description", "delimiter", "header", "names", "comment", "sample_rate",
             "detect", "ignore", "columns", "scale", "extra", "speed", "metadata"}
    unknown = sorted(set(data) - known)
    if unknown:
        raise fail(f"unknown key(s) {', '.join(unknown)}")
    columns = _string_table(data.get("columns", {}), "columns", fail)
    if not columns:
        raise fail("[columns] must map at least one file column")
    for target in columns.values():
        if target not in SPEC_COLUMNS:
            raise fail(f"[columns] target '{target}' is not a run-file column "
                       f"({', '.join(SPEC_COLUMNS)})")
    if "roll_rate" not in columns.values():
        raise fail("no column maps to roll_rate")
    scale = data.get("scale", {})
    if not isinstance(scale, dict) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) and v != 0 for v in scale.values()
    ):
        raise fail("[scale] must map column names to non-zero numbers")
    delimiter = data.get("delimiter", ",")
    if not isinstance(delimiter, str) or not (len(delimiter) == 1 or delimiter == "whitespace"):
        raise fail("delimiter must be one character or \"whitespace\"")
    sample_rate = data.get("sample_rate")
    if sample_rate is not None and (
        not isinstance(sample_rate, int | float) or isinstance(sample_rate, bool) or sample_rate <= 0
    ):
        raise fail("sample_rate must be a positive number [Hz]")
    header = data.get("header", True)
    names = data.get("names", [])
    if not isinstance(header, bool) or not isinstance(names, list):
        raise fail("header must be true/false and names a list of strings")
    if not header and not names:
        raise fail("a layout without header line needs names = [...]")
    speed = data.get("speed", {})
    if not isinstance(speed, dict) or speed.get("source", "column") not in SPEED_SOURCES:
        raise fail(f"[speed] source must be one of {', '.join(SPEED_SOURCES)}")
    return RunLayout(
        name=str(data.get("name", name)),
        columns=columns,
        scale={str(k): float(v) for k, v in scale.items()},
        extra=_string_table(data.get("extra", {}), "extra", fail),
        ignore=tuple(str(v) for v in data.get("ignore", [])),
        delimiter=None if delimiter == "whitespace" else delimiter,
        header=header,
        names=tuple(str(v) for v in names),
        comment=str(data.get("comment", "#")),
        sample_rate=None if sample_rate is None else float(sample_rate),
        detect=str(data.get("detect", "")),
        speed=dict(speed),
        metadata={str(k): str(v) for k, v in _table(data.get("metadata", {}), "metadata", fail).items()},
        description=str(data.get("description", "")),
    )


def detect_layout(first_line: str) -> RunLayout | None:
    """Return the built-in layout whose ``detect`` prefix starts `first_line`, if any."""
    for name in builtin_layouts():
        layout = load_layout(name)
        if layout.detect and first_line.strip().startswith(layout.detect):
            return layout
    return None


def _table(value: Any, key: str, fail: Any) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise fail(f"[{key}] must be a table")
    return value


def _string_table(value: Any, key: str, fail: Any) -> dict[str, str]:
    table = _table(value, key, fail)
    if not all(isinstance(v, str) for v in table.values()):
        raise fail(f"[{key}] values must be strings")
    return {str(k): str(v) for k, v in table.items()}
