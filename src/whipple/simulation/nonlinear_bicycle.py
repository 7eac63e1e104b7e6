"""The nonlinear bicycle with what acts on it in a run: controller, steer damping, drive, hand.

The equations of the independent rates (:func:`whipple.model.nonlinear.casadi_reduced_equations`)
are ``mass @ a = force + tau``: ``a`` the roll, steer and rear wheel accelerations, ``tau``
the roll torque, the steer torque and a torque of the rear frame on the rear wheel (a hub
drive). Each row can be driven either by a known torque or by a prescribed acceleration, the
unknown torque following from the equations:

- **roll and steer**: free, the torques of the pushes, the bicycle's controller (its state
  feedback, gains polynomials in the speed ``-rR * rear_wheel_rate``) and its steer damping;
  or held by a hand that prescribes the accelerations (the catch's spring) whatever the
  torques it takes.
- **rear wheel**: *driven*, its rate follows the scenario's speed profile (a treadmill's
  constant speed, or the ground's steady deceleration), the hub torque being whatever that
  takes, as the linear model assumes the speed given; or *free*, no hub torque, the speed
  exchanging energy with the lateral motion (on flat ground without resistance).

The linear model's speed is the rear wheel's rolling speed; in the nonlinear model the rear
contact's speed also contains the pitch rate, ``-rR (rear_wheel_rate + pitch_rate)``, which
differs from it at second order in the lateral motion.

The nonlinear model has no payloads, extra or reflected steer inertia or tyre compliance, and
its controller acts without delay or lag (its gain scale is applied): bicycles with these
extensions, or a delayed or lagging controller, are refused. Where a bicycle file lacks IByy
or IHyy (which the linear model does not need), they are estimated as for a body lying in its plane of symmetry,
``Iyy = Ixx + Izz`` (perpendicular-axis theorem; the benchmark's frames: 11 against 12 and 0.06
against 0.066 kg m^2). They enter only through the pitch motion, which is of second order in
the lateral motion; the estimate is reported wherever it is used.
"""

from __future__ import annotations

import re
from typing import Any

import casadi
import numpy as np
from numpy.typing import NDArray

from whipple.errors import AnalysisError, InputError
from whipple.model.nonlinear import (
    casadi_reduced_equations,
    parameter_vector,
    upright_state,
    with_planar_estimates,
)
from whipple.model.parameters import Bicycle
from whipple.model.steer_friction import SMOOTHING_RATE

#: Speed controls: the rear wheel rate held on the speed profile, or left free.
SPEED_CONTROLS = ("driven", "free")


def nonlinear_parameters(bicycle: Bicycle) -> tuple[dict[str, float], tuple[str, ...]]:
    """Return the bicycle's 26 parameters for the nonlinear model, and which were estimated.

    Raises
    ------
    InputError
        If the bicycle has an extension the nonlinear model does not hold (payloads, extra or
        reflected steer inertia, tyre compliance,
        linear terms) or a controller with a delay or lag; one line
        naming the bicycle's file.
    """
    extensions, controller = bicycle.extensions, bicycle.controller
    missing = [name for name, present in (("payload", extensions.payload is not None),
                                          ("front_payload", extensions.front_payload is not None),
                                          ("steer_inertia", extensions.steer_inertia != 0.0),
                                          ("reflected_steer_inertia", extensions.reflected_steer_inertia != 0.0),
                                          ("tyre_compliance", extensions.tyre_compliance is not None),
                                          ("linear_terms", extensions.linear_terms is not None))
               if present]
    source = bicycle.source or bicycle.name or None
    if missing:
        raise InputError(f"the nonlinear model has no {', '.join(missing)} extension: simulate this bicycle with "
                         "the linear model", source)
    if controller.has_dynamics():
        raise InputError("the nonlinear model's controller acts without delay or lag (controller delay "
                         f"{controller.delay:g} s, lag {controller.lag:g} s): simulate this bicycle with the "
                         "linear model", source)
    return with_planar_estimates(bicycle.parameters)


