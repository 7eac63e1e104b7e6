"""A rigid rider on a bicycle: BicycleParameters' rider files, and adding the rider to the rear frame.

BicycleParameters stores a rider seated on a given bicycle as the rider's own body in the
benchmark frame (``riders/<Rider>/Parameters/<Rider><Bicycle>Benchmark.txt``: ``mB``, ``xB``,
``yB``, ``zB``, ``IBxx``, ``IByy``, ``IBzz``, ``IBxz``, lines ``name = value+/-std``). In the
Whipple model the rider is rigidly attached to the rear frame, so the bicycle with its rider
has the rear frame and the rider joined into one body B (masses added, the mass centre their
weighted mean, inertias moved to it by parallel axes: :func:`whipple.model.bodies.combine`);
nothing else changes. The joined body's standard deviations follow from the stated ones of
both bodies by first-order propagation (independent inputs).
"""

from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

from whipple.errors import BicycleFileError, ParameterError
from whipple.model.benchmark_text import RIDER_KEYS, parse_benchmark_text
from whipple.model.bicycle_file import read_text
from whipple.model.bodies import Body, combine, frame_body
from whipple.model.parameter_set import Bicycle, check_physical

#: The fields of a body, in the order of :class:`whipple.model.bodies.Body`, as rear-frame keys.
_BODY_KEYS = ("mB", "xB", "zB", "IBxx", "IByy", "IBzz", "IBxz")
_REQUIRED = tuple(key for key in _BODY_KEYS if key != "IByy")  # IByy does not enter the model


@dataclass(frozen=True)
class Rider:
    """A rider's body in the benchmark frame of the bicycle it sits on.

    Attributes
    ----------
    body : Body
        Mass [kg], mass centre x, z [m] (z down) and inertia about it [kg m^2]; ``yy`` NaN
        when not given.
    name : str
        Name (BicycleParameters' file name without ``Benchmark.txt``).
    uncertainty : dict of str to float
        One standard deviation of some of ``mB, xB, zB, IBxx, IByy, IBzz, IBxz`` (their units).
    source : str
        Where the rider was read from.
    """

    body: Body
    name: str = ""
    uncertainty: dict[str, float] = field(default_factory=dict)
    source: str = ""


def read_rider_txt(path: str | os.PathLike[str]) -> Rider:
    """Read a BicycleParameters rider file (``<Rider><Bicycle>Benchmark.txt``).

    Parameters
    ----------
    path : str or os.PathLike
        The rider file.

    Returns
    -------
    Rider
        The rider's mass [kg], mass centre [m] and inertia [kg m^2] in the benchmark frame, with
        their standard deviations.

    Raises
    ------
    BicycleFileError
        Unreadable file, a line of another form, a bicycle file or another key, a missing key.
    ParameterError
        A value that is not finite, a rider off the bicycle's plane of symmetry (``yB`` not
        zero), a mass or an inertia that no body has.
    """
    source = os.fspath(path)
    values, sigma, rounding = parse_benchmark_text(read_text(path), source)
    other = sorted(set(values) - RIDER_KEYS)
    if other:
        what = "a bicycle file" if {"w", "c", "lam"} <= set(values) else "not a rider file"
        raise BicycleFileError(f"{what}: a rider file holds only {', '.join(sorted(RIDER_KEYS))}; "
                               f"found {', '.join(other[:5])}{' ...' if len(other) > 5 else ''}", source)
    missing = [key for key in _REQUIRED if key not in values]
    if missing:
        raise BicycleFileError(f"missing key{'s' if len(missing) > 1 else ''} in the rider file: "
                               f"{', '.join(missing)}", source)
    bad = [key for key, value in values.items() if not math.isfinite(value)]
    if bad:
        raise ParameterError(f"not a finite number: {', '.join(bad)}", source)
    # The symmetric model cannot hold a rider off the plane of symmetry; printed rounding of a
    # zero is not an offset.
    lateral = values.get("yB", 0.0)
    if abs(lateral) > 3.0 * sigma.get("yB", 0.0) + rounding.get("yB", 0.0):
        raise ParameterError(f"yB = {lateral:g} m: the rider sits off the bicycle's plane of symmetry, "
                             "which the symmetric Whipple model cannot hold", source)
    body = Body(values["mB"], values["xB"], values["zB"], values["IBxx"], values.get("IByy", math.nan),
                values["IBzz"], values["IBxz"])
    _check_body(body, source)
    stem = Path(source).stem
    uncertainty = {key: s for key, s in sigma.items() if key in _BODY_KEYS and s != 0.0}
    return Rider(body, stem.removesuffix("Benchmark") or stem, uncertainty, source)


