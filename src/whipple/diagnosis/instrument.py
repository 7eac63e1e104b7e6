"""The instrument's plausible errors, fitted as nuisance values shared by every window of a run set.

An instrumented bicycle's roll gyro reads the roll rate through its own gain (a scale error of a
few percent) and, where the IMU is pitched about the lateral axis by an angle ``a``, picks up
part of the yaw rate: it reads ``s (cos(a) roll_rate - sin(a) yaw_rate)``. Both change the
roll/steer amplitude ratio a model must match in every window (its mode shape), which a hidden
effect (a payload) can mimic. Fitted for every model compared with the samples, the base model
included, they cannot make a candidate look better than the base model: each model is compared
with the samples at its own best instrument (:meth:`~whipple.diagnosis.samples.SampleComparison.residuals`).

The fit profiles them out: for given values, each window's modal amplitudes and offsets are a
linear least squares; the two values are found by Gauss-Newton steps on the projected residuals
(variable projection, Kaufman's Jacobian), each step one more least squares of every window,
with a Gaussian prior (which also holds them where the samples cannot tell them, e.g. a roll
rate logged without a steer angle: its scale is then the windows' amplitudes) and hard bounds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.growing_modes import orthonormal_columns
from whipple.model.parameters import Bicycle
from whipple.stability.nearest_modes import MODE_SHAPE_STATES

#: Values the instrument's fit frees for each set of windows fitted apart: the scale and the misalignment.
INSTRUMENT_VALUES = 2


@dataclass(frozen=True)
class InstrumentErrors:
    """The roll gyro's errors fitted with every model, and what is plausible for them.

    Attributes
    ----------
    scale_prior, scale_bound : float
        Standard deviation and largest magnitude of the roll gyro's relative scale error
        (default 0.05 and 0.10: MEMS gyros are specified to a few percent).
    misalignment_prior, misalignment_bound : float
        Standard deviation and largest magnitude of the IMU's pitch misalignment [rad] (default
        3 and 5 degrees: an IMU strapped to a frame by hand).
    steps : int
        Gauss-Newton steps (default 1: on simulated runs with 1-5 % scale and up to 3 degrees
        the fit converged in 1-2 steps, the third moving the chi-square by less than 0.01 of the
        noise's; on both bundled experiments one step gave the same model offered and held-out
        gain as three, at 162 s CPU against 206 s).
    """

    scale_prior: float = 0.05
    scale_bound: float = 0.10
    misalignment_prior: float = float(np.radians(3.0))
    misalignment_bound: float = float(np.radians(5.0))
    steps: int = 1

    def __post_init__(self) -> None:
        if not (self.scale_prior > 0 and self.misalignment_prior > 0):
            raise ValueError("the instrument's priors must be positive")
        if not (0 <= self.scale_bound < 1 and 0 <= self.misalignment_bound < np.pi / 2):
            raise ValueError("the instrument's bounds must be below 1 (scale) and pi/2 (misalignment)")
        if self.steps < 0:
            raise ValueError("the instrument's Gauss-Newton steps must be 0 or more")


def yaw_gains(bicycle: Bicycle) -> NDArray[np.float64]:
    """Return the yaw rate's gains on the steer angle per unit speed [1/m] and on the steer rate [-].

    The knife-edge front wheel's kinematics to first order:
    ``psi' = (v delta + c delta') cos(lambda) / w``.
    """
    parameters = bicycle.parameters
    tilt = np.cos(float(parameters["lam"])) / float(parameters["w"])
    return np.array([tilt, float(parameters["c"]) * tilt])


def yaw_row(vectors: NDArray[np.complex128], speeds: NDArray[np.float64], gains: NDArray[np.float64]
            ) -> NDArray[np.complex128]:
    """Return the yaw rate's row (..., n) in the eigenvectors (..., n, n).

    ``speeds`` (...): the model's speed [m/s]; ``gains`` (..., 2): :func:`yaw_gains`. What a roll
    gyro pitched about the lateral axis picks up, linear in the states.
    """
    steer, steer_rate = MODE_SHAPE_STATES["steer_angle"], MODE_SHAPE_STATES["steer_rate"]
    return ((speeds * gains[..., 0])[..., None] * vectors[..., steer, :]
            + gains[..., 1, None] * vectors[..., steer_rate, :])


def profiled_residuals(design: NDArray[np.float64], yaw: NDArray[np.float64], targets: NDArray[np.float64],
                       row: int, finite: NDArray[np.bool_], errors: InstrumentErrors) -> NDArray[np.float64]:
    """Return M models' residuals (M, W, k, L), each at the roll gyro's errors it fits best.

    ``design`` (M, W, k, L, n): each window's response columns per signal; ``yaw`` (M, W, L, n):
    the yaw rate's, in units of the roll rate's noise; ``targets`` (W, k, L): the signals in
    units of their noise, all centred on each window's mean (offsets out); ``row``: the roll
    rate's signal; ``finite`` (M, W): windows taken into the fit. The roll gyro reads
    ``s (roll_rate + b yaw_rate)`` (``b = -tan(a)``, ``cos(a)`` taken into ``s``): ``s`` and ``b``
    are fitted per model over all its windows by Gauss-Newton steps on the residuals with the
    amplitudes projected out, each step pulled to the prior and clipped to the bounds.
    """
    models, windows, count, length, states = design.shape
    targets = np.broadcast_to(targets.reshape(windows, count * length), (models, windows, count * length))
    prior = np.array([1.0, 0.0])
    weight = np.diag([errors.scale_prior ** -2, np.tan(errors.misalignment_prior) ** -2])
    low = np.array([1.0 - errors.scale_bound, -np.tan(errors.misalignment_bound)])
    high = np.array([1.0 + errors.scale_bound, np.tan(errors.misalignment_bound)])
    values = np.broadcast_to(prior, (models, 2)).copy()  # (M, 2): s and b of each model
    for step in range(errors.steps + 1):
        scale, mixing = values[:, 0, None, None, None], values[:, 1, None, None, None]
        current = design.copy()
        current[:, :, row] = scale * (design[:, :, row] + mixing * yaw)
        q, inverse = orthonormal_columns(current.reshape(models, windows, count * length, states))
        coefficients = np.einsum("mwsc,mws->mwc", q, targets)
        residual = targets - np.einsum("mwsc,mwc->mws", q, coefficients)
        if step == errors.steps:
            break
        amplitudes = np.einsum("mwcd,mwd->mwc", inverse, coefficients)
        # Kaufman's Jacobian: each value's change of the response, projected off the columns.
        along = np.zeros((2, models, windows, count, length))
        along[0, :, :, row] = np.einsum("mwlc,mwc->mwl", design[:, :, row] + mixing * yaw, amplitudes)
        along[1, :, :, row] = scale[..., 0] * np.einsum("mwlc,mwc->mwl", yaw, amplitudes)
        along = along.reshape(2, models, windows, count * length) * finite[None, :, :, None]
        along = along - np.einsum("mwsc,jmwc->jmws", q, np.einsum("mwsc,jmws->jmwc", q, along))
        normal = np.einsum("imws,jmws->mij", along, along) + weight
        gradient = np.einsum("imws,mws->mi", along, residual * finite[..., None]) - (values - prior) @ weight
        values = np.clip(values + np.linalg.solve(normal, gradient[..., None])[..., 0], low, high)
    return residual.reshape(models, windows, count, length)
