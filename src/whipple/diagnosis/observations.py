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
from numpy.typing import ArrayLike, NDArray

from whipple.measurement.experiment import WindowMeasurement
from whipple.measurement.weavefit import WeaveFit
from whipple.model.assembly import linear_model, second_order_matrices
from whipple.model.parameters import Bicycle
from whipple.stability.quartic import second_order_eigenvalues, second_order_eigenvectors


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
        samples get (:func:`whipple.diagnosis.samples.signal_noise`).
    noise : ndarray, shape (k,), or None
        Each signal's noise [signal unit] where stated apart from the samples (a noise-free twin
        keeps its measured window's, :func:`whipple.diagnosis.samples.noise_free_samples`); None:
        estimated from the samples (:func:`whipple.diagnosis.samples.signal_noise`).
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
    def of(cls, bicycle: Bicycle, observations: Sequence[Observation]) -> Prediction:
        """Return the prediction of a bicycle's model (see :func:`predicted_modes`)."""
        return cls(*predicted_modes(bicycle, observations))


#: Model states a mode shape can relate: the first four states of every model.
MODE_SHAPE_STATES = {"roll_angle": 0, "steer_angle": 1, "roll_rate": 2, "steer_rate": 3}


def predicted_weave(bicycle: Bicycle, observations: Sequence[Observation]) -> NDArray[np.complex128]:
    """For each observation, the model eigenvalue (upper half plane) nearest the measured one.

    The measured oscillation is one of the model's modes; matching the nearest one (rather
    than a label) keeps the comparison meaningful for models with extra modes and below the
    speed where the weave forms.
    """
    return predicted_modes(bicycle, observations)[0]


