"""Models scored on measured windows: what ``whipple evaluate`` reports, and the held-out gain's figures.

A model is scored on a set of windows (measured by :func:`whipple.measurement.measure.measure_runs`,
the one weave measurement) by two figures:

- the error of its weave eigenvalue: ``|measured - predicted|`` [1/s] per window, the model's
  mode nearest the measured eigenvalue at the window's speed
  (:func:`~whipple.diagnosis.observations.predicted_weave`), summarised by its RMS and its
  median;
- its samples' residual: the chi-square per sample of its free response fitted to each
  window's samples (:meth:`~whipple.diagnosis.samples.SampleComparison.chi2_per_sample`; 1
  where a model leaves only the noise).

Per speed (the windows grouped by speed as the held-out folds group them,
:func:`~whipple.diagnosis.observations.speed_groups`) and over all windows. The held-out gain
(:mod:`whipple.diagnosis.gain`) scores each fold's models on the left-out speed with
:func:`score_windows` too, so that its per-speed figures are what :func:`evaluate` gives for
those models on those windows.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.diagnosis.observations import Observation, observations, predicted_weave, speed_groups
from whipple.diagnosis.samples import SampleComparison
from whipple.errors import InputError
from whipple.measurement.experiment import WindowMeasurement
from whipple.measurement.experiment_file import Experiment
from whipple.measurement.measure import MeasuredRuns, MeasurementOptions, Progress, unusable_text
from whipple.model.fleet import Model
from whipple.model.parameters import Bicycle

__all__ = ["METRICS", "Windows", "Score", "score_windows", "pooled", "ModelScores", "GroupEvaluation", "Evaluation",
           "evaluate", "evaluate_experiment"]

#: What the scores measure, for reports.
METRICS = {
    "rms": "RMS over the windows of |measured - predicted| weave eigenvalue [1/s] (the model's mode nearest "
           "the measured eigenvalue at the window's speed)",
    "median": "median over the windows of |measured - predicted| weave eigenvalue [1/s]",
    "chi2_per_sample": "chi-square per sample of the model's free response fitted to each window's samples "
                       "(1: only the noise left); null where the windows carry no samples",
}

#: Windows to score: measured runs, measured windows (the usable ones are scored), or observations.
Windows = MeasuredRuns | Sequence[WindowMeasurement] | Sequence[Observation]


@dataclass(frozen=True)
class Score:
    """One model's error on a set of windows.

    Attributes
    ----------
    speed : float
        Mean measured speed of the windows [m/s].
    speed_range : tuple of float
        Lowest and highest window speed [m/s].
    windows : int
        Number of windows.
    rms, median : float
        RMS and median over the windows of |measured - predicted| weave eigenvalue [1/s].
    chi2_per_sample : float or None
        The model's chi-square per sample on the windows' samples; None where they carry none.
    samples : int
        Number of residuals behind ``chi2_per_sample`` (0 without).
    errors : ndarray
        |measured - predicted| weave eigenvalue of each window [1/s], in the order scored.
    predicted : ndarray of complex
        The model's eigenvalue nearest each window's measured one [1/s], in the same order.
    """

    speed: float
    speed_range: tuple[float, float]
    windows: int
    rms: float
    median: float
    chi2_per_sample: float | None
    samples: int
    errors: NDArray[np.float64] = field(repr=False, compare=False)
    predicted: NDArray[np.complex128] = field(repr=False, compare=False)

    def to_dict(self) -> dict[str, Any]:
        """Return the score as JSON-ready data (the per-window errors left out)."""
        return {"speed": self.speed, "speed_range": list(self.speed_range), "windows": self.windows,
                "rms": self.rms, "median": self.median, "chi2_per_sample": self.chi2_per_sample,
                "samples": self.samples}


def rms(values: ArrayLike) -> float:
    """Return the root mean square of `values` (real or complex: of their magnitudes), in their units."""
    return float(np.sqrt(np.mean(np.abs(np.asarray(values)) ** 2)))


def score_windows(model: Model, windows: Sequence[Observation], samples: bool | SampleComparison | None = True
                  ) -> Score:
    """Score one model on a set of windows.

    Parameters
    ----------
    model : Bicycle or Fleet
        The model (with its controller and extensions; a fleet: each window's group's bicycle).
    windows : sequence of Observation
        The windows, at least one.
    samples : bool or SampleComparison, optional
        Whether to compare the model with the windows' samples too (True: build the comparison
        here; a :class:`SampleComparison` of these windows: use it; False or None: not).

    Returns
    -------
    Score
    """
    if not windows:
        raise InputError("no windows to score a model on")
    predicted = predicted_weave(model, windows)
    errors = np.abs(np.array([o.eigenvalue for o in windows], dtype=complex) - predicted)
    comparison = SampleComparison.of(windows, bicycle=model) if samples is True else samples or None
    chi2 = None if comparison is None else comparison.chi2_per_sample(model)
    speeds = [o.speed for o in windows]
    return Score(float(np.mean(speeds)), (float(min(speeds)), float(max(speeds))), len(windows), rms(errors),
                 float(np.median(errors)), chi2, 0 if comparison is None else comparison.samples, errors, predicted)


def pooled(scores: Sequence[Score]) -> Score:
    """Return the score over the windows of several scores together (RMS and median of all windows' errors).

    The chi-square per sample is that of all their residuals (each score's weighted by its
    samples), None where one of them has none.
    """
    errors = np.concatenate([s.errors for s in scores])
    windows = sum(s.windows for s in scores)
    speed = float(sum(s.speed * s.windows for s in scores) / windows)
    low, high = min(s.speed_range[0] for s in scores), max(s.speed_range[1] for s in scores)
    chi2: float | None = None
    count = sum(s.samples for s in scores)
    weighted = [s.chi2_per_sample * s.samples for s in scores if s.chi2_per_sample is not None]
    if len(weighted) == len(scores) and count:
        chi2 = float(sum(weighted) / count)
    return Score(speed, (low, high), windows, rms(errors), float(np.median(errors)), chi2,
                 count if chi2 is not None else 0, errors, np.concatenate([s.predicted for s in scores]))


@dataclass(frozen=True)
class ModelScores:
    """One model's scores on one group of windows: per speed and over all.

    Attributes
    ----------
    model : str
        The model's label.
    speeds : tuple of Score
        Per speed group, by speed.
    overall : Score
        Over all the group's windows.
    """

    model: str
    speeds: tuple[Score, ...]
    overall: Score

    def to_dict(self) -> dict[str, Any]:
        """Return the scores as JSON-ready data."""
        return {"overall": self.overall.to_dict(), "speeds": [s.to_dict() for s in self.speeds]}


@dataclass(frozen=True)
class GroupEvaluation:
    """The models scored on one group's windows.

    Attributes
    ----------
    name : str or None
        The group's name (None: runs given without an experiment file).
    runs : tuple of str
        The runs whose usable windows were scored.
    scores : tuple of ModelScores
        One per model, in the evaluation's order.
    """

    name: str | None
    runs: tuple[str, ...]
    scores: tuple[ModelScores, ...]

    @property
    def windows(self) -> int:
        """Return the number of windows scored."""
        return self.scores[0].overall.windows

    def to_dict(self) -> dict[str, Any]:
        """Return the group's scores as JSON-ready data."""
        return {"name": self.name, "runs": list(self.runs), "windows": self.windows,
                "models": {s.model: s.to_dict() for s in self.scores}}


@dataclass(frozen=True)
class Evaluation:
    """Models scored on measured windows, per group, per speed and over all (:func:`evaluate`).

    Attributes
    ----------
    models : tuple of str
        The models' labels, in order.
    groups : tuple of GroupEvaluation
        Per group (one, named None, for runs given without an experiment file).
    overall : tuple of Score
        Per model, over every window of every group.
    measurement : dict
        How the windows were measured (:meth:`~whipple.measurement.measure.MeasurementOptions.to_dict`),
        where known.
    """

    models: tuple[str, ...]
    groups: tuple[GroupEvaluation, ...]
    overall: tuple[Score, ...]
    measurement: dict[str, Any] | None = None

    def rows(self) -> list[dict[str, Any]]:
        """Return the scores as table rows: per group each speed, the group, then every group together.

        Each row: ``scope`` (``"speed"``, ``"group"`` or ``"all"``), ``group`` (None for runs
        given without an experiment file, and for ``"all"``), ``model`` and the
        :class:`Score`'s fields (``to_dict``). The ``"all"`` rows are left out when there is one group.
        """
        rows = []
        for group in self.groups:
            for k in range(len(group.scores[0].speeds)):
                rows += [{"scope": "speed", "group": group.name, "model": scores.model, **scores.speeds[k].to_dict()}
                         for scores in group.scores]
            rows += [{"scope": "group", "group": group.name, "model": scores.model, **scores.overall.to_dict()}
                     for scores in group.scores]
        if len(self.groups) > 1:
            rows += [{"scope": "all", "group": None, "model": model, **score.to_dict()}
                     for model, score in zip(self.models, self.overall, strict=True)]
        return rows

    def to_dict(self) -> dict[str, Any]:
        """Return the evaluation as JSON-ready data (``whipple evaluate --json``)."""
        return {"metrics": dict(METRICS), "measurement": self.measurement, "models": list(self.models),
                "groups": [g.to_dict() for g in self.groups],
                "overall": {model: score.to_dict() for model, score in zip(self.models, self.overall, strict=True)}}


def _observations(windows: Windows) -> tuple[list[Observation], dict[str, Any] | None]:
    """Return the usable windows as observations, and the measurement's options where known."""
    if isinstance(windows, MeasuredRuns):
        return observations(windows.windows), windows.options.to_dict()
    items = list(windows)
    if all(isinstance(item, Observation) for item in items):
        return items, None  # type: ignore[return-value]
    if all(isinstance(item, WindowMeasurement) for item in items):
        return observations(items), None  # type: ignore[arg-type]
    raise InputError("windows must be measured runs, measured windows or observations, not a mixture")


def _group_scores(models: Mapping[str, Bicycle], windows: list[Observation], samples: bool
                  ) -> tuple[ModelScores, ...]:
    """Score every model on the windows, per speed group and over all."""
    groups = [[windows[i] for i in group] for group in speed_groups(windows)]
    comparisons = [SampleComparison.of(group) if samples else None for group in groups]
    result = []
    for label, model in models.items():
        per_speed = [score_windows(model, group, comparison or False)
                     for group, comparison in zip(groups, comparisons, strict=True)]
        per_speed.sort(key=lambda score: score.speed)
        result.append(ModelScores(label, tuple(per_speed), pooled(per_speed)))
    return tuple(result)


def evaluate(windows: Windows | Mapping[str, Windows], models: Mapping[str, Bicycle | Mapping[str, Bicycle]], *,
             samples: bool = True) -> Evaluation:
    """Score models on measured windows: per speed and over all, the eigenvalue error and the samples' residual.

    Parameters
    ----------
    windows : MeasuredRuns, sequence of WindowMeasurement or Observation, or mapping
        The windows (their usable ones): one set, or a mapping of group name to a set (the
        groups of an experiment file, each measured on its own bicycle,
        :meth:`whipple.measurement.experiment_file.Group.measure`).
    models : mapping
        Label to model: a :class:`Bicycle` (scored on every group), or, per group, a mapping
        of group name to the group's :class:`Bicycle` (the models of an experiment, one file
        per group). Labels are kept in order.
    samples : bool
        Also compare each model with the windows' samples (the chi-square per sample); False
        scores the eigenvalues alone (faster).

    Returns
    -------
    Evaluation
        Per group, per model: per speed and overall; per model over every group.

    Raises
    ------
    InputError
        No models, a group without usable windows, or a model missing for a group.
    """
    if not models:
        raise InputError("no models to evaluate")
    sets: list[tuple[str | None, Windows]] = (list(windows.items()) if isinstance(windows, Mapping)
                                              else [(None, windows)])
    groups = []
    measurement = None
    for name, members in sets:
        found, options = _observations(members)
        measurement = measurement or options
        where = f"group {name!r}: " if name is not None else ""
        if not found:
            measured = members.windows if isinstance(members, MeasuredRuns) else [
                m for m in members if isinstance(m, WindowMeasurement)]
            within, why = unusable_text(measured)
            raise InputError(f"{where}no usable window with a fitted weave eigenvalue{within} to score the models "
                             f"on{why}")
        chosen = {}
        for label, model in models.items():
            if isinstance(model, Bicycle):
                chosen[label] = model
            elif name is not None and name in model:
                chosen[label] = model[name]
            elif name is None:
                raise InputError(f"model {label!r} gives a bicycle per group, but the windows are not in groups")
            else:
                raise InputError(f"{where}model {label!r} has no bicycle for this group")
        runs = tuple(dict.fromkeys(o.run for o in found))
        groups.append(GroupEvaluation(name, runs, _group_scores(chosen, found, samples)))
    overall = tuple(pooled([group.scores[k].overall for group in groups]) for k in range(len(models)))
    return Evaluation(tuple(models), tuple(groups), overall, measurement)


def evaluate_experiment(experiment: Experiment, models: Mapping[str, Mapping[str, Bicycle]] | None = None,
                        options: MeasurementOptions | None = None, *, samples: bool = True,
                        progress: Progress | None = None) -> Evaluation:
    """Measure every group of an experiment on its own bicycle and score models on it (:func:`evaluate`).

    Parameters
    ----------
    experiment : Experiment
        The experiment (:func:`whipple.measurement.experiment_file.read_experiment`).
    models : mapping, optional
        Label to a model per group (group name to :class:`Bicycle`, e.g.
        :func:`~whipple.measurement.experiment_file.read_group_models`). Default: the groups'
        own bicycles, labelled ``"experiment"``.
    options : MeasurementOptions, optional
        How the runs are measured (default :class:`MeasurementOptions`); each group is measured
        against its own bicycle (:meth:`~whipple.measurement.experiment_file.Group.measure`),
        whichever models are scored, so that every model meets the same windows.
    samples : bool
        Also the samples' residual (as :func:`evaluate`).
    progress : callable, optional
        Called as ``progress("runs", done, total)`` as each group's runs are measured.

    Returns
    -------
    Evaluation
        As :func:`evaluate`: per group, per model, per speed and overall.
    """
    measured = {group.name: group.measure(options, progress=progress) for group in experiment.groups}
    return evaluate(measured, dict(models) if models is not None else {"experiment": experiment.bicycles()},
                    samples=samples)
