"""Check the nonlinear equations against a published state and against the linear model.

1. Basu-Mandal, Chatterjee & Papadopoulos (2007), Table 1: at a state of the benchmark bicycle
   far from upright (35 degrees of lean, turning) they print all coordinates, rates and
   accelerations to 12-14 significant figures (``whipple/data/reference/basu-mandal2007.toml``).
   Their conventions differ: a ground frame with z up whose x axis points backwards relative to
   the benchmark's (so that y still points right), the rear wheel centre instead of the rear
   contact, the lean measured from the ground, the pitch from pi, and every angle turning the
   other way. From the published roll, steer and independent rates (roll, steer, rear wheel)
   everything else is computed here: the pitch, the dependent rates, the rear wheel centre's
   velocity and all accelerations; each is compared with its published value.
2. The Jacobian of the nonlinear equations (CasADi automatic differentiation, through the
   rootfinder of the pitch) about upright straight-ahead motion at speed v must give the
   generated linear matrices M, C1, K0, K2 (a different derivation: first-order Kane
   expansion), and the state derivative's Jacobian the state matrix built from them.
"""

from __future__ import annotations

import functools
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import resources

import casadi
import numpy as np
from numpy.typing import NDArray

from whipple.errors import InputError
from whipple.generated import whipple_nonlinear_casadi, whipple_numpy
from whipple.model.nonlinear import (
    STATES,
    casadi_residual,
    casadi_state_derivative,
    motion,
    parameter_vector,
    upright_state,
)
from whipple.model.parameters import load_bicycle

#: Absolute tolerance on the Basu-Mandal accelerations [rad/s^2, m/s^2]: they are printed to
#: 13-14 significant figures (rounding below 1e-12); 1e-10 leaves room for evaluation only.
BASU_MANDAL_TOLERANCE = 1e-10
#: Absolute tolerance on the entries of M, C1, K0 and K2 from the nonlinear equations' Jacobian.
LINEARIZATION_TOLERANCE = 1e-8
#: Speeds of the linearization check [m/s].
LINEARIZATION_SPEEDS = (0.5, 2.0, 4.0, 6.0, 10.0)


@dataclass(frozen=True)
class PublishedValue:
    """One published quantity with the value computed from the nonlinear equations."""

    name: str
    published: float
    computed: float

    @property
    def error(self) -> float:
        """Absolute difference of computed and published value."""
        return abs(self.computed - self.published)


@dataclass(frozen=True)
class BasuMandalComparison:
    """Accelerations, and the quantities computed from the published state, against Table 1."""

    accelerations: tuple[PublishedValue, ...]
    state: tuple[PublishedValue, ...]
    tolerance: float

    @property
    def max_abs_error(self) -> float:
        """Largest absolute error of the nine accelerations."""
        return max(entry.error for entry in self.accelerations)

    @property
    def passed(self) -> bool:
        """Whether every acceleration and state is within the tolerance."""
        return self.max_abs_error <= self.tolerance and max(e.error for e in self.state) <= self.tolerance

    def to_dict(self) -> dict:
        """Return the comparison as JSON-ready data."""

        def table(entries: tuple[PublishedValue, ...]) -> list[dict]:
            return [{"name": e.name, "published": e.published, "computed": e.computed, "error": e.error}
                    for e in entries]

        return {"max_abs_error": self.max_abs_error, "tolerance": self.tolerance, "passed": self.passed,
                "state_max_abs_error": max(e.error for e in self.state),
                "accelerations": table(self.accelerations), "state": table(self.state)}


def basu_mandal_reference() -> dict:
    """Return the published Table 1 (coordinates, rates, accelerations, significant figures)."""
    text = resources.files("whipple.data").joinpath("reference", "basu-mandal2007.toml").read_text("utf-8")
    return tomllib.loads(text)


