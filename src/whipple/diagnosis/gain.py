"""The gain of an extended model: its error on speeds that its fit and its choice never saw.

Each speed group is left out in turn. On the other speeds alone the diagnosis is redone: the
cause is chosen again among all candidates and fitted; the model so extended predicts the
left-out speed, and its error is compared with the base model's there. Per left-out speed the
report gives the RMS and the median of ``|measured - predicted|`` weave eigenvalue, and the
overall RMS and median over all left-out windows.

An earlier form of this figure chose the cause once on all speeds and refitted only its value
per fold, and gave only the median over all left-out windows pooled: the choice had seen the
left-out speed, and the pooled median is dominated by the speeds with many windows, where the
model helps most, hiding the speeds where it does not help at all.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause, with_cause
from whipple.diagnosis.consistency import refits_without, without
from whipple.diagnosis.evaluation import Score, pooled, rms, score_windows
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.families import cause_pairs, general_forms
from whipple.diagnosis.fitting import fit_cause, pinned_values
from whipple.diagnosis.model_terms import is_term
from whipple.diagnosis.observations import Observation, predicted_weave, speed_groups
from whipple.diagnosis.offer import group_errors, offer
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import candidate_causes
from whipple.distributed import map_ordered
from whipple.errors import AnalysisError
from whipple.measurement.measure import Progress
from whipple.measurement.weavefit import response_with_eigenvalue
from whipple.model.fleet import Model

__all__ = ["Result", "HELPS", "HeldOutSpeed", "Gain", "held_out_gain", "CauseGain", "cause_gains",
           "held_out_candidates"]

Result = TypeVar("Result")

#: A held-out speed where the extended model cuts the RMS eigenvalue error by less than this
#: fraction is reported as one where the extended model does not help.
HELPS = 0.10


@dataclass(frozen=True)
class HeldOutSpeed:
    """The base and extended model's error on one speed group that the fit never saw.

    Attributes
    ----------
    speed : float
        Mean measured speed of the group's windows [m/s].
    windows : int
        Number of windows.
    cause, verdict : str
        The cause chosen (and the verdict) on the other speeds alone ("none": base model kept).
    values : tuple of float
        The cause's values fitted on the other speeds alone.
    base_rms, extended_rms, base_median, extended_median : float
        RMS and median over the group's windows of ``|measured - predicted|`` weave eigenvalue [1/s].
    """

    speed: float
    windows: int
    cause: str
    verdict: str
    values: tuple[float, ...]
    base_rms: float
    extended_rms: float
    base_median: float
    extended_median: float

    @property
    def cut(self) -> float:
        """Fraction by which the extended model cuts the RMS error (negative: it is worse)."""
        return 1.0 - self.extended_rms / self.base_rms if self.base_rms > 0 else 0.0

    @property
    def helps(self) -> bool:
        """Whether the RMS cut reaches ``HELPS``."""
        return self.cut >= HELPS


@dataclass(frozen=True)
class Gain:
    """Held-out errors of the base and the extended model.

    ``base``/``extended``: median of ``|measured - predicted|`` weave eigenvalue [1/s] over all
    held-out windows; ``base_rms``/``extended_rms`` their RMS [1/s]; ``speeds`` the same per
    held-out speed group. ``time_base``/``time_extended``: median over held-out windows of the
    RMS roll-rate residual when the window is explained by the model's eigenvalue (amplitude,
    phase and baseline free), relative to the window's own RMS (dimensionless); None without
    the time series. ``reselected``: whether the cause was chosen again on each fold's
    training speeds (True) or a given cause only refitted. ``held_out_by``: "speed" (each
    speed group left out in turn) or "window" (the windows share one speed, so each window is
    left out in turn: the gain then says how well the model fits that speed's other windows,
    not how well it predicts a speed it never saw).
    """

    metric: str
    base: float
    extended: float
    held_out: bool
    folds: int
    time_base: float | None = None
    time_extended: float | None = None
    base_rms: float = 0.0
    extended_rms: float = 0.0
    speeds: tuple[HeldOutSpeed, ...] = ()
    reselected: bool = True
    held_out_by: str = "speed"

    @property
    def cut(self) -> float:
        """Fraction by which the extended model cuts the overall RMS error."""
        return 1.0 - self.extended_rms / self.base_rms if self.base_rms > 0 else 0.0

    def not_helped(self) -> list[HeldOutSpeed]:
        """Return the held-out speeds where the extended model cuts the RMS error by less than HELPS."""
        return [speed for speed in self.speeds if not speed.helps]


def _fold_model(bicycle: Model, training: Sequence[Observation], causes: Sequence[Cause] | None,
                fixed: Cause | None, choose: str = "evidence", options: DiagnosisOptions | None = None
                ) -> tuple[Model, str, str, tuple[float, ...]]:
    """Return the model extended on the training windows alone: bicycle, cause, verdict, values.

    ``options``: the diagnosis' options, with which a fold chooses by evidence.
    """
    if fixed is not None:
        fit = fit_cause(bicycle, fixed, training)
        return with_cause(bicycle, fixed, fit.values), fixed.name, "refitted", fit.values
    if choose == "prediction":
        return _predictive_choice(bicycle, training, causes)
    diagnosis = diagnose_observations(bicycle, training, causes, options, estimate_spread=False, quick=True)
    # The model this fold's diagnosis offers, chosen as the whole diagnosis chooses it
    # (by prediction on the fold's own training speeds where no candidate explains them).
    options = options or DiagnosisOptions()
    chosen = offer(bicycle, diagnosis, causes if causes is not None else options.candidates(bicycle), options)
    if chosen.cause is None or chosen.fit is None:
        return bicycle, "none", diagnosis.verdict, ()
    return (with_cause(bicycle, chosen.cause, chosen.fit.values), chosen.fit.cause, diagnosis.verdict,
            chosen.fit.values)


def _predictive_choice(bicycle: Model, training: Sequence[Observation], causes: Sequence[Cause] | None
                       ) -> tuple[Model, str, str, tuple[float, ...]]:
    """Choose, among ``causes``, the one whose refits best predict training speeds left out in turn.

    The choice by prediction rather than by evidence: each candidate is fitted to all training
    windows, then refitted locally from those values with each training speed left out in turn
    (as the jackknife does, :mod:`whipple.diagnosis.consistency`) and made to predict it; the
    candidate with the smallest RMS eigenvalue error over those predictions is chosen (the base
    model when none beats it), with its values fitted to all training windows.
    """
    causes = candidate_causes(bicycle) if causes is None else causes
    groups = _speed_folds(training)
    measured = np.array([o.eigenvalue for o in training])
    # The base model on the same windows as the candidates: those of the groups left out.
    predicted = np.concatenate(groups)
    base_rms = rms(np.abs(measured[predicted] - predicted_weave(bicycle, [training[i] for i in predicted])))
    best: tuple[float, int, Cause, tuple[float, ...]] | None = None
    for cause in causes:
        values = fit_cause(bicycle, cause, training).values
        refits = refits_without(bicycle, cause, training, values, groups)
        models = [with_cause(bicycle, cause, inner) for inner in refits]
        errors = group_errors(models, training, groups)
        score = (rms(np.concatenate(errors)), len(cause.parameters), cause, values)
        if best is None or score[:2] < best[:2]:
            best = score
    if best is None or best[0] >= base_rms:
        return bicycle, "none", "chosen by prediction", ()
    _, _, cause, values = best
    return with_cause(bicycle, cause, values), cause.name, "chosen by prediction", values


def _fold_task(task: tuple[Model, Sequence[Observation], Sequence[Cause] | None, Cause | None, str,
                           DiagnosisOptions | None]) -> tuple[Model, str, str, tuple[float, ...]]:
    """One fold as a task of :func:`whipple.distributed.map_ordered`."""
    return _fold_model(*task)


def _speed_folds(observations: Sequence[Observation]) -> list[list[int]]:
    """Return the held-out groups: each speed group (each window, with one speed) leaving at least 2."""
    groups = speed_groups(observations)
    if len(groups) < 2:
        groups = [[i] for i in range(len(observations))]
    groups = [group for group in groups if len(observations) - len(group) >= 2]
    if not groups:
        raise AnalysisError("too few windows for a held-out comparison")
    return groups


def held_out_gain(bicycle: Model, observations: Sequence[Observation], causes: Sequence[Cause] | None = None,
                  series: Sequence[tuple[NDArray[np.float64], NDArray[np.float64], str]] | None = None,
                  fixed: Cause | None = None, *, choose: str = "evidence", scheduler: str | None = None,
                  workers: int | None = None, options: DiagnosisOptions | None = None,
                  progress: Progress | None = None) -> Gain:
    """Leave each speed group out: choose and fit the cause on the others, predict it.

    Parameters
    ----------
    bicycle : Bicycle
        The base model.
    observations : sequence of Observation
        All windows.
    causes : sequence of Cause, optional
        The candidates among which each fold chooses (default: all of the bicycle's).
    series : sequence of (time [s], values, baseline), optional
        The measured window behind each observation (same order) and the non-oscillating part
        its fit used (see ``whipple.measurement.weavefit``), for the time-domain error.
    fixed : Cause, optional
        Only refit this cause on each fold instead of choosing again (faster; the choice then
        has seen every speed).
    choose : {"evidence", "prediction"}
        How each fold chooses its cause: "evidence", the diagnosis itself (the default);
        "prediction", the candidate whose refits best predict the fold's own training speeds
        left out in turn (a nested leave-one-speed-out; many times the cost: every candidate
        is fitted on every fold and refitted locally once per pair of left-out speeds).
    scheduler, workers : optional
        Run the folds (each a whole diagnosis) on a Dask cluster: an existing one at
        ``scheduler``, or a local one of ``workers`` processes, see
        :func:`whipple.distributed.map_ordered`. The results are those of the serial run.
    options : DiagnosisOptions, optional
        Choosing by evidence, the diagnosis' options (as
        :func:`~whipple.diagnosis.evidence.diagnose_observations` takes them).
    progress : callable, optional
        Called as ``progress("folds", done, total)`` as each fold is done.

    With a single speed group, falls back to leave-one-window-out.

    Returns
    -------
    Gain
        Per left-out speed and over all: the cause chosen without it, the RMS and the median of
        ``|measured - predicted|`` weave eigenvalue [1/s] for the base and the extended model.
    """
    if choose not in ("evidence", "prediction"):
        raise ValueError(f"choose must be 'evidence' or 'prediction', got {choose!r}")
    observations = tuple(observations)
    groups = _speed_folds(observations)
    tasks = ((bicycle, without(observations, group), causes, fixed, choose, options) for group in groups)
    with map_ordered(_fold_task, tasks, scheduler=scheduler, workers=workers) as folds:
        models = _collected(folds, len(groups), progress)
    return _scored(bicycle, observations, groups, models, series, reselected=fixed is None)


def _collected(results: Iterable[Result], total: int, progress: Progress | None) -> list[Result]:
    """Return the results in order, reporting each as done."""
    collected = []
    for result in results:
        collected.append(result)
        if progress is not None:
            progress("folds", len(collected), total)
    return collected


@dataclass(frozen=True)
class CauseGain:
    """One candidate's held-out gain, refitted on every fold's other speeds (no choice made).

    Attributes
    ----------
    cause : str
        The cause (or pair ``A + B``).
    parameters, units : tuple of str
        Its fitted values' names and units.
    gain : Gain
        Its held-out errors; ``gain.speeds[k].values`` are its values fitted without speed k.
    at_bound : int
        Folds in which a fitted value sits at a bound of the cause that is not its no-effect
        value (a payload of the largest mass allowed, say): a stand-in, not a measurement.
    """

    cause: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    gain: Gain
    at_bound: int


def _folds_at_bound(cause: Cause, gain: Gain) -> int:
    return sum(bool(pinned_values(cause, speed.values)) for speed in gain.speeds)


def cause_gains(bicycle: Model, observations: Sequence[Observation], causes: Sequence[Cause], *,
                scheduler: str | None = None, workers: int | None = None,
                progress: Progress | None = None) -> tuple[CauseGain, ...]:
    """Each candidate's held-out gain, no choice made: refitted on every fold's other speeds.

    What each cause (or pair, see :func:`whipple.diagnosis.families.cause_pairs`) would gain on
    speeds its fit never saw, had it been chosen: the bound on what any choice among them
    could reach. Choosing by these figures has seen every speed; the report gives them beside
    the gain of the diagnosis' own choice, never in its place. One result per cause, in order;
    ``scheduler``/``workers`` as in :func:`held_out_gain` (one task per cause and speed).

    Parameters
    ----------
    bicycle : Bicycle or Fleet
        The base model.
    observations : sequence of Observation
        All windows.
    causes : sequence of Cause
        The candidates, each refitted on every fold.
    scheduler, workers : optional
        A Dask cluster, as in :func:`held_out_gain`.
    progress : callable, optional
        Called as ``progress("candidates", done, total)``.

    Returns
    -------
    tuple of CauseGain
        One per cause, in the order given: its held-out errors per speed and overall.
    """
    observations = tuple(observations)
    groups = _speed_folds(observations)
    tasks = ((bicycle, without(observations, group), None, cause, "evidence", None)
             for cause in causes for group in groups)
    with map_ordered(_fold_task, tasks, scheduler=scheduler, workers=workers) as folds:
        models = _collected(folds, len(causes) * len(groups), progress)
    step = len(groups)
    results = []
    for k, cause in enumerate(causes):
        gain = _scored(bicycle, observations, groups, models[k * step:(k + 1) * step], None, reselected=False)
        results.append(CauseGain(cause.name, cause.parameters, cause.units, gain, _folds_at_bound(cause, gain)))
    return tuple(results)


def _scored(bicycle: Model, observations: Sequence[Observation], groups: Sequence[Sequence[int]],
            models: Sequence[tuple[Model, str, str, tuple[float, ...]]],
            series: Sequence[tuple[NDArray[np.float64], NDArray[np.float64], str]] | None,
            reselected: bool) -> Gain:
    """Compare each fold's extended model with the base model on the fold's left-out speed."""
    scores: dict[str, list[Score]] = {"base": [], "extended": []}
    times: dict[str, list[float]] = {"base": [], "extended": []}
    speeds = []
    for group, (extended, name, verdict, values) in zip(groups, models, strict=True):
        held = [observations[i] for i in group]
        # The figures `whipple evaluate` gives for these models on these windows (evaluation.score_windows).
        fold = {key: score_windows(model, held, samples=False) for key, model in (("base", bicycle),
                                                                                  ("extended", extended))}
        for key, score in fold.items():
            scores[key].append(score)
            if series is None:
                continue
            for index, eigenvalue in zip(group, score.predicted, strict=True):
                time, signal, baseline = series[index]
                fitted = response_with_eigenvalue(time, signal, complex(eigenvalue), baseline)
                signal = np.atleast_2d(signal)
                scale = np.sqrt(np.mean((signal - signal.mean(axis=1, keepdims=True)) ** 2))
                times[key].append(float(np.sqrt(np.mean((signal - fitted) ** 2)) / scale))
        base, extended_score = fold["base"], fold["extended"]
        speeds.append(HeldOutSpeed(base.speed, base.windows, name, verdict, tuple(float(v) for v in values),
                                   base.rms, extended_score.rms, base.median, extended_score.median))

    def median(key: str) -> float | None:
        return float(np.median(times[key])) if times[key] else None

    base_all, extended_all = pooled(scores["base"]), pooled(scores["extended"])
    by = "speed" if len(speed_groups(observations)) >= 2 else "window"
    return Gain(f"|measured - predicted| weave eigenvalue on held-out {by}s [1/s]",
                base_all.median, extended_all.median, True, len(speeds), median("base"), median("extended"),
                base_all.rms, extended_all.rms, tuple(sorted(speeds, key=lambda s: s.speed)), reselected, by)


def held_out_candidates(causes: Sequence[Cause], pairs: bool = False) -> list[Cause]:
    """Return the models compared on held-out speeds: each cause in its most general form, and pairs.

    With ``pairs`` also every pair of the physical causes (not ``parameter:<key>``), fitted
    jointly (45 pairs for a bicycle with a controller).
    """
    candidates = general_forms(causes)
    if pairs:
        candidates += cause_pairs([cause for cause in causes
                                   if not cause.name.startswith("parameter:") and not is_term(cause.name)])
    return candidates
