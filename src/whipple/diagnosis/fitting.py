"""Fitting a cause to observations: whitened residuals and robust weighted least squares.

Each window's measured weave eigenvalue (and mode shape, where measured) minus the model's is
whitened by the window's covariance; the residuals of a model are combined with a soft-L1 loss
(:func:`robust_chi2`), and a cause's values are those that minimise it within the cause's bounds
(:func:`fit_cause`). :mod:`whipple.diagnosis.evidence` compares the fits of all causes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.instrument import InstrumentErrors
from whipple.diagnosis.observations import Observation, compared_shapes, mode_targets
from whipple.diagnosis.priors import robust_prior_residuals
from whipple.diagnosis.samples import SampleComparison
from whipple.diagnosis.starts import default_starts, grid_starts
from whipple.errors import AnalysisError, InputError
from whipple.model.fleet import Model
from whipple.stability.nearest_modes import nearest_modes_and_holds, nearest_modes_of_models

#: Whitened residuals beyond about this many standard deviations count less than quadratically
#: (soft L1 loss): a few windows at very unstable speeds are fitted far worse than their stated
#: uncertainty (the seed paper reports the same spread below 3 m/s) and must not decide alone.
ROBUST_SCALE = 3.0
#: A value within this fraction of its range from a bound is at the bound (:func:`pinned_values`).
AT_BOUND = 1e-3


def robust_chi2(residuals: NDArray[np.float64]) -> float:
    """Soft-L1 sum of squares: ~ sum r^2 for |r| << ROBUST_SCALE, ~ linear beyond."""
    return float(np.sum(robust_squares(residuals)))


def robust_squares(residuals: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each residual's share of :func:`robust_chi2`."""
    c2 = ROBUST_SCALE**2
    return np.asarray(2.0 * c2 * (np.sqrt(1.0 + residuals**2 / c2) - 1.0))


@dataclass(frozen=True)
class CauseFit:
    """A cause fitted to all observations."""

    cause: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    values: tuple[float, ...]
    std: tuple[float, ...]
    chi2: float
    evidence: float = 0.0
    predicted: NDArray[np.complex128] = field(default_factory=lambda: np.zeros(0, complex), repr=False)
    block_chi2: tuple[float, ...] = (0.0, 0.0)
    #: Whitened residuals, each kind divided by its dispersion: the difference of two fits'
    #: residuals is the difference of their predictions in units of the observations' noise.
    residuals: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0), repr=False)
    #: The values fitted at a bound of the cause's range that is not their no-effect value,
    #: as (name, bound) (:func:`pinned_values`).
    pinned: tuple[tuple[str, float], ...] = ()
    #: Covariance of the values from the least-squares fit (before any widening of ``std``).
    covariance: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)), repr=False, compare=False)
    #: Derivative of the whitened residuals by each value at the fit (a column each; SciPy's
    #: Jacobian for the robust loss), for the Occam factor (:func:`~whipple.diagnosis.evidence.occam_factor`).
    jacobian: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 0)), repr=False, compare=False)


#: How models are compared with the windows: ``"samples"``, each model's free response fitted to
#: the windows' samples (:mod:`whipple.diagnosis.samples`); ``"fitting-function"``, each window's
#: eigenvalue and mode shape with the model's plus the bias the fitting function shows on the
#: model's own response (:mod:`whipple.diagnosis.fit_bias`); ``"eigenvalues"``, with the model's
#: directly. Windows read from a list of eigenvalues have no samples: they are compared directly.
COMPARISONS = ("samples", "fitting-function", "eigenvalues")