def predicted_modes(bicycle: Bicycle, observations: Sequence[Observation]
                    ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each measured one, and its mode shape.

    The eigenvalue is as in :func:`predicted_weave`; the mode shape is the eigenvector's ratio
    of the observation's ``shape_signals`` (NaN where the observation has no shape).
    """
    return nearest_modes(bicycle, *mode_targets(observations))


def mode_targets(observations: Sequence[Observation]
                 ) -> tuple[NDArray[np.float64], NDArray[np.complex128], list[tuple[str, str] | None]]:
    """Return what :func:`nearest_modes` compares with, per window.

    The measured speed [m/s], eigenvalue [1/s] and shape signals (None where the window has
    no shape).
    """
    speeds = np.array([o.speed for o in observations], dtype=float)
    targets = np.array([o.eigenvalue for o in observations], dtype=complex)
    return speeds, targets, [o.shape_signals if _has_shape(o) else None for o in observations]


def nearest_modes(bicycle: Bicycle, speeds: NDArray[np.float64], targets: NDArray[np.complex128],
                  signals: Sequence[tuple[str, str] | None]
                  ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each target, and its eigenvector's ratio of two signals.

    At each measured speed [m/s] (speed_scale applied), the model eigenvalue (upper half plane)
    nearest ``targets`` [1/s], and its eigenvector's ratio of two signals (MODE_SHAPE_STATES;
    NaN where ``signals`` is None).
    """
    chosen, shapes = nearest_modes_of_models([bicycle], speeds, targets, signals)
    return chosen[0], shapes[0]


def nearest_modes_of_models(bicycles: Sequence[Bicycle], speeds: NDArray[np.float64],
                            targets: NDArray[np.complex128], signals: Sequence[tuple[str, str] | None]
                            ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """:func:`nearest_modes` of several bicycles at the same windows; each result (bicycles, windows).

    Models with the states ``[q, q']`` only are solved together: one closed-form solve of all
    their quartics costs little more than one model's, whose many small array operations are
    what an evaluation costs (a fit's finite-difference Jacobian evaluates several models at
    once). Other models are solved one by one.
    """
    rows = np.array([n for n, pair in enumerate(signals) if pair is not None], dtype=int)
    true_speeds = [bicycle.model_speed(speeds) for bicycle in bicycles]
    matrices = [second_order_matrices(bicycle, v) for bicycle, v in zip(bicycles, true_speeds, strict=True)]
    if all(m is not None for m in matrices):
        M, C, K = (np.stack([m[k] for m in matrices if m is not None]) for k in range(3))
        chosen, vectors = _nearest_second_order(M[:, None], C, K, targets, rows)
    else:
        # Each model once, those with the states [q, q'] from the matrices already built.
        solved = [_nearest_second_order(*m, targets, rows) if m is not None
                  else _nearest_by_eig(bicycle, v, targets, rows)
                  for bicycle, v, m in zip(bicycles, true_speeds, matrices, strict=True)]
        chosen = np.stack([values for values, _ in solved])
        vectors = np.stack([vector[:, :4] for _, vector in solved])
    shapes = np.full(chosen.shape, np.nan, dtype=complex)
    if len(rows):
        numerator = [MODE_SHAPE_STATES[signals[n][0]] for n in rows]  # type: ignore[index]
        denominator = [MODE_SHAPE_STATES[signals[n][1]] for n in rows]  # type: ignore[index]
        along = np.arange(len(rows))
        shapes[:, rows] = vectors[:, along, numerator] / vectors[:, along, denominator]
    return chosen, shapes


def nearest_eigen(bicycle: Bicycle, true_speeds: NDArray[np.float64], targets: ArrayLike,
                  rows: NDArray[np.intp]) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Return the model's eigenvalue nearest each target and, for `rows`, its eigenvector.

    At each true speed [m/s], of the bicycle's linear model (controller and extensions
    included) the eigenvalue in the upper half plane nearest the target [1/s], and for the
    speeds listed in `rows` its eigenvector over the model's states (``[q, q']`` first),
    shape (len(rows), states).
    """
    matrices = second_order_matrices(bicycle, true_speeds)
    if matrices is not None:
        # The closed form of the 4-state models: a fraction of eig's cost at this size.
        return _nearest_second_order(*matrices, np.asarray(targets), rows)
    return _nearest_by_eig(bicycle, true_speeds, targets, rows)


def _nearest_by_eig(bicycle: Bicycle, true_speeds: NDArray[np.float64], targets: ArrayLike,
                    rows: NDArray[np.intp]) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """:func:`nearest_eigen` by ``numpy.linalg.eig`` of the state matrices (a model with more states)."""
    values, vectors = np.linalg.eig(linear_model(bicycle).state_matrix(true_speeds))
    lower = values.imag < 0
    values = np.where(lower, np.conj(values), values)
    nearest = np.argmin(np.abs(values - np.asarray(targets)[:, None]), axis=1)
    chosen = np.asarray(values[np.arange(len(nearest)), nearest], dtype=complex)
    if not len(rows):
        return chosen, np.zeros((0, vectors.shape[-1]), dtype=complex)
    vector = vectors[rows, :, nearest[rows]]
    # The eigenvector of the upper-half-plane eigenvalue: conjugated where eig gave the lower.
    return chosen, np.where(lower[rows, nearest[rows]][:, None], np.conj(vector), vector)


def _nearest_second_order(M: NDArray[np.float64], C: NDArray[np.float64], K: NDArray[np.float64],
                          targets: NDArray[np.complex128], rows: NDArray[np.intp]
                          ) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """:func:`nearest_eigen` of ``M q'' + C q' + K q = 0``, C and K (..., windows, 2, 2).

    Returns the eigenvalues (..., windows) and the eigenvectors of `rows` (..., len(rows), 4).
    """
    values = second_order_eigenvalues(M, C, K)
    values = np.where(values.imag < 0, np.conj(values), values)
    nearest = np.argmin(np.abs(values - targets[:, None]), axis=-1)
    chosen = np.take_along_axis(values, nearest[..., None], axis=-1)[..., 0]
    if not len(rows):
        return chosen, np.zeros(chosen.shape[:-1] + (0, 4), dtype=complex)
    return chosen, second_order_eigenvectors(M, C[..., rows, :, :], K[..., rows, :, :], chosen[..., rows])


def _has_shape(observation: Observation) -> bool:
    return (observation.shape is not None and observation.shape_covariance is not None
            and all(name in MODE_SHAPE_STATES for name in observation.shape_signals))



#: A window's mode shape is compared only where the base model has an oscillatory mode within
#: this fraction of the measured eigenvalue's magnitude: a "weave" fitted to a catch or to
#: noise (strongly damped, far from every model mode) has no mode shape to speak of, and the
#: shape of whichever real mode lies nearest would make it a huge outlier.
SHAPE_MATCH = 0.3


def compared_shapes(bicycle: Bicycle, observations: Sequence[Observation],
                    predicted: NDArray[np.complex128] | None = None) -> NDArray[np.bool_]:
    """Return which windows' mode shapes are compared with the model.

    Those with a shape whose eigenvalue the bicycle's model matches with an oscillatory mode
    (see SHAPE_MATCH).

    ``predicted`` is the model's eigenvalue nearest each observation (:func:`predicted_weave`)
    when already at hand.
    """
    if predicted is None:
        predicted = predicted_weave(bicycle, observations)
    measured = np.array([o.eigenvalue for o in observations])
    matched = (predicted.imag > 0) & (np.abs(measured - predicted) < SHAPE_MATCH * np.abs(measured))
    return np.array([_has_shape(o) for o in observations], dtype=bool) & matched



def noise_free(bicycle: Bicycle, observations: Sequence[Observation]) -> list[Observation]:
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
                                     residual_rms=np.asarray(measurement.fit.rms_residual, dtype=float)))


def _joint_weights(fit: WeaveFit) -> NDArray[np.float64] | None:
    """Return a joint fit's signal weights, or None for one signal.

    One signal's weight only scales it; the refits then weigh it by its spread, as before joint
    fits kept their weights, to the last bit.
    """
    return np.asarray(fit.signal_weights, dtype=float) if len(fit.signal_weights) > 1 else None


def observations(measurements: Sequence[WindowMeasurement]) -> list[Observation]:
    """Observations of all usable windows."""
    return [observation(m) for m in measurements if m.usable]

