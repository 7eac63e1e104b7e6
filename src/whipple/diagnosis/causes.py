"""Candidate causes of model error: what a cause is, and the building blocks of the loads and parameters.

A :class:`Cause` is one form of a candidate cause for one bicycle: its fitted values with units,
bounds, start and no-effect values, prior, and how they change the bicycle, so that every cause
passes through the same derived equations. The causes themselves are declared in
:mod:`whipple.diagnosis.registry`; here are the forms that need more than one line: a payload on
the rear or front frame (:func:`payload_form`) and one wrong benchmark parameter
(:func:`parameter_cause`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.priors import Prior, gross_error_prior
from whipple.model.fleet import Model
from whipple.model.parameter_set import PARAMETER_UNITS
from whipple.model.parameters import Payload

__all__ = ["DEFAULT_CAMBER_STIFFNESS", "Cause", "PAYLOAD_FRAMES", "payload_bounds", "MAX_GYRATION", "LOAD_MASS_FLOOR",
           "LOAD_MASS_SCALE", "GYRATION_SCALE", "payload_priors", "payload_form", "BLAMEABLE_PARAMETERS",
           "POSITIVE_PARAMETERS", "parameter_cause", "with_cause"]

# Reported bicycle tyre values (shared spec tyre-model.md): the camber stiffness is not fitted
# (eigenvalues barely constrain it); cornering stiffness and relaxation length are.
DEFAULT_CAMBER_STIFFNESS = 0.57  # 1/rad


@dataclass(frozen=True)
class Cause:
    """A candidate cause: how its parameters change a bicycle.

    Attributes
    ----------
    name : str
        Vocabulary name.
    parameters : tuple of str
        Names of the fitted values; ``units`` gives their units.
    start : tuple of float
        Starting values for the fit (the "no effect" value where one exists).
    bounds : tuple of (float, float)
        Physical bounds of each value.
    apply : callable
        ``apply(bicycle, values) -> Bicycle``.
    prior : float
        Prior weight: 1 for each named physical cause; the parameter causes share one unit of
        weight among themselves (a wrong parameter is one hypothesis, whichever parameter).
    null : tuple of float or None
        Values at which the cause changes nothing (None for tyre compliance, which never
        reduces exactly to knife edges).
    refines : tuple of str or None
        The values of a simpler form of the same cause that this one extends (its leading
        values): fitted among the same candidates, that form's fit starts this one
        (:func:`whipple.diagnosis.starts.refinement_starts`) instead of a search of its own;
        fitted alone, the coarse grid of starts spans those values only, the others held at
        their start (:func:`whipple.diagnosis.starts.grid_starts`).
    value_priors : tuple of Prior or None
        Each value's physical prior (:mod:`whipple.diagnosis.priors`), where the evidence is a
        marginal likelihood with priors (``DiagnosisOptions(occam="prior")``): the fit then
        finds the values' maximum a posteriori. None: no prior (the BIC's charge).
    """

    name: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    start: tuple[float, ...]
    bounds: tuple[tuple[float, float], ...]
    apply: Callable[[Model, Sequence[float]], Model]
    prior: float = 1.0
    null: tuple[float, ...] | None = None
    refines: tuple[str, ...] | None = None
    value_priors: tuple[Prior, ...] | None = None

    @property
    def limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper bounds of the values, as arrays (units as ``units``)."""
        bounds = np.array(self.bounds, dtype=float).reshape(-1, 2)
        return bounds[:, 0], bounds[:, 1]


#: The frame letter of each payload cause: its mass centre anchors the simpler forms.
PAYLOAD_FRAMES = {"payload": "B", "front_payload": "H"}
#: Least upper bound of each load's mass [kg], whatever its frame weighs: a riderless bicycle's
#: rear frame weighs 3-12 kg (BicycleParameters' bicycles), yet carries a child seat with its
#: child (children up to 22 kg) or loaded panniers; a fork of well under a kilogram carries a
#: loaded basket. Three times the frame's mass alone left a 23 kg load on a 4.5 kg frame out of
#: reach, fitted as a load at its bound plus a second cause.
LOAD_MASS_FLOOR = {"payload": 30.0, "front_payload": 20.0}


