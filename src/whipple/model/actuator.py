"""The controller's actuator: gain error, pure time delay and first-order lag, as extra states.

A controller commands ``T_cmd = sum_k v^k F_k x`` (:meth:`Controller.feedback_coefficients`,
its ``gain_scale`` included). The torque that acts is ``T = G(s) T_cmd`` per torque row in use,
with ``G(s) = exp(-s delay) / (1 + s lag)``. The lag is one state per row,
``T' = (T_cmd - T) / lag``. The delay is not rational; it is replaced by its Pade approximant
of order :data:`PADE_ORDER`, ``exp(-s tau) ~ Q(-s tau) / Q(s tau)``, realised in states of unit
N m (time scaled by tau, so the realisation's matrices are dimensionless), in series before the
lag.

The extra states have constant coefficients, so ``A(v)`` stays a polynomial in v and every
analysis (eigenvalues, critical speeds from characteristic coefficients polynomial in v, the
linear simulator, the diagnosis) sees them without change. :func:`delay_eigenvalue` solves the
exact characteristic equation with ``exp(-s tau)`` by Newton's method, to check the
approximant (tests/test_actuator.py). On the weave of sbw2024 at 3 m/s the error of orders 1, 2, 3,
4 is 0.26, 3.4e-3, 2.0e-5, 6e-8 1/s with a 0.1 s delay and 0.71, 2.1e-2, 3.1e-4, 2.6e-6 1/s
with 0.2 s, against a change of the weave by the delay of several 1/s.

Why order 3: the approximant's phase error at ``w tau`` grows like ``(w tau)^(2n+1)``. The
weave of the bicycles here is at 3-10 rad/s and the delays worth diagnosing are up to 0.3 s,
so ``w tau`` reaches about 2: the weave is then off by tens of percent of the delay's effect at
order 1, by about one percent at order 2 and by well under 0.1 percent at order 3, below the
measurement's uncertainty; order 3 costs three states per torque row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.model.first_order import NUMPY_OPS, actuator_coefficients
from whipple.model.linear import LinearModel
from whipple.model.parameter_set import Controller

#: Order of the Pade approximant of the controller's time delay (numerator and denominator).
PADE_ORDER = 3
_ROW_NAMES = ("roll_torque", "steer_torque")


@dataclass(frozen=True)
class Actuator:
    """A single-input single-output linear system ``z' = a z + b u``, ``y = c z + d u``.

    Attributes
    ----------
    a : ndarray, shape (m, m)
        State matrix [1/s].
    b : ndarray, shape (m, 1)
        Input matrix [1/s].
    c : ndarray, shape (1, m)
        Output matrix [-].
    d : float
        Feedthrough [-].
    states : tuple of str
        Name of each state (all in N m).
    """

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    c: NDArray[np.float64]
    d: float
    states: tuple[str, ...]


def pade_denominator(order: int) -> NDArray[np.float64]:
    """Coefficients ``q_k`` of ``Q(x) = sum_k q_k x^k`` with ``exp(-x) ~ Q(-x) / Q(x)``, ``q_0 = 1``.

    ``q_k = (2n - k)! n! / ((2n)! k! (n - k)!)`` for the diagonal approximant of order n.
    """
    n = order
    return np.array([math.factorial(2 * n - k) * math.factorial(n)
                     / (math.factorial(2 * n) * math.factorial(k) * math.factorial(n - k)) for k in range(n + 1)])


def _pade(delay: float, order: int) -> Actuator:
    q = pade_denominator(order)
    alpha = q[:-1] / q[-1]  # Q monic: x^n + alpha_(n-1) x^(n-1) + ... + alpha_0
    beta = (q * (-1.0) ** np.arange(order + 1))[:-1] / q[-1]  # Q(-x) / q_n, without its x^n term
    d = (-1.0) ** order
    a = np.zeros((order, order))
    a[:-1, 1:] = np.eye(order - 1)
    a[-1, :] = -alpha
    b = np.zeros((order, 1))
    b[-1, 0] = 1.0
    c = (beta - d * alpha)[None, :]
    return Actuator(a / delay, b / delay, c, d, tuple(f"delay{k + 1}" for k in range(order)))


def actuator_realisation(delay: float, lag: float, order: int = PADE_ORDER) -> Actuator:
    """Return the actuator of one torque row: the delay's Pade approximant, then the lag.

    Parameters
    ----------
    delay : float
        Pure time delay [s]; 0 for none.
    lag : float
        First-order lag time constant [s]; 0 for none.
    order : int
        Order of the Pade approximant (>= 1).

    Returns
    -------
    Actuator
        With no state at all when both are zero (``y = u``).
    """
    if order < 1:
        raise ValueError(f"the Pade order must be at least 1, got {order}")
    system = _pade(delay, order) if delay > 0 else Actuator(np.zeros((0, 0)), np.zeros((0, 1)),
                                                           np.zeros((1, 0)), 1.0, ())
    if lag <= 0:
        return system
    m = system.a.shape[0]
    a = np.zeros((m + 1, m + 1))
    a[:m, :m] = system.a
    a[m, :m] = system.c[0] / lag
    a[m, m] = -1.0 / lag
    b = np.vstack([system.b, [[system.d / lag]]])
    c = np.zeros((1, m + 1))
    c[0, m] = 1.0
    return Actuator(a, b, c, 0.0, system.states + ("lag",))


def used_rows(controller: Controller) -> tuple[int, ...]:
    """Torque rows (0 roll, 1 steer) with a nonzero gain: each gets its own actuator states."""
    gains = controller.feedback_coefficients()
    return tuple(row for row in (0, 1) if any(np.any(gain[row] != 0) for gain in gains))


def with_actuator(plant: LinearModel, controller: Controller, order: int = PADE_ORDER) -> LinearModel:
    """Close the controller's loop through its actuator around a model without feedback.

    Parameters
    ----------
    plant : LinearModel
        The bicycle without the controller (first four states roll, steer and their rates).
    controller : Controller
        Gains, gain scale, delay [s] and lag [s].
    order : int
        Order of the delay's Pade approximant.

    Returns
    -------
    LinearModel
        The plant's states, then the actuator states of each torque row in use (N m; the plant
        itself when no gain is nonzero), named
        e.g. ``steer_torque_delay1``, ``steer_torque_lag``; the same inputs (external torques
        act directly, not through the actuator).
    """
    actuator = actuator_realisation(controller.delay, controller.lag, order)
    rows = used_rows(controller)
    if not rows:  # every gain zero (e.g. gain_scale 0): no torque to delay
        return plant
    gains = controller.feedback_coefficients()
    plant_coefficients = [plant.A[..., k, :, :] for k in range(plant.A.shape[-3])]
    coefficients, inputs = actuator_coefficients(plant_coefficients, plant.B[..., 0, :, :], gains, rows,
                                                 (actuator.a, actuator.b, actuator.c, actuator.d), NUMPY_OPS)
    names = tuple(f"{_ROW_NAMES[row]}_{state}" for row in rows for state in actuator.states)
    return LinearModel(A=np.stack(coefficients, axis=-3), B=inputs[..., None, :, :],
                       state_names=plant.state_names + names,
                       state_units=plant.state_units + ("N m",) * len(names),
                       input_names=plant.input_names, input_units=plant.input_units,
                       description=plant.description)


def transfer(controller: Controller, s: complex) -> complex:
    """Return the actuator's exact transfer function ``exp(-s delay) / (1 + s lag)`` at s [1/s]."""
    return complex(np.exp(-s * controller.delay) / (1.0 + s * controller.lag))


