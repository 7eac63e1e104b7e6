"""BicycleParameters' text files: ``<Name>Benchmark.txt`` bicycles, and the files that are not.

A benchmark file has one ``name = value`` or ``name = value+/-uncertainty`` a line (one
standard deviation). Besides the 26 benchmark parameters, real files carry values the
symmetric Whipple model does not use but which must agree with it, and they are checked:

- ``IRzz``, ``IFzz``: a wheel's inertia about its vertical diameter, equal to ``IRxx``/``IFxx``
  for a wheel symmetric about its axle (refused where they differ: the model cannot hold it);
- ``yB``, ``yH`` (and ``yG``, ``yS``): lateral offsets of the mass centres, zero for a
  laterally symmetric bicycle (refused where not zero);
- a front frame split into the fork ``G`` and the handlebar ``S`` (``mG``, ``xG``, ``zG``,
  ``IGxx``, ``IGyy``, ``IGzz``, ``IGxz`` and the same for ``S``) beside the combined front frame
  ``H``: G and S joined must give H (a warning where they do not; the model uses H, computed
  from G and S when the file gives no H).

"Agree" means within three standard deviations of the stated uncertainties plus the rounding
of the printed digits (half a unit in the last digit of each value), both propagated to
the difference. Keys that mean nothing are still refused.

The data set's rider files (a rider's own mass and inertia, the Yeadon body model's
measurements and joint angles) are recognised and refused in one line that says what they are.
"""

from __future__ import annotations

import difflib
import math
import os
import re
from collections.abc import Callable, Mapping
from pathlib import Path

from whipple.errors import BicycleFileError, ParameterError
from whipple.model.bicycle_file import read_text
from whipple.model.bodies import Body, combine, frame_body
from whipple.model.parameter_set import OPTIONAL_PARAMETERS, PARAMETER_NAMES, Bicycle, check_physical
from whipple.number_text import UNSIGNED_DECIMAL

# A decimal number as BicycleParameters writes it (optionally nan or inf; see
# whipple.number_text), narrower than float(), which would also accept "1_0" or "infinity".
_NUMBER = rf"[+-]?(?:{UNSIGNED_DECIMAL}|nan|inf)"
_TEXT_LINE = re.compile(rf"^\s*(\w+)\s*=\s*({_NUMBER})\s*(?:\+/-\s*({_NUMBER}))?\s*$")
_REQUIRED = tuple(name for name in PARAMETER_NAMES if name not in OPTIONAL_PARAMETERS)
#: Checks pass within this many standard deviations (plus the printed rounding).
SIGMAS = 3.0
_WHEEL_ZZ = {"IRzz": "IRxx", "IFzz": "IFxx"}
_LATERAL = ("yB", "yH", "yG", "yS")
_BODY_FIELDS = ("m", "x", "z", "Ixx", "Iyy", "Izz", "Ixz")
_SPLIT = tuple(f"{f[0]}{part}{f[1:]}" for part in "GS" for f in _BODY_FIELDS)
_FRONT = tuple(f"{f[0]}H{f[1:]}" for f in _BODY_FIELDS)
_UNITS = {"m": "kg", "x": "m", "z": "m"}
#: What BicycleParameters stores for a rider: a body to add to the rear frame.
RIDER_KEYS = frozenset({"mB", "xB", "yB", "zB", "IBxx", "IByy", "IBzz", "IBxz"})
_YEADON_ANGLES = frozenset({"somersault", "somersalt", "tilt", "twist"})


def read_benchmark_txt(path: str | os.PathLike[str]) -> Bicycle:
    """Read a BicycleParameters ``<Name>Benchmark.txt`` file (see the module notes).

    Lines starting with ``#`` are comments; zero uncertainties are dropped. The bicycle's name
    is the file name without ``Benchmark.txt``; disagreements worth a warning are in its
    ``notes``.

    Parameters
    ----------
    path : str or os.PathLike
        The ``<Name>Benchmark.txt`` file.

    Returns
    -------
    Bicycle
        The bicycle, with the file's uncertainties as its ``[uncertainty]`` table.

    Raises
    ------
    BicycleFileError
        Unreadable file, a line of another form, unknown or missing keys, a rider file.
    ParameterError
        Physically impossible values, or values the symmetric Whipple model cannot hold.
    """
    source = str(path)
    text = read_text(path)
    other = _not_a_bicycle(text, Path(path).name)
    if other:
        raise BicycleFileError(other, source)
    values, sigma, rounding = parse_benchmark_text(text, source)
    _check_keys(values, source, Path(path).name)
    problems, notes = _check_redundant(values, sigma, rounding)
    if problems:
        raise ParameterError("; ".join(problems), source)
    stem = Path(path).stem
    name = stem.removesuffix("Benchmark") or stem
    parameters = {key: values[key] for key in PARAMETER_NAMES if key in values}
    uncertainty = {key: s for key, s in sigma.items() if key in PARAMETER_NAMES and s != 0.0}
    bicycle = Bicycle(parameters, name=name, uncertainty=uncertainty, source=source, notes=tuple(notes))
    check_physical(bicycle)
    return bicycle