class ForcedBicycle:
    """A bicycle's nonlinear equations with its controller, steer damping and speed control.

    The state derivative with everything acting is one CasADi function per regime (free or
    held), built once per bicycle with the parameters, controller gains and damping in it:
    one call per evaluation.

    Parameters
    ----------
    bicycle : Bicycle
        Parameters, controller and steer damping (other extensions are refused, see
        :func:`nonlinear_parameters`).
    speed_control : {"driven", "free"}
        Whether the rear wheel rate is prescribed (a hub torque holds it) or free.
    """

    def __init__(self, bicycle: Bicycle, speed_control: str = "driven"):
        if speed_control not in SPEED_CONTROLS:
            raise InputError(f"speed control must be one of {', '.join(SPEED_CONTROLS)}, got {speed_control!r}")
        self.parameters, self.estimated = nonlinear_parameters(bicycle)
        self.speed_control = speed_control
        self.evaluations = 0
        self._free, self._held = _forced_functions(self.parameters, bicycle, speed_control == "driven")

    def upright(self, speed: float, roll: float = 0.0, steer: float = 0.0, roll_rate: float = 0.0,
                steer_rate: float = 0.0) -> NDArray[np.float64]:
        """Return the state upright at the origin at ``speed`` [m/s] (angles [rad], rates [rad/s])."""
        return upright_state(self.parameters, speed, roll, steer, roll_rate, steer_rate)

    def free(self, state: NDArray[np.float64], torques: NDArray[np.float64],
             rear_acceleration: float = 0.0) -> NDArray[np.float64]:
        """Return the state derivative and the power of all torques, free of the hand (shape (11,)).

        Parameters
        ----------
        state : ndarray, shape (10,)
            See :data:`whipple.model.nonlinear.STATES`.
        torques : ndarray, shape (2,)
            External roll and steer torques [N m] (pushes), added to the bicycle's own
            (controller, steer damping).
        rear_acceleration : float
            Rear wheel acceleration [rad/s^2] of a driven wheel (ignored when free).

        Returns
        -------
        ndarray, shape (11,)
            The derivative of the state (units of the state per second) and the power [W] of
            every torque acting (pushes, controller, damping, hub drive).
        """
        return self._evaluate(self._free, state, torques, np.zeros(3), rear_acceleration)

    def coasting_derivative(self, state: casadi.MX) -> casadi.MX:
        """Return the state derivative of free coasting (no pushes, no hand), a CasADi expression of `state`."""
        return self._free(state, casadi.DM.zeros(2), casadi.DM.zeros(3), 0.0)[:10]

    def held(self, state: NDArray[np.float64], torques: NDArray[np.float64], omega: float,
             wobble: NDArray[np.float64], rear_acceleration: float = 0.0) -> NDArray[np.float64]:
        """Return the derivative and power as :meth:`free`, held by a hand.

        The hand applies whatever roll and steer torques make the roll and steer accelerations
        those of a critically damped spring of natural frequency ``omega`` [rad/s] plus
        ``wobble`` [rad/s^2], and lets the external ``torques`` [N m] act on the held roll and
        steer as they would on the bicycle.
        """
        return self._evaluate(self._held, state, torques, np.append(wobble, omega), rear_acceleration)

    def _evaluate(self, function, state, torques, hand, rear_acceleration) -> NDArray[np.float64]:
        self.evaluations += 1
        try:
            value = np.asarray(function(state, torques, hand, rear_acceleration), dtype=float).ravel()
        except RuntimeError:  # CasADi's evaluation failed: no contact configuration near this state
            value = np.full(11, np.nan)
        if not np.all(np.isfinite(value)):
            raise AnalysisError(f"no pitch puts the front wheel on the ground (roll {state[3]:.3g} rad, "
                                f"steer {state[4]:.3g} rad): the bicycle has fallen over")
        return value


