"""Diagnosis from measured weave eigenvalues and mode shapes: which cause explains the model's error.

Each candidate cause (:mod:`whipple.diagnosis.causes`) is fitted to all observations jointly by robust
weighted least squares. Each window contributes the measured weave eigenvalue minus the model's
eigenvalue at the window's speed and, where a steer signal was measured, the measured mode
shape (steer amplitude per roll-rate amplitude, complex) minus the model's eigenvector ratio;
each residual is whitened by its fit's covariance. Eigenvalues alone leave some causes nearly
interchangeable (a longer trail and a high payload move the weave alike); the mode shape tells
them apart. Causes are compared by an approximate log Bayes factor against the base model (the
*evidence*, see ``docs/diagnosis.md``)::

    evidence = (chi2_base - chi2_cause) / 2 - (k / 2) ln(n) + ln(prior)

with n residuals, k fitted values, and each kind of residual (eigenvalue, shape) divided by
its own s^2 >= 1, the reduced chi-square of the best model on that kind (window uncertainties
that are too small inflate every chi-square alike). ``none`` has evidence 0. The verdict:
``none`` when no cause reaches ``named_threshold``; ``ambiguous`` when the runner-up is within
``margin`` of the best; otherwise ``named``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from whipple.diagnosis.causes import Cause, candidate_causes
from whipple.diagnosis.observations import (
    Observation,
    compared_shapes,
    predicted_modes,
    speed_groups,
)
from whipple.errors import AnalysisError, InputError
from whipple.model.parameters import Bicycle

NAMED_THRESHOLD = 3.0  # evidence (log Bayes factor) a cause needs over the base model: ~20:1
MARGIN = 2.0  # evidence by which the best must beat the runner-up: ~7:1
#: Whitened residuals beyond about this many standard deviations count less than quadratically
#: (soft L1 loss): a few windows at very unstable speeds are fitted far worse than their stated
#: uncertainty (the seed paper reports the same spread below 3 m/s) and must not decide alone.
ROBUST_SCALE = 3.0


def robust_chi2(residuals: NDArray[np.float64]) -> float:
    """Soft-L1 sum of squares: ~ sum r^2 for |r| << ROBUST_SCALE, ~ linear beyond."""
    c2 = ROBUST_SCALE**2
    return float(np.sum(2.0 * c2 * (np.sqrt(1.0 + residuals**2 / c2) - 1.0)))


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


@dataclass(frozen=True)
class Diagnosis:
    """Verdict, ranking and fits of every cause."""

    verdict: str
    cause: str
    best: CauseFit | None
    base: CauseFit
    fits: tuple[CauseFit, ...]
    scale: float
    observations: tuple[Observation, ...]
    shape_scale: float = 1.0
    n_shapes: int = 0

    def ranking(self) -> list[tuple[str, float]]:
        """Causes by decreasing evidence, with ``none`` at 0."""
        entries = [(fit.cause, fit.evidence) for fit in self.fits] + [("none", 0.0)]
        return sorted(entries, key=lambda entry: -entry[1])


@dataclass(frozen=True)
class _Whitening:
    """Whitening of the residuals: inverse Cholesky factors and dispersions.

    Per window the inverse Cholesky factors of the eigenvalue's and the shape's covariance,
    and the dispersion (reduced chi-square >= 1) by which each kind of residual is scaled.
    """

    eigenvalue: NDArray[np.float64]
    shape_index: NDArray[np.int_]
    shape: NDArray[np.float64]
    scales: tuple[float, float] = (1.0, 1.0)


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


def _whitening(observations: Sequence[Observation], bicycle: Bicycle,
               scales: tuple[float, float] = (1.0, 1.0)) -> _Whitening:
    """Whitening of every window's eigenvalue, and of the shapes the base ``bicycle`` compares."""
    eigenvalue = np.array([_inverse_cholesky(_with_floor(o), o, "eigenvalue") for o in observations])
    index = np.flatnonzero(compared_shapes(bicycle, observations))
    shape = np.array([_inverse_cholesky(observations[int(n)].shape_covariance, observations[int(n)], "mode shape")
                      for n in index]).reshape(-1, 2, 2)
    return _Whitening(eigenvalue, index, shape, scales)


def _residual_blocks(bicycle: Bicycle, observations: Sequence[Observation], whitening: _Whitening
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.complex128]]:
    """Return the whitened residuals at unit dispersion and the predicted eigenvalues.

    Eigenvalue residuals are 2 per window, shape residuals 2 per window with a shape.
    """
    predicted, shapes = predicted_modes(bicycle, observations)
    difference = np.array([[o.eigenvalue.real, o.eigenvalue.imag] for o in observations])
    difference -= np.column_stack([predicted.real, predicted.imag])
    eigenvalue = np.einsum("nij,nj->ni", whitening.eigenvalue, difference).ravel()
    index = whitening.shape_index
    measured = np.array([complex(observations[int(n)].shape or 0.0) for n in index])
    shape_difference = np.column_stack([(measured - shapes[index]).real, (measured - shapes[index]).imag])
    shape = np.einsum("nij,nj->ni", whitening.shape, shape_difference.reshape(-1, 2)).ravel()
    return eigenvalue, shape, predicted


