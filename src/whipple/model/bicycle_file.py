"""Reading and writing bicycle files in TOML (parameter-file spec).

The format rules are strict: numbers only and never evaluated, no unknown keys, every error a
one-line BicycleFileError naming the file. Physical checks follow reading
(:func:`whipple.model.parameter_set.check_physical`, a ParameterError naming the file). Import the
public functions from :mod:`whipple.model.parameters`; BicycleParameters' text files are read by
:mod:`whipple.model.benchmark_text`.
"""

from __future__ import annotations

import dataclasses
import datetime
import difflib
import os
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import tomli_w

from whipple import __version__
from whipple.atomic import refuse_input_overwrite, write_text_atomic
from whipple.errors import BicycleFileError
from whipple.input_files import read_small_file
from whipple.model.linear_terms import TERM_NAMES, LinearTerms
from whipple.model.parameter_set import (
    CONTROLLER_STATES,
    OPTIONAL_PARAMETERS,
    PARAMETER_NAMES,
    Bicycle,
    Controller,
    Extensions,
    Payload,
    TyreCompliance,
    check_physical,
)


def _kind(value: object) -> str:
    """Return the TOML name of a value's type, for error messages."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        return "a number"
    if isinstance(value, str):
        return f"a string ({value[:30]!r})"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, datetime.date | datetime.time):
        return "a date/time"
    return type(value).__name__


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


@dataclass(frozen=True)
class StrictTable:
    """One table of a bicycle file, with what is needed to name it in an error.

    Attributes
    ----------
    values : Mapping
        The table's keys and values as parsed.
    where : str
        How to name the table in a message, e.g. ``"[parameters]"`` or ``"the top level"``.
    source : str
        The file (or built-in name) the table was read from.
    """

    values: Mapping[str, Any]
    where: str
    source: str

    def error(self, message: str) -> BicycleFileError:
        """Return a BicycleFileError for this file."""
        return BicycleFileError(message, self.source)

    def check_keys(self, allowed: Iterable[str], required: Iterable[str] = ()) -> None:
        """Raise BicycleFileError on the first unknown key or on missing required keys."""
        allowed = tuple(allowed)
        for key in self.values:
            if key not in allowed:
                raise self.error(f"unknown key {key!r} in {self.where}{_suggestion(key, allowed)}")
        missing = [key for key in required if key not in self.values]
        if missing:
            plural = "s" if len(missing) > 1 else ""
            raise self.error(f"missing key{plural} in {self.where}: {', '.join(missing)}")

    def table(self, key: str) -> StrictTable | None:
        """Return the subtable `key`, or None when absent; an error if it is not a table."""
        if key not in self.values:
            return None
        value = self.values[key]
        where = f"[{key}]" if self.where.startswith("the") else f"{self.where[:-1]}.{key}]"
        if not isinstance(value, dict):
            raise self.error(f"{where} must be a table, got {_kind(value)}")
        return StrictTable(value, where, self.source)

    def number(self, key: str) -> float:
        """Return the number under `key` (integers become floats; booleans are not numbers)."""
        value = self.values[key]
        if not _is_number(value):
            raise self.error(f"{key!r} in {self.where} must be a number, got {_kind(value)}")
        return self._float(key, value)

    def numbers(self, key: str) -> tuple[float, ...]:
        """Return a non-empty array of numbers under `key` (a single number is a one-element array)."""
        value = self.values[key]
        if _is_number(value):
            return (self._float(key, value),)
        if not isinstance(value, list) or not value or not all(map(_is_number, value)):
            raise self.error(
                f"{key!r} in {self.where} must be a non-empty array of numbers, got {_kind(value)}"
            )
        return tuple(self._float(key, item) for item in value)

    def _float(self, key: str, value: float) -> float:
        # TOML integers are unbounded; beyond about 1.8e308 they have no float.
        try:
            return float(value)
        except OverflowError:
            raise self.error(f"{key!r} in {self.where} is too large a number ({len(str(abs(int(value))))} "
                             "digits)") from None

    def string(self, key: str, default: str = "") -> str:
        """Return the string under `key`, or `default` when absent."""
        value = self.values.get(key, default)
        if not isinstance(value, str):
            raise self.error(f"{key!r} in {self.where} must be a string, got {_kind(value)}")
        return value


def _suggestion(key: str, allowed: tuple[str, ...]) -> str:
    by_case = [name for name in allowed if name.lower() == key.lower()]
    close = by_case or difflib.get_close_matches(key, allowed, n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def read_text(path: str | os.PathLike[str]) -> str:
    """Return a text file's content; any failure is a one-line BicycleFileError.

    At most :data:`whipple.input_files.MAX_SMALL_FILE_BYTES` are read (a device or an endless
    pipe is refused, not read to the end).
    """
    data = read_small_file(path, "bicycle file", BicycleFileError)
    try:
        return data.decode("utf-8-sig")  # tolerate a byte-order mark
    except UnicodeDecodeError:
        raise BicycleFileError("not a UTF-8 text file", os.fspath(path)) from None


def parse_toml(text: str, source: str) -> StrictTable:
    """Parse TOML text; a syntax error becomes a one-line BicycleFileError naming `source`."""
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        # The message already ends with "(at line L, column C)".
        raise BicycleFileError(f"TOML syntax error: {error}", source) from None
    return StrictTable(document, "the top level", source)


def _read_toml(path: str | os.PathLike[str]) -> StrictTable:
    """Read and parse a TOML file; any failure is a one-line BicycleFileError."""
    return parse_toml(read_text(path), str(path))


def _write_toml(document: Mapping[str, Any], path: str | os.PathLike[str], header: str) -> None:
    """Write `document` as TOML atomically, preceded by `header` as comment lines.

    Floats are written with ``repr`` precision (by tomli_w), so reading them back is exact.
    """
    comments = "".join(f"# {line}\n".replace("# \n", "#\n") for line in header.splitlines())
    write_text_atomic(Path(path), comments + "\n" + tomli_w.dumps(document))


_REQUIRED = tuple(name for name in PARAMETER_NAMES if name not in OPTIONAL_PARAMETERS)
_TOP_LEVEL = ("name", "description", "parameters", "uncertainty", "extensions", "controller")
_EXTENSION_SCALARS = ("steer_damping", "steer_inertia", "speed_scale", "reflected_steer_inertia", "steer_friction")
_PAYLOADS = ("payload", "front_payload")
_CONTROLLER_SCALARS = ("gain_scale", "delay", "lag")


def read_bicycle_toml(path: str | os.PathLike[str]) -> Bicycle:
    """Read a bicycle TOML file (the name defaults to the file's stem).

    Parameters
    ----------
    path : str or os.PathLike
        The TOML bicycle file.

    Returns
    -------
    Bicycle
        The bicycle, with its uncertainty, extensions and controller.

    Raises
    ------
    BicycleFileError
        Unreadable file, TOML syntax error, unknown or missing key, value of the wrong type.
    ParameterError
        The values are not physically possible (see :func:`check_physical`).
    """
    return bicycle_from_toml(_read_toml(path), Path(path).stem)


def bicycle_from_toml(document: StrictTable, default_name: str) -> Bicycle:
    """Build and check a bicycle from a parsed TOML document (see :func:`parse_toml`)."""
    document.check_keys(_TOP_LEVEL, required=("parameters",))
    bicycle = Bicycle(
        _numbers(document.table("parameters"), PARAMETER_NAMES, _REQUIRED),
        name=document.string("name", default_name),
        description=document.string("description"),
        uncertainty=_numbers(document.table("uncertainty"), PARAMETER_NAMES),
        extensions=_read_extensions(document.table("extensions")),
        controller=_read_controller(document.table("controller")),
        source=document.source,
    )
    check_physical(bicycle)
    return bicycle


def _numbers(
    table: StrictTable | None, allowed: tuple[str, ...], required: tuple[str, ...] = ()
) -> dict[str, float]:
    if table is None:
        return {}
    table.check_keys(allowed, required)
    return {key: table.number(key) for key in allowed if key in table.values}


def _read_extensions(table: StrictTable | None) -> Extensions:
    if table is None:
        return Extensions()
    table.check_keys((*_EXTENSION_SCALARS, *_PAYLOADS, "tyre_compliance", "linear_terms"))
    scalars = {key: table.number(key) for key in _EXTENSION_SCALARS if key in table.values}
    payloads = {}
    for key in _PAYLOADS:
        payload_table = table.table(key)
        if payload_table is not None:
            payloads[key] = Payload(**_numbers(payload_table, ("mass", "x", "z"), ("mass", "x", "z")))
    tyre_table = table.table("tyre_compliance")
    tyre = None
    if tyre_table is not None:
        names = tuple(f.name for f in dataclasses.fields(TyreCompliance))
        tyre = TyreCompliance(**_numbers(tyre_table, names, names[:3]))
    terms_table = table.table("linear_terms")
    terms = LinearTerms.from_mapping(_numbers(terms_table, TERM_NAMES)) if terms_table is not None else None
    return Extensions(**scalars, payload=payloads.get("payload"), front_payload=payloads.get("front_payload"),
                      tyre_compliance=tyre, linear_terms=terms)


def _read_controller(table: StrictTable | None) -> Controller:
    if table is None:
        return Controller()
    table.check_keys(("steer", "roll", *_CONTROLLER_SCALARS))
    gains: dict[str, Any] = {}
    for row in ("steer", "roll"):
        sub = table.table(row)
        if sub is not None:
            sub.check_keys(CONTROLLER_STATES)
            gains[row] = {s: sub.numbers(s) for s in CONTROLLER_STATES if s in sub.values}
    scalars = {key: table.number(key) for key in _CONTROLLER_SCALARS if key in table.values}
    if scalars and not gains:
        verb = "acts" if len(scalars) == 1 else "act"
        raise table.error(f"{', '.join(scalars)} in {table.where} {verb} on the controller's torque: "
                          "give its gains in [controller.steer] or [controller.roll]")
    return Controller(**gains, gain_scale=scalars.get("gain_scale", 1.0), delay=scalars.get("delay", 0.0),
                      lag=scalars.get("lag", 0.0))


def _state_order(state: str) -> tuple[int, str]:
    known = state in CONTROLLER_STATES
    return (CONTROLLER_STATES.index(state) if known else len(CONTROLLER_STATES), state)


def write_bicycle_toml(bicycle: Bicycle, path: str | os.PathLike[str]) -> None:
    """Write a bicycle as TOML, atomically; reading it back gives an equal Bicycle.

    Uncertainty, extensions and controller tables are written only when not empty or default.
    The file the bicycle was read from (its ``source``) is never overwritten.

    Parameters
    ----------
    bicycle : Bicycle
        The bicycle to write.
    path : str or os.PathLike
        The file to write.

    Returns
    -------
    None
        The file is written (atomically: a failed write leaves an existing file as it was).
    """
    if bicycle.source:
        refuse_input_overwrite(Path(path), [bicycle.source])
    document: dict[str, Any] = {}
    if bicycle.name:
        document["name"] = bicycle.name
    if bicycle.description:
        document["description"] = bicycle.description
    order = [*PARAMETER_NAMES, *(k for k in bicycle.parameters if k not in PARAMETER_NAMES)]
    document["parameters"] = {k: bicycle.parameters[k] for k in order if k in bicycle.parameters}
    if bicycle.uncertainty:
        document["uncertainty"] = {
            k: bicycle.uncertainty[k] for k in order if k in bicycle.uncertainty
        }
    if not bicycle.extensions.is_base():
        extensions: dict[str, Any] = {}
        for f in dataclasses.fields(Extensions):
            value = getattr(bicycle.extensions, f.name)
            if isinstance(value, Payload | TyreCompliance):
                extensions[f.name] = dataclasses.asdict(value)
            elif isinstance(value, LinearTerms):
                extensions[f.name] = value.as_dict()
            elif value != f.default and value is not None:
                extensions[f.name] = value
        document["extensions"] = extensions
    controller = bicycle.controller
    if not controller.is_empty():
        rows = (("steer", controller.steer), ("roll", controller.roll))
        document["controller"] = {
            row: {s: list(gains[s]) for s in sorted(gains, key=_state_order)}
            for row, gains in rows
            if gains
        }
        for f in dataclasses.fields(Controller):
            if f.name in _CONTROLLER_SCALARS and getattr(controller, f.name) != f.default:
                document["controller"][f.name] = getattr(controller, f.name)
    header = (
        f"Bicycle parameter file written by whipple {__version__}.\n"
        "Parameters in the benchmark form of Meijaard et al. (2007), SI units."
    )
    _write_toml(document, path, header)
