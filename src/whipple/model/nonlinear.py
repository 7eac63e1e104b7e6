"""The nonlinear Whipple bicycle: state derivative from the generated equations.

The generated code (``whipple.generated.whipple_nonlinear_*``, derived in
derivation/nonlinear.py) gives, for the six angle rates u = (yaw, roll, pitch, steer, rear
wheel, front wheel rates), Kane's equations ``M u' = F + C^T f`` with the front contact
constraint ``C u = 0`` (``C u' = b`` along the motion), and the holonomic constraint
``h(roll, pitch, steer) = 0`` that fixes the pitch. Here they are solved numerically:

1. the pitch by Newton's method on h (quadratic convergence from any nearby guess);
2. the dependent rates (yaw, pitch, front wheel) from ``C u = 0``, given the independent
   roll, steer and rear wheel rates;
3. the accelerations by projecting Kane's equations onto the independent rates: with
   ``u = P u_i`` (``P`` from step 2) and a particular solution ``r`` of ``C r = b``,
   ``(P^T M P) u_i' = P^T (F - M r)`` and ``u' = P u_i' + r``; the contact force f follows
   from the dependent rows.

Nothing is ever drifting off the constraints: every evaluation re-solves the pitch and the
dependent rates from the state.

State (10 entries, axes of Meijaard et al. 2007: x forward, y right, z down)::

    x, y             rear contact point on the ground [m]
    yaw, roll        of the rear frame [rad]
    steer            front frame relative to the rear frame, about the steer axis [rad]
    rear_wheel       rear wheel angle relative to the rear frame [rad]
    front_wheel      front wheel angle relative to the front frame [rad]
    roll_rate, steer_rate, rear_wheel_rate   [rad/s]

Rolling forward makes the wheel rates negative: upright at speed v the rear wheel rate is
-v / rR. Inputs: roll torque on the rear frame and steer torque (rear frame on front frame)
[N m], as in the benchmark.

Examples
--------
>>> import tomllib, importlib.resources
>>> text = importlib.resources.files("whipple.data").joinpath("benchmark.toml").read_text()
>>> parameters = tomllib.loads(text)["parameters"]
>>> state = upright_state(parameters, speed=5.0, roll_rate=0.5)
>>> state_derivative(parameters, state).shape
(10,)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import casadi
import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import AnalysisError, InputError, ParameterError
from whipple.generated import whipple_nonlinear_casadi, whipple_nonlinear_numpy

#: The 26 benchmark parameters, in the order of the generated code (Meijaard et al. 2007, Table 1).
PARAMETERS: tuple[str, ...] = tuple(whipple_nonlinear_numpy.PARAMETERS)
#: Names of the state entries.
STATES: tuple[str, ...] = ("x", "y", "yaw", "roll", "steer", "rear_wheel", "front_wheel",
                           "roll_rate", "steer_rate", "rear_wheel_rate")
#: SI unit of each state entry.
STATE_UNITS: dict[str, str] = {name: "m" if name in ("x", "y") else "rad/s" if name.endswith("rate") else "rad"
                               for name in STATES}
#: Names of the inputs [N m].
INPUTS: tuple[str, ...] = ("roll_torque", "steer_torque")
#: The six angle rates u of the generated equations, in their order.
RATES: tuple[str, ...] = tuple(whipple_nonlinear_numpy.VARIABLES["dynamics"][3:9])
#: Positions in u of the independent (roll, steer, rear wheel) and dependent rates.
INDEPENDENT, DEPENDENT = (1, 3, 4), (0, 2, 5)

# Newton's method for the pitch: a step below this [rad] is at the level of rounding.
_PITCH_STEP_TOLERANCE = 1e-15
_PITCH_MAX_ITERATIONS = 30
# A front contact height above this [m] after Newton's method means no solution.
_CONTACT_TOLERANCE = 1e-9


class Motion(NamedTuple):
    """Everything the equations give at one state (leading axes broadcast).

    Attributes
    ----------
    pitch : ndarray
        Rear frame pitch solving the holonomic constraint [rad].
    rates : ndarray, shape (..., 6)
        u = yaw, roll, pitch, steer, rear wheel, front wheel rates [rad/s].
    accelerations : ndarray, shape (..., 6)
        u' [rad/s^2].
    contact_force : ndarray, shape (..., 3)
        Force of the ground on the front wheel, along the yaw frame's x, y, z (z down) [N].
    rear_contact_velocity : ndarray, shape (..., 2)
        (x', y') of the rear contact point [m/s].
    """

    pitch: NDArray[np.float64]
    rates: NDArray[np.float64]
    accelerations: NDArray[np.float64]
    contact_force: NDArray[np.float64]
    rear_contact_velocity: NDArray[np.float64]


def _parameter_arrays(parameters: Mapping[str, ArrayLike]) -> list[NDArray[np.float64]]:
    missing = [name for name in PARAMETERS if name not in parameters]
    if missing:
        raise ParameterError(f"the nonlinear model needs all 26 benchmark parameters; missing {', '.join(missing)}")
    return [np.asarray(parameters[name], dtype=float) for name in PARAMETERS]


def _state_array(state: ArrayLike) -> NDArray[np.float64]:
    array = np.asarray(state, dtype=float)
    if array.ndim == 0 or array.shape[-1] != len(STATES):
        raise InputError(f"a state has {len(STATES)} entries ({', '.join(STATES)}), got shape {array.shape}")
    return array


def solve_pitch(parameters: Mapping[str, ArrayLike], roll: ArrayLike, steer: ArrayLike,
                guess: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Pitch of the rear frame that puts the front wheel on the ground.

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters (SI units), arrays broadcast against the angles.
    roll, steer : array_like
        Roll and steer angles [rad].
    guess : array_like
        Starting pitch for Newton's method [rad]; 0 (the reference configuration) converges
        for all but extreme roll and steer angles.

    Returns
    -------
    ndarray
        Pitch [rad], zero in the upright reference configuration.

    Raises
    ------
    AnalysisError
        Newton's method does not converge (no contact: e.g. the bicycle lies on the ground).
    """
    p = _parameter_arrays(parameters)
    roll_, steer_ = np.asarray(roll, dtype=float), np.asarray(steer, dtype=float)
    pitch = np.broadcast_to(np.asarray(guess, dtype=float), np.broadcast_shapes(
        roll_.shape, steer_.shape, np.shape(guess), *(a.shape for a in p))).copy()
    for _ in range(_PITCH_MAX_ITERATIONS):
        height, gradient = whipple_nonlinear_numpy.contact_height(*p, roll_, pitch, steer_)
        step = height / gradient[..., 1]
        pitch = pitch - step
        if np.all(np.abs(step) <= _PITCH_STEP_TOLERANCE * np.maximum(1.0, np.abs(pitch))):
            return pitch
    if not np.all(np.isfinite(pitch)) or np.max(np.abs(step)) > 1e-12:
        raise AnalysisError("the pitch does not converge: no configuration with both wheels on the ground "
                            "near this roll and steer")
    return pitch