def delay_eigenvalue(plant: LinearModel, controller: Controller, speed: float, guess: complex,
                     tolerance: float = 1e-12, iterations: int = 50) -> complex:
    """Return an eigenvalue of the loop with the exact delay, by Newton's method from `guess`.

    Solves ``det(s I - A(v) - B(v) G(s) F(v) P) = 0`` with ``G(s) = exp(-s delay) /
    (1 + s lag)`` on the rows in use and P the projection onto the first four states: the
    characteristic equation of the delayed loop, of which the Pade model's eigenvalues are
    approximations (use one of them as `guess`).

    Parameters
    ----------
    plant : LinearModel
        One bicycle without the controller.
    controller : Controller
        Gains, gain scale, delay [s], lag [s].
    speed : float
        Forward speed [m/s].
    guess : complex
        Starting point [1/s].
    tolerance : float
        Stop when the Newton step is below this [1/s].
    iterations : int
        Most Newton steps.

    Returns
    -------
    complex
        The root [1/s].

    Raises
    ------
    ArithmeticError
        If Newton's method does not converge.
    """
    A = plant.state_matrix(speed)
    B = plant.input_matrix(speed)
    n = A.shape[-1]
    gain = np.zeros((2, n))
    for k, coefficient in enumerate(controller.feedback_coefficients()):
        gain[:, :4] += speed**k * coefficient
    mask = np.zeros((2, 1))
    mask[list(used_rows(controller)), 0] = 1.0

    def residual(s: complex) -> complex:
        loop = A + B @ (mask * transfer(controller, s) * gain)
        # Scaled by s^n so the residual is of order one far from the origin too.
        return complex(np.linalg.det(s * np.eye(n) - loop)) / max(abs(s), 1.0) ** n

    s = complex(guess)
    for _ in range(iterations):
        h = 1e-7 * max(abs(s), 1.0)
        derivative = (residual(s + h) - residual(s - h)) / (2 * h)
        step = residual(s) / derivative
        s -= step
        if abs(step) < tolerance * max(abs(s), 1.0):
            return s
    raise ArithmeticError(f"Newton's method did not converge from {guess}")
