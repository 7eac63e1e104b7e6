"""Observations: one window's measured weave eigenvalue and mode shape, and the model's nearest mode.

The diagnosis compares each observation with the mode of the bicycle's model nearest to it at the
window's speed (the measured speed divided by the bicycle's ``speed_scale``), rather than with a
labelled weave: that keeps the comparison meaningful for models with extra modes and below the
speed where the weave forms.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.window_speed import window_speeds
from whipple.measurement.experiment import WindowMeasurement
from whipple.measurement.weavefit import WeaveFit
from whipple.model.fleet import Model
from whipple.model.steer_friction import describing_gain, representative_amplitude
from whipple.stability.nearest_modes import MODE_SHAPE_STATES, near_oscillation, nearest_modes

__all__ = ["WindowSignals", "Observation", "Prediction", "predicted_weave", "predicted_modes", "mode_targets",
           "compared_shapes", "noise_free", "speed_groups", "observation", "observations"]


@dataclass(frozen=True)
class WindowSignals:
    """The samples a window's weave fit used: what :mod:`whipple.diagnosis.samples` compares models with.

    Attributes
    ----------
    time : ndarray, shape (n,)
        Sample times [s].
    values : ndarray, shape (k, n)
        The fitted signals, in SI units.
    names : tuple of str
        Their run-file names (``roll_rate``, ...).
    baseline : str
        The fitted function's non-oscillating part
        (:data:`~whipple.measurement.weavefit.BASELINES`).
    weights : ndarray, shape (k,), or None
        Each signal's weight in a joint fit [1/signal unit]
        (:attr:`~whipple.measurement.weavefit.WeaveFit.signal_weights`); None: the inverse of
        its spread over the window (one signal, or samples from elsewhere).
    residual_rms : ndarray, shape (k,), or None
        Each signal's RMS residual of the window's weave fit [signal unit] (where the window was
        fitted): how far the fitting function leaves it, which bounds the weight the window's
        samples get (:func:`whipple.diagnosis.window_bins.signal_noise`).
    noise : ndarray, shape (k,), or None
        Each signal's noise [signal unit] where stated apart from the samples (a noise-free twin
        keeps its measured window's, :func:`whipple.diagnosis.samples.noise_free_samples`); None:
        estimated from the samples (:func:`whipple.diagnosis.window_bins.signal_noise`).
    """

    time: NDArray[np.float64]
    values: NDArray[np.float64]
    names: tuple[str, ...]
    baseline: str
    weights: NDArray[np.float64] | None = None
    residual_rms: NDArray[np.float64] | None = None
    noise: NDArray[np.float64] | None = None

    def reference_only(self) -> WindowSignals:
        """Return the samples of the first signal alone (the mode shape's reference)."""
        return replace(self, values=self.values[:1], names=self.names[:1], weights=None,
                       residual_rms=None if self.residual_rms is None else self.residual_rms[:1],
                       noise=None if self.noise is None else self.noise[:1])


@dataclass(frozen=True)
class Observation:
    """One window's measured weave eigenvalue.

    Attributes
    ----------
    run : str
        Run name.
    start, stop : float
        Window [s].
    speed : float
        Measured mean speed over the window [m/s].
    speed_range : tuple of float
        Speed at the window's start and end from the linear regression [m/s].
    eigenvalue : complex
        Fitted weave eigenvalue d + i w [1/s].
    covariance : ndarray, shape (2, 2)
        Covariance of (d, w) [1/s^2].
    shape : complex or None
        The weave's mode shape where a second signal was measured: the complex amplitude of
        ``shape_signals[0]`` relative to ``shape_signals[1]`` (see
        :func:`whipple.measurement.mode_shape.amplitude_ratio`); e.g. steer angle per roll rate [s].
    shape_covariance : ndarray, shape (2, 2), or None
        Covariance of the shape's (real, imaginary) part.
    shape_signals : tuple of str
        The two signals of the shape, each a state of the model (see MODE_SHAPE_STATES).
    signals : WindowSignals or None
        The samples the eigenvalue was fitted to, where known (windows fitted from runs; not
        windows read from a list of fitted eigenvalues).
    group : str
        The group of an experiment the window belongs to ("" outside experiments of several
        groups): a :class:`~whipple.model.fleet.Fleet` is evaluated with that group's bicycle.
    amplitudes : tuple of (str, float)
        Each fitted signal's representative amplitude over the window [signal unit]: the
        amplitude-weighted mean of its fitted envelope
        (:func:`~whipple.model.steer_friction.representative_amplitude`); what a Coulomb steer
        friction's equivalent damping is taken at (:func:`friction_gains`). Empty where unknown.
    acceleration : float
        The forward acceleration over the window [m/s^2] (the slope of the measured speed's
        regression; negative while slowing down): the model follows the window's speed profile
        (:mod:`whipple.diagnosis.window_speed`). 0 for a run on a treadmill (its metadata
        ``setting = treadmill``) and for windows read from a list of eigenvalues.
    """

    run: str
    start: float
    stop: float
    speed: float
    speed_range: tuple[float, float]
    eigenvalue: complex
    covariance: NDArray[np.float64]
    shape: complex | None = None
    shape_covariance: NDArray[np.float64] | None = None
    shape_signals: tuple[str, str] = ("steer_angle", "roll_rate")
    signals: WindowSignals | None = field(default=None, repr=False, compare=False)
    group: str = ""
    amplitudes: tuple[tuple[str, float], ...] = ()
    acceleration: float = 0.0



@dataclass(frozen=True)
class Prediction:
    """A model's mode nearest each observation.

    Attributes
    ----------
    eigenvalues : ndarray of complex, shape (N,)
        The model eigenvalue [1/s] (upper half plane) nearest each measured one.
    shapes : ndarray of complex, shape (N,)
        Its eigenvector's ratio of the observation's ``shape_signals`` (NaN where the
        observation has no shape).
    """

    eigenvalues: NDArray[np.complex128]
    shapes: NDArray[np.complex128]

    @classmethod
    def of(cls, bicycle: Model, observations: Sequence[Observation]) -> Prediction:
        """Return the prediction of a bicycle's model (see :func:`predicted_modes`)."""
        return cls(*predicted_modes(bicycle, observations))


def predicted_weave(bicycle: Model, observations: Sequence[Observation]) -> NDArray[np.complex128]:
    """For each observation, the model eigenvalue (upper half plane) nearest the measured one.

    The measured oscillation is one of the model's modes; matching the nearest one (rather
    than a label) keeps the comparison meaningful for models with extra modes and below the
    speed where the weave forms.
    """
    return predicted_modes(bicycle, observations)[0]


def predicted_modes(bicycle: Model, observations: Sequence[Observation]
                    ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each measured one, and its mode shape.

    The eigenvalue is as in :func:`predicted_weave`; the mode shape is the eigenvector's ratio
    of the observation's ``shape_signals`` (NaN where the observation has no shape).
    """
    return nearest_modes(bicycle, *mode_targets(observations, bicycle))


def mode_targets(observations: Sequence[Observation], bicycle: Model | None = None
                 ) -> tuple[NDArray[np.float64], NDArray[np.complex128], list[tuple[str, str] | None], list[str],
                            NDArray[np.float64], NDArray[np.float64] | None]:
    """Return what :func:`nearest_modes` compares with, per window.

    The measured speed the model is evaluated at [m/s] (the mean, or where a changing speed is
    read: :func:`~whipple.diagnosis.window_speed.window_speeds`), eigenvalue [1/s], shape
    signals (None where the window has no shape), group (for a model that is a
    :class:`~whipple.model.fleet.Fleet`), the Coulomb steer friction's equivalent damping per
    unit friction [s/rad] (:func:`friction_gains`; ``bicycle`` gives the mode shape of windows
    without a steer angle) and the measured accelerations [m/s^2] (None where every window's
    speed is constant).
    """
    speeds, accelerations = window_speeds(observations)
    targets = np.array([o.eigenvalue for o in observations], dtype=complex)
    return (speeds, targets, [o.shape_signals if _has_shape(o) else None for o in observations],
            [o.group for o in observations], friction_gains(observations, bicycle), accelerations)


def steer_amplitudes(observations: Sequence[Observation], bicycle: Model | None = None) -> NDArray[np.float64]:
    """Return each window's representative steer-angle amplitude [rad] (NaN where unknown).

    The fitted steer angle's (:attr:`Observation.amplitudes`) where the window has one; else the
    roll rate's times the steer angle per roll rate of ``bicycle``'s mode nearest the window's
    eigenvalue (without any steer friction of its own: the friction's damping would depend on
    the amplitude it is to give); NaN where neither is known.
    """
    result = np.full(len(observations), np.nan)
    roll_only = []
    for n, o in enumerate(observations):
        amplitudes = dict(o.amplitudes)
        if "steer_angle" in amplitudes:
            result[n] = amplitudes["steer_angle"]
        elif "roll_rate" in amplitudes:
            roll_only.append(n)
    if roll_only and bicycle is not None:
        rows = np.array(roll_only)
        speeds = np.array([observations[n].speed for n in rows], dtype=float)
        targets = np.array([observations[n].eigenvalue for n in rows], dtype=complex)
        _, ratio = nearest_modes(bicycle.with_extensions(steer_friction=0.0), speeds, targets,
                                 [("steer_angle", "roll_rate")] * len(rows), [observations[n].group for n in rows])
        result[rows] = [dict(observations[n].amplitudes)["roll_rate"] for n in rows] * np.abs(ratio)
    return result


def friction_gains(observations: Sequence[Observation], bicycle: Model | None = None) -> NDArray[np.float64]:
    """Return each window's equivalent viscous steer damping per unit Coulomb friction [s/rad].

    ``4 / (pi omega A)`` (:func:`~whipple.model.steer_friction.describing_gain`) with the
    window's measured weave frequency omega and representative steer amplitude A
    (:func:`steer_amplitudes`); 0 where the amplitude is unknown (the friction then does not
    enter that window's model).
    """
    frequency = np.array([o.eigenvalue.imag for o in observations], dtype=float)
    return describing_gain(frequency, steer_amplitudes(observations, bicycle))


def _has_shape(observation: Observation) -> bool:
    return (observation.shape is not None and observation.shape_covariance is not None
            and all(name in MODE_SHAPE_STATES for name in observation.shape_signals))



def compared_shapes(bicycle: Model, observations: Sequence[Observation],
                    predicted: NDArray[np.complex128] | None = None) -> NDArray[np.bool_]:
    """Return which windows' mode shapes are compared with the model.

    Those with a shape whose eigenvalue the bicycle's model matches with an oscillatory mode
    (see SHAPE_MATCH).

    ``predicted`` is the model's eigenvalue nearest each observation (:func:`predicted_weave`)
    when already at hand.
    """
    if predicted is None:
        predicted = predicted_weave(bicycle, observations)
    matched = near_oscillation(predicted, [o.eigenvalue for o in observations])
    return np.array([_has_shape(o) for o in observations], dtype=bool) & matched



def noise_free(bicycle: Model, observations: Sequence[Observation]) -> list[Observation]:
    """Return the observations that ``bicycle``'s model would give at the same windows without noise.

    Each window keeps its speed, its uncertainties and whether it has a mode shape; its
    eigenvalue [1/s] and shape become those of the model's mode nearest the measured one. The
    window's samples are dropped, so that a diagnosis compares models with these eigenvalues
    directly. Diagnosing them asks what windows of these speeds and this noise could tell if
    ``bicycle`` were true: a cause it cannot single out from them no amount of luck in the
    noise makes identifiable.
    """
    eigenvalues, shapes = predicted_modes(bicycle, observations)
    return [replace(o, eigenvalue=complex(eigenvalue), shape=complex(shape) if _has_shape(o) else o.shape,
                    signals=None)
            for o, eigenvalue, shape in zip(observations, eigenvalues, shapes, strict=True)]


def speed_groups(observations: Sequence[Observation], gap: float = 0.3) -> list[list[int]]:
    """Return the indices of observations grouped by speed: a new group where sorted speeds jump > gap [m/s]."""
    order = np.argsort([o.speed for o in observations])
    groups: list[list[int]] = [[int(order[0])]]
    for previous, current in zip(order[:-1], order[1:], strict=True):
        if observations[current].speed - observations[previous].speed > gap:
            groups.append([])
        groups[-1].append(int(current))
    return groups


def observation(measurement: WindowMeasurement) -> Observation:
    """Return the diagnosis' view of a usable window."""
    if measurement.fit is None or measurement.speed is None:
        raise ValueError("window has no fit")
    speed, shape = measurement.speed, measurement.shape
    return Observation(measurement.run.name, measurement.window.start, measurement.window.stop, float(speed.mean),
                       (float(speed.start_speed), float(speed.stop_speed)), complex(measurement.fit.eigenvalue),
                       np.asarray(measurement.fit.covariance, dtype=float),
                       None if shape is None else complex(shape.ratio),
                       None if shape is None else np.asarray(shape.covariance, dtype=float),
                       ("steer_angle", "roll_rate") if shape is None else (shape.signal, shape.reference),
                       WindowSignals(measurement.fit.time, measurement.fit.measured, measurement.fit.signal_names,
                                     measurement.fit.baseline, _joint_weights(measurement.fit),
                                     residual_rms=np.asarray(measurement.fit.rms_residual, dtype=float)),
                       measurement.group, _amplitudes(measurement.fit), window_acceleration(measurement))


def _amplitudes(fit: WeaveFit) -> tuple[tuple[str, float], ...]:
    """Return each fitted signal's amplitude-weighted mean amplitude over the window [signal unit]."""
    start = np.hypot(fit.coefficients[:, -2], fit.coefficients[:, -1])
    amplitude = representative_amplitude(start, fit.damping, fit.stop - fit.start)
    return tuple((name, float(value)) for name, value in zip(fit.signal_names, amplitude, strict=True))


def window_acceleration(measurement: WindowMeasurement) -> float:
    """Return the forward acceleration over a window [m/s^2]: its speed regression's slope.

    0 on a treadmill (run metadata ``setting = treadmill``): the belt's speed fluctuations are
    not the bicycle's acceleration over the ground, and treadmill windows stay at constant speed.
    """
    if measurement.speed is None or measurement.run.metadata.get("setting", "").strip().lower() == "treadmill":
        return 0.0
    return float(measurement.speed.slope)


def _joint_weights(fit: WeaveFit) -> NDArray[np.float64] | None:
    """Return a joint fit's signal weights, or None for one signal.

    One signal's weight only scales it; the refits then weigh it by its spread, as before joint
    fits kept their weights, to the last bit.
    """
    return np.asarray(fit.signal_weights, dtype=float) if len(fit.signal_weights) > 1 else None


def observations(measurements: Sequence[WindowMeasurement]) -> list[Observation]:
    """Observations of all usable windows.

    Parameters
    ----------
    measurements : sequence of WindowMeasurement
        Measured windows (:func:`whipple.measurement.measure.measure_runs`).

    Returns
    -------
    list of Observation
        One per window with a fitted eigenvalue and a speed, in order.
    """
    return [observation(m) for m in measurements if m.usable]