def _rate_projection(C: NDArray[np.float64]) -> NDArray[np.float64]:
    """P of u = P u_i: the identity on the independent rates, -C_d^-1 C_i on the dependent ones."""
    C_d, C_i = C[..., list(DEPENDENT)], C[..., list(INDEPENDENT)]
    P = np.zeros(C.shape[:-2] + (6, 3))
    P[..., list(INDEPENDENT), :] = np.eye(3)
    P[..., list(DEPENDENT), :] = -np.linalg.solve(C_d, C_i)
    return P


def dependent_rates(parameters: Mapping[str, ArrayLike], roll: ArrayLike, pitch: ArrayLike, steer: ArrayLike,
                    independent: ArrayLike) -> NDArray[np.float64]:
    """All six rates u from the independent roll, steer and rear wheel rates.

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters (SI units).
    roll, pitch, steer : array_like
        Angles [rad]; the pitch must solve the holonomic constraint (:func:`solve_pitch`).
    independent : array_like, shape (..., 3)
        Roll, steer and rear wheel rates [rad/s].

    Returns
    -------
    ndarray, shape (..., 6)
        Yaw, roll, pitch, steer, rear wheel and front wheel rates [rad/s].
    """
    p = _parameter_arrays(parameters)
    C = whipple_nonlinear_numpy.constraints(*p, roll, pitch, steer)[0]
    u_i = np.asarray(independent, dtype=float)
    return np.einsum("...ij,...j->...i", _rate_projection(C), u_i)


