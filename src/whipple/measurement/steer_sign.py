"""Whether a run's steer signal has the sign convention and the units of the model, judged by the weave's mode shape.

A steer angle logged with the opposite sign to the convention of Meijaard et al. (2007) (an
encoder mounted the other way, a layout's scale factor of the wrong sign) turns the weave's
measured mode shape, steer per roll rate, half a turn away from the model's. A steer angle in
degrees (or a roll rate in degrees per second) scales it by 57.3, one in milliradians by 1000.
Fitted jointly with the roll rate such a signal would mislead every comparison with a model, so
the measurement (:func:`whipple.measurement.measure.measure_runs`) then fits the roll rate alone.
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


#: Factor by which the median magnitude of measured over model mode shapes must differ from 1
#: for the steer signal's (or the roll rate's) units to be taken as other than the model's.
#: The causes a diagnosis weighs move the weave's mode shape by tens of percent (the bundled
#: treadmill runs: -13 %); a unit error by 57.3 (degrees) or 1000 (milliradians).
SCALE_MISMATCH = 10.0


def scale_offset(ratios: ArrayLike) -> float:
    """Return the median magnitude of measured over model mode shapes (1 without any).

    Parameters
    ----------
    ratios : array_like of complex
        Measured over model mode shape, one per window compared.
    """
    values = np.asarray(ratios, dtype=complex)
    return float(np.median(np.abs(values))) if values.size else 1.0


def is_scaled(ratios: ArrayLike) -> bool:
    """Return whether measured mode shapes are :data:`SCALE_MISMATCH` times the model's or more, or as much smaller."""
    factor = scale_offset(ratios)
    return not 1.0 / SCALE_MISMATCH < factor < SCALE_MISMATCH


def scale_text(factor: float) -> str:
    """Say how many times the model's the measured mode shapes are, and which unit error that suggests."""
    if factor > 1:
        return (f"{factor:.3g} times the model's (a unit error? a steer angle in degrees gives 57.3, in milliradians "
                "1000)")
    return (f"{factor:.3g} times the model's (a unit error? a roll rate in degrees per second gives 1/57.3 = "
            "0.0175)")


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


def steer_signal_check(bicycle: Model, measurements: Sequence[WindowMeasurement]) -> str:
    """Return what the usable windows' mode shapes say of the steer signal against the model's.

    Parameters
    ----------
    bicycle : Bicycle
        The model whose mode shapes are the reference.
    measurements : sequence of WindowMeasurement
        The windows (see :func:`shape_ratios`).

    Returns
    -------
    str
        ``"opposite to the model's"`` when the median phase of measured over model shapes
        exceeds :data:`FLIPPED_PHASE`; ``"<factor> times the model's (...)"`` when their median
        magnitude is :data:`SCALE_MISMATCH` times the model's or more, or as much smaller
        (:func:`scale_text`); else ``"as the model's"``.
    """
    ratios = shape_ratios(bicycle, measurements)
    if is_flipped(ratios):
        return "opposite to the model's"
    if is_scaled(ratios):
        return scale_text(scale_offset(ratios))
    return "as the model's"
