"""The model a diagnosis offers: by evidence where a candidate explains the data, by prediction where none does.

The evidence ranks candidates by how well each fits every window, assuming one of them is the
truth. On simulated bicycles with one hidden effect that holds, and the best-supported
physically consistent candidate is offered (:func:`whipple.diagnosis.admissible.offer_of`).
On real bicycles it often does not: several parameters are off at once and effects no candidate
has act too, and even the best model leaves the typical window several times its noise off
(a dispersion above ``VerdictRules.high_dispersion``). The evidence then rewards whichever
flexible candidate absorbs most of the windows' details, which need not be the one that carries
over to speeds it has not seen, and carrying over is what a corrected model is for.

So, where no candidate explains the data and the windows span at least :data:`MIN_SPEED_GROUPS`
speeds, the model offered is chosen among the ``DiagnosisOptions.prediction_shortlist``
best-supported physically consistent candidates by prediction: each is refitted with each speed
left out in turn (a few Gauss-Newton steps from its values, as the jackknife does,
:mod:`whipple.diagnosis.consistency`) and predicts the weave eigenvalue there
(:func:`held_out_errors`). The choice follows the one-standard-error rule (Breiman et al. 1984;
Hastie, Tibshirani & Friedman, *The Elements of Statistical Learning*, sec. 7.10): the best
predictor is the candidate, the base model among them, with the smallest mean squared
``|measured - predicted|`` over every left-out window (the square of the RMS the report gives);
offered is the simplest candidate (fewest fitted values, the base model none; then the smaller
error) whose mean squared error exceeds the best's by at most
``DiagnosisOptions.prediction_standard_errors`` (default 1) standard errors of that excess
(:func:`excess_over_best`, :func:`simplest_within`). Two predictors equal within the noise are
thus not told apart by which of them a window more or less happens to favour: the simpler one
is offered, and the base model when no candidate beats it by more than a standard error.

The standard error is honest about what is independent. The windows of one speed share a refit
(the candidate refitted without that speed predicts all of them), so the units are the speed
groups, not the windows: per group, the mean of the squared errors; the excess over the best is
the pooled one, the groups' paired differences weighted by their windows; its standard error is
that of a weighted mean over the groups (the clustered standard error, with the factor
G/(G - 1) for G groups), which for groups of equal size is the standard deviation of the
per-group differences over the square root of G. A multiplier of 0 offers the best predictor
(the smaller RMS; ties to fewer values), as the choice did before the rule.

The held-out gain's folds make the same choice on their own training speeds, so the gain
reported is that of this procedure on speeds it never saw.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.admissible import HeldOutPrediction, Offer, form_of, inconsistencies, offer_of
from whipple.diagnosis.causes import Cause, with_cause
from whipple.diagnosis.consistency import gauss_newton_refits, left_out_groups, refits_without
from whipple.diagnosis.evaluation import rms
from whipple.diagnosis.evidence import Diagnosis
from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.instrument import InstrumentErrors
from whipple.diagnosis.observations import Observation, predicted_weave
from whipple.diagnosis.options import DiagnosisOptions
from whipple.model.fleet import Model

#: Speeds (groups of windows) the windows must span for a choice by prediction: with each left
#: out in turn, every refit still sees at least two.
MIN_SPEED_GROUPS = 3


def offer(bicycle: Model, diagnosis: Diagnosis, causes: Sequence[Cause], options: DiagnosisOptions) -> Offer:
    """Return the model a diagnosis offers.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    diagnosis : Diagnosis
        The diagnosis (its ranked fits, windows and dispersions).
    causes : sequence of Cause
        The candidates, every form.
    options : DiagnosisOptions
        The diagnosis' options: ``verdict.named_threshold`` (evidence a model needs to be
        offered), ``verdict.high_dispersion`` (above it no candidate explains the data),
        ``prediction_shortlist`` (how many consistent candidates a choice by prediction weighs;
        0: always by evidence) and ``prediction_standard_errors`` (the rule's multiplier).

    Returns
    -------
    Offer
        By evidence: the leading cause if physically consistent, else the best-supported
        consistent one. By prediction (no candidate explains the data): the simplest of the base
        model and the shortlisted consistent candidates whose error on the speeds left out in
        turn is within ``prediction_standard_errors`` standard errors of the best predictor's.
    """
    evidence_offer = offer_of(bicycle, diagnosis, causes, options.verdict.named_threshold)
    observations = diagnosis.observations
    groups = left_out_groups(observations) if observations else []
    if not _by_prediction(diagnosis, options, groups):
        return evidence_offer
    shortlist, rejected = _shortlist(bicycle, diagnosis, causes, options)
    if not shortlist:
        return evidence_offer
    errors = [held_out_errors(bicycle, None, None, diagnosis, groups),
              *(held_out_errors(bicycle, cause, fit, diagnosis, groups, options.instrument)
                for cause, fit in shortlist)]
    names = ["none", *(fit.cause for _, fit in shortlist)]
    sizes = [0, *(len(cause.parameters) for cause, _ in shortlist)]
    excess, standard_error = excess_over_best(errors)
    predictions = tuple(HeldOutPrediction(name, size, rms(np.concatenate(error)), float(e), float(se))
                        for name, size, error, e, se in zip(names, sizes, errors, excess, standard_error, strict=True))
    chosen = simplest_within(sizes, excess, standard_error, options.prediction_standard_errors)
    if chosen == 0:
        return Offer(None, None, rejected, "prediction", predictions, options.prediction_standard_errors)
    cause, fit = shortlist[chosen - 1]
    return Offer(cause, fit, rejected, "prediction", predictions, options.prediction_standard_errors)


def excess_over_best(errors: Sequence[Sequence[NDArray[np.float64]]]
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return each candidate's mean squared error above the best's, and the standard error of that excess.

    Parameters
    ----------
    errors : sequence of sequence of array
        Per candidate, per group of windows (the same groups, in the same order, for every
        candidate), the ``|measured - predicted|`` weave eigenvalue [1/s] of each window.

    Returns
    -------
    excess : array
        Per candidate, its mean squared error over every window minus the smallest one [1/s^2]
        (0 for the best).
    standard_error : array
        Per candidate, the standard error [1/s^2] of its excess with the groups as the units:
        sqrt(G/(G-1) sum_g (n_g/N)^2 (d_g - excess)^2), d_g the group's paired difference of mean
        squared errors, n_g its windows, N all; std(d_g)/sqrt(G) for groups of equal size.
    """
    sizes = np.array([len(group) for group in errors[0]], dtype=float)
    if len(sizes) < 2 or any(len(candidate) != len(sizes) for candidate in errors):
        raise ValueError("every candidate needs its errors on the same two or more groups")
    per_group = np.array([[np.mean(np.abs(group) ** 2) for group in candidate] for candidate in errors])
    pooled = per_group @ sizes / sizes.sum()
    best = int(np.argmin(pooled))
    excess = pooled - pooled[best]
    weights = sizes / sizes.sum()
    spread = weights * (per_group - per_group[best] - excess[:, None])
    count = len(sizes)
    return excess, np.sqrt(count / (count - 1) * np.sum(spread ** 2, axis=1))


def simplest_within(sizes: Sequence[int], excess: Sequence[float] | NDArray[np.float64],
                    standard_error: Sequence[float] | NDArray[np.float64], standard_errors: float) -> int:
    """Return the candidate the one-standard-error rule picks: the simplest one close enough to the best.

    Parameters
    ----------
    sizes : sequence of int
        Each candidate's number of fitted values (the base model: 0).
    excess, standard_error : sequence of float
        Each candidate's mean squared error above the best's and its standard error [1/s^2]
        (:func:`excess_over_best`).
    standard_errors : float
        How many standard errors above the best's a candidate's error may be (0: the best).

    Returns
    -------
    int
        Index of the candidate with the fewest values among those within the bound; ties in
        values to the smaller error, then the earlier candidate.
    """
    within = [k for k in range(len(sizes)) if excess[k] <= standard_errors * standard_error[k]]
    return min(within, key=lambda k: (sizes[k], excess[k], k))


def _by_prediction(diagnosis: Diagnosis, options: DiagnosisOptions, groups: Sequence[Sequence[int]]) -> bool:
    """Whether the offer is chosen by prediction: no candidate explains the data, and speeds enough to leave out."""
    if options.prediction_shortlist < 1 or diagnosis.verdict == "none" or diagnosis.best is None:
        return False
    if diagnosis.comparison not in ("samples", "eigenvalues"):
        return False  # a fitting function's bias would have to be refitted with each speed left out
    if max(diagnosis.typical_scales) <= options.verdict.high_dispersion:
        return False
    return len(groups) >= MIN_SPEED_GROUPS


def _shortlist(bicycle: Model, diagnosis: Diagnosis, causes: Sequence[Cause], options: DiagnosisOptions
               ) -> tuple[list[tuple[Cause, CauseFit]], tuple[tuple[str, tuple[str, ...]], ...]]:
    """Return the best-supported physically consistent candidates, and the better-supported inconsistent ones."""
    shortlist: list[tuple[Cause, CauseFit]] = []
    rejected: list[tuple[str, tuple[str, ...]]] = []
    for fit in sorted(diagnosis.fits, key=lambda f: -f.evidence):
        if fit.evidence < options.verdict.named_threshold or len(shortlist) >= options.prediction_shortlist:
            break
        cause = form_of(fit, causes)
        if cause is None:
            continue
        problems = inconsistencies(bicycle, cause, fit, diagnosis.observations)
        if problems:
            rejected.append((fit.cause, problems))
        else:
            shortlist.append((cause, fit))
    return shortlist, tuple(rejected)


def held_out_errors(bicycle: Model, cause: Cause | None, fit: CauseFit | None, diagnosis: Diagnosis,
                    groups: Sequence[Sequence[int]], instrument: InstrumentErrors | None = None
                    ) -> list[NDArray[np.float64]]:
    """Return a candidate's weave-eigenvalue errors [1/s] on each group of windows left out in turn.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    cause : Cause or None
        The candidate's form (None: the base model, nothing refitted).
    fit : CauseFit or None
        Its values fitted to every window of ``diagnosis``.
    diagnosis : Diagnosis
        The diagnosis: its windows, its comparison and its dispersions.
    groups : sequence of sequence of int
        The groups of windows (indices into ``diagnosis.observations``) left out in turn, each
        leaving at least two.
    instrument : InstrumentErrors or None
        The roll gyro's errors fitted with the refits as with the diagnosis' own fits
        (``DiagnosisOptions.instrument``; None: the signals taken as read).

    Returns
    -------
    list of array
        Per group, ``|measured - predicted|`` weave eigenvalue of each of its windows, predicted
        by the candidate refitted without the group (locally from ``fit.values``).
    """
    observations = diagnosis.observations
    models: list[Model] = [bicycle] * len(groups)
    if cause is not None and fit is not None:
        scales = (diagnosis.scale, diagnosis.shape_scale)
        if diagnosis.comparison == "samples":
            refits = gauss_newton_refits(bicycle, cause, observations, fit.values, groups, scales, instrument)
        else:
            refits = refits_without(bicycle, cause, observations, fit.values, groups, scales, diagnosis.comparison,
                                    instrument)
        models = [with_cause(bicycle, cause, values) for values in refits]
    return group_errors(models, observations, groups)


def group_errors(models: Sequence[Model], observations: Sequence[Observation], groups: Sequence[Sequence[int]]
                 ) -> list[NDArray[np.float64]]:
    """Return ``|measured - predicted|`` weave eigenvalues [1/s] of each group's windows, each by its own model."""
    errors = []
    for group, model in zip(groups, models, strict=True):
        held = [observations[i] for i in group]
        measured = np.array([o.eigenvalue for o in held], dtype=complex)
        errors.append(np.abs(measured - predicted_weave(model, held)))
    return errors