@dataclass(frozen=True)
class Whitening:
    """Whitening of the residuals: inverse Cholesky factors and dispersions.

    Per window the inverse Cholesky factors of the eigenvalue's and the shape's covariance,
    and the dispersion (reduced chi-square >= 1) by which each kind of residual is scaled.
    ``targets`` and ``measured_shapes`` are the windows' measured values
    (:func:`~whipple.diagnosis.observations.mode_targets`, and the shapes compared, in the order
    of ``shape_index``), gathered once for the thousands of residual evaluations of a fit.
    With ``samples``, a model's residuals are its residuals on the windows' samples instead
    (one kind; :mod:`whipple.diagnosis.samples`).
    """

    eigenvalue: NDArray[np.float64]
    shape_index: NDArray[np.int_]
    shape: NDArray[np.float64]
    targets: tuple[NDArray[np.float64], NDArray[np.complex128], list[tuple[str, str] | None], list[str],
                   NDArray[np.float64], NDArray[np.float64] | None] = field(repr=False)
    measured_shapes: NDArray[np.complex128] = field(repr=False)
    scales: tuple[float, float] = (1.0, 1.0)
    #: The fitting function's bias on the fitted model's own response, per window
    #: (:mod:`whipple.diagnosis.fit_bias`): the model's eigenvalue plus it is what a window's
    #: fit would report if the model were true. None: no bias.
    bias: NDArray[np.complex128] | None = field(default=None, repr=False)
    #: The windows' samples, where models are compared with them (None: with the eigenvalues).
    samples: SampleComparison | None = field(default=None, repr=False)

    @property
    def comparison(self) -> str:
        """How models are compared with the windows (one of :data:`COMPARISONS`)."""
        if self.samples is not None:
            return "samples"
        return "eigenvalues" if self.bias is None else "fitting-function"

    @property
    def counts(self) -> tuple[int, int]:
        """Number of residuals of each kind: eigenvalues (or samples) and mode shapes."""
        if self.samples is not None:
            return self.samples.samples, 0
        return 2 * len(self.eigenvalue), 2 * len(self.shape_index)

    @property
    def charged(self) -> int:
        """The n of the evidence's ln(n)/2 charge per fitted value: the eigenvalue and mode-shape residuals.

        Also with ``samples``: a window's samples inform a cause's values through the few modal
        quantities they fix (the weave's eigenvalue and shape above all), not sample by sample,
        so the charge stays that of the eigenvalue comparison.
        """
        return 2 * len(self.eigenvalue) + 2 * len(self.shape_index)

    def residual_layout(self) -> tuple[NDArray[np.int_], NDArray[np.int_]]:
        """Return the window and the kind of each residual, in :func:`model_residuals`' order.

        Kinds: 0 and 1 the eigenvalue's real and imaginary part, 2 and 3 the mode shape's; with
        ``samples``, every residual is of kind 0.
        """
        if self.samples is not None:
            windows = self.samples.window_of_residuals()
            return windows, np.zeros(windows.size, dtype=int)
        n = len(self.eigenvalue)
        windows = np.concatenate([np.repeat(np.arange(n), 2), np.repeat(self.shape_index, 2)])
        kinds = np.concatenate([np.tile([0, 1], n), np.tile([2, 3], len(self.shape_index))])
        return windows, kinds

    def window_dispersions(self, residuals: NDArray[np.float64], block: int) -> NDArray[np.float64]:
        """Return each window's squared residual of one kind over its expectation (1 for noise alone).

        ``block`` 0: eigenvalues (or samples), 1: mode shapes; ``residuals`` at unit dispersion.
        A window's eigenvalue (or shape) residual has two parts: its squared norm over the
        median of a chi-square of 2 degrees of freedom (2 ln 2), so that the median over windows
        is 1 for noise alone; a window's samples: their mean square.
        """
        begin, end = (0, self.counts[0]) if block == 0 else (self.counts[0], sum(self.counts))
        part = residuals[begin:end] ** 2
        if self.samples is not None and block == 0:
            windows = self.samples.window_of_residuals()
            return np.bincount(windows, weights=part) / np.maximum(np.bincount(windows), 1)
        return np.sum(part.reshape(-1, 2), axis=1) / _MEDIAN_CHI2_2


#: Median of a chi-square variable with 2 degrees of freedom (2 ln 2).
_MEDIAN_CHI2_2 = 2.0 * np.log(2.0)


#: Whitened residual [standard deviations] of an eigenvalue or a mode shape a model cannot give:
#: its weave vanishes at the window's speed, or it cannot hold the window (a mode it does not fit
#: grows there). Large and finite, so that a fit steps away from it instead of stopping.
EIGENVALUE_MISFIT = 1e3


