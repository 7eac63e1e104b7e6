"""Candidate causes of model error: each a model change with one or two physical parameters.

Names follow the diagnosis-report vocabulary: ``steer_damping``, ``steer_inertia``,
``reflected_steer_inertia``, ``tyre_compliance``, ``speed_scale``, ``payload``,
``front_payload``, for a bicycle with a controller ``controller_gain``, ``controller_delay`` and
``controller_lag``, and ``parameter:<key>`` for one wrong benchmark parameter. Each cause maps
fitted values onto a modified bicycle, so that every cause passes through the same derived
equations.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from whipple.model.parameter_set import PARAMETER_UNITS
from whipple.model.parameters import Bicycle, Payload, TyreCompliance

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
    """

    name: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    start: tuple[float, ...]
    bounds: tuple[tuple[float, float], ...]
    apply: Callable[[Bicycle, Sequence[float]], Bicycle]
    prior: float = 1.0
    null: tuple[float, ...] | None = None
    refines: tuple[str, ...] | None = None

    @property
    def limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper bounds of the values, as arrays (units as ``units``)."""
        bounds = np.array(self.bounds, dtype=float).reshape(-1, 2)
        return bounds[:, 0], bounds[:, 1]


def _steer_damping(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(steer_damping=bicycle.extensions.steer_damping + float(values[0]))


def _steer_inertia(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(steer_inertia=bicycle.extensions.steer_inertia + float(values[0]))


def _speed_scale(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(speed_scale=bicycle.extensions.speed_scale * float(values[0]))


def _reflected_steer_inertia(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(
        reflected_steer_inertia=bicycle.extensions.reflected_steer_inertia + float(values[0]))


def _controller_gain(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, gain_scale=controller.gain_scale * float(values[0])))


def _controller_delay(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, delay=controller.delay + float(values[0])))


def _controller_lag(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, lag=controller.lag + float(values[0])))


#: The frame letter of each payload cause: its mass centre anchors the simpler forms.
PAYLOAD_FRAMES = {"payload": "B", "front_payload": "H"}


def payload_bounds(bicycle: Bicycle, name: str) -> dict[str, tuple[float, float]]:
    """Physical bounds of a payload's mass [kg], x [m] and z [m] on its frame.

    Rear frame: up to three times the frame's mass, from 0.5 m behind the rear contact (a
    rack's overhang) forward to where the steer axis meets the ground (w + c: the rear frame
    ends at the head tube, which lies behind that point at every height; a rear-frame load
    fitted beyond it stands in for a load on the front assembly). Front frame: up to three
    times its mass or 20 kg (a loaded basket on a light fork), from the nearer frame mass
    centre forward to 0.5 m ahead of the front contact (handlebar, basket, lamp). Heights:
    from the ground up to twice the larger wheel radius plus 1 m.
    """
    p = bicycle.parameters
    height = (-2.0 * max(p["rR"], p["rF"]) - 1.0, 0.0)
    if name == "payload":
        return {"mass": (0.0, 3.0 * p["mB"]), "x": (-0.5, p["w"] + p["c"]), "z": height}
    return {"mass": (0.0, max(3.0 * p["mH"], 20.0)), "x": (min(p["xB"], p["xH"]), p["w"] + 0.5), "z": height}


#: Upper bound of a load's own radii of gyration [m]: a solid cube 0.7 m on a side (a
#: uniform box of side a has a / sqrt(6)), larger than any rack or basket load.
MAX_GYRATION = 0.3
#: The fitted values of a payload form, by letter of ``free``, and their units.
_PAYLOAD_VALUES = {"m": ("mass",), "x": ("x",), "z": ("z",), "k": ("roll_gyration", "yaw_gyration")}
_PAYLOAD_UNITS = {"mass": "kg", "x": "m", "z": "m", "roll_gyration": "m", "yaw_gyration": "m"}


def payload_form(bicycle: Bicycle, name: str, free: str, prior: float = 1.0) -> Cause:
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
    """
    letter = PAYLOAD_FRAMES[name]
    if free not in ("m", "mx", "mz", "mxz", "mxzk"):
        raise ValueError(f"unknown payload form {free!r}")
    centre = {"x": float(bicycle.parameters[f"x{letter}"]), "z": float(bicycle.parameters[f"z{letter}"])}
    bounds = {**payload_bounds(bicycle, name), "roll_gyration": (0.0, MAX_GYRATION),
              "yaw_gyration": (0.0, MAX_GYRATION)}
    axes = tuple(axis for letter_ in free for axis in _PAYLOAD_VALUES[letter_])

    def apply(changed: Bicycle, values: Sequence[float]) -> Bicycle:
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
                 refines=tuple(f"{name}_{axis}" for axis in ("mass", "x", "z")) if "k" in free else None)


#: Whether the payloads' rigid-load form is among the candidates (an experiment, not the
#: default): over seeds 0-24 of every family and bicycle it named a rack load right more often
#: (64 -> 66 of 75) but a basket less often (55 -> 46; docs/diagnosis.md, "A rigid load").
RIGID_LOADS = True


