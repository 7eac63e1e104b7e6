"""Whether a run's steer signal has the sign convention of the model, judged by the weave's mode shape.

A steer angle logged with the opposite sign to the convention of Meijaard et al. (2007) (an
encoder mounted the other way, a layout's scale factor of the wrong sign) turns the weave's
measured mode shape, steer per roll rate, half a turn away from the model's. Fitted jointly with
the roll rate such a signal would mislead every comparison with a model, so the measurement
(:func:`whipple.measurement.measure.measure_runs`) then fits the roll rate alone.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from whipple.measurement.experiment import WindowMeasurement
from whipple.model.fleet import Model
from whipple.stability.nearest_modes import MODE_SHAPE_STATES, near_oscillation, nearest_modes

#: Median phase difference between measured and model mode shapes beyond which the steer
#: signal's sign is taken to be opposite to the model's [deg]. A right sign leaves the measured
#: shapes within some tens of degrees of the model's even where the model is poor (the bundled
#: treadmill runs: median within 30 degrees); a flipped one near 180.
FLIPPED_PHASE = 120.0


def phase_offset(ratios: ArrayLike) -> float:
    """Return the median phase of measured over model mode shapes [deg] (0 without any).

    Parameters
    ----------
    ratios : array_like of complex
        Measured over model mode shape, one per window compared.

    Returns
    -------
    float
        The phase [deg] of the median of the real parts plus i times the median of the
        imaginary parts: robust to a few windows far off.
    """
    values = np.asarray(ratios, dtype=complex)
    if not values.size:
        return 0.0
    return float(np.degrees(np.angle(np.median(values.real) + 1j * np.median(values.imag))))


def is_flipped(ratios: ArrayLike) -> bool:
    """Return whether measured over model mode shapes are more than :data:`FLIPPED_PHASE` out of phase.

    Parameters
    ----------
    ratios : array_like of complex
        Measured over model mode shape, one per window compared.

    Returns
    -------
    bool
        True when the median phase (:func:`phase_offset`) exceeds :data:`FLIPPED_PHASE` either way.
    """
    return abs(phase_offset(ratios)) > FLIPPED_PHASE


def shape_ratios(bicycle: Model, measurements: Sequence[WindowMeasurement]) -> np.ndarray:
    """Return measured over model mode shapes of the usable windows whose shapes can be compared.

    Parameters
    ----------
    bicycle : Bicycle
        The model.
    measurements : sequence of WindowMeasurement
        Windows; those usable with a measured mode shape of two model states are compared where
        the model's nearest mode at the window's speed is an oscillation near the measured
        eigenvalue (:func:`~whipple.stability.nearest_modes.near_oscillation`).

    Returns
    -------
    ndarray of complex
        One ratio per compared window, in order (dimensionless).
    """
    shaped = [(m.fit.eigenvalue, m.speed.mean, m.shape, m.group) for m in measurements
              if m.usable and m.fit is not None and m.speed is not None and m.shape is not None
              and m.shape.signal in MODE_SHAPE_STATES and m.shape.reference in MODE_SHAPE_STATES]
    if not shaped:
        return np.zeros(0, dtype=complex)
    measured = np.array([eigenvalue for eigenvalue, _, _, _ in shaped], dtype=np.complex128)
    speeds = np.array([speed for _, speed, _, _ in shaped], dtype=np.float64)
    signals: list[tuple[str, str] | None] = [(shape.signal, shape.reference) for _, _, shape, _ in shaped]
    predicted, shapes = nearest_modes(bicycle, speeds, measured, signals, [group for *_, group in shaped])
    compared = near_oscillation(predicted, measured) & np.isfinite(shapes)
    ratios = np.array([shape.ratio for _, _, shape, _ in shaped], dtype=np.complex128)
    return ratios[compared] / shapes[compared]


def steer_sign_flipped(bicycle: Model, measurements: Sequence[WindowMeasurement]) -> bool:
    """Return whether the usable windows' mode shapes are out of phase with the model's.

    Parameters
    ----------
    bicycle : Bicycle
        The model whose mode shapes are the reference.
    measurements : sequence of WindowMeasurement
        The windows (see :func:`shape_ratios`).

    Returns
    -------
    bool
        True when the median phase of measured over model shapes exceeds :data:`FLIPPED_PHASE`:
        the steer signal's sign is probably opposite to the convention of Meijaard et al. (2007).
    """
    return is_flipped(shape_ratios(bicycle, measurements))