def _inverse_cholesky(covariance: NDArray[np.float64] | None, observation: Observation,
                      what: str) -> NDArray[np.float64]:
    where = f"window {observation.run} {observation.start:.2f}-{observation.stop:.2f} s"
    covariance = np.asarray(covariance, dtype=float)
    if covariance.shape != (2, 2) or not np.all(np.isfinite(covariance)):
        raise InputError(f"{where}: {what} covariance must be a finite 2x2 matrix")
    try:
        return np.asarray(np.linalg.inv(np.linalg.cholesky(covariance)))
    except np.linalg.LinAlgError:
        raise InputError(f"{where}: {what} covariance is not positive definite") from None



#: Systematic error of a window's eigenvalue, relative to its magnitude, added to each part's
#: variance: the fitting function's own bias. On noise-free simulated runs of the benchmark,
#: kooijman2008 and sbw2024 bicycles at 2.5-8 m/s it is 0.01-0.3% of |lambda| at most speeds and
#: up to 2.5% near the weave speed, where windows are long and their stated uncertainty tiny;
#: without a floor such windows alone decided between causes (a 0.1% speed scale was "named"
#: in 2 of 8 effect-free trials of kooijman2008).
EIGENVALUE_FLOOR = 0.005


def _with_floor(observation: Observation) -> NDArray[np.float64]:
    covariance = np.asarray(observation.covariance, dtype=float)
    if covariance.shape != (2, 2):
        return covariance
    return covariance + np.eye(2) * (EIGENVALUE_FLOOR * abs(observation.eigenvalue)) ** 2


def window_whitening(observations: Sequence[Observation], bicycle: Model,
                     scales: tuple[float, float] = (1.0, 1.0), comparison: str = "eigenvalues",
                     instrument: InstrumentErrors | None = None) -> Whitening:
    """Whitening of every window's eigenvalue, and of the shapes the base ``bicycle`` compares.

    ``comparison`` ``"samples"``: models are compared with the windows' samples where every
    window has them (:meth:`~whipple.diagnosis.samples.SampleComparison.of`), else with the
    eigenvalues; other comparisons: the eigenvalues (a fitting function's bias is set by the
    caller, :mod:`whipple.diagnosis.fit_bias`). ``instrument``: the roll gyro's errors fitted
    with every model compared with the samples (:mod:`whipple.diagnosis.instrument`; None: not).
    """
    if comparison not in COMPARISONS:
        raise ValueError(f"comparison must be one of {', '.join(COMPARISONS)}, got {comparison!r}")
    eigenvalue = np.array([_inverse_cholesky(_with_floor(o), o, "eigenvalue") for o in observations])
    index = np.flatnonzero(compared_shapes(bicycle, observations))
    shape = np.array([_inverse_cholesky(observations[int(n)].shape_covariance, observations[int(n)], "mode shape")
                      for n in index]).reshape(-1, 2, 2)
    measured_shapes = np.array([complex(observations[int(n)].shape or 0.0) for n in index], dtype=complex)
    samples = (SampleComparison.of(observations, bicycle=bicycle, instrument=instrument)
               if comparison == "samples" else None)
    return Whitening(eigenvalue, index, shape, mode_targets(observations, bicycle), measured_shapes, scales,
                     samples=samples)


def _residual_blocks(models: Sequence[Model], observations: Sequence[Observation], whitening: Whitening,
                     predict: bool = True) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.complex128]]:
    """Return each model's whitened residuals at unit dispersion and predicted eigenvalues (a row each).

    Eigenvalue residuals are 2 per window, shape residuals 2 per window with a shape; with the
    samples, a residual per sample and no shape residuals, and the predicted eigenvalues only
    where ``predict`` (NaN otherwise: a fit's steps need only the residuals).
    """
    if len(observations) != len(whitening.eigenvalue):
        raise ValueError(f"{len(observations)} observations, whitening of {len(whitening.eigenvalue)}")
    if whitening.samples is not None:
        predicted = (nearest_modes_of_models(models, *whitening.targets)[0] if predict
                     else np.full((len(models), len(observations)), np.nan, dtype=complex))
        return whitening.samples.residuals(models), np.zeros((len(models), 0)), predicted
    predicted, shapes, unheld = nearest_modes_and_holds(models, *whitening.targets)
    targets = whitening.targets[1] if whitening.bias is None else whitening.targets[1] - whitening.bias
    difference = np.stack([targets.real - predicted.real, targets.imag - predicted.imag], axis=-1)
    # A model that cannot hold a window (a mode it does not fit grows there) misfits it, as in
    # the comparison with the samples: NaN, which models_residuals counts as EIGENVALUE_MISFIT.
    difference = np.where(unheld[..., None], np.nan, difference)
    shapes = np.where(unheld, np.nan, shapes)
    eigenvalue = np.einsum("nij,knj->kni", whitening.eigenvalue, difference).reshape(len(models), -1)
    shape_difference = whitening.measured_shapes - shapes[:, whitening.shape_index]
    shape_difference = np.stack([shape_difference.real, shape_difference.imag], axis=-1)
    shape = np.einsum("nij,knj->kni", whitening.shape, shape_difference).reshape(len(models), -1)
    return eigenvalue, shape, predicted


