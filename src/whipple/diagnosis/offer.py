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
:mod:`whipple.diagnosis.consistency`) and predicts the weave eigenvalue there; the one with the
smallest RMS error over those predictions is offered, the base model where none predicts better
than it. The held-out gain's folds make the same choice on their own training speeds, so the
gain reported is that of this procedure on speeds it never saw.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from whipple.diagnosis.admissible import Offer, form_of, inconsistencies, offer_of
from whipple.diagnosis.causes import Cause, with_cause
from whipple.diagnosis.consistency import gauss_newton_refits, left_out_groups, refits_without
from whipple.diagnosis.evaluation import rms
from whipple.diagnosis.evidence import Diagnosis
from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.instrument import InstrumentErrors
from whipple.diagnosis.observations import predicted_weave
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
        offered), ``verdict.high_dispersion`` (above it no candidate explains the data) and
        ``prediction_shortlist`` (how many consistent candidates a choice by prediction weighs;
        0: always by evidence).

    Returns
    -------
    Offer
        By evidence: the leading cause if physically consistent, else the best-supported
        consistent one. By prediction (no candidate explains the data): the shortlisted
        consistent candidate that best predicts each speed left out in turn, or the base model.
    """
    evidence_offer = offer_of(bicycle, diagnosis, causes, options.verdict.named_threshold)
    observations = diagnosis.observations
    groups = left_out_groups(observations) if observations else []
    if not _by_prediction(diagnosis, options, groups):
        return evidence_offer
    shortlist, rejected = _shortlist(bicycle, diagnosis, causes, options)
    if not shortlist:
        return evidence_offer
    measured = np.array([o.eigenvalue for o in observations], dtype=complex)
    held = np.concatenate(groups)
    base_rms = rms(measured[held] - predicted_weave(bicycle, [observations[i] for i in held]))
    scores = [(prediction_rms(bicycle, cause, fit, diagnosis, groups, options.instrument), len(cause.parameters), k)
              for k, (cause, fit) in enumerate(shortlist)]
    predictions = (("none", base_rms), *((fit.cause, score[0]) for (_, fit), score in zip(shortlist, scores,
                                                                                          strict=True)))
    best_rms, _, best = min(scores)
    if not best_rms < base_rms:
        return Offer(None, None, rejected, "prediction", predictions)
    cause, fit = shortlist[best]
    return Offer(cause, fit, rejected, "prediction", predictions)


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


def prediction_rms(bicycle: Model, cause: Cause, fit: CauseFit, diagnosis: Diagnosis,
                   groups: Sequence[Sequence[int]], instrument: InstrumentErrors | None = None) -> float:
    """Return a candidate's RMS weave-eigenvalue error [1/s] on each group of windows left out in turn.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    cause : Cause
        The candidate's form.
    fit : CauseFit
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
    float
        The RMS of ``|measured - predicted|`` weave eigenvalue over every left-out window, each
        predicted by the candidate refitted without its group (locally from ``fit.values``).
    """
    observations = diagnosis.observations
    scales = (diagnosis.scale, diagnosis.shape_scale)
    if diagnosis.comparison == "samples":
        refits = gauss_newton_refits(bicycle, cause, observations, fit.values, groups, scales, instrument)
    else:
        refits = refits_without(bicycle, cause, observations, fit.values, groups, scales, diagnosis.comparison,
                                instrument)
    errors = []
    for group, values in zip(groups, refits, strict=True):
        held = [observations[i] for i in group]
        measured = np.array([o.eigenvalue for o in held], dtype=complex)
        errors.append(np.abs(measured - predicted_weave(with_cause(bicycle, cause, values), held)))
    return rms(np.concatenate(errors))