def payload_bounds(bicycle: Model, name: str) -> dict[str, tuple[float, float]]:
    """Physical bounds of a payload's mass [kg], x [m] and z [m] on its frame.

    Rear frame: up to three times the frame's mass or :data:`LOAD_MASS_FLOOR` (a child seat
    with its child, or loaded panniers, on a light frame), from 0.5 m behind the rear contact (a
    rack's overhang) forward to where the steer axis meets the ground (w + c: the rear frame
    ends at the head tube, which lies behind that point at every height; a rear-frame load
    fitted beyond it stands in for a load on the front assembly). Front frame: up to three
    times its mass or its floor (a loaded basket on a light fork), from the nearer frame mass
    centre forward to 0.5 m ahead of the front contact (handlebar, basket, lamp). Heights:
    from the ground up to twice the larger wheel radius plus 1 m.
    """
    p = bicycle.parameters
    height = (-2.0 * max(p["rR"], p["rF"]) - 1.0, 0.0)
    mass = (0.0, max(3.0 * p[f"m{PAYLOAD_FRAMES[name]}"], LOAD_MASS_FLOOR[name]))
    if name == "payload":
        return {"mass": mass, "x": (-0.5, p["w"] + p["c"]), "z": height}
    return {"mass": mass, "x": (min(p["xB"], p["xH"]), p["w"] + 0.5), "z": height}


#: Upper bound of a load's own radii of gyration [m]: a solid cube 0.7 m on a side (a
#: uniform box of side a has a / sqrt(6)), larger than any rack or basket load.
MAX_GYRATION = 0.3
#: The fitted values of a payload form, by letter of ``free``, and their units.
_PAYLOAD_VALUES = {"m": ("mass",), "x": ("x",), "z": ("z",), "k": ("roll_gyration", "yaw_gyration")}
_PAYLOAD_UNITS = {"mass": "kg", "x": "m", "z": "m", "roll_gyration": "m", "yaw_gyration": "m"}


#: Prior scale [kg] of a load's mass (half-normal): luggage on a rack weighs 2-15 kg, a basket's
#: load 1-8 kg; a load far heavier than these is not luggage.
LOAD_MASS_SCALE = {"payload": 10.0, "front_payload": 5.0}
#: Prior scale [m] of a load's own radii of gyration (half-normal): a box 0.5 m across has 0.2 m.
GYRATION_SCALE = 0.1


def payload_priors(bicycle: Model, name: str, axes: Sequence[str]) -> tuple[Prior, ...]:
    """Return the priors of a payload form's values.

    The mass half-normal (:data:`LOAD_MASS_SCALE`); x and z normal over the frame's extent (the
    middle of their bounds, a quarter of their range: the bounds two standard deviations away);
    the radii of gyration half-normal (:data:`GYRATION_SCALE`).
    """
    bounds = payload_bounds(bicycle, name)
    priors = {"mass": Prior("halfnormal", 0.0, LOAD_MASS_SCALE[name], "luggage on a bicycle's frame"),
              "roll_gyration": Prior("halfnormal", 0.0, GYRATION_SCALE, "a load's own size"),
              "yaw_gyration": Prior("halfnormal", 0.0, GYRATION_SCALE, "a load's own size")}
    for axis in ("x", "z"):
        low, high = bounds[axis]
        priors[axis] = Prior("normal", 0.5 * (low + high), 0.25 * (high - low), "anywhere on the frame")
    return tuple(priors[axis] for axis in axes)