def _check_body(body: Body, source: str) -> None:
    problems = []
    if not body.mass > 0:
        problems.append(f"mB = {body.mass:g} kg: a rider's mass must be positive")
    if not (body.xx > 0 and body.zz > 0 and body.xx * body.zz > body.xz ** 2):
        problems.append(f"IBxx = {body.xx:g}, IBzz = {body.zz:g}, IBxz = {body.xz:g} kg m^2: not the "
                        "inertia of a body (needs IBxx > 0, IBzz > 0 and IBxx IBzz > IBxz^2)")
    if problems:
        raise ParameterError("; ".join(problems), source)


def add_rider(bicycle: Bicycle, rider: Rider) -> Bicycle:
    """Return `bicycle` with `rider` rigidly joined to its rear frame.

    The rear frame's ``mB, xB, zB, IBxx, IBzz, IBxz`` (and ``IByy`` where both bodies give it)
    become the joined body's, with standard deviations propagated from both; extensions,
    controller and the other parameters are kept. The name becomes ``"<bicycle> + <rider>"``.

    Parameters
    ----------
    bicycle : Bicycle
        The bicycle without its rider.
    rider : Rider
        The rider (:func:`read_rider_txt`).

    Returns
    -------
    Bicycle
        A new bicycle; `bicycle` is not changed.

    Raises
    ------
    ParameterError
        When the bicycle with its rider is not physical (naming the rider's file).
    """
    inputs = {("bicycle", key): float(bicycle.parameters[key]) for key in _BODY_KEYS if key in bicycle.parameters}
    inputs.update({("rider", key): float(value) for key, value in zip(_BODY_KEYS, _fields(rider.body), strict=True)})
    sigmas = {(owner, key): (bicycle.uncertainty if owner == "bicycle" else rider.uncertainty).get(key, 0.0)
              for owner, key in inputs}
    joined = _joined(inputs)
    stds = _propagated(inputs, sigmas)
    parameters = dict(bicycle.parameters)
    uncertainty = dict(bicycle.uncertainty)
    for key, value in joined.items():
        if math.isnan(value):
            parameters.pop(key, None)
            uncertainty.pop(key, None)
            continue
        parameters[key] = value
        std = stds[key]
        if std > 0:
            uncertainty[key] = std
        else:
            uncertainty.pop(key, None)
    name = f"{bicycle.name} + {rider.name}" if bicycle.name and rider.name else bicycle.name or rider.name
    with_rider = dataclasses.replace(bicycle, parameters=parameters, uncertainty=uncertainty, name=name)
    check_physical(with_rider, rider.source or None)
    return with_rider


def _fields(body: Body) -> tuple[float, ...]:
    return tuple(float(getattr(body, f.name)) for f in dataclasses.fields(Body))


def _joined(inputs: dict[tuple[str, str], float]) -> dict[str, float]:
    """Return the rear frame joined with the rider, by key (IByy NaN unless both give it)."""
    frame = frame_body({key: value for (owner, key), value in inputs.items() if owner == "bicycle"}, "B")
    rider = Body(*(inputs[("rider", key)] for key in _BODY_KEYS))
    return dict(zip(_BODY_KEYS, _fields(combine(frame, rider)), strict=True))


def _propagated(inputs: dict[tuple[str, str], float], sigmas: dict[tuple[str, str], float]) -> dict[str, float]:
    """First-order standard deviation of each joined key (central differences, independent inputs)."""
    variance = dict.fromkeys(_BODY_KEYS, 0.0)
    for name, sigma in sigmas.items():
        if sigma <= 0 or math.isnan(inputs[name]):
            continue
        step = 1e-6 * max(abs(inputs[name]), sigma)
        up, down = dict(inputs), dict(inputs)
        up[name] += step
        down[name] -= step
        above, below = _joined(up), _joined(down)
        for key in _BODY_KEYS:
            variance[key] += ((above[key] - below[key]) / (2.0 * step) * sigma) ** 2
    return {key: math.sqrt(value) if math.isfinite(value) else 0.0 for key, value in variance.items()}