def singularity_measure(parameters: Mapping[str, ArrayLike], roll: ArrayLike, pitch: ArrayLike,
                        steer: ArrayLike) -> NDArray[np.float64]:
    """How far the velocity constraints are from singular: 1 upright, 0 where they fail.

    The ratio of det C_d, the constraints' matrix for the dependent (yaw, pitch, front wheel)
    rates, to its value in the reference configuration. It vanishes where the front wheel's
    path on the ground points through the rear contact (a steer angle near 90 degrees): the
    yaw rate the wheels demand is unbounded there unless the rear wheel stands still.

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters (SI units).
    roll, pitch, steer : array_like
        Angles [rad], the pitch solving the holonomic constraint.
    """
    p = _parameter_arrays(parameters)
    C = whipple_nonlinear_numpy.constraints(*p, roll, pitch, steer)[0][..., list(DEPENDENT)]
    reference = whipple_nonlinear_numpy.constraints(*p, 0.0, 0.0, 0.0)[0][..., list(DEPENDENT)]
    return np.linalg.det(C) / np.linalg.det(reference)


def motion(parameters: Mapping[str, ArrayLike], state: ArrayLike, inputs: ArrayLike | None = None,
           pitch_guess: ArrayLike = 0.0) -> Motion:
    """Pitch, rates, accelerations and front contact force at a state.

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters (SI units), arrays broadcast against the state.
    state : array_like, shape (..., 10)
        See :data:`STATES`.
    inputs : array_like, shape (..., 2), optional
        Roll and steer torque [N m]; zero by default.
    pitch_guess : array_like
        Starting value for the pitch [rad].
    """
    x = _state_array(state)
    p = _parameter_arrays(parameters)
    torques = np.zeros(2) if inputs is None else np.asarray(inputs, dtype=float)
    roll, steer = x[..., 3], x[..., 4]
    pitch = solve_pitch(parameters, roll, steer, pitch_guess)
    C = whipple_nonlinear_numpy.constraints(*p, roll, pitch, steer)[0]
    P = _rate_projection(C)
    u = np.einsum("...ij,...j->...i", P, x[..., 7:10])
    M, F, b = whipple_nonlinear_numpy.dynamics(*p, roll, pitch, steer, *np.moveaxis(u, -1, 0),
                                               torques[..., 0], torques[..., 1])
    # A particular solution of C r = b, zero in the independent rates.
    r = np.zeros(b.shape[:-1] + (6,))
    r[..., list(DEPENDENT)] = np.linalg.solve(C[..., list(DEPENDENT)], b[..., None])[..., 0]
    Pt = np.swapaxes(P, -1, -2)
    reduced_mass = Pt @ M @ P
    reduced_force = np.einsum("...ij,...j->...i", Pt, F - np.einsum("...ij,...j->...i", M, r))
    u_i_dot = np.linalg.solve(reduced_mass, reduced_force[..., None])[..., 0]
    u_dot = np.einsum("...ij,...j->...i", P, u_i_dot) + r
    # M u' - F = C^T f: the dependent rows determine f.
    residual = np.einsum("...ij,...j->...i", M, u_dot) - F
    force = np.linalg.solve(np.swapaxes(C[..., list(DEPENDENT)], -1, -2),
                            residual[..., list(DEPENDENT), None])[..., 0]
    velocity = whipple_nonlinear_numpy.rear_contact_velocity(*p, x[..., 2], u[..., 2], u[..., 4])[0]
    return Motion(pitch, u, u_dot, force, velocity)