def _residuals(bicycle: Bicycle, observations: Sequence[Observation], whitening: _Whitening
               ) -> tuple[NDArray[np.float64], NDArray[np.complex128], tuple[float, float]]:
    """Return all residuals, the predicted eigenvalues and each kind's robust chi-square.

    Each kind of residual is divided by its dispersion; the chi-squares are at unit dispersion
    (for :func:`_dispersions`).
    """
    eigenvalue, shape, predicted = _residual_blocks(bicycle, observations, whitening)
    # A model whose weave vanishes at a window's speed has no shape to compare: count it as a
    # large, finite misfit rather than stopping the fit.
    eigenvalue, shape = (np.nan_to_num(block, nan=1e3, posinf=1e3, neginf=-1e3) for block in (eigenvalue, shape))
    scaled = np.concatenate([eigenvalue / np.sqrt(whitening.scales[0]), shape / np.sqrt(whitening.scales[1])])
    return scaled, predicted, (robust_chi2(eigenvalue), robust_chi2(shape))


def fit_cause(bicycle: Bicycle, cause: Cause, observations: Sequence[Observation],
              whitening: _Whitening | None = None) -> CauseFit:
    """Fit one cause's values to all observations by robust weighted least squares."""
    whitening = _whitening(observations, bicycle) if whitening is None else whitening
    lower = np.array([b[0] for b in cause.bounds])
    upper = np.array([b[1] for b in cause.bounds])
    scale = np.maximum(np.abs(np.array(cause.start)), (upper - lower) * 1e-3)

    def residual(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return _residuals(cause.apply(bicycle, x * scale), observations, whitening)[0]

    # A few deterministic starts spread over the bounds guard against local minima.
    starts = [np.array(cause.start)] + [np.clip(np.array(cause.start) + (upper - lower) * f, lower, upper)
                                        for f in (0.02, 0.1)]
    if len(cause.parameters) > 1:
        starts += [lower + (upper - lower) * np.resize(np.array(f), len(lower))
                   for f in ((0.02, 0.1, 0.5), (0.1, 0.3, 0.4), (0.4, 0.05, 0.6))]
    best = None
    for start in starts:
        x0 = np.clip(start, lower, upper) / scale
        try:
            result = least_squares(residual, x0, bounds=(lower / scale, upper / scale), x_scale="jac",
                                   diff_step=1e-6, loss="soft_l1", f_scale=ROBUST_SCALE)
        except (np.linalg.LinAlgError, ValueError):
            continue
        if best is None or result.cost < best.cost:
            best = result
    if best is None:
        raise AnalysisError(f"fit of {cause.name} failed")
    values = best.x * scale
    jacobian = best.jac / scale
    try:
        covariance = np.linalg.pinv(jacobian.T @ jacobian)
        std = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    except np.linalg.LinAlgError:
        std = np.full(len(values), np.inf)
    final, predicted, block_chi2 = _residuals(cause.apply(bicycle, values), observations, whitening)
    return CauseFit(cause.name, cause.parameters, cause.units, tuple(float(v) for v in values),
                    tuple(float(s) for s in std), robust_chi2(final), predicted=predicted, block_chi2=block_chi2)


def _dispersions(fits: Sequence[CauseFit], counts: tuple[int, int]) -> tuple[float, float]:
    """Reduced chi-square (at least 1) of each kind of residual, for the best-fitting model.

    Window uncertainties that are too small inflate every model's chi-square alike; eigenvalue
    and mode-shape residuals are scaled separately, so that one kind of data that no model
    explains (a miscalibrated steer sensor, say) cannot outweigh the other.
    """
    total = max(sum(counts), 1)
    scales = []
    for block, count in enumerate(counts):
        if count == 0:
            scales.append(1.0)
            continue
        reduced = [fit.block_chi2[block] / max(count - len(fit.parameters) * count / total, 1.0) for fit in fits]
        scales.append(max(1.0, min(reduced)))
    return scales[0], scales[1]


def diagnose_observations(bicycle: Bicycle, observations: Sequence[Observation],
                          causes: Sequence[Cause] | None = None,
                          named_threshold: float = NAMED_THRESHOLD, margin: float = MARGIN) -> Diagnosis:
    """Fit every cause to the observations and decide which, if any, explains them."""
    observations = tuple(observations)
    if len(observations) < 2:
        raise InputError(f"need at least 2 windows with fitted eigenvalues, got {len(observations)}")
    causes = list(candidate_causes(bicycle)) if causes is None else list(causes)
    estimators = [cause for cause in causes if not cause.for_evidence]
    causes = [cause for cause in causes if cause.for_evidence]
    whitening = _whitening(observations, bicycle)
    counts = (2 * len(observations), 2 * len(whitening.shape_index))
    base, fits = _fit_all(bicycle, causes, observations, whitening)
    scales = _dispersions([base, *fits], counts)
    if scales != (1.0, 1.0):
        # Refit with each kind of residual at its own dispersion (weights the fits, too).
        whitening = replace(whitening, scales=scales)
        base, fits = _fit_all(bicycle, causes, observations, whitening)
    n = sum(counts)
    scored = []
    for cause, fit in zip(causes, fits, strict=True):
        evidence = (base.chi2 - fit.chi2) / 2.0 - 0.5 * len(fit.parameters) * np.log(n) + np.log(cause.prior)
        scored.append(replace(fit, evidence=float(evidence)))
    scored = _merge_forms(scored)
    if scored:
        # The leading cause's values, from its estimate-only form where it has one, with an
        # uncertainty that also covers errors shared by the windows of one speed.
        leading = [c for c in estimators if c.name == scored[0].cause]
        if not leading:
            leading = [c for c in causes if c.name == scored[0].cause
                       and len(c.parameters) == len(scored[0].parameters)]
        cause = leading[0]
        fit = fit_cause(bicycle, cause, observations, whitening) if not cause.for_evidence else scored[0]
        spread = np.maximum(np.array(fit.std), jackknife_std(bicycle, cause, observations, fit.values, scales))
        scored[0] = replace(fit, std=tuple(float(s) for s in spread), evidence=scored[0].evidence)
    best = scored[0] if scored else None
    if best is None or best.evidence < named_threshold:
        verdict, name = "none", "none"
    elif len(scored) > 1 and scored[1].evidence > best.evidence - margin:
        verdict, name = "ambiguous", best.cause
    else:
        verdict, name = "named", best.cause
    return Diagnosis(verdict, name, best if verdict != "none" else None, base, tuple(scored), scales[0],
                     observations, shape_scale=scales[1], n_shapes=len(whitening.shape_index))


def _fit_all(bicycle: Bicycle, causes: Sequence[Cause], observations: Sequence[Observation],
             whitening: _Whitening) -> tuple[CauseFit, list[CauseFit]]:
    residual, predicted, block_chi2 = _residuals(bicycle, observations, whitening)
    base = CauseFit("none", (), (), (), (), robust_chi2(residual), predicted=predicted, block_chi2=block_chi2)
    return base, [fit_cause(bicycle, cause, observations, whitening) for cause in causes]


def _merge_forms(scored: list[CauseFit]) -> list[CauseFit]:
    """One entry per cause, by decreasing evidence.

    A cause with several forms (payload: mass alone, or mass and position) is supported as
    well as its best form; its estimate is that of its most general form, so that the interval
    also carries the uncertainty of what the simpler form holds fixed.
    """
    merged: dict[str, CauseFit] = {}
    for fit in scored:
        forms = [other for other in scored if other.cause == fit.cause]
        if fit.cause in merged:
            continue
        general = max(forms, key=lambda other: len(other.parameters))
        evidence = max(other.evidence for other in forms)
        merged[fit.cause] = CauseFit(general.cause, general.parameters, general.units, general.values,
                                     general.std, general.chi2, evidence, general.predicted)
    return sorted(merged.values(), key=lambda fit: -fit.evidence)


def jackknife_std(bicycle: Bicycle, cause: Cause, observations: Sequence[Observation],
                  values: Sequence[float], scales: tuple[float, float] = (1.0, 1.0)) -> NDArray[np.float64]:
    """Leave-one-speed-group-out jackknife standard deviation of a cause's values.

    The fit's own standard deviation assumes independent windows; errors shared by the windows
    of one speed (a fitting-function bias that depends on speed, a speed error) are not in it.
    The jackknife over speed groups is robust to such errors. Zero with fewer than 3 groups.
    """
    groups = speed_groups(observations)
    if len(groups) < 3:
        return np.zeros(len(values))
    estimates = []
    for group in groups:
        kept = [o for i, o in enumerate(observations) if i not in group]
        if len(kept) < 2:
            continue
        estimates.append(fit_cause(bicycle, replace(cause, start=tuple(values)), kept,
                                   _whitening(kept, bicycle, scales)).values)
    if len(estimates) < 3:
        return np.zeros(len(values))
    estimates_array = np.array(estimates)
    g = len(estimates_array)
    return np.asarray(np.sqrt((g - 1) / g * np.sum((estimates_array - estimates_array.mean(axis=0)) ** 2, axis=0)))