def _resolution(number: str) -> float:
    """Half a unit in the last printed digit of a number (0 for nan and inf)."""
    mantissa, _, exponent = number.lower().partition("e")
    if not any(ch.isdigit() for ch in mantissa):
        return 0.0
    decimals = len(mantissa.partition(".")[2])
    power = int(exponent or 0) - decimals
    # Beyond the float range the value itself is infinite or zero, and refused or exact as such.
    return 0.5 * 10.0 ** power if abs(power) < 300 else 0.0


def parse_benchmark_text(text: str, source: str) -> tuple[dict[str, float], dict[str, float], dict[str, float]]:
    """Values, standard deviations and printed rounding of every ``name = value[+/-std]`` line, by name.

    Raises BicycleFileError (naming `source`) for a line of another form or a name given twice.
    """
    values: dict[str, float] = {}
    sigma: dict[str, float] = {}
    rounding: dict[str, float] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        match = _TEXT_LINE.match(line)
        if match is None:
            raise BicycleFileError(
                f"line {number}: expected 'name = value' or 'name = value+/-uncertainty', "
                f"got {line.strip()[:60]!r}", source)
        name, value, uncertainty = match.groups()
        if name in values:
            raise BicycleFileError(f"line {number}: {name!r} given twice", source)
        values[name] = float(value)
        if math.isinf(values[name]) and "inf" not in value.lower():
            raise BicycleFileError(f"line {number}: {name} = {value[:12]}... is too large a number", source)
        sigma[name] = float(uncertainty) if uncertainty is not None else 0.0
        rounding[name] = _resolution(value)
    return values, sigma, rounding


def _not_a_bicycle(text: str, file_name: str) -> str | None:
    """One line saying what a non-bicycle file of the data set is, or None."""
    keys = set()
    for line in text.splitlines():
        match = re.match(r"\s*(\w+)\s*[=:]", line)
        if match and not line.lstrip().startswith("#"):
            keys.add(match.group(1))
    wanted = "whipple reads a bicycle's benchmark parameters (BicycleParameters' <Name>Benchmark.txt)"
    if keys & _YEADON_ANGLES:
        return (f"a Yeadon configuration file (a rider's joint angles: {', '.join(sorted(keys & _YEADON_ANGLES))}, "
                f"...), not a bicycle; {wanted}")
    lengths = [key for key in keys if re.fullmatch(r"L[a-z]\d+[Lpwd]", key)]
    if "measurementconversionfactor" in keys or len(lengths) > 10:
        return (f"a Yeadon measurement file (a rider's {len(lengths)} segment lengths, perimeters, widths "
                f"and depths), not a bicycle; {wanted}")
    return None