def payload_form(bicycle: Model, name: str, free: str, prior: float = 1.0, priors: bool = False) -> Cause:
    """Return one form of a payload cause, its fixed coordinates at the frame's mass centre.

    Parameters
    ----------
    bicycle : Bicycle
        Supplies the frame's mass centre and the bounds (:func:`payload_bounds`).
    name : {"payload", "front_payload"}
        The rear-frame or the front-frame payload.
    free : {"m", "mx", "mz", "mxz", "mxzk"}
        The fitted values: always the mass [kg], and x and/or z [m]; a coordinate not fitted is
        the frame's mass centre's (xB, zB or xH, zH). ``"mxzk"`` adds the load's own radii of
        gyration [m] about the roll (x) and yaw (z) axes, each 0 to :data:`MAX_GYRATION`: a
        rigid load (a box on a rack, a full basket) rather than a point mass, whose central
        inertia is added to the frame's inertia tensor (the point mass carries the
        parallel-axis terms; about y, the sum of the two, as for a flat load: pitch does not
        enter the linear model, and the sum keeps the tensor physical).
    prior : float
        As in :class:`Cause`.
    priors : bool
        Give the values their physical priors (:func:`payload_priors`).
    """
    letter = PAYLOAD_FRAMES[name]
    if free not in ("m", "mx", "mz", "mxz", "mxzk"):
        raise ValueError(f"unknown payload form {free!r}")
    centre = {"x": float(bicycle.parameters[f"x{letter}"]), "z": float(bicycle.parameters[f"z{letter}"])}
    bounds = {**payload_bounds(bicycle, name), "roll_gyration": (0.0, MAX_GYRATION),
              "yaw_gyration": (0.0, MAX_GYRATION)}
    axes = tuple(axis for letter_ in free for axis in _PAYLOAD_VALUES[letter_])

    def apply(changed: Model, values: Sequence[float]) -> Model:
        given = dict(zip(axes, (float(value) for value in values), strict=True))
        position = {axis: given.get(axis, float(changed.parameters[f"{axis}{letter}"])) for axis in "xz"}
        loaded = changed.with_extensions(**{name: Payload(mass=given["mass"], x=position["x"], z=position["z"])})
        if "roll_gyration" not in given:
            return loaded
        roll, yaw = given["mass"] * given["roll_gyration"] ** 2, given["mass"] * given["yaw_gyration"] ** 2
        own = {f"I{letter}xx": roll, f"I{letter}yy": roll + yaw, f"I{letter}zz": yaw}
        return loaded.with_parameters(**{key: float(loaded.parameters[key]) + added for key, added in own.items()
                                         if key in loaded.parameters})

    return Cause(name, tuple(f"{name}_{axis}" for axis in axes), tuple(_PAYLOAD_UNITS[axis] for axis in axes),
                 tuple(centre.get(axis, 0.0) for axis in axes),
                 tuple(bounds[axis] for axis in axes), apply, prior=prior,
                 null=(0.0,) if free == "m" else None,
                 # A rigid load is a point mass refined: the point mass's fit places it (or,
                 # fitted alone, the grid does, its own inertia held at none).
                 refines=tuple(f"{name}_{axis}" for axis in ("mass", "x", "z")) if "k" in free else None,
                 value_priors=payload_priors(bicycle, name, axes) if priors else None)


def _parameter(key: str) -> Callable[[Model, Sequence[float]], Model]:
    def apply(bicycle: Model, values: Sequence[float]) -> Model:
        return bicycle.with_parameters(**{key: float(values[0])})

    return apply


# Benchmark parameters a diagnosis may blame; g is a constant of nature, not a measurement.
BLAMEABLE_PARAMETERS = ("w", "c", "lam", "rR", "mR", "IRxx", "IRyy", "xB", "zB", "mB", "IBxx", "IBzz", "IBxz",
                        "xH", "zH", "mH", "IHxx", "IHzz", "IHxz", "rF", "mF", "IFxx", "IFyy")


#: Blameable parameters that no real bicycle has at or below zero (masses, wheel radii, the
#: wheelbase, principal inertias); the trail, head angle, positions and products of inertia may
#: take either sign.
POSITIVE_PARAMETERS = frozenset(("w", "rR", "mR", "IRxx", "IRyy", "mB", "IBxx", "IBzz", "mH", "IHxx", "IHzz", "rF",
                                 "mF", "IFxx", "IFyy"))


def parameter_cause(bicycle: Model, key: str, share: float, priors: bool = False) -> Cause:
    """``parameter:<key>``: the bicycle's value of key is wrong.

    Bounds: the value +/- its magnitude, except that a positive quantity stays above a third
    of its value (a fit at 0 would blame a massless frame or a zero wheelbase, and makes the
    model singular).
    """
    value = float(bicycle.parameters[key])
    span = max(abs(value), 1e-3)
    lower = value / 3.0 if key in POSITIVE_PARAMETERS and value >= 0 else value - span
    return Cause(f"parameter:{key}", (key,), (PARAMETER_UNITS.get(key, ""),), (value,), ((lower, value + span),),
                 _parameter(key), prior=share, null=(value,),
                 value_priors=(gross_error_prior(key, bicycle.parameters, bicycle.uncertainty),) if priors else None)


def with_cause(bicycle: Model, cause: Cause, values: Sequence[float]) -> Model:
    """Return the bicycle modified by a cause, its description noting the change."""
    changed = cause.apply(bicycle, [float(value) for value in values])
    note = ", ".join(f"{name} = {value:.6g}" for name, value in zip(cause.parameters, values, strict=True))
    return replace(changed, description=(bicycle.description + f" [diagnosed: {cause.name}: {note}]").strip())
