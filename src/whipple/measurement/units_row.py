"""Units given in a run file: a row of units under the header, or units after the column names.

Loggers and spreadsheet exports often put each column's unit on the line after the column
names (``s,deg/s,deg,km/h``). Such a row holds no number. Read as data it would stop the file
at its first cell; skipped unread it would let a roll rate in deg/s pass for rad/s. So the row
is read: a unit whipple knows is converted to the SI unit the run-file spec asks for (and
said in the run's notes), an SI unit or an empty cell is taken as it is, and a unit whipple
does not know, in a column it reads, is refused with the column named. Other loggers write the
unit after each column's name (``roll_rate (deg/s)``, ``speed [km/h]``): a run-file column so
named is read as that column, in that unit (:func:`named_units`).
"""

from __future__ import annotations

import math
import re

from whipple.errors import RunFileError
from whipple.measurement.layouts import SPEC_COLUMNS
from whipple.number_text import parse_number

_DEGREE = math.pi / 180.0
#: Factors to SI of the units each kind of spec column may be logged in (normalized spelling,
#: see :func:`_normalized`).
_FACTORS = {
    "s": {"s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6,
          "μs": 1e-6},
    "rad/s": {"rad/s": 1.0, "deg/s": _DEGREE, "dps": _DEGREE},
    "rad": {"rad": 1.0, "deg": _DEGREE},
    "m/s": {"m/s": 1.0, "km/h": 1 / 3.6, "kmh": 1 / 3.6, "kph": 1 / 3.6, "mph": 0.44704},
    "V": {"v": 1.0, "mv": 1e-3},
    "N m": {"nm": 1.0},
}
#: Cells that state no unit (a dimensionless column, a placeholder).
_NO_UNIT = frozenset({"", "-", "1", "none", "n/a", "na"})


def _normalized(text: str) -> str:
    """Return a unit's spelling reduced to one form: lower case, no brackets or spaces, ``/s`` for ``s^-1``."""
    unit = text.strip().strip("[](){}").strip().lower()
    unit = re.sub(r"[\s·*.]", "", unit)
    unit = unit.replace("°", "deg").replace("degrees", "deg").replace("degree", "deg").replace("radians", "rad")
    unit = re.sub(r"(?<=.)s\^?-1$", "/s", unit)
    return re.sub(r"/sec$", "/s", unit)


def named_units(names: list[str]) -> tuple[list[str], dict[str, str], list[str]]:
    """Return header names read as run-file columns, the units given after them, and what was renamed.

    A name that is a run-file column's but for case, blanks or hyphens for underscores, or a
    unit in brackets after it (``Roll Rate (deg/s)``, ``speed [km/h]``), becomes that column
    (``roll_rate``, ``speed``), with its unit ({"roll_rate": "deg/s", "speed": "km/h"}). Other
    names are kept as they are, as is one whose column the header already names exactly (or
    names twice).

    Returns
    -------
    names : list of str
        The header's names, renamed where they are a run-file column's.
    units : dict of str to str
        Run-file column -> the unit after its name.
    renamed : list of str
        The names renamed other than by their unit alone (``'Roll Rate' as roll_rate``), for the
        run's notes.
    """
    bare, units, renamed, taken = [], {}, [], set(names)
    for name in names:
        match = re.fullmatch(r"(.*?)\s*[\[(]([^\])]*)[\])]", name)
        base, unit = (match.group(1), match.group(2)) if match else (name, None)
        column = re.sub(r"[\s-]+", "_", base.strip().lower())
        if name in SPEC_COLUMNS or column not in SPEC_COLUMNS or column in taken:
            bare.append(name)
            continue
        taken.add(column)
        bare.append(column)
        if unit is not None:
            units[column] = unit
        if base != column:
            renamed.append(f"{base!r} as {column}")
    return bare, units, renamed


def is_units_row(cells: list[str]) -> bool:
    """Whether a row's cells (quotes removed) hold no number and some text: a row of units."""
    stated = [cell.strip() for cell in cells if cell.strip()]
    if not stated:
        return False
    for cell in stated:
        try:
            parse_number(cell)
        except ValueError:
            continue
        return False
    return True


def unit_factors(units: dict[str, str], line: int, scaled: set[str], source: str,
                 where: str = "the row of units under the header") -> tuple[dict[str, float], list[str]]:
    """Return the factors to SI of a units row's columns, and a note that says what was converted.

    Parameters
    ----------
    units : dict of str to str
        Run-file column (``roll_rate``, ...) -> its file column's cell in the units row. Columns
        outside the run-file spec (a layout's extra signals) are not looked at.
    line : int
        The row's line number, for messages.
    scaled : set of str
        Run-file columns a layout's ``[scale]`` converts: their unit cell is the layout's
        business, and is left alone.
    source : str
        The file's name, for messages.
    where : str
        What gives the units, for messages: the row under the header, or the header's names
        (``roll_rate (deg/s)``).

    Raises
    ------
    RunFileError
        A unit that is not one whipple knows for the column's quantity (a roll rate in volts).
    """
    factors: dict[str, float] = {}
    converted: list[str] = []
    for column, cell in units.items():
        if column not in SPEC_COLUMNS or column in scaled:
            continue
        unit = _normalized(cell)
        if unit in _NO_UNIT:
            continue
        si = SPEC_COLUMNS[column]
        factor = _FACTORS[si].get(unit)
        if factor is None:
            known = ", ".join(sorted(_FACTORS[si]))
            raise RunFileError(f"line {line}: {where} gives {cell.strip()!r} for {column}, "
                               f"a unit whipple does not convert (it knows {known}; a layout's [scale] converts "
                               "others)", source)
        if factor != 1.0:
            factors[column] = factor
            converted.append(f"{column} from {cell.strip()} to {si}")
    notes = [f"{where} (line {line}): converted {', '.join(converted)}"] if converted else []
    return factors, notes