def model_residuals(bicycle: Model, observations: Sequence[Observation], whitening: Whitening
                    ) -> tuple[NDArray[np.float64], NDArray[np.complex128], tuple[float, float]]:
    """Return all residuals, the predicted eigenvalues and each kind's robust chi-square.

    Each kind of residual is divided by its dispersion; the chi-squares are at unit dispersion
    (for :func:`_dispersions`).
    """
    residuals, predicted, block_chi2 = models_residuals([bicycle], observations, whitening)
    return residuals[0], predicted[0], block_chi2[0]


def models_residuals(models: Sequence[Model], observations: Sequence[Observation], whitening: Whitening,
                     predict: bool = True
                     ) -> tuple[NDArray[np.float64], NDArray[np.complex128], list[tuple[float, float]]]:
    """:func:`model_residuals` of several models at once: residuals and predictions a row per model.

    ``predict``: also the predicted eigenvalues where the samples are compared (NaN otherwise).
    """
    # A trial value at the edge of a cause's bounds (a wheelbase or a wheel radius near 0) can
    # make the model singular; such a model is a misfit or a failed step of the fit, not
    # something to warn the user about.
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        eigenvalue, shape, predicted = _residual_blocks(models, observations, whitening, predict)
    # A model whose weave vanishes at a window's speed has no shape to compare: count it as a
    # large, finite misfit rather than stopping the fit.
    eigenvalue, shape = (np.nan_to_num(block, nan=EIGENVALUE_MISFIT, posinf=EIGENVALUE_MISFIT,
                                       neginf=-EIGENVALUE_MISFIT) for block in (eigenvalue, shape))
    scaled = np.concatenate([eigenvalue / np.sqrt(whitening.scales[0]), shape / np.sqrt(whitening.scales[1])],
                            axis=1)
    return scaled, predicted, [(robust_chi2(e), robust_chi2(s)) for e, s in zip(eigenvalue, shape, strict=True)]


