"""Candidate causes of model error: each a model change with one or two physical parameters.

Names follow the diagnosis-report vocabulary: ``steer_damping``, ``steer_inertia``,
``tyre_compliance``, ``speed_scale``, ``payload`` and ``parameter:<key>`` for one wrong
benchmark parameter. Each cause maps fitted values onto a modified bicycle, so that every
cause passes through the same derived equations.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

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
    for_evidence : bool
        False for a form fitted only to estimate the cause's values once it is named (see
        ``payload``), not to decide between causes.
    """

    name: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    start: tuple[float, ...]
    bounds: tuple[tuple[float, float], ...]
    apply: Callable[[Bicycle, Sequence[float]], Bicycle]
    prior: float = 1.0
    null: tuple[float, ...] | None = None
    for_evidence: bool = True


def _steer_damping(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(steer_damping=bicycle.extensions.steer_damping + float(values[0]))


def _steer_inertia(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(steer_inertia=bicycle.extensions.steer_inertia + float(values[0]))


def _speed_scale(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return bicycle.with_extensions(speed_scale=bicycle.extensions.speed_scale * float(values[0]))


def _payload(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    mass, x, z = (float(value) for value in values)
    return bicycle.with_extensions(payload=Payload(mass=mass, x=x, z=z))


def _payload_at_mass_centre(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return _payload(bicycle, (values[0], bicycle.parameters["xB"], bicycle.parameters["zB"]))


def _payload_at_height(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    return _payload(bicycle, (values[0], bicycle.parameters["xB"], values[1]))


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


def parameter_cause(bicycle: Bicycle, key: str, share: float) -> Cause:
    """``parameter:<key>``: the bicycle's value of key is wrong."""
    value = float(bicycle.parameters[key])
    span = max(abs(value), 1e-3)
    return Cause(f"parameter:{key}", (key,), (PARAMETER_UNITS.get(key, ""),), (value,), ((value - span, value + span),),
                 _parameter(key), prior=share, null=(value,))


def candidate_causes(bicycle: Bicycle, include_parameters: bool = True) -> list[Cause]:
    """Return the candidate causes for a bicycle, with starting values and bounds."""
    p = bicycle.parameters
    causes = [
        Cause("steer_damping", ("steer_damping",), ("N m s/rad",), (0.0,), ((0.0, 20.0),), _steer_damping,
              null=(0.0,)),
        Cause("steer_inertia", ("steer_inertia",), ("kg m^2",), (0.0,), ((0.0, 2.0),), _steer_inertia, null=(0.0,)),
        Cause("speed_scale", ("speed_scale",), ("",), (1.0,), ((0.5, 2.0),), _speed_scale, null=(1.0,)),
        # A payload has two forms, of which the diagnosis keeps the better supported: its mass
        # alone, at the rear frame's mass centre; and mass and height, for a payload above or
        # below it (height changes the roll inertia, which a mass alone cannot mimic). A free
        # fore-aft position as well made the payload mimic other causes (steer inertia, trail)
        # in hidden-effect tests: the weave eigenvalues do not identify three payload values
        # well enough to decide between causes.
        # The two forms share the cause's one unit of prior weight, so that taking the better of
        # them is not a free second chance.
        Cause("payload", ("payload_mass",), ("kg",), (0.0,), ((0.0, 3.0 * p["mB"]),), _payload_at_mass_centre,
              prior=0.5, null=(0.0,)),
        Cause("payload", ("payload_mass", "payload_z"), ("kg", "m"), (0.0, p["zB"]),
              ((0.0, 3.0 * p["mB"]), (-2.0 * max(p["rR"], p["rF"]) - 1.0, 0.0)), _payload_at_height, prior=0.5),
        # The estimate of a named payload comes from mass and full position, so that its
        # interval carries what the simpler forms hold fixed.
        Cause("payload", ("payload_mass", "payload_x", "payload_z"), ("kg", "m", "m"), (0.0, p["xB"], p["zB"]),
              ((0.0, 3.0 * p["mB"]), (-0.5, p["w"] + 0.5), (-2.0 * max(p["rR"], p["rF"]) - 1.0, 0.0)), _payload,
              for_evidence=False),
        Cause("tyre_compliance", ("cornering_stiffness", "relaxation_length"), ("1/rad", "m"), (12.0, 0.15),
              ((1.0, 500.0), (0.005, 1.0)), _tyre),
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
