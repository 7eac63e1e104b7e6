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
        Gauss-Newton steps (default 3: on simulated runs with 1-5 % scale and up to 3 degrees,
        the third moved the chi-square by less than 0.01 of the noise's).
    """

    scale_prior: float = 0.05
    scale_bound: float = 0.10
    misalignment_prior: float = float(np.radians(3.0))
    misalignment_bound: float = float(np.radians(5.0))
    steps: int = 3

    def __post_init__(self) -> None:
        if not (self.scale_prior > 0 and self.misalignment_prior > 0):
            raise ValueError("the instrument's priors must be positive")
        if not (0 <= self.scale_bound < 1 and 0 <= self.misalignment_bound < np.pi / 2):
            raise ValueError("the instrument's bounds must be below 1 (scale) and pi/2 (misalignment)")
        if self.steps < 0:
            raise ValueError("the instrument's Gauss-Newton steps must be 0 or more")