def fit_cause(bicycle: Model, cause: Cause, observations: Sequence[Observation],
              whitening: Whitening | None = None,
              starts: Sequence[Sequence[float]] | None = None, grid: bool = True) -> CauseFit:
    """Fit one cause's values to all observations by robust weighted least squares.

    ``starts``: starting values to try instead of the default few spread over the bounds.
    ``grid``: also start from the best points of a coarse grid over the bounds (False: a local
    refit from ``starts``, e.g. from values fitted to more of the same data). A cause with
    priors on its values (:attr:`Cause.value_priors`) is fitted to its maximum a posteriori: its
    priors' residuals join the data's (:func:`~whipple.diagnosis.priors.robust_prior_residuals`);
    the fit's chi-square and residuals stay the data's.
    """
    whitening = window_whitening(observations, bicycle) if whitening is None else whitening
    lower, upper = cause.limits
    scale = np.maximum(np.abs(np.array(cause.start)), (upper - lower) * 1e-3)
    priors = cause.value_priors

    def with_priors(residual: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
        if priors is None:
            return residual
        return np.concatenate([residual, robust_prior_residuals(priors, _floats(values), ROBUST_SCALE)])

    def one(values: NDArray[np.float64]) -> NDArray[np.float64]:
        data = models_residuals([cause.apply(bicycle, _floats(values))], observations, whitening, predict=False)[0][0]
        return with_priors(data, values)

    def misfits(points: list[NDArray[np.float64]]) -> list[NDArray[np.float64]]:
        # The residuals at several points (values in their units) in one evaluation; one at a
        # time where one of them fails, so that the failure is raised as without it.
        try:
            data = models_residuals([cause.apply(bicycle, _floats(values)) for values in points], observations,
                                    whitening, predict=False)[0]
            return [with_priors(residual, values) for residual, values in zip(data, points, strict=True)]
        except (np.linalg.LinAlgError, ValueError):
            return [one(values) for values in points]

    def residual(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return one(x * scale)

    def chi2(points: list[NDArray[np.float64]]) -> list[float]:
        try:
            return [robust_chi2(r) for r in misfits(points)]
        except (np.linalg.LinAlgError, ValueError):
            return [_chi2_or_inf(one, point) for point in points]

    # Given starts first; the fixed ones only if every given start fails. The grid's best points
    # (:mod:`whipple.diagnosis.starts`) join the first round either way.
    best_of_grid = grid_starts(cause, chi2) if grid else []
    tries = default_starts(cause)
    rounds = ([tries + best_of_grid] if starts is None
              else [[np.array(start, dtype=float) for start in starts] + best_of_grid, tries])
    best = None
    for round_ in rounds:
        for start in round_:
            x0 = np.clip(start, lower, upper) / scale
            try:
                result = least_squares(residual, x0, bounds=(lower / scale, upper / scale), x_scale="jac",
                                       diff_step=1e-6, loss="soft_l1", f_scale=ROBUST_SCALE,
                                       # SciPy maps a finite-difference Jacobian's evaluations with ``workers``:
                                       # all of them at once here.
                                       workers=lambda _, points: misfits([x * scale for x in points]))
            except (np.linalg.LinAlgError, ValueError):
                continue
            if best is None or result.cost < best.cost:
                best = result
        if best is not None:
            break
    if best is None:
        raise AnalysisError(f"fit of {cause.name} failed")
    values = best.x * scale
    full = np.asarray(best.jac / scale, dtype=float)
    # The data's rows (the Occam factor's Fisher information); the priors' rows join them in
    # the covariance, the posterior's.
    jacobian = full if priors is None else full[:-len(priors)]
    if priors is not None:
        full = np.vstack([jacobian, np.diag([prior.slope(float(v)) for prior, v in zip(priors, values, strict=True)])])
    try:
        covariance = np.linalg.pinv(full.T @ full)
        std = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    except np.linalg.LinAlgError:
        covariance = np.full((len(values), len(values)), np.inf)
        std = np.full(len(values), np.inf)
    model = cause.apply(bicycle, values)
    final, predicted, block_chi2 = model_residuals(model, observations, whitening)
    return CauseFit(cause.name, cause.parameters, cause.units, tuple(float(v) for v in values),
                    tuple(float(s) for s in std), robust_chi2(final), predicted=predicted, block_chi2=block_chi2,
                    residuals=final, pinned=pinned_values(cause, values), covariance=covariance, jacobian=jacobian)


def _floats(values: NDArray[np.float64]) -> list[float]:
    return [float(v) for v in values]


def _chi2_or_inf(residual: Callable[[NDArray[np.float64]], NDArray[np.float64]], values: NDArray[np.float64]
                 ) -> float:
    try:
        return robust_chi2(residual(values))
    except (np.linalg.LinAlgError, ValueError):
        return float("inf")


def pinned_values(cause: Cause, values: Sequence[float] | NDArray[np.float64]) -> tuple[tuple[str, float], ...]:
    """Return the values (as name, bound) at a bound of the cause's range other than their no-effect value.

    Such a fit is the cause stretched as far as it physically goes (a load at the ground, a
    parameter doubled): the data ask for more than the cause can be, and the evidence, an
    expansion about an optimum inside the bounds, no longer measures its support. A value at
    its no-effect bound (a mass of 0) only says that the cause is not needed.
    """
    lower, upper = cause.limits
    start = np.array(cause.start, dtype=float)
    pinned = []
    for name, value, low, high, null in zip(cause.parameters, values, lower, upper, start, strict=True):
        tolerance = AT_BOUND * (high - low)
        for bound in (low, high):
            if abs(value - bound) <= tolerance and abs(null - bound) > tolerance:
                pinned.append((name, float(bound)))
                break
    return tuple(pinned)
