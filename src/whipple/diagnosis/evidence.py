"""Diagnosis from measured weave eigenvalues and mode shapes: which cause explains the model's error.

Each candidate cause (:mod:`whipple.diagnosis.causes`) is fitted to all observations jointly by robust
weighted least squares. Where every window's samples are known, a model is compared with them
(``comparison="samples"``, the default: :mod:`whipple.diagnosis.samples`): each window's free
response of the model, its modal amplitudes fitted, leaves a residual on every sample, in units
of the noise. Otherwise, or with ``comparison="eigenvalues"``, each window contributes the measured
weave eigenvalue minus the model's eigenvalue at the window's speed (with
``comparison="fitting-function"``, plus the bias the fitting function shows on that model's own
response, :mod:`whipple.diagnosis.fit_bias`) and, where a steer signal was measured, the
measured mode shape (steer amplitude per roll-rate amplitude, complex) minus the model's
eigenvector ratio; each residual is whitened by its fit's covariance. Eigenvalues alone leave some causes nearly
interchangeable (a longer trail and a high payload move the weave alike); the mode shape tells
them apart. Causes are compared by an approximate log Bayes factor against the base model (the
*evidence*, see ``docs/diagnosis.md``)::

    evidence = (chi2_base - chi2_cause) / 2 - (k / 2) ln(n) + ln(prior)

with n the eigenvalue and mode-shape residuals (also where the samples are compared:
:attr:`~whipple.diagnosis.fitting.Whitening.charged`), k fitted values, when the evidence charges
the BIC's ln(n)/2 per value (``DiagnosisOptions(occam="bic")``, the default); with
``occam="prior"`` a cause with priors is charged the Laplace approximation of its marginal
likelihood instead (:func:`occam_factor`), and each kind of residual
(eigenvalue, shape; or the samples) divided by its own s^2 >= 1, the reduced chi-square of the
best model on that kind (window uncertainties that are too small inflate every chi-square
alike). ``none`` has evidence 0. The verdict:
``none`` when no cause reaches ``named_threshold``, or when the leading cause has one value
and it lies within ``null_distance`` of its standard deviations (the jackknife over speed groups
included) of no effect; ``ambiguous`` when the runner-up is within
``margin`` of the best, when a runner-up within ``close_evidence`` predicts the observations
within ``separation`` of the best (:func:`separation`), when the windows of one speed carry the
best's lead over a rival (its lead less that speed's share below ``one_speed_lead``), or when
even the best model leaves the typical window far off (:func:`typical_dispersion` above
``high_dispersion``);
otherwise ``named``. When no single cause explains the typical window, pairs of causes are fitted jointly
(:mod:`whipple.diagnosis.families`; which pairs: :mod:`whipple.diagnosis.pair_search`) and
kept only when they beat every single cause by ``margin``; a leading pair is reported, never
named outright, and a pair of two other causes ahead of the best single cause by less than
``margin`` makes its verdict ambiguous. Model terms (entries added to the linear equations,
:mod:`whipple.diagnosis.model_terms`) compete like causes but are never paired; a leading term
is never named either: it says what form the error has when no physical cause has it. The
thresholds are the options' (:class:`~whipple.diagnosis.options.VerdictRules`,
:class:`~whipple.diagnosis.options.PairRules`), each documented there with its reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.candidate_fits import fit_all, refit_through_bias, refit_to_samples, singles_from_pairs
from whipple.diagnosis.causes import Cause
from whipple.diagnosis.consistency import SpeedDependence, jackknife_std, lead_of_one_speed, speed_dependence
from whipple.diagnosis.correlated_residuals import correlated
from whipple.diagnosis.families import COMBINATION, components, describe_family
from whipple.diagnosis.fit_bias import debiased, fitting_bias
from whipple.diagnosis.fitting import CauseFit, Whitening, fit_cause, robust_chi2, window_whitening
from whipple.diagnosis.model_terms import is_term, term_words
from whipple.diagnosis.observations import Observation
from whipple.diagnosis.options import DiagnosisOptions, VerdictRules
from whipple.diagnosis.pair_search import leading_pairs, screened_pairs
from whipple.diagnosis.priors import laplace_evidence
from whipple.diagnosis.registry import CALIBRATION
from whipple.diagnosis.samples import SampleComparison
from whipple.diagnosis.starts import quick_starts
from whipple.errors import InputError
from whipple.measurement.experiment import MIN_WINDOWS
from whipple.measurement.measure import Progress
from whipple.model.fleet import Model

__all__ = ["Diagnosis", "diagnose_observations", "typical_dispersion", "separation", "occam_factor"]


@dataclass(frozen=True)
class Diagnosis:
    """Verdict, ranking and fits of every cause.

    Attributes
    ----------
    verdict : str
        ``named``, ``ambiguous`` or ``none``.
    cause : str
        The leading cause (``"A + B"`` for a combination), ``none`` for the verdict none.
    best : CauseFit or None
        Its fit (values from its estimate form, std including the jackknife).
    scale, shape_scale : float
        Dispersion (reduced chi2 >= 1) of the best model's eigenvalue and mode-shape residuals.
    correlation : float
        The best model's residual where a changed model moves the windows, in times the noise's
        (:mod:`~whipple.diagnosis.correlated_residuals`; 1 without samples): in ``scale`` too.
    chosen : Cause or None
        The form of the leading cause whose values ``best`` holds (to extend the model).
    rivals : tuple of str
        The causes the data cannot tell from the leading one (verdict ambiguous).
    family : str
        What the leading cause and its rivals have in common, in physical words, with their
        names (:func:`whipple.diagnosis.families.describe_family`); empty unless ambiguous.
    reasons : tuple of str
        Why the verdict is ambiguous (close evidence, predictions alike, high dispersion).
    combinations : tuple of str
        The pairs of causes fitted jointly (only when no single cause explained the data).
    single_scales : tuple of float
        Typical-window dispersions (:func:`typical_dispersion`) of the best single cause, before
        any combination: pairs are tried above the options' ``pairs.dispersion``.
    typical_scales : tuple of float
        Typical-window dispersions of the leading cause: above ``verdict.high_dispersion`` the verdict
        is not a confident name.
    speed_dependence : SpeedDependence or None
        The leading cause fitted to the low and the high speeds apart (:func:`speed_dependence`),
        where its name was otherwise confident; above ``verdict.speed_dependence`` it is not named.
    comparison : str
        How each model was compared with the windows (:data:`~whipple.diagnosis.fitting.COMPARISONS`):
        with their samples, through the fitting function, or with their eigenvalues directly
        (always where no window's samples were known).
    """

    verdict: str
    cause: str
    best: CauseFit | None
    base: CauseFit
    fits: tuple[CauseFit, ...]
    scale: float
    observations: tuple[Observation, ...]
    shape_scale: float = 1.0
    correlation: float = 1.0
    n_shapes: int = 0
    chosen: Cause | None = None
    rivals: tuple[str, ...] = ()
    family: str = ""
    reasons: tuple[str, ...] = ()
    combinations: tuple[str, ...] = ()
    single_scales: tuple[float, float] = (1.0, 1.0)
    typical_scales: tuple[float, float] = (1.0, 1.0)
    speed_dependence: SpeedDependence | None = None
    comparison: str = "eigenvalues"

    @property
    def dispersion(self) -> float:
        """The best model's reduced chi-square on the eigenvalues or samples (``scale`` without ``correlation``)."""
        return self.scale / self.correlation

    def ranking(self) -> list[tuple[str, float]]:
        """Causes by decreasing evidence, with ``none`` at 0."""
        entries = [(fit.cause, fit.evidence) for fit in self.fits] + [("none", 0.0)]
        return sorted(entries, key=lambda entry: -entry[1])


def _dispersions(fits: Sequence[CauseFit], counts: tuple[int, int]) -> tuple[float, float]:
    """Reduced chi-square (at least 1) of each kind of residual, for the best-fitting model.

    Window uncertainties that are too small inflate every model's chi-square alike; eigenvalue
    and mode-shape residuals are scaled separately, so that one kind of data that no model
    explains (a miscalibrated steer sensor, say) cannot outweigh the other.
    """
    first, second = (max(1.0, min(_reduced(fit, block, counts) for fit in fits)) if count else 1.0
                     for block, count in enumerate(counts))
    return first, second


def _reduced(fit: CauseFit, block: int, counts: tuple[int, int]) -> float:
    """Return a fit's reduced chi-square on one kind of residual (its values shared among the kinds)."""
    count = counts[block]
    return fit.block_chi2[block] / max(count - len(fit.parameters) * count / max(sum(counts), 1), 1.0)


def _sample_dispersions(fits: Sequence[CauseFit], counts: tuple[int, int], whitening: Whitening,
                        observations: Sequence[Observation]) -> tuple[tuple[float, float], float]:
    """Return the dispersions, the samples' times the least dispersed fit's correlation in time, and that factor."""
    best = min(fits, key=lambda fit: _reduced(fit, 0, counts))
    return correlated(_dispersions(fits, counts), best.residuals, whitening.samples, observations)


def diagnose_observations(bicycle: Model, observations: Sequence[Observation],
                          causes: Sequence[Cause] | None = None, options: DiagnosisOptions | None = None, *,
                          estimate_spread: bool = True, quick: bool = False,
                          progress: Progress | None = None) -> Diagnosis:
    """Fit every cause to the observations and decide which, if any, explains them.

    ``causes`` (default: the options' candidates, :meth:`~whipple.diagnosis.options.DiagnosisOptions.candidates`);
    ``options`` (default :class:`~whipple.diagnosis.options.DiagnosisOptions`) hold the comparison,
    the verdict's and the pairs' rules and the evidence's charges; ``progress`` is called as
    ``progress("candidates", done, total)`` while the causes are fitted.
    When the best single cause leaves a dispersion above ``pairs.dispersion``, or (not
    ``quick``) has at least ``pairs.flexible_values`` fitted values and the evidence for a name, pairs
    of the leading causes are fitted jointly as well (:func:`whipple.diagnosis.families.combined_cause`).
    ``estimate_spread``: also compute the jackknife spread of the leading cause's values
    (skipped by the held-out gain, which uses only the values). ``quick``: start each fit from
    the cause's no-effect values and a step of 5% of its bounds away (each pair once, from its
    members' values; a refinement from the form it refines, as always), and rescale the
    residuals by the dispersions instead of refitting (several times faster; used by the
    held-out gain's folds). The options' ``comparison``:
    ``"samples"`` (the default) compares each model with the windows' samples
    (:mod:`whipple.diagnosis.samples`): every cause is fitted to the eigenvalues first, then
    refitted to the samples from there, those more than ``samples_screen`` behind the best only
    evaluated on them at their eigenvalue fit; ``"fitting-function"`` compares each window's
    eigenvalue through the fitting function (:mod:`whipple.diagnosis.fit_bias`): every fit is
    refitted once with the bias of the fitting function on its own model's response, computed
    at its first fitted values (the base model's bias for a cause more than ``bias_screen``
    behind the best at those values); ``"eigenvalues"`` compares each window's eigenvalue with
    the model's own. Windows without samples (read from a list of eigenvalues) are compared
    directly whatever ``comparison`` says.

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    observations : sequence of Observation
        The windows (:func:`whipple.diagnosis.observations.observations`).
    causes : sequence of Cause, optional
        The candidates (above).
    options : DiagnosisOptions, optional
        The comparison and the rules (above).
    estimate_spread : bool
        Also compute the jackknife spread of the leading cause's values (above).
    quick : bool
        Faster fits, for the held-out gain's folds (above).
    progress : callable, optional
        Called as ``progress("candidates", done, total)``.

    Returns
    -------
    Diagnosis
        The verdict, the leading cause and its fit, the ranking, the reasons and the fits of
        every cause.
    """
    options = options or DiagnosisOptions()
    rules, comparison = options.verdict, options.comparison
    observations = tuple(observations)
    if len(observations) < MIN_WINDOWS:
        raise InputError(f"need at least {MIN_WINDOWS} windows with fitted eigenvalues, got {len(observations)}")
    causes = options.candidates(bicycle) if causes is None else list(causes)
    whitening = window_whitening(observations, bicycle)
    counts, n = whitening.counts, whitening.charged
    base, fits = fit_all(bicycle, causes, observations, whitening,
                         [quick_starts(cause) if cause.refines is None else None for cause in causes]
                         if quick else None, progress=progress)
    biases: list[NDArray[np.complex128]] | None = None
    direct = [fit.evidence for fit in _scored(causes, base, fits, n, options)]
    # In units of the data's dispersion: where no model explains the windows, every difference
    # of chi-square is that many times larger.
    dispersion = max(_dispersions([base, *fits], counts))
    # The fits to the eigenvalues: where the samples are compared, the pairs' screen and first
    # fits still use them (a comparison with the samples costs several times as much).
    eigen = (whitening, base, fits)
    near = [True] * len(causes)
    samples = (SampleComparison.of(observations, bicycle=bicycle, instrument=options.instrument)
               if comparison == "samples" else None)
    if samples is not None:
        whitening = replace(whitening, samples=samples)
        counts = whitening.counts
        near = [evidence >= max(direct) - options.samples_screen * dispersion for evidence in direct]
        # The held-out gain's quick folds refit from the eigenvalues' values only, without the grid.
        base, fits = refit_to_samples(bicycle, causes, fits, observations, whitening, near, search=not quick)
    elif comparison == "fitting-function" and any(o.signals is not None for o in observations):
        near = [evidence >= max(direct) - options.bias_screen * dispersion for evidence in direct]
        base_bias = fitting_bias(bicycle, observations, start=options.fixed_point_start)
        biased_base, biased_fits, own = refit_through_bias(bicycle, causes, fits, observations, whitening,
                                                           base_bias, near, start=options.fixed_point_start)
        if any(np.any(b != 0) for b in [base_bias, *own]):
            base, fits, biases = biased_base, biased_fits, [base_bias, *own]
        # else no window's samples known (observations from a table): the direct fits stand
    scales, correlation = _sample_dispersions([base, *fits], counts, whitening, observations)
    single_scales = typical_dispersion(fits, whitening)
    pairs: list[Cause] = []
    leader = max(_scored(causes, base, fits, n, options), key=lambda fit: fit.evidence,
                 default=None)
    # The quick fits of the held-out gain's folds choose a cause to predict with, where a
    # verdict's confidence is not at stake: there the pairs would only add time.
    flexible = (not quick and leader is not None and leader.evidence >= rules.named_threshold
                and len(leader.parameters) >= options.pairs.flexible_values)
    if max(single_scales) > options.pairs.dispersion or flexible:
        # No single cause explains the data, or the best could stand in for two: try the
        # leading few in pairs, each pair started from its members' fitted values. Model terms
        # are never paired, nor refinements (a rigid load: see families.cause_pairs).
        pairable = [k for k, cause in enumerate(causes) if not is_term(cause.name) and cause.refines is None
                    and cause.name != CALIBRATION]
        members, member_fits = [causes[k] for k in pairable], [fits[k] for k in pairable]
        started = leading_pairs(members, _scored(members, base, member_fits, n, options),
                                options.pairs.leading)
        eigen_whitening, eigen_base, eigen_fits = eigen
        screen_scales = _dispersions([eigen_base, *eigen_fits], eigen_whitening.counts)
        started += screened_pairs(bicycle, members, [eigen_fits[k] for k in pairable], observations,
                                  eigen_whitening, {pair.name for pair, _ in started},
                                  (eigen_whitening.counts[0], screen_scales),
                                  (options.pairs.screened, options.pairs.screened_away))
        pairs = [pair for pair, _ in started]
        pair_fits = [fit_cause(bicycle, pair, observations, eigen_whitening,
                               [start] if quick else [start, list(pair.start)])
                     for pair, start in started]
        near += [True] * len(pairs)
        if whitening.samples is not None:
            _, pair_fits = refit_to_samples(bicycle, pairs, pair_fits, observations, whitening, [True] * len(pairs),
                                            search=False)
            fits, refitted = singles_from_pairs(bicycle, causes, fits, pairs, pair_fits, observations, whitening)
            near = [is_near or k in refitted for k, is_near in enumerate(near)]
        if biases is not None:
            # Every pair through its own bias: a pair's joint fit may move far between the direct
            # and the biased comparison, and the pairs are few.
            _, pair_fits, pair_biases = refit_through_bias(bicycle, pairs, pair_fits, observations, whitening,
                                                           biases[0], [True] * len(pairs),
                                                           start=options.fixed_point_start)
            biases += pair_biases
        causes, fits = causes + pairs, fits + pair_fits
        scales, correlation = _sample_dispersions([base, *fits], counts, whitening, observations)
    if scales != (1.0, 1.0) and quick:
        # The fits' values kept, their residuals rescaled: no refit (the held-out gain's folds).
        whitening = replace(whitening, scales=scales)
        base = _rescaled(base, counts[0], scales)
        fits = [_rescaled(fit, counts[0], scales) for fit in fits]
    elif scales != (1.0, 1.0) and whitening.samples is not None:
        # Refit the causes near the best from their values with the samples at their dispersion.
        whitening = replace(whitening, scales=scales)
        base, fits = refit_to_samples(bicycle, causes, fits, observations, whitening, near, search=False)
    elif scales != (1.0, 1.0):
        # Refit with each kind of residual at its own dispersion (weights the fits, too).
        whitening = replace(whitening, scales=scales)
        single = len(causes) - len(pairs)
        again = [[fit.values] if n_cause >= single else None for n_cause, fit in enumerate(fits)]
        base, fits = fit_all(bicycle, causes, observations, whitening, again, biases)
    scored, rival_pairs = _clearly_better_pairs(
        _merge_forms(_scored(causes, base, fits, n, options)), rules.margin)
    chosen = None
    compared: Sequence[Observation] = observations
    if scored:
        # The leading cause's values, with an uncertainty that also covers errors shared by the
        # windows of one speed.
        fit = scored[0]
        index = next(k for k, cause in enumerate(causes)
                     if cause.name == fit.cause and len(cause.parameters) == len(fit.parameters))
        chosen = causes[index]
        spread = np.array(fit.std)
        compared = observations if biases is None else debiased(observations, biases[1 + index])
        if estimate_spread:
            spread = np.maximum(spread, jackknife_std(bicycle, chosen, compared, fit.values, scales,
                                                      whitening.comparison, options.instrument))
        scored[0] = replace(fit, std=tuple(float(s) for s in spread))
    best = scored[0] if scored else None
    typical = typical_dispersion(scored[:1], whitening)
    verdict, name, rivals, reasons = _verdict(scored, typical, rules, rival_pairs, whitening.samples is not None)
    if verdict != "none" and best is not None and chosen is not None and estimate_spread:
        unsupported = _near_null(best, chosen, rules.null_distance)
        if unsupported is not None:
            verdict, name, rivals, reasons = "none", "none", (), (unsupported,)
    if verdict == "named" and not quick and rules.one_speed_lead > 0:
        carried = lead_of_one_speed(scored, whitening, observations, rules.one_speed_lead)
        if carried is not None:
            verdict, rivals, reasons = "ambiguous", carried[0], (carried[1],)
    dependence = None
    if verdict == "named" and chosen is not None and best is not None and not quick:
        dependence = speed_dependence(bicycle, chosen, compared, best.values, scales, whitening.comparison,
                                      options.instrument)
        if dependence is not None and dependence.evidence > rules.speed_dependence:
            verdict, reasons = "ambiguous", (_speed_dependence_reason(best, dependence),)
    return Diagnosis(verdict, name, best if verdict != "none" else None, base, tuple(scored), scales[0],
                     observations, shape_scale=scales[1], correlation=correlation, n_shapes=len(whitening.shape_index),
                     chosen=chosen if verdict != "none" else None, rivals=rivals,
                     family=describe_family([name, *rivals], options.causes) if verdict == "ambiguous" else "",
                     reasons=reasons, combinations=tuple(pair.name for pair in pairs),
                     single_scales=single_scales, typical_scales=typical, speed_dependence=dependence,
                     comparison="fitting-function" if biases is not None else whitening.comparison)


def _near_null(best: CauseFit, cause: Cause, distance: float) -> str | None:
    """Say why a leading cause of one value within ``distance`` standard deviations of no effect is no cause.

    None where it lies farther, or the cause has no value at which it changes nothing, or more
    values than one: their standard deviations are each value's alone, and values that trade
    off (a load's mass and position) each spread far more than their joint effect does.
    ``best.std`` includes the spread of the values refitted with each speed's windows left out.
    """
    if cause.null is None or len(cause.null) != 1 or len(best.values) != 1:
        return None
    (name,), (unit,), (value,), (spread,), (null,) = best.parameters, best.units, best.values, best.std, cause.null
    if not (np.isfinite(spread) and abs(value - null) < distance * spread):
        return None
    return (f"{best.cause} leads (evidence {best.evidence:.1f}), but its value lies within {distance:g} standard "
            f"deviations of no effect ({name} = {value:.4g} +/- {spread:.2g}{' ' + unit if unit else ''}, no effect "
            f"at {null:.4g}; the windows of each speed left out in turn included): its evidence rests on errors some "
            "windows share, not on a cause")


def _speed_dependence_reason(best: CauseFit, dependence: SpeedDependence) -> str:
    change = ", ".join(f"{name} {low:.4g} -> {high:.4g}{' ' + unit if unit else ''}" for name, unit, low, high
                       in zip(best.parameters, best.units, dependence.low, dependence.high, strict=True))
    return (f"{best.cause} fitted below and above {dependence.split:.2f} m/s apart takes different values ({change}; "
            f"evidence {dependence.evidence:.1f} for values that change with speed): its form does not follow how "
            "the error changes with speed, so the truth may be none of the candidates")


def typical_dispersion(fits: Sequence[CauseFit], whitening: Whitening) -> tuple[float, float]:
    """Dispersion of the typical window: the median over windows of its squared whitened residual over its expectation.

    For eigenvalues (or samples) and mode shapes, the smallest over ``fits`` (at least 1), at
    the dispersions ``whitening.scales`` by which the fits' residuals were divided
    (:meth:`~whipple.diagnosis.fitting.Whitening.window_dispersions`). Unlike the reduced
    chi-square (which scales the evidence), one or two windows fitted far off (a catch, a
    window at a very unstable speed) barely move it: it says whether the bulk of the windows is
    explained. The pairs of causes and the high-dispersion verdict are decided on it.
    """
    if not fits:
        return 1.0, 1.0
    result = []
    for block, count in enumerate(whitening.counts):
        if count == 0:
            result.append(1.0)
            continue
        medians = [np.median(whitening.window_dispersions(fit.residuals, block)) * whitening.scales[block]
                   for fit in fits if fit.residuals.size >= sum(whitening.counts)]
        result.append(max(1.0, float(min(medians))) if medians else 1.0)
    return result[0], result[1]


def _rescaled(fit: CauseFit, split: int, scales: tuple[float, float]) -> CauseFit:
    """Return a fit at unit dispersion with its residuals divided by the dispersions (no refit)."""
    divisor = np.sqrt(np.where(np.arange(fit.residuals.size) < split, scales[0], scales[1]))
    residuals = fit.residuals / divisor
    # The Jacobian too, for the Laplace Occam factor; the values' std stay those of the fit.
    jacobian = fit.jacobian / divisor[:, None] if fit.jacobian.shape[0] == divisor.size else fit.jacobian
    return replace(fit, residuals=residuals, chi2=robust_chi2(residuals), jacobian=jacobian)


def _clearly_better_pairs(scored: list[CauseFit], margin: float) -> tuple[list[CauseFit], list[CauseFit]]:
    """Drop the pairs of causes that do not beat every single cause by ``margin`` (not clearly better).

    Returns the fits kept, and the pairs dropped that have more evidence than the best single
    cause without holding it: two other effects together that explain the observations better,
    though not clearly (rivals of the single cause, which is then not the best-supported
    explanation; a pair holding it only adds a second cause to it). A pair behind the single
    cause is no rival: among the many pairs tried, one often comes within the margin by chance,
    and counting those cost a loaded frame's right name in 5 of 130 hidden-effect trials
    (docs/diagnosis.md, "Two effects together").
    """
    singles = [fit for fit in scored if COMBINATION not in fit.cause]
    best_single = max(singles, key=lambda fit: fit.evidence) if singles else None
    if best_single is None:
        return scored, []
    kept = [fit for fit in scored if COMBINATION not in fit.cause or fit.evidence >= best_single.evidence + margin]
    rivals = [fit for fit in scored if COMBINATION in fit.cause and fit.evidence < best_single.evidence + margin
              and fit.evidence > best_single.evidence and best_single.cause not in components(fit.cause)]
    return kept, rivals


def separation(first: CauseFit, second: CauseFit) -> float:
    """How far apart two fits' predictions are, in units of the observations' noise.

    Half the sum of squared whitened differences (each kind of residual at its dispersion):
    the log-likelihood ratio by which the observations would favour the one if the other were
    true. Below the verdict rules' ``separation`` no data of this kind and amount could single out one of them.
    """
    if first.residuals.shape != second.residuals.shape:
        return float("inf")
    return float(0.5 * np.sum((first.residuals - second.residuals) ** 2))


def _verdict(scored: Sequence[CauseFit], scales: tuple[float, float], rules: VerdictRules,
             rival_pairs: Sequence[CauseFit] = (), samples: bool = False
             ) -> tuple[str, str, tuple[str, ...], tuple[str, ...]]:
    """Return the verdict, the leading cause, the causes it cannot be told from, and why.

    ``ambiguous`` when a runner-up is within ``margin`` of the best; when a pair of two other
    causes leads the best by less than ``margin`` (``rival_pairs``, from
    :func:`_clearly_better_pairs`: two effects together would explain the observations as
    well); when one within
    ``close_evidence`` predicts the observations within ``separation`` of the best (the data
    could not tell them apart whichever were true: a different prior or one more fitted value
    is then all that ranks them); when the best is a pair of causes (no single candidate
    explained the data, and one effect outside the candidates fits two causes' freedom as
    well as two effects do: in the hidden-effect trials most named pairs stood in for one);
    when the best is a model term (the error's form, no physical cause);
    when the best fits only at the edge of its physical range (:func:`~whipple.diagnosis.fitting.pinned_values`);
    or when even the best model leaves a dispersion above ``high_dispersion`` (no candidate
    explains the data: its name would be a guess).
    """
    named_threshold, margin = rules.named_threshold, rules.margin
    if not scored or scored[0].evidence < named_threshold:
        return "none", "none", (), ()
    best = scored[0]
    reasons = []
    close = [fit.cause for fit in scored[1:] if fit.evidence > best.evidence - margin]
    if close:
        reasons.append(f"{', '.join(close)} within {margin:g} of the best evidence")
    pairs = [fit.cause for fit in rival_pairs] if COMBINATION not in best.cause else []
    if pairs:
        reasons.append(f"{', '.join(pairs)} (two causes together) has more evidence than {best.cause}, though by "
                       f"less than {margin:g}: two effects acting together would explain the observations as well")
    # A pair holding the best cause predicting alike says its second cause is not needed.
    alike = [fit for fit in scored[1:] if fit.cause not in close
             and fit.evidence > best.evidence - rules.close_evidence and best.cause not in components(fit.cause)
             and separation(best, fit) < rules.separation]
    if alike:
        reasons.append(f"{', '.join(fit.cause for fit in alike)} predict(s) the observations within the noise of "
                       f"{best.cause} ({_windows_to_tell(best, alike, rules.separation)})")
    if is_term(best.cause):
        value = f"{best.values[0]:+.3g} {best.units[0]}" if best.values else ""
        reasons.append(f"the error has the form of {term_words(best.cause)} {value}, which none of the physical "
                       "candidate causes has: the truth is likely none of them")
    if COMBINATION in best.cause:
        reasons.append(f"the best explanation is two causes together ({best.cause}); a single effect outside the "
                       "candidates that acts like them would fit as well")
    if best.pinned:
        at = ", ".join(f"{name} at its bound {bound:.4g}" for name, bound in best.pinned)
        reasons.append(f"{best.cause} fits best only at the edge of its physical range ({at}): the data ask for "
                       "more than it can be, so the truth may be another cause or none of the candidates")
    if max(scales) > rules.high_dispersion and samples:
        reasons.append(f"even the best model leaves the typical window's samples {np.sqrt(scales[0]):.1f} times their "
                       f"noise off (median dispersion {scales[0]:.1f}): no candidate explains the data")
    elif max(scales) > rules.high_dispersion:
        reasons.append(f"even the best model leaves the typical window {np.sqrt(scales[0]):.1f} (eigenvalue) and "
                       f"{np.sqrt(scales[1]):.1f} (mode shape) times its stated uncertainty off (median dispersion "
                       f"{scales[0]:.1f} and {scales[1]:.1f}): no candidate explains the data")
    if reasons:
        return "ambiguous", best.cause, tuple(close + pairs + [fit.cause for fit in alike]), tuple(reasons)
    return "named", best.cause, (), ()


def _windows_to_tell(best: CauseFit, rivals: Sequence[CauseFit], needed: float) -> str:
    """Say how many times as many windows would separate the closest rival from the best.

    Separate: predictions apart by more than the noise. The separation grows in proportion to the
    number of windows at the same speeds and noise; it must reach ``needed``. Identical
    predictions (a special case of the best) no number of windows separates.
    """
    factor = needed / max(min(separation(best, fit) for fit in rivals), 1e-12)
    if factor > 1e6:
        return "no number of windows of this kind separates their predictions"
    return (f"about {np.ceil(factor):.0f} times as many windows at these speeds would separate their "
            "predictions beyond the noise")


def _scored(causes: Sequence[Cause], base: CauseFit, fits: Sequence[CauseFit], n: int,
            options: DiagnosisOptions | None = None) -> list[CauseFit]:
    """Each fit with its evidence against the base model (see the module docstring).

    ``options``: the evidence's charge of fitted values (``occam``). Compared with the samples,
    every model fits as many modal amplitudes per window as the base model
    (:func:`~whipple.stability.slow_modes.slowest_modes`): none is charged for them.
    """
    options = options or DiagnosisOptions()
    return [replace(fit, evidence=float((base.chi2 - fit.chi2) / 2.0 + occam_factor(cause, fit, n, options.occam)
                                        + np.log(cause.prior)))
            for cause, fit in zip(causes, fits, strict=True)]


def occam_factor(cause: Cause, fit: CauseFit, n: int, occam: str = "bic") -> float:
    """Log of the share of a cause's prior range that its fit leaves open (below 0; 0 with no values).

    The Laplace approximation of the Bayes factor, with a uniform prior over the cause's bounds:
    ln(sqrt(det(2 pi C)) / prod(range)) for the values' covariance C, the inverse of the
    information J^T J of the whitened residuals, summed over the principal directions of C in
    units of the ranges. It charges each combination of values by how finely the data set it
    within its physical range. Where the data barely inform a direction (a fit at a bound: a
    tyre relaxation length at its shortest) the likelihood is far from Gaussian and the
    approximation fails (it would charge nothing); each direction is therefore charged at least
    ln(n) / 2, the BIC's charge (n residuals). With ``occam="bic"`` (the diagnosis' default), that
    charge alone: -k ln(n) / 2. With ``occam="prior"``, the Laplace approximation with the cause's
    physical priors (:func:`~whipple.diagnosis.priors.laplace_evidence`: the prior density at
    the values and the share of the prior the data leave open); a cause without priors is
    charged the BIC's.
    """
    k = len(fit.parameters)
    floor = -0.5 * np.log(max(n, 1))
    if occam == "prior" and cause.value_priors is not None:
        return laplace_evidence(cause.value_priors, fit.values, fit.jacobian)
    if occam in ("bic", "prior"):
        return k * floor
    jacobian = np.asarray(fit.jacobian, dtype=float)
    if jacobian.ndim != 2 or jacobian.shape[1] != k or not np.all(np.isfinite(jacobian)):
        return k * floor
    lower, upper = cause.limits
    scaled = jacobian * (np.asarray(upper, dtype=float) - np.asarray(lower, dtype=float))
    information = np.clip(np.linalg.eigvalsh(scaled.T @ scaled), 0.0, None)
    with np.errstate(divide="ignore"):
        return float(np.sum(np.minimum(floor, 0.5 * np.log(2.0 * np.pi / information))))


def _merge_forms(scored: list[CauseFit]) -> list[CauseFit]:
    """One entry per cause, by decreasing evidence.

    A cause with several forms (payload: mass alone, or mass and position) is supported as
    well as its best form; its estimate (values, std, covariance) is that of its most general
    form, so that the interval also carries the uncertainty of what the simpler form holds
    fixed; its residuals and values at a bound are those of the best-supported form (the claim
    the evidence makes).
    """
    merged: dict[str, CauseFit] = {}
    for fit in scored:
        forms = [other for other in scored if other.cause == fit.cause]
        if fit.cause in merged:
            continue
        general = max(forms, key=lambda other: len(other.parameters))
        evidence = max(other.evidence for other in forms)
        supported = max(forms, key=lambda other: other.evidence)
        merged[fit.cause] = CauseFit(general.cause, general.parameters, general.units, general.values,
                                     general.std, general.chi2, evidence, general.predicted,
                                     residuals=supported.residuals, pinned=supported.pinned,
                                     covariance=general.covariance)
    return sorted(merged.values(), key=lambda fit: -fit.evidence)
