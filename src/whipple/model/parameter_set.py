"""A bicycle's parameter set: the 26 benchmark parameters, extensions, controller, and checks.

The parameterisation is that of Meijaard, Papadopoulos, Ruina & Schwab (2007), "Linearized
dynamics equations for the balance and steer of a bicycle: a benchmark and review",
Proc. R. Soc. A 463, 1955-1982, doi:10.1098/rspa.2007.1857: SI units, benchmark frame with x
forward from the rear contact point and z down, inertias about each body's mass centre.

Import these names from :mod:`whipple.model.parameters`, which also reads and writes bicycle files.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from numbers import Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import ParameterError
from whipple.generated import whipple_numpy
from whipple.model.linear_terms import LinearTerms, term_findings
from whipple.model.parameter_table import BY_NAME, names
from whipple.model.physical_checks import (
    BODIES,
    LIMITS,
    excess_std,
    gyration_findings,
    magnitude_findings,
    placement_findings,
    principal_moments,
    singular_mass_matrix,
    triangle_message,
    triangle_remedy,
    tyre_point_wheel_problem,
    uncertainty_findings,
)

#: The 26 benchmark parameters in the order of Meijaard et al. (2007), Table 1.
PARAMETER_NAMES: tuple[str, ...] = names("benchmark")
#: Parameters that do not enter the linear model; they may be absent.
OPTIONAL_PARAMETERS: tuple[str, ...] = ("IByy", "IHyy")
#: SI unit of each parameter.
PARAMETER_UNITS: dict[str, str] = {name: BY_NAME[name].unit for name in PARAMETER_NAMES}
#: One-line description of each parameter, with its unit in brackets.
PARAMETER_DESCRIPTIONS: dict[str, str] = {name: BY_NAME[name].described for name in PARAMETER_NAMES}

#: States a controller may feed back, in the order of the Whipple state vector.
CONTROLLER_STATES = ("roll", "steer", "roll_rate", "steer_rate")
#: Largest magnitude of a controller gain coefficient (any unit): beyond it a typing error.
CONTROLLER_GAIN_LIMIT = 1e6
# Triangle inequality of principal moments, excess as a fraction of their sum: up to _EXACT is
# floating-point rounding (an ideal thin disc sits exactly on the limit); up to _ROUNDING is
# within the rounding of values published to three or four digits, so only a warning.
_EXACT, _ROUNDING = 1e-9, 5e-3


def _as_float(value: Any) -> Any:
    return float(value) if isinstance(value, Real) and not isinstance(value, bool) else value


@dataclass(frozen=True)
class Payload:
    """A point mass rigidly attached to a frame (the rear frame, or the front frame).

    Attributes
    ----------
    mass : float
        Mass [kg].
    x, z : float
        Position [m]: forward of the rear contact, and down (negative above the ground); at steer angle zero.
    """

    mass: float
    x: float
    z: float


@dataclass(frozen=True)
class TyreCompliance:
    """Linear tyre forces with relaxation, normalised by the static wheel load Fz.

    Attributes
    ----------
    cornering_stiffness : float
        C_alpha [1/rad]: lateral force per unit load per slip angle.
    camber_stiffness : float
        C_gamma [1/rad]: lateral force per unit load per camber angle.
    relaxation_length : float
        sigma [m]: distance rolled for a force to build up.
    pneumatic_trail : float
        [m]; self-aligning moment ``-Fz * pneumatic_trail * C_alpha * alpha``.
    """

    cornering_stiffness: float
    camber_stiffness: float
    relaxation_length: float
    pneumatic_trail: float = 0.0


@dataclass(frozen=True)
class Extensions:
    """Effects beyond the Whipple model (TOML table ``[extensions]``).

    Attributes
    ----------
    steer_damping : float
        Viscous damping about the steer axis [N m s/rad].
    steer_inertia : float
        Extra moment of inertia of the front frame about the steer axis [kg m^2] (turning with it).
    speed_scale : float
        Measured speed / true speed [-].
    payload, front_payload : Payload or None
        A point mass on the rear frame; on the front frame (a basket, a lamp), turning with it.
    tyre_compliance : TyreCompliance or None
        Tyre slip instead of knife-edge wheels.
    reflected_steer_inertia : float
        A steer motor's rotor inertia reflected to the steer axis, ``N^2 J_rotor`` [kg m^2] (steer equation alone).
    linear_terms : LinearTerms or None
        Entries added to the linear model's matrices (:mod:`whipple.model.linear_terms`).
    steer_friction : float
        Coulomb steer friction torque [N m] (:mod:`whipple.model.steer_friction`; not in the linear model).
    """

    steer_damping: float = 0.0
    steer_inertia: float = 0.0
    speed_scale: float = 1.0
    payload: Payload | None = None
    tyre_compliance: TyreCompliance | None = None
    front_payload: Payload | None = None
    reflected_steer_inertia: float = 0.0
    linear_terms: LinearTerms | None = None
    steer_friction: float = 0.0

    def is_base(self) -> bool:
        """Return True when the extensions change nothing in the Whipple model."""
        return self == Extensions()

    def model_values(self) -> dict[str, float]:
        """Values of the derived models' extension parameters (zero when absent).

        Keys: ``payload_mass`` [kg], ``payload_x``, ``payload_z`` [m], the same with prefix ``front_`` for the front
        payload, ``steer_inertia`` and ``reflected_steer_inertia`` [kg m^2], ``steer_damping`` [N m s/rad],
        ``pneumatic_trail`` [m], and with tyre compliance ``cornering_stiffness``, ``camber_stiffness`` [1/rad],
        ``relaxation_length`` [m].
        """
        values = {"payload_mass": 0.0, "payload_x": 0.0, "payload_z": 0.0,
                  "front_payload_mass": 0.0, "front_payload_x": 0.0, "front_payload_z": 0.0,
                  "steer_inertia": self.steer_inertia, "reflected_steer_inertia": self.reflected_steer_inertia,
                  "steer_damping": self.steer_damping, "pneumatic_trail": 0.0}
        for prefix, payload in (("", self.payload), ("front_", self.front_payload)):
            if payload is not None:
                values.update({f"{prefix}payload_mass": payload.mass, f"{prefix}payload_x": payload.x,
                               f"{prefix}payload_z": payload.z})
        tyre = self.tyre_compliance
        if tyre is not None:
            values.update(cornering_stiffness=tyre.cornering_stiffness, camber_stiffness=tyre.camber_stiffness,
                          relaxation_length=tyre.relaxation_length, pneumatic_trail=tyre.pneumatic_trail)
        return values


@dataclass(frozen=True)
class Controller:
    """Linear state feedback whose gains are polynomials in the forward speed v.

    Attributes
    ----------
    steer, roll : dict of str to tuple of float
        For the steer torque and the roll torque: state name (``roll`` [rad], ``steer`` [rad], ``roll_rate`` [rad/s],
        ``steer_rate`` [rad/s]) to the gain's polynomial coefficients in v [m/s], constant first; e.g. ``{"roll_rate":
        (13.0, -2.0)}`` is ``T_steer = (13 - 2 v) * roll_rate`` [N m].
    gain_scale : float
        Factor on every torque the controller commands [-] (an actuator's gain error; 1: none).
    delay : float
        Pure time delay between the measured state and the torque [s] (0: none).
    lag : float
        Time constant of a first-order actuator lag [s], ``T' = (T_cmd - T) / lag`` (0: none).

    The linear model realises the delay by a Pade approximant and the lag by one state per
    torque row in use (:mod:`whipple.model.actuator`).
    """

    steer: dict[str, tuple[float, ...]] = field(default_factory=dict)
    roll: dict[str, tuple[float, ...]] = field(default_factory=dict)
    gain_scale: float = 1.0
    delay: float = 0.0
    lag: float = 0.0

    def __post_init__(self) -> None:
        for row in ("steer", "roll"):
            gains = {
                key: (float(value),) if isinstance(value, Real) else tuple(map(float, value))
                for key, value in getattr(self, row).items()
            }
            object.__setattr__(self, row, gains)

    def is_empty(self) -> bool:
        """Return True when there is no feedback term at all."""
        return not self.steer and not self.roll

    def has_dynamics(self) -> bool:
        """Return True when the torque lags or is delayed (the model needs actuator states)."""
        return not self.is_empty() and (self.delay != 0.0 or self.lag != 0.0)

    def feedback_coefficients(self) -> list[NDArray[np.float64]]:
        """Gain matrices F_k, shape (2, 4), with ``f = sum_k v^k F_k x``, ``gain_scale`` included.

        ``x = [roll, steer, roll_rate, steer_rate]`` and the rows of f are the roll torque and the steer torque [N m]:
        the commanded torque, before any delay or lag. An empty controller gives ``[]``.
        """
        rows = ((0, self.roll), (1, self.steer))
        order = max((len(c) for _, gains in rows for c in gains.values()), default=0)
        matrices = [np.zeros((2, 4)) for _ in range(order)]
        for row, gains in rows:
            for state, coefficients in gains.items():
                if state not in CONTROLLER_STATES:
                    raise ParameterError(f"controller: unknown state {state!r}")
                for k, value in enumerate(coefficients):
                    matrices[k][row, CONTROLLER_STATES.index(state)] = value * self.gain_scale
        return matrices


@dataclass(frozen=True)
class Bicycle:
    """One bicycle: benchmark parameters, their uncertainty, extensions and controller.

    Attributes
    ----------
    parameters : dict of str to float
        Benchmark parameters by name (see PARAMETER_DESCRIPTIONS for units).
    name, description : str
        Free text.
    uncertainty : dict of str to float
        One standard deviation of some parameters, same keys and units.
    extensions : Extensions
        Effects beyond the Whipple model.
    controller : Controller
        State feedback acting on the bicycle.
    source : str
        Where the bicycle was read from (a path or a built-in name); not part of equality.
    notes : tuple of str
        What reading the file found worth a warning (e.g. redundant values that disagree);
        :func:`validate` reports them. Not part of equality.
    """

    parameters: dict[str, float]
    name: str = ""
    description: str = ""
    uncertainty: dict[str, float] = field(default_factory=dict)
    extensions: Extensions = Extensions()
    controller: Controller = field(default_factory=Controller)
    source: str = field(default="", compare=False)
    notes: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        # Copies, so that changing the caller's dict never changes the bicycle; anything that
        # is not a real number is kept as given, for validate() to report.
        for name in ("parameters", "uncertainty"):
            values = {k: _as_float(v) for k, v in getattr(self, name).items()}
            object.__setattr__(self, name, values)

    def with_parameters(self, **changes: float) -> Bicycle:
        """Return a copy with some parameters changed (unknown names are a ParameterError)."""
        unknown = sorted(set(changes) - set(PARAMETER_NAMES))
        if unknown:
            raise ParameterError(f"unknown parameter(s): {', '.join(unknown)}")
        return dataclasses.replace(self, parameters={**self.parameters, **changes})

    def with_extensions(self, **changes: Any) -> Bicycle:
        """Return a copy with some fields of the extensions changed."""
        return dataclasses.replace(self, extensions=dataclasses.replace(self.extensions, **changes))

    def with_controller(self, controller: Controller) -> Bicycle:
        """Return a copy with another controller."""
        return dataclasses.replace(self, controller=controller)

    def model_speed(self, measured: ArrayLike) -> NDArray[np.float64]:
        """Return the model's (true) forward speed [m/s] at a measured speed [m/s].

        A speedometer or treadmill may misreport the speed by the factor ``speed_scale`` of
        the extensions (measured speed = speed_scale * true speed).
        """
        return np.asarray(measured, dtype=float) / self.extensions.speed_scale

    def measured_speed(self, true: ArrayLike) -> NDArray[np.float64]:
        """Return the speed [m/s] a measurement reports at the model's (true) speed [m/s]."""
        return np.asarray(true, dtype=float) * self.extensions.speed_scale


@dataclass(frozen=True)
class ValidationReport:
    """Outcome of :func:`validate`.

    Attributes
    ----------
    problems : tuple of str
        What makes the parameter set unusable, one line each.
    warnings : tuple of str
        Checks that were skipped or values that are suspicious but usable.
    """

    problems: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        """True when there are no problems."""
        return not self.problems


class _Findings:
    """Problems and warnings collected over a batch of parameter sets (any broadcast shape)."""

    def __init__(self) -> None:
        self.problems: list[str] = []
        self.warnings: list[str] = []

    def flag(self, bad: ArrayLike, text: str, warning: bool = False) -> None:
        bad = np.asarray(bad)
        if not bad.any():
            return
        if bad.ndim:
            index = tuple(int(i) for i in np.argwhere(bad)[0])
            first = index[0] if len(index) == 1 else index
            text += f" (in {int(bad.sum())} of {bad.size} sets, first at index {first})"
        (self.warnings if warning else self.problems).append(text)

    def gating_problems(self) -> bool:
        """Whether problems found so far make the mass-matrix check pointless."""
        return bool(self.problems)


class _RowFindings(_Findings):
    """Only where (which sets of a batch) any problem was found; no messages, no warnings."""

    def __init__(self) -> None:
        super().__init__()
        self.rows: NDArray[np.bool_] = np.zeros((), dtype=bool)

    def flag(self, bad: ArrayLike, text: str, warning: bool = False) -> None:
        if not warning:
            self.rows = self.rows | np.asarray(bad, dtype=bool)

    def gating_problems(self) -> bool:
        # Other sets' problems must not skip this check for the sets without any.
        return False


def _show(name: str, value: NDArray[np.float64]) -> str:
    """``name = value`` for one set, just ``name`` for a batch."""
    return f"{name} = {float(value):.6g}" if value.ndim == 0 else name


def validate(bicycle_or_parameters: Bicycle | Mapping[str, ArrayLike]) -> ValidationReport:
    """Check that a parameter set describes a physically possible bicycle.

    Parameters
    ----------
    bicycle_or_parameters : Bicycle or mapping
        A bicycle (its uncertainty, extensions and controller are checked too), or parameters
        by name; values may be arrays that broadcast together (a batch of sets).

    Returns
    -------
    ValidationReport
        Problems (unusable) and warnings (checks skipped, values within rounding of a limit).
    """
    found = _Findings()
    uncertainty: Mapping[str, float] = {}
    if isinstance(bicycle_or_parameters, Bicycle):
        _check_additions(bicycle_or_parameters, found)
        parameters: Mapping[str, ArrayLike] = bicycle_or_parameters.parameters
        uncertainty = bicycle_or_parameters.uncertainty
        found.warnings.extend(bicycle_or_parameters.notes)
    else:
        parameters = bicycle_or_parameters
    _check_parameters(parameters, found, uncertainty)
    return ValidationReport(tuple(found.problems), tuple(found.warnings))


def validate_rows(parameters: Mapping[str, ArrayLike]) -> tuple[str, ...]:
    """Return the problems of every set of a batch, as :func:`validate` states them one by one.

    Equal to ``"; ".join(validate(set).problems)`` for each set, but vectorised: the checks run once over the batch to
    find the sets with problems, and only those are checked again one by one for their messages.

    Parameters
    ----------
    parameters : mapping of str to array_like
        Benchmark parameters by name, 1-D arrays (one value per set) or scalars that broadcast.

    Returns
    -------
    tuple of str
        One entry per set: its problems joined by ``"; "``, empty if it has none.
    """
    arrays = {name: np.asarray(value) for name, value in parameters.items()}
    found = _RowFindings()
    with np.errstate(all="ignore"):  # overflow in absurd sets is reported, not warned about
        _check_parameters(arrays, found, {})
    count = int(np.broadcast_shapes(*(value.shape for value in arrays.values()), (1,))[0])
    bad = np.broadcast_to(found.rows, (count,))
    problems = [""] * count
    for row in np.flatnonzero(bad).tolist():
        one = {name: value if value.ndim == 0 else value[row] for name, value in arrays.items()}
        problems[row] = "; ".join(validate(one).problems)
    return tuple(problems)


def _check_parameters(parameters: Mapping[str, ArrayLike], found: _Findings,
                      uncertainty: Mapping[str, float]) -> None:
    """Run the checks of :func:`validate` on parameter values (any broadcast shape)."""
    unknown = [key for key in parameters if key not in PARAMETER_NAMES]
    found.flag(bool(unknown), f"unknown parameter(s): {', '.join(map(str, unknown))}")
    missing = [n for n in PARAMETER_NAMES if n not in parameters and n not in OPTIONAL_PARAMETERS]
    found.flag(bool(missing), f"missing parameter(s): {', '.join(missing)}")
    p: dict[str, NDArray[np.float64]] = {}
    for name in PARAMETER_NAMES:
        if name in parameters:
            value = np.asarray(parameters[name])
            if value.dtype.kind in "iuf":  # booleans and strings are not numbers
                p[name] = value.astype(float)
            else:
                found.flag(True, f"{name} is not a number: {parameters[name]!r}")
    for name, value in p.items():
        found.flag(~np.isfinite(value), f"{_show(name, value)} is not finite")
    finite = {name: np.where(np.isfinite(value), value, np.nan) for name, value in p.items()}
    for bad, text, warning in [*magnitude_findings(finite, PARAMETER_UNITS), *placement_findings(finite),
                               *gyration_findings(finite)]:
        found.flag(bad, text, warning)
    for name in ("w", "g"):
        if name in finite:
            found.flag(finite[name] <= 0, f"{_show(name, finite[name])} must be positive")
    # Zero masses, radii and inertias are legitimate limits (point masses, the skates of the
    # two-mass-skate bicycle); negative ones are not.
    for name in ("rR", "rF", "mR", "mB", "mH", "mF"):
        if name in finite:
            found.flag(finite[name] < 0, f"{_show(name, finite[name])} must not be negative")
    for wheel, label in (("R", "rear"), ("F", "front")):
        radius, spin = f"r{wheel}", f"I{wheel}yy"
        if radius in finite and spin in finite:
            found.flag((finite[radius] == 0) & (finite[spin] != 0),
                       f"{radius} = 0 (a point {label} wheel) needs {spin} = 0: a wheel of zero radius "
                       "spins infinitely fast and cannot carry spin inertia")
    if "lam" in finite:
        lam = finite["lam"]
        found.flag(np.abs(lam) >= math.pi / 2, f"{_show('lam', lam)} must be in (-pi/2, pi/2)")
    singular = []
    for label, _, xx, yy, zz, xz in BODIES:
        singular.append(_check_inertia(label, (xx, yy, zz, xz), finite, found, uncertainty))
    needed = whipple_numpy.PARAMETERS
    if not found.gating_problems() and any(np.any(s) for s in singular) and all(n in finite for n in needed):
        # Point masses: the bicycle as a whole may have no inertia to roll or to steer.
        bad = singular_mass_matrix({n: finite[n] for n in needed})
        found.flag(bad, "the mass matrix M is not positive definite: with these point masses the "
                        "bicycle has no inertia to roll or to steer (e.g. all front mass on the steer axis)")


def _check_inertia(
    label: str,
    keys: tuple[str, str, str, str | None],
    p: Mapping[str, NDArray[np.float64]],
    found: _Findings,
    uncertainty: Mapping[str, float],
) -> NDArray[np.bool_] | bool:
    """Check one body's inertia (see :mod:`whipple.model.physical_checks`).

    Returns where its inertia in the xz plane is singular (a point mass or a thin rod), for
    the mass-matrix check.
    """
    xx, yy, zz, xz = keys
    if any(key is not None and key not in p for key in (xx, zz, xz)):
        return False  # reported as missing
    ixx, izz = p[xx], p[zz]
    ixz = p[xz] if xz is not None else np.zeros_like(ixx)
    names = ", ".join(key for key in dict.fromkeys(keys) if key is not None)
    wheel = xz is None
    moments = principal_moments(ixx, p[yy] if yy in p else np.full_like(ixx, np.nan), izz, ixz)
    shown = "" if moments.ndim > 1 else " (principal moments " + ", ".join(f"{m:.6g}" for m in moments) + ")"
    # The moments in the xz plane enter the linear equations, and so does a wheel's spin moment.
    used = moments if wheel else moments[:2]
    found.flag(np.nanmin(used, axis=0) < 0,
               f"{label} inertia ({names}) is not positive semi-definite: a negative principal moment" + shown)
    if yy not in p:
        if yy in OPTIONAL_PARAMETERS:
            found.warnings.append(f"{yy} absent: {label} inertia checks needing it were skipped")
        return moments[1] <= 0
    if not wheel:
        found.flag(p[yy] < 0, f"{yy} = {float(p[yy]) if p[yy].ndim == 0 else 'a value'} < 0 is not a "
                              "moment of inertia (it does not enter the linear equations)", True)
    total = moments.sum(axis=0)
    excess = 2 * moments.max(axis=0) - total
    relative = excess / np.where(total > 0, total, np.nan)
    text = f"{label} inertia ({names}) violates the triangle inequality of principal moments"
    rounding = (relative > _EXACT) & (relative <= _ROUNDING)
    if rounding.any():
        worst = float(np.max(relative[rounding]))
        found.flag(rounding, f"{text} by {worst:.2%} of their sum (taken as rounding)", True)
    beyond = relative > _ROUNDING
    if beyond.any():
        if moments.ndim == 1:
            values = {key: float(p[key]) for key in (xx, yy, zz) + ((xz,) if xz else ())}
            values.setdefault("_xz", 0.0)
            std = excess_std(values, (xx, yy, zz, xz or "_xz"), uncertainty)
            remedy = triangle_remedy(yy, int(np.argmax(moments)) == 2, float(excess), wheel)
            found.flag(True, triangle_message(text, float(excess), moments, std, remedy), True)
        else:
            found.flag(beyond, f"{text} by more than {_ROUNDING:.1%} of their sum", True)
    return moments[1] <= 0


def _check_additions(bicycle: Bicycle, found: _Findings) -> None:
    """Uncertainty, extensions and controller of a bicycle."""
    ext = bicycle.extensions
    for bad, text in uncertainty_findings(bicycle.uncertainty, PARAMETER_UNITS) + term_findings(ext.linear_terms):
        found.flag(bad, text)
    point = [name for name in ("rR", "rF") if bicycle.parameters.get(name) == 0]
    found.flag(ext.tyre_compliance is not None and bool(point), tyre_point_wheel_problem(point))
    # (name, value, lowest, lowest allowed itself, largest magnitude of anything like a bicycle:
    # beyond it a unit or typing error, and the model's arithmetic would overflow)
    checks = [
        ("steer_damping", ext.steer_damping, -math.inf, False, 1e4),
        ("steer_inertia", ext.steer_inertia, 0.0, True, LIMITS["kg m^2"]),
        ("reflected_steer_inertia", ext.reflected_steer_inertia, 0.0, True, LIMITS["kg m^2"]),
        ("speed_scale", ext.speed_scale, 0.0, False, 100.0),
        ("steer_friction", ext.steer_friction, 0.0, True, 1e4),
    ]
    found.flag(ext.steer_damping < 0, f"extension steer_damping = {ext.steer_damping:.6g} is negative: it feeds "
                                      "energy into the steering (an active device, or a sign error?)", True)
    found.flag(0 < ext.speed_scale < 0.01, f"extension speed_scale = {ext.speed_scale:.6g} is below 0.01: "
                                           "not a speed measurement (a typing error?)")
    for label, payload in (("payload", ext.payload), ("front_payload", ext.front_payload)):
        if payload is not None:
            checks += [
                (f"{label} mass", payload.mass, 0.0, False, LIMITS["kg"]),
                (f"{label} x", payload.x, -math.inf, False, LIMITS["m"]),
                (f"{label} z", payload.z, -math.inf, False, LIMITS["m"]),
            ]
    if ext.tyre_compliance is not None:
        tyre = ext.tyre_compliance
        checks += [
            ("cornering_stiffness", tyre.cornering_stiffness, 0.0, False, 1e6),
            ("camber_stiffness", tyre.camber_stiffness, 0.0, True, 1e6),
            ("relaxation_length", tyre.relaxation_length, 0.0, False, LIMITS["m"]),
            ("pneumatic_trail", tyre.pneumatic_trail, -math.inf, False, LIMITS["m"]),
        ]
    for name, value, low, inclusive, limit in checks:
        bound = "" if low == -math.inf else f" and {'>=' if inclusive else '>'} {low:g}"
        inside = value >= low if inclusive else value > low
        found.flag(
            not (math.isfinite(value) and inside),
            f"extension {name} = {value:.6g} must be finite{bound}",
        )
        found.flag(math.isfinite(value) and abs(value) > limit,
                   f"extension {name} = {value:.6g} is beyond {limit:g}: not a bicycle (a unit or typing error?)")
    for row, gains in (("steer", bicycle.controller.steer), ("roll", bicycle.controller.roll)):
        for state, coefficients in gains.items():
            found.flag(state not in CONTROLLER_STATES, f"controller.{row}: unknown state {state!r}")
            found.flag(
                not all(map(math.isfinite, coefficients)),
                f"controller.{row}.{state} has a coefficient that is not finite",
            )
            found.flag(any(abs(c) > CONTROLLER_GAIN_LIMIT for c in coefficients if math.isfinite(c)),
                       f"controller.{row}.{state} has a coefficient beyond {CONTROLLER_GAIN_LIMIT:g}: not a "
                       "bicycle's controller (a unit or typing error?)")
    controller = bicycle.controller
    for name, value, limit in (("gain_scale", controller.gain_scale, 1e3), ("delay", controller.delay, 10.0),
                               ("lag", controller.lag, 10.0)):
        found.flag(not (math.isfinite(value) and value >= 0),
                   f"controller {name} = {value:.6g} must be finite and >= 0")
        found.flag(math.isfinite(value) and value > limit,
                   f"controller {name} = {value:.6g} is beyond {limit:g}: not a bicycle's controller")


def check_physical(bicycle_or_parameters: Bicycle | Mapping[str, ArrayLike], source: str | None = None
                   ) -> ValidationReport:
    """Like :func:`validate`, but raise ParameterError (one line, every problem) on problems.

    Parameters
    ----------
    bicycle_or_parameters : Bicycle or mapping of str to array_like
        The bicycle, or its benchmark parameters by name (SI units; arrays checked element-wise).
    source : str, optional
        The file named in the message (default: a bicycle's own source).

    Returns
    -------
    ValidationReport
        The checks' findings: no problems, possibly warnings.
    """
    report = validate(bicycle_or_parameters)
    if source is None and isinstance(bicycle_or_parameters, Bicycle):
        source = bicycle_or_parameters.source or None
    if report.problems:
        raise ParameterError("; ".join(report.problems), source)
    return report