def state_derivative(parameters: Mapping[str, ArrayLike], state: ArrayLike, inputs: ArrayLike | None = None,
                     pitch_guess: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Time derivative of the state (see :data:`STATES`), shape (..., 10).

    Arguments as for :func:`motion`. Units: [m/s] for x and y, [rad/s] for the angles,
    [rad/s^2] for the rates.
    """
    result = motion(parameters, state, inputs, pitch_guess)
    u, u_dot = result.rates, result.accelerations
    return np.concatenate([result.rear_contact_velocity, u[..., [0, 1, 3, 4, 5]],
                           u_dot[..., list(INDEPENDENT)]], axis=-1)


def energy(parameters: Mapping[str, ArrayLike], state: ArrayLike,
           pitch_guess: ArrayLike = 0.0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Kinetic and potential energy [J] at a state (potential zero with all mass on the ground)."""
    x = _state_array(state)
    p = _parameter_arrays(parameters)
    roll, steer = x[..., 3], x[..., 4]
    pitch = solve_pitch(parameters, roll, steer, pitch_guess)
    u = dependent_rates(parameters, roll, pitch, steer, x[..., 7:10])
    return whipple_nonlinear_numpy.energy(*p, roll, pitch, steer, *np.moveaxis(u, -1, 0))


def upright_state(parameters: Mapping[str, float], speed: float, roll: float = 0.0, steer: float = 0.0,
                  roll_rate: float = 0.0, steer_rate: float = 0.0) -> NDArray[np.float64]:
    """Return a state at the origin, heading along x, with rear wheel rate -speed / rR.

    Parameters
    ----------
    parameters : mapping
        The benchmark parameters (only rR is used) [m].
    speed : float
        Forward speed of the rear contact when the pitch rate is zero [m/s].
    roll, steer : float
        Angles [rad] (the pitch is solved where needed).
    roll_rate, steer_rate : float
        [rad/s].
    """
    if not np.isfinite(speed):
        raise InputError(f"speed must be finite, got {speed}")
    rear_rate = -speed / float(parameters["rR"])
    return np.array([0.0, 0.0, 0.0, roll, steer, 0.0, 0.0, roll_rate, steer_rate, rear_rate])


def _casadi_pitch() -> casadi.Function:
    """(roll, steer, p) -> pitch, differentiable; NaN where Newton's method finds no contact.

    CasADi's rootfinder is told not to raise (it would print its inputs to stderr when nested
    in another function); a pitch that leaves the front wheel off the ground becomes NaN.
    """
    pitch = casadi.SX.sym("pitch")
    data = casadi.SX.sym("data", 2 + len(PARAMETERS))
    height = whipple_nonlinear_casadi.contact_height(data[2:], casadi.vertcat(data[0], pitch, data[1]))[0]
    residual = casadi.Function("contact_height", [pitch, data], [height])
    newton = casadi.rootfinder("pitch_newton", "newton", residual,
                               {"abstol": 1e-15, "abstolStep": _PITCH_STEP_TOLERANCE,
                                "max_iter": _PITCH_MAX_ITERATIONS, "error_on_fail": False})
    data_mx = casadi.MX.sym("data", 2 + len(PARAMETERS))
    solution = newton(0, data_mx)
    solved = casadi.fabs(residual(solution, data_mx)) <= _CONTACT_TOLERANCE
    return casadi.Function("pitch", [data_mx], [casadi.if_else(solved, solution, casadi.MX.nan())])


def _casadi_equations(p, angles, u_i, torques):
    """u, the particular solution r of C r = b, P, M and F at (roll, pitch, steer) = angles (SX)."""
    C = whipple_nonlinear_casadi.constraints(p, angles)[0]
    C_d, C_i = C[:, list(DEPENDENT)], C[:, list(INDEPENDENT)]
    T = -casadi.solve(C_d, C_i)
    P = casadi.SX.zeros(6, 3)
    for row, k in enumerate(INDEPENDENT):
        P[k, row] = 1
    for row, k in enumerate(DEPENDENT):
        P[k, :] = T[row, :]
    u = P @ u_i
    M, F, b = whipple_nonlinear_casadi.dynamics(p, casadi.vertcat(angles, u, torques))
    r = casadi.SX.zeros(6)
    r_d = casadi.solve(C_d, b)
    for row, k in enumerate(DEPENDENT):
        r[k] = r_d[row]
    return u, r, P, M, F


def _derivative_given_pitch() -> casadi.Function:
    """(p, state, inputs, pitch) -> state derivative, for the pitch that solves h = 0 (SX)."""
    p = casadi.SX.sym("p", len(PARAMETERS))
    x = casadi.SX.sym("state", len(STATES))
    torques = casadi.SX.sym("inputs", 2)
    pitch = casadi.SX.sym("pitch")
    u, r, P, M, F = _casadi_equations(p, casadi.vertcat(x[3], pitch, x[4]), x[7:10], torques)
    u_dot = P @ casadi.solve(P.T @ M @ P, P.T @ (F - M @ r)) + r
    velocity = whipple_nonlinear_casadi.rear_contact_velocity(p, casadi.vertcat(x[2], u[2], u[4]))[0]
    derivative = casadi.vertcat(velocity, u[[0, 1, 3, 4, 5]], u_dot[list(INDEPENDENT)])
    return casadi.Function("derivative_given_pitch", [p, x, torques, pitch], [derivative])


def _residual_given_pitch() -> casadi.Function:
    """(p, roll and steer, rates, accelerations, inputs, pitch) -> P^T (M u' - F) (SX)."""
    p = casadi.SX.sym("p", len(PARAMETERS))
    angles = casadi.SX.sym("angles", 2)
    u_i = casadi.SX.sym("rates", 3)
    u_i_dot = casadi.SX.sym("accelerations", 3)
    torques = casadi.SX.sym("inputs", 2)
    pitch = casadi.SX.sym("pitch")
    u, r, P, M, F = _casadi_equations(p, casadi.vertcat(angles[0], pitch, angles[1]), u_i, torques)
    residual = P.T @ (M @ (P @ u_i_dot + r) - F)
    return casadi.Function("residual_given_pitch", [p, angles, u_i, u_i_dot, torques, pitch], [residual])


def casadi_state_derivative() -> casadi.Function:
    """Return the state derivative as a differentiable CasADi function.

    Returns
    -------
    casadi.Function
        ``(p, state, inputs) -> (derivative, pitch)`` with p the 26 parameters in the order of
        :data:`PARAMETERS`, state as :data:`STATES`, inputs the roll and steer torques [N m].
        The pitch is found by a CasADi rootfinder (Newton from 0), so derivatives with respect
        to roll and steer include the pitch's dependence on them (implicit function theorem).
        Where no pitch puts the front wheel on the ground, the outputs are NaN.
    """
    p = casadi.MX.sym("p", len(PARAMETERS))
    x = casadi.MX.sym("state", len(STATES))
    torques = casadi.MX.sym("inputs", 2)
    pitch = _casadi_pitch()(casadi.vertcat(x[3], x[4], p))
    derivative = _derivative_given_pitch()(p, x, torques, pitch)
    return casadi.Function("whipple_nonlinear", [p, x, torques], [derivative, pitch],
                           ["p", "state", "inputs"], ["derivative", "pitch"])


def casadi_reduced_equations() -> casadi.Function:
    """Return the equations of the independent rates with the torques left out, as a CasADi function.

    Returns
    -------
    casadi.Function
        ``(p, state) -> (kinematics, mass, force, pitch)``: ``kinematics`` (7) the derivatives
        of x, y [m/s] and of the seven angles [rad/s] (the first seven entries of the state
        derivative); ``mass`` (3x3) [kg m^2] and ``force`` (3) [N m] of
        ``mass @ a = force + tau``, with ``a`` the roll, steer and rear wheel accelerations
        [rad/s^2] and ``tau`` the roll torque, the steer torque and a torque of the rear frame
        on the rear wheel about its axle [N m]. Each torque enters its own row only: the
        independent rates' rows of the rate projection are the identity, and a hub torque
        does no virtual work on any other rate (its reaction on the frame cancels its action
        on the wheel in every other partial angular velocity). With the accelerations known,
        any of them can be prescribed and the corresponding torque solved for (a drive that
        holds the rear wheel rate, a hand that holds roll and steer). The pitch is solved as
        in :func:`casadi_state_derivative`; NaN where no pitch puts the front wheel on the ground.
    """
    p = casadi.MX.sym("p", len(PARAMETERS))
    x = casadi.MX.sym("state", len(STATES))
    pitch = _casadi_pitch()(casadi.vertcat(x[3], x[4], p))
    kinematics, mass, force = _reduced_given_pitch()(p, x, pitch)
    return casadi.Function("whipple_nonlinear_reduced", [p, x], [kinematics, mass, force, pitch],
                           ["p", "state"], ["kinematics", "mass", "force", "pitch"])


def _reduced_given_pitch() -> casadi.Function:
    """(p, state, pitch) -> kinematics, P^T M P and P^T (F - M r) without torques (SX)."""
    p = casadi.SX.sym("p", len(PARAMETERS))
    x = casadi.SX.sym("state", len(STATES))
    pitch = casadi.SX.sym("pitch")
    u, r, P, M, F = _casadi_equations(p, casadi.vertcat(x[3], pitch, x[4]), x[7:10], casadi.SX.zeros(2))
    velocity = whipple_nonlinear_casadi.rear_contact_velocity(p, casadi.vertcat(x[2], u[2], u[4]))[0]
    kinematics = casadi.vertcat(velocity, u[[0, 1, 3, 4, 5]])
    return casadi.Function("reduced_given_pitch", [p, x, pitch], [kinematics, P.T @ M @ P, P.T @ (F - M @ r)])


def casadi_residual() -> casadi.Function:
    """Kane's equations of the independent rates in residual form, as a CasADi function.

    Returns
    -------
    casadi.Function
        ``(p, angles, rates, accelerations, inputs) -> residual``: angles are roll and steer
        [rad], rates and accelerations those of roll, steer and the rear wheel [rad/s,
        rad/s^2], inputs the roll and steer torques [N m]. The residual ``P^T (M u' - F)``
        [N m] (roll, steer, rear wheel rows) vanishes along every motion; its derivatives are
        the linearized equations (``M q'' + v C1 q' + (K0 + v^2 K2) q - f`` in the roll and
        steer rows about upright straight-ahead motion). The pitch is solved as in
        :func:`casadi_state_derivative`.
    """
    p = casadi.MX.sym("p", len(PARAMETERS))
    angles = casadi.MX.sym("angles", 2)
    rates = casadi.MX.sym("rates", 3)
    accelerations = casadi.MX.sym("accelerations", 3)
    torques = casadi.MX.sym("inputs", 2)
    pitch = _casadi_pitch()(casadi.vertcat(angles, p))
    residual = _residual_given_pitch()(p, angles, rates, accelerations, torques, pitch)
    return casadi.Function("whipple_nonlinear_residual", [p, angles, rates, accelerations, torques], [residual],
                           ["p", "angles", "rates", "accelerations", "inputs"], ["residual"])


def parameter_vector(parameters: Mapping[str, ArrayLike]) -> NDArray[np.float64]:
    """Return the 26 parameters as a vector in the order of :data:`PARAMETERS` (for the CasADi functions)."""
    arrays = _parameter_arrays(parameters)
    if any(array.ndim for array in arrays):
        raise InputError("parameter_vector takes one parameter set (scalar values)")
    return np.array([array.item() for array in arrays], dtype=float)


#: Parameters the linear model does not need, estimated when absent: name -> (Ixx, Izz).
PLANAR_ESTIMATES = {"IByy": ("IBxx", "IBzz"), "IHyy": ("IHxx", "IHzz")}


def with_planar_estimates(parameters: Mapping[str, float]) -> tuple[dict[str, float], tuple[str, ...]]:
    """Return the parameters with IByy and IHyy estimated where absent, and which were.

    A frame lying in its plane of symmetry has ``Iyy = Ixx + Izz`` [kg m^2] (perpendicular-axis
    theorem); the linear model does not need these inertias, the nonlinear one only through the
    pitch motion (second order in the lateral motion).
    """
    completed = dict(parameters)
    estimated = []
    for name, (xx, zz) in PLANAR_ESTIMATES.items():
        if name not in completed:
            completed[name] = float(completed[xx]) + float(completed[zz])
            estimated.append(name)
    return completed, tuple(estimated)
