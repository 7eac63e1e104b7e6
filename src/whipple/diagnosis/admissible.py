"""Whether a model the diagnosis would offer is physically consistent: only such a model is offered.

On real bicycles the truth is rarely one candidate, and a flexible candidate can fit the
windows only by going where no bicycle goes: a load as heavy as its frame allows at the edge of
its place, a mass of nothing at a fitted place, a bicycle whose weave grows where every
measured weave decays. Such a model improves the numbers and is no description of the bicycle.
:func:`inconsistencies` says what is wrong with a fitted model; :func:`offered_model` offers the
best-supported consistent one and says why the others were not offered.

A fitted model is consistent when

1. every value lies inside its physical range, none at a bound other than its no-effect value
   (:func:`~whipple.diagnosis.fitting.pinned_values`);
2. no value is degenerate: a load of no mass whose place or size was fitted;
3. the changed bicycle passes the package's physical checks
   (:func:`~whipple.model.parameter_set.validate`: positive masses, an inertia tensor a body can have);
4. its weave decays wherever the measured weave clearly decays: at every window whose real part
   is more than :data:`DECAY_SIGMAS` standard deviations below zero, the model's oscillating mode
   nearest the measured eigenvalue has a negative real part.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from whipple.diagnosis.causes import Cause, with_cause
from whipple.diagnosis.evidence import Diagnosis
from whipple.diagnosis.families import COMBINATION, combined_cause, components, general_forms
from whipple.diagnosis.fitting import AT_BOUND, CauseFit, pinned_values
from whipple.diagnosis.observations import Observation
from whipple.model.fleet import Model
from whipple.model.parameter_set import Bicycle, validate
from whipple.stability.nearest_modes import nearest_oscillations

#: A measured weave decays clearly where its real part is this many standard deviations below zero.
DECAY_SIGMAS = 2.0
#: Values of a load's form that need its mass: with no mass they describe nothing.
_NEEDS_MASS = ("_x", "_z", "_roll_gyration", "_yaw_gyration")


@dataclass(frozen=True)
class HeldOutPrediction:
    """How well one candidate of a choice by prediction predicts the speeds left out in turn.

    Attributes
    ----------
    name : str
        The candidate (``"none"``: the base model).
    values : int
        Its number of fitted values (the base model: 0).
    rms : float
        RMS [1/s] of its ``|measured - predicted|`` weave eigenvalue over every left-out window.
    excess : float
        Its mean squared error minus that of the best predictor [1/s^2] (0 for the best).
    standard_error : float
        The standard error [1/s^2] of ``excess``, the speed groups taken as the units
        (:func:`whipple.diagnosis.offer.excess_over_best`; 0 for the best).
    """

    name: str
    values: int
    rms: float
    excess: float
    standard_error: float

    def to_dict(self) -> dict[str, float | int]:
        """Return the figures as JSON-ready data."""
        return {"values": self.values, "rms": self.rms, "mse_above_best": self.excess,
                "standard_error": self.standard_error}


@dataclass(frozen=True)
class Offer:
    """The model the diagnosis offers, and what was not offered.

    Attributes
    ----------
    cause : Cause or None
        The offered cause's form (None: the base model, no consistent candidate led).
    fit : CauseFit or None
        Its fitted values.
    rejected : tuple of (str, tuple of str)
        The better-supported candidates not offered, each with what makes it inconsistent.
    chosen_by : {"evidence", "prediction"}
        How the offered model was chosen among the consistent candidates: the best-supported
        one, or by how well each predicts speeds left out in turn
        (:func:`whipple.diagnosis.offer.offer`).
    predictions : tuple of HeldOutPrediction
        Chosen by prediction: the base model and each shortlisted candidate, with its error on
        the speeds left out in turn.
    standard_errors : float
        Chosen by prediction: the simplest candidate whose mean squared error is within this
        many standard errors of the best predictor's was offered
        (``DiagnosisOptions.prediction_standard_errors``).
    """

    cause: Cause | None
    fit: CauseFit | None
    rejected: tuple[tuple[str, tuple[str, ...]], ...] = ()
    chosen_by: str = "evidence"
    predictions: tuple[HeldOutPrediction, ...] = ()
    standard_errors: float = 0.0

    def sentences(self) -> list[str]:
        """Say which candidates were not offered and why, and what is offered instead."""
        lines = [f"{name} is not offered: {'; '.join(reasons)}" for name, reasons in self.rejected]
        if self.chosen_by == "prediction":
            lines.append(self._prediction_sentence())
        elif self.rejected:
            lines.append(f"offered instead: {self.fit.cause}" if self.fit is not None else
                         "no candidate that the data support is physically consistent: the base model is offered")
        return lines

    def _prediction_sentence(self) -> str:
        """Say how the model offered was chosen by prediction, with every candidate's figures."""
        offered = self.fit.cause if self.fit is not None else "none"
        best = min(self.predictions, key=lambda p: p.rms).name if self.predictions else offered
        scores = ", ".join(f"{p.name} {p.rms:.3g}" + ("" if p.name == best else
                                                      f" ({p.excess:+.2g} +/- {p.standard_error:.2g})")
                           for p in self.predictions)
        plural = "" if self.standard_errors == 1 else "s"
        return (f"no candidate explains the data, so the model offered is chosen by prediction: of the base model "
                f"and the consistent candidates, the simplest (fewest fitted values) whose mean squared error on "
                f"the speeds left out in turn is within {self.standard_errors:g} standard error{plural} of the best "
                f"predictor's ({best}): {'the base model' if offered == 'none' else offered}. RMS weave-eigenvalue "
                f"error [1/s] on the left-out speeds, and in brackets the mean squared error above the best's +/- "
                f"its standard error over the speeds [1/s^2]: {scores}")