def _check_keys(values: Mapping[str, float], source: str, file_name: str) -> None:
    """Unknown keys, rider files and missing keys, each one line naming the file."""
    allowed = (*PARAMETER_NAMES, *_WHEEL_ZZ, *_LATERAL, *_SPLIT)
    keys = set(values)
    if keys and keys <= RIDER_KEYS:
        missing = [name for name in _REQUIRED if name not in values]
        mass = f" (mB = {values['mB']:g} kg)" if "mB" in values else ""
        raise BicycleFileError(
            f"a rider file: the rider's own mass, mass centre and inertia{mass}, which BicycleParameters "
            f"adds to a bicycle's rear frame, not a bicycle; missing the other {len(missing)} benchmark "
            f"parameters ({', '.join(missing)}); give it with --rider (Python: load_bicycle(..., rider=...))", source)
    for key in values:
        if key not in allowed:
            close = difflib.get_close_matches(key, allowed, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            if file_name.endswith("Measured.txt"):
                hint = (": this is a BicycleParameters raw measurement file; whipple reads the benchmark "
                        "parameters computed from it (Parameters/<Name>Benchmark.txt)")
            raise BicycleFileError(f"unknown key {key!r} in the file{hint}", source)
    needed = [key for key in _SPLIT if not key.endswith("yy")]  # IGyy, ISyy are optional
    missing = [key for key in needed if key not in values]
    if len(missing) < len(needed) and missing:
        raise BicycleFileError(f"incomplete split front frame: missing {', '.join(missing)}", source)
    derivable = not missing and not any(key in values for key in _FRONT)
    missing = [name for name in _REQUIRED if name not in values and not (derivable and name in _FRONT)]
    if missing:
        plural = "s" if len(missing) > 1 else ""
        raise BicycleFileError(f"missing key{plural} in the file: {', '.join(missing)}", source)


def _spread(difference: Callable[[Mapping[str, float]], float], values: Mapping[str, float],
            steps: Mapping[str, float], combine_steps: Callable[[list[float]], float]) -> float:
    """Propagate per-parameter steps to a difference: each moved by its step either way."""
    effects = []
    for key, step in steps.items():
        if step and key in values:
            up, down = dict(values), dict(values)
            up[key] += step
            down[key] -= step
            effects.append(abs(difference(up) - difference(down)) / 2)
    return combine_steps(effects)


def _agrees(difference: Callable[[Mapping[str, float]], float], values: Mapping[str, float],
            sigma: Mapping[str, float], rounding: Mapping[str, float]) -> tuple[bool, float, float]:
    """Whether a difference is zero within its uncertainty; the difference and its std."""
    value = difference(values)
    std = _spread(difference, values, sigma, lambda e: math.sqrt(sum(x * x for x in e)))
    printed = _spread(difference, values, rounding, sum)
    # A relative allowance for floating-point rounding of the arithmetic itself.
    scale = 1e-9 * max((abs(values[k]) for k in values), default=1.0)
    return abs(value) <= SIGMAS * std + printed + scale, value, std


def _in_sigmas(value: float, std: float) -> str:
    return f"{abs(value) / std:.1f} std" if std > 0 else "no uncertainty stated"


def _check_redundant(values: dict[str, float], sigma: Mapping[str, float], rounding: Mapping[str, float]
                     ) -> tuple[list[str], list[str]]:
    """Problems and notes from the redundant keys; fills in H from G and S where absent."""
    problems: list[str] = []
    notes: list[str] = []
    for zz, xx in _WHEEL_ZZ.items():
        if zz in values and xx in values:
            ok, value, std = _agrees(_difference(zz, xx), values, sigma, rounding)
            if not ok:
                problems.append(f"{zz} = {values[zz]:g} differs from {xx} = {values[xx]:g} kg m^2 "
                                f"({_in_sigmas(value, std)}): the Whipple model needs wheels symmetric "
                                f"about their axle ({zz} = {xx})")
    for key in _LATERAL:
        if key in values:
            ok, value, std = _agrees(_difference(key), values, sigma, rounding)
            if not ok:
                problems.append(f"{key} = {values[key]:g} m is not zero ({_in_sigmas(value, std)}): the "
                                "Whipple model needs a laterally symmetric bicycle")
    if all(key in values for key in _SPLIT if not key.endswith("yy")):
        notes += _check_split(values, sigma, rounding)
    return problems, notes


def _difference(key: str, other: str | None = None) -> Callable[[Mapping[str, float]], float]:
    """``p[key] - p[other]`` (or ``p[key]``) as a function of the values ``p``."""
    return lambda p: p[key] - (p[other] if other is not None else 0.0)


def _split_difference(key: str, field: str) -> Callable[[Mapping[str, float]], float]:
    """G and S joined minus H, for one field of the front frame (H's key `key`)."""
    return lambda p: float(getattr(_joined(p), field)) - p[key]


def _joined(p: Mapping[str, float]) -> Body:
    parts = []
    for letter in "GS":
        values = dict(p)
        values.setdefault(f"I{letter}yy", math.nan)
        parts.append(frame_body(values, letter))
    return combine(*parts)


def _check_split(values: dict[str, float], sigma: Mapping[str, float], rounding: Mapping[str, float]
                 ) -> list[str]:
    """Fork G and handlebar S joined against the front frame H (computed when absent)."""
    fields = dict(zip(_FRONT, ("mass", "x", "z", "xx", "yy", "zz", "xz"), strict=True))
    if not any(key in values for key in _FRONT):
        joined = _joined(values)
        for key, field in fields.items():
            value = float(getattr(joined, field))
            if not math.isnan(value):
                values[key] = value
        return ["front frame H computed from the fork (G) and handlebar (S) given in the file"]
    disagree = []
    for key, field in fields.items():
        if key not in values or (field == "yy" and not all(k in values for k in ("IGyy", "ISyy"))):
            continue
        ok, value, std = _agrees(_split_difference(key, field), values, sigma, rounding)
        if not ok:
            unit = _UNITS.get(key[0], "kg m^2")
            disagree.append(f"{key} {values[key]:.6g} vs {values[key] + value:.6g} {unit} "
                            f"({_in_sigmas(value, std)})")
    if not disagree:
        return []
    return ["the fork (G) and handlebar (S) joined do not give the front frame H beyond the stated "
            f"uncertainties: {', '.join(disagree)}; the model uses the H values"]
