"""Every candidate fitted to the same windows: to their eigenvalues, their samples, or through the fitting function.

:func:`fit_all` fits the base model and each cause. :func:`refit_to_samples` compares each
with the windows' samples (:mod:`whipple.diagnosis.samples`), starting from its fit to the
eigenvalues: a comparison with the samples costs several times one with the eigenvalues, so
only the causes near the best are refitted, the others evaluated at their values.
:func:`refit_through_bias` compares each with the windows through the fitting function
(:mod:`whipple.diagnosis.fit_bias`): the bias of a model is costly (refits of every window), so
only the causes near the best get their own model's bias and a refit; the others, far behind,
are evaluated at their values with the base model's bias, which moves them little against a
lead of ``screen`` (docs/diagnosis.md, "All windows at once, and the bias only where it can
matter").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.families import components
from whipple.diagnosis.fit_bias import fitting_bias
from whipple.diagnosis.fitting import CauseFit, Whitening, fit_cause, model_residuals, robust_chi2
from whipple.diagnosis.observations import Observation
from whipple.diagnosis.samples import OVERFLOW_MISFIT
from whipple.diagnosis.starts import GRID_MAX_VALUES, refinement_starts
from whipple.measurement.measure import Progress
from whipple.model.fleet import Model


def fit_all(bicycle: Model, causes: Sequence[Cause], observations: Sequence[Observation],
            whitening: Whitening, starts: Sequence[Sequence[Sequence[float]] | None] | None = None,
            biases: Sequence[NDArray[np.complex128]] | None = None,
            progress: Progress | None = None) -> tuple[CauseFit, list[CauseFit]]:
    """Fit the base model and every cause; ``biases``: the fitting bias of the base model, then of each cause.

    ``progress`` is called as ``progress("candidates", done, total)`` after each cause.
    """
    own = [whitening] * (1 + len(causes)) if biases is None else [replace(whitening, bias=b) for b in biases]
    base = _evaluated(bicycle, CauseFit("none", (), (), (), (), 0.0), observations, own[0])
    starts = [None] * len(causes) if starts is None else starts
    fits: list[CauseFit] = []
    for cause, start, cause_whitening in zip(causes, starts, own[1:], strict=True):
        simpler = None
        if start is None and cause.refines is not None:
            simpler = next((fit for fit in fits if fit.cause == cause.name and fit.parameters == cause.refines), None)
        if simpler is None:
            fits.append(fit_cause(bicycle, cause, observations, cause_whitening, start))
        else:  # a refinement of a form fitted just before: start from its fit, no search
            fits.append(fit_cause(bicycle, cause, observations, cause_whitening,
                                  refinement_starts(cause, simpler.values), grid=False))
        if progress is not None:
            progress("candidates", len(fits), len(causes))
    return base, fits


def refit_to_samples(bicycle: Model, causes: Sequence[Cause], fits: Sequence[CauseFit],
                     observations: Sequence[Observation], whitening: Whitening, near: Sequence[bool],
                     search: bool = True) -> tuple[CauseFit, list[CauseFit]]:
    """Compare the base model and each fitted cause with the windows' samples (``whitening.samples``).

    A cause ``near`` the best is refitted from its values (fitted to the eigenvalues); with
    ``search``, one of two or three values (a payload's mass and position, the tyres) also from
    the best points of a coarse grid over its bounds evaluated on the samples, since the
    samples may favour another part of the bounds than the eigenvalues did. Any other cause is
    evaluated at its values, and refitted so where they leave a window the samples cannot hold
    (:data:`~whipple.diagnosis.samples.OVERFLOW_MISFIT`).

    Returns
    -------
    base : CauseFit
        The base model compared with the samples.
    fits : list of CauseFit
        Each cause, in the order of `causes`.
    """
    if whitening.samples is None:
        raise ValueError("refit_to_samples needs a whitening with the windows' samples")
    base = _evaluated(bicycle, CauseFit("none", (), (), (), (), 0.0), observations, whitening)
    compared = []
    for cause, fit, is_near in zip(causes, fits, near, strict=True):
        if not is_near:
            evaluated = _evaluated(cause.apply(bicycle, list(fit.values)), fit, observations, whitening)
            if np.all(np.abs(evaluated.residuals) * np.sqrt(whitening.scales[0]) < OVERFLOW_MISFIT):
                compared.append(evaluated)
                continue
        # Near the best, or values fitted to the eigenvalues that leave a window the samples
        # cannot hold (a mode the windows do not fit grows there: a tyre relaxing slowly at a
        # low speed): such a cause's evidence at those values would say nothing of the cause.
        grid = not is_near or (search and cause.refines is None and 2 <= len(cause.parameters) <= GRID_MAX_VALUES)
        compared.append(fit_cause(bicycle, cause, observations, whitening, [fit.values], grid=grid))
    return base, compared


def singles_from_pairs(bicycle: Model, causes: Sequence[Cause], fits: Sequence[CauseFit], pairs: Sequence[Cause],
                       pair_fits: Sequence[CauseFit], observations: Sequence[Observation], whitening: Whitening
                       ) -> tuple[list[CauseFit], list[int]]:
    """Refit each single cause from its values in a pair where they fit the samples better than its own fit.

    A single cause's starts and grid can miss a narrow basin that a pair's fit reaches: a tyre
    whose growing shimmy the windows show holds them only near its true values and no window
    far from them (:mod:`whipple.diagnosis.growing_modes`); on simulated trials the single tyre
    stalled at the edge of its range while the pair of a steer damping at zero and the tyre
    reached the true values. Each member's values in each pair are evaluated alone (one
    model's comparison); where they beat the single cause's fit, it is refitted from them.
    Returns the fits, in the order of `causes`, and the indices of those refitted.
    """
    fits = list(fits)
    refitted: list[int] = []
    for pair, pair_fit in zip(pairs, pair_fits, strict=True):
        names = components(pair.name)
        for k, cause in enumerate(causes):
            size = len(cause.parameters)
            if cause.name == names[0] and pair.parameters[:size] == cause.parameters:
                values = list(pair_fit.values[:size])
            elif cause.name == names[-1] and pair.parameters[-size:] == cause.parameters:
                values = list(pair_fit.values[-size:])
            else:
                continue
            if _evaluated(cause.apply(bicycle, values), fits[k], observations, whitening).chi2 >= fits[k].chi2:
                continue
            fit = fit_cause(bicycle, cause, observations, whitening, [values], grid=False)
            if fit.chi2 < fits[k].chi2:
                fits[k] = fit
                refitted.append(k)
    return fits, refitted


def refit_through_bias(bicycle: Model, causes: Sequence[Cause], fits: Sequence[CauseFit],
                       observations: Sequence[Observation], whitening: Whitening,
                       base_bias: NDArray[np.complex128], near: Sequence[bool], start: str = "measured"
                       ) -> tuple[CauseFit, list[CauseFit], list[NDArray[np.complex128]]]:
    """Compare the base model and each fitted cause with the windows through the fitting function.

    A cause ``near`` the best is refitted from its values with its own model's bias at them;
    any other is evaluated at its values with the base model's bias ``base_bias``. ``start``:
    where the bias' fixed point starts (:func:`~whipple.diagnosis.fit_bias.fitting_bias`).

    Returns
    -------
    base : CauseFit
        The base model with its bias.
    fits : list of CauseFit
        Each cause, in the order of `causes`.
    biases : list of ndarray of complex
        The bias each cause was compared with [1/s], per window.
    """
    biases = [fitting_bias(cause.apply(bicycle, list(fit.values)), observations, start=start) if is_near
              else base_bias
              for cause, fit, is_near in zip(causes, fits, near, strict=True)]
    chosen = [k for k, is_near in enumerate(near) if is_near]
    base, refitted = fit_all(bicycle, [causes[k] for k in chosen], observations, whitening,
                             [[fits[k].values] for k in chosen], [base_bias, *[biases[k] for k in chosen]])
    with_base_bias = replace(whitening, bias=base_bias)
    in_order = iter(refitted)
    compared = [next(in_order) if is_near else
                _evaluated(cause.apply(bicycle, list(fit.values)), fit, observations, with_base_bias)
                for cause, fit, is_near in zip(causes, fits, near, strict=True)]
    return base, compared, biases


def _evaluated(model: Model, fit: CauseFit, observations: Sequence[Observation], whitening: Whitening) -> CauseFit:
    """Return `fit` with its residuals and chi-square those of `model` under `whitening` (no refit)."""
    residual, predicted, block_chi2 = model_residuals(model, observations, whitening)
    return replace(fit, chi2=robust_chi2(residual), predicted=predicted, block_chi2=block_chi2, residuals=residual)
