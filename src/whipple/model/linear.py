"""Linear bicycle models in first-order form, with matrices polynomial in the forward speed.

The Whipple model ``M q'' + v C1 q' + (K0 + v^2 K2) q = f`` and all its extensions (steer
damping, a state-feedback controller whose gains are polynomials in v, tyre states with
relaxation) share one form::

    x' = A(v) x + B(v) f,    A(v) = sum_k v^k A_k,    B(v) = sum_k v^k B_k

Keeping the polynomial coefficients (rather than a function) makes the model plain data: it
evaluates at many speeds at once, broadcasts over many parameter sets, and converts exactly to
a CasADi expression in v for root finding (:mod:`whipple.model.casadi_model`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.model.first_order import second_order_coefficients

__all__ = ["WHIPPLE_STATES", "WHIPPLE_STATE_UNITS", "WHIPPLE_INPUTS", "WHIPPLE_INPUT_UNITS", "LinearModel",
           "check_model", "second_order_model"]

#: States of the Whipple model, in order, with their units.
WHIPPLE_STATES = ("roll", "steer", "roll_rate", "steer_rate")
WHIPPLE_STATE_UNITS = ("rad", "rad", "rad/s", "rad/s")
WHIPPLE_INPUTS = ("roll_torque", "steer_torque")
WHIPPLE_INPUT_UNITS = ("N m", "N m")


@dataclass(frozen=True)
class LinearModel:
    """``x' = A(v) x + B(v) f`` with A, B polynomials in the forward speed v [m/s].

    Attributes
    ----------
    A : ndarray, shape (..., K + 1, n, n)
        Polynomial coefficients of the state matrix, constant term first; leading axes index
        parameter sets (a batch) and are broadcast against nothing else.
    B : ndarray, shape (..., K + 1, n, m)
        Polynomial coefficients of the input matrix.
    state_names, state_units : tuple of str
        Name and unit of each state; the first four are always roll [rad], steer [rad],
        roll rate [rad/s] and steer rate [rad/s].
    input_names, input_units : tuple of str
        Name and unit of each input (roll torque and steer torque [N m]).
    """

    A: NDArray[np.float64]
    B: NDArray[np.float64]
    state_names: tuple[str, ...] = WHIPPLE_STATES
    state_units: tuple[str, ...] = WHIPPLE_STATE_UNITS
    input_names: tuple[str, ...] = WHIPPLE_INPUTS
    input_units: tuple[str, ...] = WHIPPLE_INPUT_UNITS
    description: str = field(default="", compare=False)

    @property
    def n_states(self) -> int:
        """Number of states n."""
        return int(self.A.shape[-1])

    @property
    def batch_shape(self) -> tuple[int, ...]:
        """Shape of the batch of parameter sets (``()`` for one bicycle)."""
        return tuple(self.A.shape[:-3])

    def state_matrix(self, speeds: ArrayLike) -> NDArray[np.float64]:
        """Evaluate A at forward speeds.

        Parameters
        ----------
        speeds : array_like
            Forward speeds [m/s], any shape ``S``.

        Returns
        -------
        ndarray, shape batch_shape + S + (n, n)
        """
        return _evaluate_polynomial(self.A, speeds)

    def input_matrix(self, speeds: ArrayLike) -> NDArray[np.float64]:
        """Evaluate B at forward speeds [m/s]; shape ``batch_shape + S + (n, m)``."""
        return _evaluate_polynomial(self.B, speeds)

    def select(self, index: int | tuple[int, ...]) -> LinearModel:
        """Return the model of one parameter set of a batch."""
        return LinearModel(
            self.A[index], self.B[index], self.state_names, self.state_units,
            self.input_names, self.input_units, self.description,
        )


def check_model(model: LinearModel) -> None:
    """Raise InputError if the model's matrices hold NaN or infinite entries."""
    if not np.all(np.isfinite(model.A)):
        raise InputError("the model's matrices have NaN or infinite entries",
                         model.description or None)


def _evaluate_polynomial(coefficients: NDArray[np.float64], speeds: ArrayLike) -> NDArray[np.float64]:
    speeds = np.asarray(speeds, dtype=float)
    batch = coefficients.shape[:-3]
    rows, cols = coefficients.shape[-2:]
    # Horner's rule over the polynomial axis; speeds broadcast after the batch axes.
    v = speeds.reshape((1,) * len(batch) + speeds.shape + (1, 1))
    result = np.zeros(batch + speeds.shape + (rows, cols))
    for power in range(coefficients.shape[-3] - 1, -1, -1):
        term = coefficients[..., power, :, :].reshape(batch + (1,) * speeds.ndim + (rows, cols))
        result = result * v + term
    return result


def second_order_model(
    M: ArrayLike,
    C1: ArrayLike,
    K0: ArrayLike,
    K2: ArrayLike,
    damping: ArrayLike | None = None,
    feedback: Sequence[ArrayLike] | None = None,
    description: str = "",
) -> LinearModel:
    """First-order form of ``M q'' + (v C1 + D) q' + (K0 + v^2 K2) q = f + F(v) x``.

    Parameters
    ----------
    M, C1, K0, K2 : array_like, shape (..., 2, 2)
        Mass [kg m^2], velocity-damping [kg m], stiffness with gravity [kg m^2/s^2 = N m]
        and speed-squared stiffness [kg] matrices of ``q = [roll, steer]``; leading axes are a
        batch of parameter sets.
    damping : array_like, shape (..., 2, 2), optional
        Speed-independent viscous damping D [N m s/rad] (e.g. steer damping).
    feedback : sequence of array_like, each shape (..., 2, 4), optional
        Coefficients ``F_k`` of a state-feedback law ``f = sum_k v^k F_k x`` with
        ``x = [roll, steer, roll_rate, steer_rate]`` (gains in N m per state unit).
    description : str
        Free text carried along (e.g. the bicycle's name).

    Returns
    -------
    LinearModel
        States ``[roll, steer, roll_rate, steer_rate]``, inputs ``[roll_torque, steer_torque]``.
    """
    M, C1, K0, K2 = (np.asarray(matrix, dtype=float) for matrix in (M, C1, K0, K2))
    D = np.zeros_like(K0) if damping is None else np.asarray(damping, dtype=float)
    gains = [np.asarray(gain, dtype=float) for gain in (feedback or [])]
    coefficients, inputs = second_order_coefficients(M, C1, D, K0, K2, gains)
    return LinearModel(A=np.stack(coefficients, axis=-3), B=inputs[..., None, :, :], description=description)