def payload_causes(bicycle: Bicycle, name: str, rigid: bool | None = None) -> list[Cause]:
    """Return the forms of a payload cause: ``payload`` (rear frame) or ``front_payload``.

    Three forms for the evidence, sharing the cause's one unit of prior weight (so that taking
    the best of them is not a free extra chance): the mass alone at the frame's mass centre;
    mass and height at the mass centre's fore-aft position (height changes the roll inertia,
    which a mass alone cannot mimic); and mass and full position, for a load on a rack behind
    the saddle or in a basket ahead of the steer axis. The full-position form was once kept out
    of the evidence because it mimicked steer inertia and trail; with the ambiguity rules
    (:mod:`whipple.diagnosis.families`) such mimicry is reported as ``ambiguous`` instead, and
    without the form a real rack or basket load (a rigid body away from the mass centre) was
    named right in 0% and 6% of hidden-effect trials; with it, in most (docs/diagnosis.md).
    ``rigid`` (default :data:`RIGID_LOADS`): a fourth form, the same load as a rigid body with
    its own radii of gyration about the roll and yaw axes, refining the third. Other forms:
    :func:`payload_form`.
    """
    rigid = RIGID_LOADS if rigid is None else rigid
    forms = ("m", "mz", "mxz", "mxzk") if rigid else ("m", "mz", "mxz")
    return [payload_form(bicycle, name, free, prior=1.0 / len(forms)) for free in forms]


def controller_causes(bicycle: Bicycle) -> list[Cause]:
    """Return the causes in the bicycle's controller: none for a bicycle without one.

    ``controller_gain`` scales every commanded torque [-]; ``controller_delay`` delays it [s]
    (Pade approximant in the linear model, see :mod:`whipple.model.actuator`);
    ``controller_lag`` passes it through a first-order lag of that time constant [s].
    """
    if bicycle.controller.is_empty():
        return []
    return [
        Cause("controller_gain", ("controller_gain",), ("",), (1.0,), ((0.2, 5.0),), _controller_gain, null=(1.0,)),
        Cause("controller_delay", ("controller_delay",), ("s",), (0.0,), ((0.0, 0.3),), _controller_delay,
              null=(0.0,)),
        Cause("controller_lag", ("controller_lag",), ("s",), (0.0,), ((0.0, 0.3),), _controller_lag, null=(0.0,)),
    ]


def _tyre(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    camber = (bicycle.extensions.tyre_compliance.camber_stiffness
              if bicycle.extensions.tyre_compliance is not None else DEFAULT_CAMBER_STIFFNESS)
    return bicycle.with_extensions(tyre_compliance=TyreCompliance(
        cornering_stiffness=float(values[0]), camber_stiffness=camber, relaxation_length=float(values[1])))


def _parameter(key: str) -> Callable[[Bicycle, Sequence[float]], Bicycle]:
    def apply(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
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


def parameter_cause(bicycle: Bicycle, key: str, share: float) -> Cause:
    """``parameter:<key>``: the bicycle's value of key is wrong.

    Bounds: the value +/- its magnitude, except that a positive quantity stays above a third
    of its value (a fit at 0 would blame a massless frame or a zero wheelbase, and makes the
    model singular).
    """
    value = float(bicycle.parameters[key])
    span = max(abs(value), 1e-3)
    lower = value / 3.0 if key in POSITIVE_PARAMETERS and value >= 0 else value - span
    return Cause(f"parameter:{key}", (key,), (PARAMETER_UNITS.get(key, ""),), (value,), ((lower, value + span),),
                 _parameter(key), prior=share, null=(value,))


def candidate_causes(bicycle: Bicycle, include_parameters: bool = True) -> list[Cause]:
    """Return the candidate causes for a bicycle, with starting values and bounds.

    Controller causes only for a bicycle with a controller; ``parameter:<key>`` causes unless
    ``include_parameters`` is False.
    """
    causes = [
        Cause("steer_damping", ("steer_damping",), ("N m s/rad",), (0.0,), ((0.0, 20.0),), _steer_damping,
              null=(0.0,)),
        Cause("steer_inertia", ("steer_inertia",), ("kg m^2",), (0.0,), ((0.0, 2.0),), _steer_inertia, null=(0.0,)),
        Cause("reflected_steer_inertia", ("reflected_steer_inertia",), ("kg m^2",), (0.0,), ((0.0, 2.0),),
              _reflected_steer_inertia, null=(0.0,)),
        Cause("speed_scale", ("speed_scale",), ("",), (1.0,), ((0.5, 2.0),), _speed_scale, null=(1.0,)),
        *payload_causes(bicycle, "payload"),
        *payload_causes(bicycle, "front_payload"),
        Cause("tyre_compliance", ("cornering_stiffness", "relaxation_length"), ("1/rad", "m"), (12.0, 0.15),
              ((1.0, 500.0), (0.005, 1.0)), _tyre),
        *controller_causes(bicycle),
    ]
    if include_parameters:
        keys = [key for key in BLAMEABLE_PARAMETERS if key in bicycle.parameters]
        causes += [parameter_cause(bicycle, key, 1.0 / len(keys)) for key in keys]
    return causes


def cause_by_name(bicycle: Bicycle, name: str) -> Cause:
    """Return the candidate cause called ``name`` (including ``parameter:<key>``)."""
    for cause in candidate_causes(bicycle):
        if cause.name == name:
            return cause
    raise KeyError(name)


def with_cause(bicycle: Bicycle, cause: Cause, values: Sequence[float]) -> Bicycle:
    """Return the bicycle modified by a cause, its description noting the change."""
    changed = cause.apply(bicycle, [float(value) for value in values])
    note = ", ".join(f"{name} = {value:.6g}" for name, value in zip(cause.parameters, values, strict=True))
    return replace(changed, description=(bicycle.description + f" [diagnosed: {cause.name}: {note}]").strip())