def inconsistencies(bicycle: Model, cause: Cause, fit: CauseFit, observations: Sequence[Observation]
                    ) -> tuple[str, ...]:
    """Return what makes a fitted model physically inconsistent (empty when it is consistent).

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    cause : Cause
        The cause (the form whose values ``fit`` holds).
    fit : CauseFit
        Its fitted values.
    observations : sequence of Observation
        The windows: the model's weave must decay where theirs clearly does.

    Returns
    -------
    tuple of str
        One sentence per problem.
    """
    problems = [f"{name} at the edge of its physical range ({bound:.4g})" for name, bound in
                pinned_values(cause, fit.values)]
    values = dict(zip(cause.parameters, fit.values, strict=True))
    for name, value in values.items():
        if name.endswith("_mass"):
            prefix = name.removesuffix("_mass")
            low, high = dict(zip(cause.parameters, cause.bounds, strict=True))[name]
            fitted = [other for other in cause.parameters if other.startswith(prefix) and other.endswith(_NEEDS_MASS)]
            if fitted and value <= low + AT_BOUND * (high - low):
                problems.append(f"{name} is nothing ({value:.3g}) while its "
                                f"{' and '.join(o.removeprefix(prefix + '_') for o in fitted)} were fitted")
    extended = with_cause(bicycle, cause, fit.values)
    members = [extended] if isinstance(extended, Bicycle) else [member for _, member in extended.members]
    for member in members:
        report = validate(member)
        if report.problems:
            problems.append("not a physical bicycle: " + "; ".join(report.problems))
            return tuple(problems)
    growing = _growing_where_decaying(extended, observations)
    if growing:
        problems.append(f"its weave grows where the measured weave decays ({growing})")
    return tuple(problems)


def _growing_where_decaying(model: Model, observations: Sequence[Observation]) -> str:
    """Say at which speeds a model's weave grows though the measured one clearly decays ("" at none)."""
    decaying = [o for o in observations
                if o.eigenvalue.real < -DECAY_SIGMAS * float(np.sqrt(max(o.covariance[0, 0], 0.0)))]
    if not decaying:
        return ""
    speeds = np.array([o.speed for o in decaying])
    targets = np.array([o.eigenvalue for o in decaying])
    groups = [o.group for o in decaying]
    predicted = np.full(len(decaying), np.nan, dtype=complex)
    from_members = [(model, None)] if isinstance(model, Bicycle) else [
        (member, [k for k, group in enumerate(groups) if group == name]) for name, member in model.members]
    for member, index in from_members:
        rows = list(range(len(decaying))) if index is None else index
        if rows:
            predicted[rows] = nearest_oscillations(member, speeds[rows], targets[rows])[0]
    bad = np.isfinite(predicted) & (predicted.real > 0)
    if not bad.any():
        return ""
    at = sorted({round(float(speed), 2) for speed in speeds[bad]})
    return f"{int(bad.sum())} of {len(decaying)} decaying windows, at {', '.join(f'{s:.2f}' for s in at)} m/s"


def offered_model(bicycle: Model, fits: Sequence[CauseFit], causes: Sequence[Cause],
                  observations: Sequence[Observation], threshold: float) -> Offer:
    """Return the best-supported physically consistent model among the ranked fits.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    fits : sequence of CauseFit
        The diagnosis' ranked fits (best first; one per cause, pairs as ``"A + B"``).
    causes : sequence of Cause
        The candidates, every form (pairs are built from their members' general forms).
    observations : sequence of Observation
        The windows.
    threshold : float
        Evidence a model needs to be offered at all (the verdict's ``named_threshold``).

    Returns
    -------
    Offer
        The first consistent fit with at least ``threshold`` evidence, and the better ones
        rejected with their reasons.
    """
    rejected: list[tuple[str, tuple[str, ...]]] = []
    for fit in fits:
        if fit.evidence < threshold:
            break
        cause = form_of(fit, causes)
        if cause is None:
            continue
        problems = inconsistencies(bicycle, cause, fit, observations)
        if not problems:
            return Offer(cause, fit, tuple(rejected))
        rejected.append((fit.cause, problems))
    return Offer(None, None, tuple(rejected))


def offer_of(bicycle: Model, diagnosis: Diagnosis, causes: Sequence[Cause], threshold: float) -> Offer:
    """Return the model a diagnosis offers: its leading cause if consistent, else the best consistent one.

    None is offered (the base model) for the verdict ``none``.
    """
    if diagnosis.verdict == "none" or diagnosis.best is None:
        return Offer(None, None)
    if diagnosis.chosen is not None and not inconsistencies(bicycle, diagnosis.chosen, diagnosis.best,
                                                             diagnosis.observations):
        return Offer(diagnosis.chosen, diagnosis.best)
    return offered_model(bicycle, diagnosis.fits, causes, diagnosis.observations, threshold)


def form_of(fit: CauseFit, causes: Sequence[Cause]) -> Cause | None:
    """Return the form of a cause (or pair) whose values a fit holds, or None if none matches."""
    if COMBINATION in fit.cause:
        forms = {cause.name: cause for cause in general_forms(causes, refinements=False)}
        first, second = components(fit.cause)
        if first not in forms or second not in forms:
            return None
        pair = combined_cause(forms[first], forms[second])
        return pair if pair.parameters == fit.parameters else None
    return next((cause for cause in causes if cause.name == fit.cause and cause.parameters == fit.parameters), None)