def _hub_path(rear_radius: float) -> casadi.Function:
    """Rear wheel centre in the benchmark axes, and its first and second time derivatives.

    (x, y) of the rear contact, yaw and roll with their rates and accelerations; the centre is
    rR up the wheel plane from the contact.
    """
    q = casadi.SX.sym("q", 4)   # x, y, yaw, roll
    qd = casadi.SX.sym("qd", 4)
    qdd = casadi.SX.sym("qdd", 4)
    x, y, yaw, roll = casadi.vertsplit(q)
    hub = casadi.vertcat(x - rear_radius * casadi.sin(yaw) * casadi.sin(roll),
                         y + rear_radius * casadi.cos(yaw) * casadi.sin(roll),
                         -rear_radius * casadi.cos(roll))
    velocity = casadi.jtimes(hub, q, qd)
    acceleration = casadi.jtimes(velocity, q, qd) + casadi.jtimes(hub, q, qdd)
    return casadi.Function("hub", [q, qd, qdd], [hub, velocity, acceleration])


def _to_basu_mandal_axes(vector: NDArray[np.float64]) -> NDArray[np.float64]:
    """Benchmark axes (x forward, y right, z down) to the paper's (x backward, y right, z up)."""
    return np.array([-vector[0], vector[1], -vector[2]])


def compare_basu_mandal(parameters: Mapping[str, float]) -> BasuMandalComparison:
    """Compute Table 1 of Basu-Mandal et al. (2007) from the published state.

    Parameters
    ----------
    parameters : mapping
        The benchmark bicycle's 26 parameters (the paper's bicycle) [SI].
    """
    table = basu_mandal_reference()
    q, rates, published = table["coordinates"], table["rates"], table["accelerations"]
    rR = float(parameters["rR"])
    yaw, roll, steer = -q["theta"], np.pi / 2 - q["psi"], -q["psif"]
    hub_published = np.array([-q["x"], q["y"], -q["z"]])
    # The rear contact is rR down the wheel plane from the centre.
    contact = hub_published[:2] - rR * np.sin(roll) * np.array([-np.sin(yaw), np.cos(yaw)])
    state = np.array([contact[0], contact[1], yaw, roll, steer, -q["betar"], -q["betaf"],
                      -rates["psid"], -rates["psifd"], -rates["betard"]])
    result = motion(parameters, state)
    u, u_dot = result.rates, result.accelerations
    derivative = np.concatenate([result.rear_contact_velocity, u[[0, 1]]])
    second = np.concatenate([_contact_acceleration(parameters, state, u, u_dot), u_dot[[0, 1]]])
    hub, hub_velocity, hub_acceleration = (
        np.array(value, dtype=float).ravel()
        for value in _hub_path(rR)(state[[0, 1, 2, 3]], derivative, second))
    computed_state = {
        "z": _to_basu_mandal_axes(hub)[2], "phi": np.pi - float(result.pitch),
        "xd": _to_basu_mandal_axes(hub_velocity)[0], "yd": _to_basu_mandal_axes(hub_velocity)[1],
        "zd": _to_basu_mandal_axes(hub_velocity)[2],
        "thetad": -u[0], "phid": -u[2], "betafd": -u[5],
    }
    computed_accelerations = dict(zip(("xdd", "ydd", "zdd"), _to_basu_mandal_axes(hub_acceleration), strict=True))
    for name, k in (("thetadd", 0), ("psidd", 1), ("phidd", 2), ("psifdd", 3), ("betardd", 4), ("betafdd", 5)):
        computed_accelerations[name] = -u_dot[k]
    reference = {**q, **rates}
    return BasuMandalComparison(
        tuple(PublishedValue(name, float(value), float(computed_accelerations[name]))
              for name, value in published.items()),
        tuple(PublishedValue(name, float(reference[name]), float(value)) for name, value in computed_state.items()),
        BASU_MANDAL_TOLERANCE)


def _contact_acceleration(parameters: Mapping[str, float], state: NDArray[np.float64], u: NDArray[np.float64],
                          u_dot: NDArray[np.float64]) -> NDArray[np.float64]:
    """(x'', y'') of the rear contact: the derivative of the generated rear contact velocity."""
    arguments = casadi.SX.sym("arguments", 3)  # yaw, pitch rate, rear wheel rate
    velocity = whipple_nonlinear_casadi.rear_contact_velocity(parameter_vector(parameters), arguments)[0]
    rates = casadi.SX.sym("rates", 3)
    acceleration = casadi.Function("contact_acceleration", [arguments, rates],
                                   [casadi.jtimes(velocity, arguments, rates)])
    value = acceleration([state[2], u[2], u[4]], [u[0], u_dot[2], u_dot[4]])
    return np.array(value, dtype=float).ravel()


