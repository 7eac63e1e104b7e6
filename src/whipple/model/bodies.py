"""Rigid bodies of a bicycle in the benchmark frame: combining them, and point wheels.

A body is symmetric about the bicycle's xz plane: its mass, its mass centre (x forward of the
rear contact, z down) and its inertia tensor about the mass centre (``xx``, ``yy``, ``zz`` and
the tensor element ``xz``, as in Meijaard et al. 2007, where the whole bicycle's
``ITxz = IBxz - mB xB zB + ...``). Combining bodies adds masses and moves inertias to the
common mass centre (parallel axes).

A **point wheel** has radius zero (the two-mass-skate bicycle of Kooijman et al. 2011, Science
332, 339-342: skates instead of wheels). Its spin rate ``-v / r`` is unbounded, so it must
carry no spin inertia (``Iyy = 0``); then its gyroscopic coefficient ``Iyy / r`` is zero in
the limit and the wheel is, for the linear model, a body at its contact point that moves with
the frame it is mounted in (its inertia tensor is symmetric about the axle, so the spin does
not change it). :func:`fold_point_wheels` therefore moves a point wheel's mass and inertia into
its frame (rear wheel into the rear frame, front wheel into the front frame) and leaves a
massless wheel of unit radius, which contributes nothing: the linear equations depend on a
wheel's radius r only through ``m r``, ``m r^2`` and ``Iyy / r``. This is exact, not a small
radius; the generated code, which divides by the radii, can then evaluate the limit.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

#: Benchmark parameters of each wheel and of the frame its point-wheel limit folds into.
WHEEL_FRAMES = {"R": "B", "F": "H"}


@dataclass(frozen=True)
class Body:
    """Mass [kg], mass centre x, z [m] and inertia about it [kg m^2]; fields may be arrays."""

    mass: Any
    x: Any
    z: Any
    xx: Any
    yy: Any
    zz: Any
    xz: Any


def frame_body(parameters: Mapping[str, Any], letter: str) -> Body:
    """Return body `letter` (``B``, ``H``, or ``G``/``S`` of a split front frame).

    ``I<letter>yy`` may be absent (it does not enter the linear model); it is then NaN.
    """
    p = parameters
    return Body(p[f"m{letter}"], p[f"x{letter}"], p[f"z{letter}"], p[f"I{letter}xx"],
                p.get(f"I{letter}yy", np.nan), p[f"I{letter}zz"], p[f"I{letter}xz"])


def wheel_body(parameters: Mapping[str, Any], letter: str) -> Body:
    """Return wheel `letter` (``R`` or ``F``): at its centre, ``zz = xx``, no product of inertia."""
    p = parameters
    x = 0.0 if letter == "R" else p["w"]
    return Body(p[f"m{letter}"], x, -np.asarray(p[f"r{letter}"]), p[f"I{letter}xx"], p[f"I{letter}yy"],
                p[f"I{letter}xx"], 0.0)


def combine(*bodies: Body) -> Body:
    """Return the body made of `bodies` rigidly joined (arrays broadcast).

    Where the total mass is zero the mass centre is the first body's (it carries no weight).
    """
    mass = sum(np.asarray(b.mass, dtype=float) for b in bodies)
    safe = np.where(mass > 0, mass, 1.0)
    x = np.where(mass > 0, sum(b.mass * np.asarray(b.x, dtype=float) for b in bodies) / safe, bodies[0].x)
    z = np.where(mass > 0, sum(b.mass * np.asarray(b.z, dtype=float) for b in bodies) / safe, bodies[0].z)
    xx = sum(b.xx + b.mass * (b.z - z) ** 2 for b in bodies)
    yy = sum(b.yy + b.mass * ((b.x - x) ** 2 + (b.z - z) ** 2) for b in bodies)
    zz = sum(b.zz + b.mass * (b.x - x) ** 2 for b in bodies)
    xz = sum(b.xz - b.mass * (b.x - x) * (b.z - z) for b in bodies)
    return Body(mass, x, z, xx, yy, zz, xz)


def point_wheels(parameters: Mapping[str, ArrayLike]) -> dict[str, NDArray[np.bool_]]:
    """Which wheels are point wheels (radius exactly zero), by wheel letter ``R``/``F``."""
    return {wheel: np.asarray(parameters[f"r{wheel}"]) == 0 for wheel in WHEEL_FRAMES}


def fold_point_wheels(parameters: Mapping[str, ArrayLike]) -> dict[str, Any]:
    """Return parameters whose linear model equals the point-wheel limit (see the module notes).

    Where ``rR = 0`` (or ``rF = 0``) the wheel's mass and inertia join the rear (front) frame at
    the contact point and the wheel becomes massless with unit radius; elsewhere nothing
    changes. Arrays broadcast; other keys are passed through. The wheel's spin inertia must be
    zero (checked by :func:`whipple.model.parameter_set.validate`); it is dropped.
    """
    result: dict[str, Any] = dict(parameters)
    for wheel, frame in WHEEL_FRAMES.items():
        point = np.asarray(parameters[f"r{wheel}"]) == 0
        if not np.any(point):
            continue
        joined = combine(frame_body(parameters, frame), wheel_body(parameters, wheel))
        for field, value in (("m", joined.mass), ("x", joined.x), ("z", joined.z)):
            result[f"{field}{frame}"] = np.where(point, value, parameters[f"{field}{frame}"])
        for axes in ("xx", "yy", "zz", "xz"):
            key = f"I{frame}{axes}"
            if key in parameters:
                result[key] = np.where(point, getattr(joined, axes), parameters[key])
        for key, value in ((f"r{wheel}", 1.0), (f"m{wheel}", 0.0), (f"I{wheel}xx", 0.0), (f"I{wheel}yy", 0.0)):
            result[key] = np.where(point, value, parameters[key])
    return result


def folded_parameters(parameters: Mapping[str, float]) -> tuple[str, ...]:
    """Names whose values :func:`fold_point_wheels` replaces for one parameter set.

    A point wheel's own parameters, and its frame's when the wheel has mass or inertia to add.
    """
    names: list[str] = []
    for wheel, frame in WHEEL_FRAMES.items():
        if parameters[f"r{wheel}"] != 0:
            continue
        names += [f"r{wheel}", f"m{wheel}", f"I{wheel}xx", f"I{wheel}yy"]
        if parameters[f"m{wheel}"] != 0 or parameters[f"I{wheel}xx"] != 0:
            names += [f"m{frame}", f"x{frame}", f"z{frame}"] + [f"I{frame}{a}" for a in ("xx", "zz", "xz")]
    return tuple(names)