def _forced_functions(parameters: dict[str, float], bicycle: Bicycle,
                      driven: bool) -> tuple[casadi.Function, casadi.Function]:
    """(state, torques, hand, rear acceleration) -> (derivative, power), free and held (MX)."""
    x = casadi.MX.sym("state", 10)
    external = casadi.MX.sym("torques", 2)
    hand = casadi.MX.sym("hand", 3)  # wobble (2) [rad/s^2], natural frequency [rad/s]
    rear_acceleration = casadi.MX.sym("rear_acceleration")
    kinematics, mass, force, _ = casadi_reduced_equations()(parameter_vector(parameters), x)
    speed = -float(parameters["rR"]) * x[9]
    lateral = casadi.vertcat(x[3], x[4], x[7], x[8])  # roll, steer, roll rate, steer rate
    own = casadi.MX.zeros(2)
    for k, gains in enumerate(bicycle.controller.feedback_coefficients()):
        own += speed**k * (casadi.DM(gains) @ lateral)
    own[1] -= float(bicycle.extensions.steer_damping) * x[8]
    if bicycle.extensions.steer_friction:
        # Coulomb steer friction, the smooth law of whipple.model.steer_friction.
        own[1] -= float(bicycle.extensions.steer_friction) * casadi.tanh(x[8] / SMOOTHING_RATE)
    block, coupling = mass[:2, :2], mass[:2, 2]

    def outputs(a_rs, a_rear, tau_rs):
        accelerations = casadi.vertcat(a_rs, a_rear)
        if tau_rs is None:
            tau_rs = mass[:2, :] @ accelerations - force[:2]
        tau_rear = mass[2, :] @ accelerations - force[2] if driven else casadi.MX(0)
        power = casadi.dot(casadi.vertcat(tau_rs, tau_rear), x[7:10])
        return casadi.vertcat(kinematics, accelerations, power)

    tau_free = own + external
    if driven:
        a_free = casadi.solve(block, force[:2] + tau_free - coupling * rear_acceleration)
        free = outputs(a_free, rear_acceleration, tau_free)
    else:
        a_all = casadi.solve(mass, force + casadi.vertcat(tau_free, 0))
        free = outputs(a_all[:2], a_all[2], tau_free)
    omega = hand[2]
    a_held = (-omega**2 * casadi.vertcat(x[3], x[4]) - 2 * omega * casadi.vertcat(x[7], x[8]) + hand[:2]
              + casadi.solve(block, external))
    a_rear_held = rear_acceleration if driven else (force[2] - mass[2, :2] @ a_held) / mass[2, 2]
    held = outputs(a_held, a_rear_held, None)
    arguments = [x, external, hand, rear_acceleration]
    return (casadi.Function("forced_free", arguments, [free]), casadi.Function("forced_held", arguments, [held]))


def coast(forced: ForcedBicycle, state: NDArray[np.float64], times: NDArray[np.float64],
          rtol: float = 1e-9, atol: float = 1e-11) -> NDArray[np.float64]:
    """Integrate free coasting (controller and damping acting, the rear wheel at constant rate).

    CasADi's CVODES integrator (Adams, functional iteration: the coasting is not stiff) runs on
    the bicycle's CasADi function itself, without a Python call per evaluation. On 12 weave
    windows it took 0.33 s at tolerances 1e-10 and 1e-12, where SciPy's DOP853 took 1.44 s at
    1e-8 and 1e-10, and came 35 times closer to a reference integration (docs/diagnosis.md,
    "Linearity at the measured amplitude").

    Parameters
    ----------
    forced : ForcedBicycle
        The bicycle; a driven rear wheel keeps its rate (constant speed), a free one does not.
    state : ndarray, shape (10,)
        Initial state at ``times[0]`` (see :data:`whipple.model.nonlinear.STATES`).
    times : ndarray, shape (n,)
        Increasing sample times [s].
    rtol, atol : float
        Relative and absolute tolerances (absolute in the state's units).

    Returns
    -------
    ndarray, shape (n, 10)
        The states at ``times``.

    Raises
    ------
    InputError
        The sample times do not increase.
    AnalysisError
        The integration fails (e.g. the bicycle falls over).
    """
    times = np.asarray(times, dtype=float)
    start = np.asarray(state, dtype=float)
    if times.size < 2:
        return start[None, :].copy()
    if not np.all(np.diff(times) > 0):
        raise InputError("the coasting's sample times must increase")
    x = casadi.MX.sym("state", 10)
    derivative = forced.coasting_derivative(x)
    dae: dict[str, Any] = {"x": x, "ode": derivative}
    # A step below 1e-12 s is never needed while the bicycle rolls; without a floor CVODES
    # spends 100,000 ever smaller steps where it falls over.
    options: dict[str, Any] = {"abstol": atol, "reltol": rtol, "linear_multistep_method": "adams",
                               "nonlinear_solver_iteration": "functional", "max_num_steps": 100_000,
                               "min_step_size": 1e-12, "disable_internal_warnings": True}
    try:
        integrator = casadi.integrator("coast", "cvodes", dae, float(times[0]),
                                       list(times[1:]), options)
        later = np.asarray(integrator(x0=start)["xf"], dtype=float).T
    except RuntimeError as error:
        # Where no pitch keeps the front wheel on the ground the derivative is NaN, and CVODES
        # stops at its smallest step (the bicycle falls over).
        code = re.search(r'returned "(\w+)"', str(error))
        raise AnalysisError("the nonlinear coasting's integration failed (CVODES "
                            f"{code.group(1) if code else 'error'}): the bicycle falls over") from None
    if not np.all(np.isfinite(later)):
        raise AnalysisError("the nonlinear coasting's integration failed: the bicycle has fallen over")
    return np.vstack([start, later])