@dataclass(frozen=True)
class LinearizationCheck:
    """Largest absolute differences between the linearized nonlinear equations and the linear model.

    The Jacobian of the nonlinear equations against the generated linear model, over the
    parameter sets and speeds checked.
    """

    matrix_errors: dict[str, float]
    state_matrix_error: float
    parameter_sets: tuple[str, ...]
    speeds: tuple[float, ...]
    tolerance: float

    @property
    def max_error(self) -> float:
        """Largest difference over the matrices."""
        return max(self.matrix_errors.values())

    @property
    def passed(self) -> bool:
        """Whether matrices and state matrix agree within the tolerance."""
        return self.max_error <= self.tolerance and self.state_matrix_error <= self.tolerance

    def to_dict(self) -> dict:
        """Return the check as JSON-ready data."""
        return {"max_error": self.max_error, "matrix_errors": dict(self.matrix_errors),
                "state_matrix_max_error": self.state_matrix_error, "tolerance": self.tolerance,
                "parameter_sets": list(self.parameter_sets), "speeds": list(self.speeds), "passed": self.passed}


def _residual_jacobians() -> casadi.Function:
    """(p, rear wheel rate) -> d residual / d(angles, rates, accelerations) at upright, roll and steer rows."""
    residual = casadi_residual()
    p = casadi.MX.sym("p", residual.size1_in(0))
    rear_rate = casadi.MX.sym("rear_rate")
    angles, rates2, accelerations2 = (casadi.MX.sym(name, 2) for name in ("angles", "rates", "accelerations"))
    value = residual(p, angles, casadi.vertcat(rates2, rear_rate), casadi.vertcat(accelerations2, 0),
                     casadi.MX.zeros(2))[:2]
    jacobians = [casadi.jacobian(value, variable) for variable in (angles, rates2, accelerations2)]
    at_upright = casadi.Function("jacobians", [p, rear_rate, angles, rates2, accelerations2], jacobians)
    zero = casadi.MX.zeros(2)
    return casadi.Function("upright_jacobians", [p, rear_rate], list(at_upright(p, rear_rate, zero, zero, zero)))


def _state_matrix_function() -> casadi.Function:
    """(p, state) -> d (roll', steer', roll'', steer'') / d (roll, steer, roll rate, steer rate)."""
    derivative = casadi_state_derivative()
    p = casadi.MX.sym("p", derivative.size1_in(0))
    x = casadi.MX.sym("state", len(STATES))
    rows = [STATES.index(name) for name in ("roll", "steer", "roll_rate", "steer_rate")]
    # The derivative of roll and steer are entries 3 and 4; of their rates, 7 and 8.
    output = derivative(p, x, casadi.MX.zeros(2))[0][[3, 4, 7, 8]]
    return casadi.Function("state_matrix", [p, x], [casadi.jacobian(output, x)[:, rows]])


def _linear_state_matrix(M: NDArray[np.float64], C1: NDArray[np.float64], K0: NDArray[np.float64],
                         K2: NDArray[np.float64], speed: float) -> NDArray[np.float64]:
    inverse = np.linalg.inv(M)
    return np.block([[np.zeros((2, 2)), np.eye(2)],
                     [-inverse @ (K0 + speed**2 * K2), -speed * inverse @ C1]])


@functools.cache
def _jacobian_functions() -> tuple[casadi.Function, casadi.Function]:
    return _residual_jacobians(), _state_matrix_function()


def jacobian_matrices(parameters: Mapping[str, float], speed: float) -> tuple[NDArray[np.float64], ...]:
    """M, C1, K0, K2 from the Jacobian of the nonlinear equations (automatic differentiation).

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters [SI].
    speed : float
        Forward speed v > 0 of the upright straight-ahead motion [m/s] (C1 and K2 are the
        Jacobian's speed-dependent parts divided by v and v^2).

    Returns
    -------
    tuple of ndarray, shape (2, 2)
        M [kg m^2], C1 [kg m], K0 [N m/rad] (with gravity), K2 [kg] of
        ``M q'' + v C1 q' + (K0 + v^2 K2) q = f``, q = [roll, steer].
    """
    if not speed > 0:
        raise InputError(f"the speed must be positive to separate C1 and K2, got {speed}")
    jacobians, _ = _jacobian_functions()
    vector = parameter_vector(parameters)
    K0 = np.array(jacobians(vector, 0.0)[0], dtype=float)
    stiffness, damping, mass = (np.array(value, dtype=float)
                                for value in jacobians(vector, -speed / float(parameters["rR"])))
    return mass, damping / speed, K0, (stiffness - K0) / speed**2


