"""Simulate the nonlinear Whipple bicycle (scipy's solve_ivp on the 10-entry state).

The state (:data:`whipple.model.nonlinear.STATES`) holds only free coordinates and the
independent rates: at every evaluation of the derivative the pitch is re-solved from the
holonomic constraint (Newton's method to rounding) and the dependent rates from the velocity
constraints. The constraints therefore cannot drift; what the result reports as drift is their
residual at the output samples, evaluated independently with the generated NumPy code (the
integration uses the CasADi functions, about ten times faster per evaluation). The total
energy is reported too: without inputs it is conserved, so its change measures the
integration error.

Examples
--------
>>> from whipple.model.parameters import load_bicycle
>>> from whipple.model.nonlinear import upright_state
>>> parameters = load_bicycle("benchmark").parameters
>>> result = simulate(parameters, upright_state(parameters, 5.0, roll_rate=0.3), duration=1.0)
>>> result.states.shape
(101, 10)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from whipple.errors import AnalysisError, InputError
from whipple.generated import whipple_nonlinear_numpy
from whipple.model.nonlinear import (
    PARAMETERS,
    STATES,
    casadi_state_derivative,
    dependent_rates,
    energy,
    parameter_vector,
    singularity_measure,
    solve_pitch,
)

#: The simulation stops where |singularity_measure| falls to this: within about half a degree
#: of steer of the configuration where the rolling constraints demand an unbounded yaw rate.
SINGULARITY_THRESHOLD = 0.01
#: Evaluations of the derivative after which the integration is abandoned (it would otherwise
#: crawl on for ever near a singular configuration).
MAX_EVALUATIONS = 500_000

#: Inputs: None (no torques), a constant pair, or a function of time [s] and state giving the
#: roll and steer torques [N m].
Inputs = None | ArrayLike | Callable[[float, NDArray[np.float64]], ArrayLike]


@dataclass(frozen=True)
class NonlinearSimulation:
    """A simulated motion and how well it keeps the constraints and the energy.

    Attributes
    ----------
    time : ndarray, shape (n,)
        Sample times [s].
    states : ndarray, shape (n, 10)
        States at the samples (see :data:`whipple.model.nonlinear.STATES`).
    pitch : ndarray, shape (n,)
        Rear frame pitch solving the holonomic constraint [rad].
    rates : ndarray, shape (n, 6)
        Yaw, roll, pitch, steer, rear and front wheel rates [rad/s].
    energy : ndarray, shape (n,)
        Kinetic plus potential energy [J].
    holonomic_drift : float
        Largest |front contact height| at the samples [m].
    velocity_drift : float
        Largest |front contact velocity| at the samples [m/s].
    energy_drift : float
        Largest |energy - initial energy| over the samples, relative to the initial kinetic
        energy (meaningful without inputs, when the energy is conserved).
    evaluations : int
        Evaluations of the state derivative.
    stop_reason : str
        ``"duration"`` (ran to the end), ``"fallen"`` (|roll| reached ``max_roll``) or
        ``"singular"`` (the steer angle reached the singular configuration of the rolling
        constraints, see :func:`whipple.model.nonlinear.singularity_measure`); the samples end
        at the stop.
    """

    time: NDArray[np.float64]
    states: NDArray[np.float64]
    pitch: NDArray[np.float64]
    rates: NDArray[np.float64]
    energy: NDArray[np.float64]
    holonomic_drift: float
    velocity_drift: float
    energy_drift: float
    evaluations: int
    stop_reason: str


def _input_function(inputs: Inputs) -> Callable[[float, NDArray[np.float64]], NDArray[np.float64]]:
    if inputs is None:
        return lambda t, x: np.zeros(2)
    if callable(inputs):
        return lambda t, x: np.asarray(inputs(t, x), dtype=float).reshape(2)
    constant = np.asarray(inputs, dtype=float)
    if constant.shape != (2,) or not np.all(np.isfinite(constant)):
        raise InputError(f"inputs must be two finite torques [N m] (roll, steer), got {inputs!r}")
    return lambda t, x: constant


def simulate(
    parameters: Mapping[str, float],
    initial_state: ArrayLike,
    duration: float,
    sample_rate: float = 100.0,
    inputs: Inputs = None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str = "DOP853",
    max_roll: float = 1.4,
) -> NonlinearSimulation:
    """Integrate the nonlinear equations from ``initial_state``.

    Parameters
    ----------
    parameters : mapping
        The 26 benchmark parameters [SI].
    initial_state : array_like, shape (10,)
        See :data:`whipple.model.nonlinear.STATES` (angles [rad], rates [rad/s], x, y [m]).
    duration : float
        Simulated time [s].
    sample_rate : float
        Output samples per second [Hz]; samples at 0, 1/rate, ..., duration.
    inputs : None, array_like (2,) or callable
        Roll and steer torques [N m]: none, constant, or ``inputs(t, state)``.
    rtol, atol : float
        Tolerances of solve_ivp (absolute in the state's units).
    method : str
        solve_ivp method (an explicit high-order one suits this non-stiff system).
    max_roll : float
        The simulation stops when |roll| reaches this [rad]: the model has no contact of the
        frame with the ground, and the bicycle has fallen over long before.

    Raises
    ------
    InputError
        Non-finite initial state, non-positive duration or sample rate, bad inputs.
    AnalysisError
        The integration fails, or the pitch cannot be solved (both wheels cannot touch the
        ground, e.g. the bicycle has fallen over).
    """
    x0 = np.asarray(initial_state, dtype=float)
    if x0.shape != (len(STATES),) or not np.all(np.isfinite(x0)):
        raise InputError(f"initial state must be {len(STATES)} finite values ({', '.join(STATES)})")
    if not (np.isfinite(max_roll) and 0 < max_roll < np.pi / 2):
        raise InputError(f"max_roll must be between 0 and pi/2 rad, got {max_roll}")
    if abs(x0[3]) >= max_roll:
        raise InputError(f"the initial roll {x0[3]:.3g} rad is beyond max_roll {max_roll:.3g} rad")
    if not (np.isfinite(duration) and duration > 0 and np.isfinite(sample_rate) and sample_rate > 0):
        raise InputError(f"duration and sample rate must be positive, got {duration} s and {sample_rate} Hz")
    torques = _input_function(inputs)
    p = parameter_vector(parameters)
    derivative = casadi_state_derivative()
    count = [0]
    pitch_guess = [0.0]

    def rhs(t: float, x: NDArray[np.float64]) -> NDArray[np.float64]:
        count[0] += 1
        if count[0] > MAX_EVALUATIONS:
            raise AnalysisError(f"the integration needs more than {MAX_EVALUATIONS} evaluations (at t = {t:.4g} s)")
        value = np.asarray(derivative(p, x, torques(t, x))[0], dtype=float).ravel()
        if not np.all(np.isfinite(value)):
            raise AnalysisError(f"at t = {t:.4g} s no pitch puts the front wheel on the ground "
                                f"(roll {x[3]:.3g} rad, steer {x[4]:.3g} rad)")
        return value

    def fallen(t: float, x: NDArray[np.float64]) -> float:
        return max_roll - abs(x[3])

    def singular(t: float, x: NDArray[np.float64]) -> float:
        pitch_guess[0] = float(solve_pitch(parameters, x[3], x[4], pitch_guess[0]))
        return abs(float(singularity_measure(parameters, x[3], pitch_guess[0], x[4]))) - SINGULARITY_THRESHOLD

    for event in (fallen, singular):
        event.terminal = True  # type: ignore[attr-defined]
    if singular(0.0, x0) <= 0:
        raise InputError("the initial state is at the singular configuration of the rolling constraints "
                         f"(steer {x0[4]:.3g} rad)")
    times = np.arange(int(np.floor(duration * sample_rate + 1e-9)) + 1) / sample_rate
    solution = solve_ivp(rhs, (0.0, float(times[-1])), x0, method=method, t_eval=times, rtol=rtol, atol=atol,
                         events=(fallen, singular))
    if not solution.success:
        raise AnalysisError(f"the integration failed: {solution.message}")
    reason = "duration"
    if solution.status == 1:
        reason = "fallen" if solution.t_events[0].size else "singular"
    return with_diagnostics(parameters, solution.t, solution.y.T, count[0], reason)


def with_diagnostics(parameters: Mapping[str, float], times: NDArray[np.float64], states: NDArray[np.float64],
                     evaluations: int, stop_reason: str) -> NonlinearSimulation:
    """Return a simulation's samples with the pitch, rates, energy and constraint residuals.

    Evaluated with the generated NumPy code, independently of the CasADi functions that
    integrate the equations. ``times`` [s] and ``states`` (n, 10) are the samples;
    ``evaluations`` and ``stop_reason`` are passed on (see :class:`NonlinearSimulation`).
    """
    roll, steer = states[:, 3], states[:, 4]
    pitch = solve_pitch(parameters, roll, steer)
    rates = dependent_rates(parameters, roll, pitch, steer, states[:, 7:10])
    p = [np.asarray(parameters[name], dtype=float) for name in PARAMETERS]
    height = whipple_nonlinear_numpy.contact_height(*p, roll, pitch, steer)[0]
    C = whipple_nonlinear_numpy.constraints(*p, roll, pitch, steer)[0]
    velocity = np.einsum("...ij,...j->...i", C, rates)
    kinetic, potential = energy(parameters, states, pitch_guess=pitch)
    total = kinetic + potential
    return NonlinearSimulation(
        time=times, states=states, pitch=pitch, rates=rates, energy=total,
        holonomic_drift=float(np.max(np.abs(height))), velocity_drift=float(np.max(np.abs(velocity))),
        energy_drift=float(np.max(np.abs(total - total[0])) / max(float(kinetic[0]), np.finfo(float).tiny)),
        evaluations=evaluations, stop_reason=stop_reason)