def check_linearization(parameter_sets: Mapping[str, Mapping[str, float]],
                        speeds: Sequence[float] = LINEARIZATION_SPEEDS) -> LinearizationCheck:
    """Compare the nonlinear equations' Jacobian at upright straight-ahead motion with M, C1, K0, K2.

    Parameters
    ----------
    parameter_sets : mapping of name to parameter mapping
        Each with the 26 benchmark parameters [SI].
    speeds : sequence of float
        Forward speeds [m/s], all positive.
    """
    _, state_matrix = _jacobian_functions()
    errors = {"M": 0.0, "C1": 0.0, "K0": 0.0, "K2": 0.0}
    state_error = 0.0
    for parameters in parameter_sets.values():
        linear = whipple_numpy.matrices(*(parameters[name] for name in whipple_numpy.PARAMETERS))
        expected = dict(zip(errors, (np.asarray(matrix, dtype=float) for matrix in linear), strict=True))
        for speed in speeds:
            computed = dict(zip(errors, jacobian_matrices(parameters, speed), strict=True))
            for name in errors:
                errors[name] = max(errors[name], float(np.max(np.abs(computed[name] - expected[name]))))
            A = np.array(state_matrix(parameter_vector(parameters), upright_state(parameters, speed)), dtype=float)
            linear_A = _linear_state_matrix(expected["M"], expected["C1"], expected["K0"], expected["K2"], speed)
            state_error = max(state_error, float(np.max(np.abs(A - linear_A))))
    return LinearizationCheck(errors, state_error, tuple(parameter_sets), tuple(float(v) for v in speeds),
                              LINEARIZATION_TOLERANCE)


def perturbed_parameters(parameters: Mapping[str, float], count: int, seed: int = 2007,
                         spread: float = 0.1) -> dict[str, dict[str, float]]:
    """``count`` parameter sets with every parameter scaled by a uniform factor in 1 +- spread."""
    rng = np.random.default_rng(seed)
    names = sorted(parameters)
    return {f"perturbed-{k}": {name: float(parameters[name]) * (1 + spread * rng.uniform(-1, 1)) for name in names}
            for k in range(count)}


def nonlinear_report() -> dict:
    """Return the nonlinear model's checks as plain data, for ``whipple verify --json`` (key ``nonlinear``).

    Basu-Mandal et al. (2007) Table 1 at the benchmark; the linearization at the benchmark, the
    Kooijman et al. (2008) bicycle and three random perturbations of the benchmark (10 %), at
    :data:`LINEARIZATION_SPEEDS`.
    """
    benchmark = dict(load_bicycle("benchmark").parameters)
    sets = {"benchmark": benchmark, "kooijman2008": dict(load_bicycle("kooijman2008").parameters),
            **perturbed_parameters(benchmark, 3)}
    basu_mandal = compare_basu_mandal(benchmark)
    linearization = check_linearization(sets)
    return {
        "passed": basu_mandal.passed and linearization.passed,
        "max_abs_error": basu_mandal.max_abs_error,
        "linearization_max_error": max(linearization.max_error, linearization.state_matrix_error),
        "basu_mandal": {"citation": basu_mandal_reference()["source"]["citation"], **basu_mandal.to_dict()},
        "linearization": linearization.to_dict(),
    }


__all__ = ["BASU_MANDAL_TOLERANCE", "LINEARIZATION_SPEEDS", "LINEARIZATION_TOLERANCE", "BasuMandalComparison",
           "LinearizationCheck", "PublishedValue", "basu_mandal_reference", "check_linearization",
           "compare_basu_mandal", "jacobian_matrices", "nonlinear_report", "perturbed_parameters"]
