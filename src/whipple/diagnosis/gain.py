"""The gain of an extended model: its error on speeds that its fit never saw.

Leave-one-speed-out: the cause is refitted without each speed group and predicts that group.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause, with_cause
from whipple.diagnosis.evidence import fit_cause
from whipple.diagnosis.observations import Observation, predicted_weave, speed_groups
from whipple.errors import AnalysisError
from whipple.measurement.weavefit import response_with_eigenvalue
from whipple.model.parameters import Bicycle


@dataclass(frozen=True)
class Gain:
    """Held-out errors of the base and the extended model.

    ``base``/``extended``: median of |measured - predicted| weave eigenvalue [1/s] over
    held-out windows. ``time_base``/``time_extended``: median over held-out windows of the
    RMS roll-rate residual when the window is explained by the model's eigenvalue (amplitude,
    phase and baseline free), relative to the window's own RMS (dimensionless); None without
    the time series.
    """

    metric: str
    base: float
    extended: float
    held_out: bool
    folds: int
    time_base: float | None = None
    time_extended: float | None = None


def held_out_gain(bicycle: Bicycle, cause: Cause, observations: Sequence[Observation],
                  series: Sequence[tuple[NDArray[np.float64], NDArray[np.float64], str]] | None = None) -> Gain:
    """Leave-one-speed-out: refit the cause without each speed group, predict that group.

    Parameters
    ----------
    series : sequence of (time [s], values, baseline), optional
        The measured window behind each observation (same order) and the non-oscillating part
        its fit used (see ``whipple.measurement.weavefit``), for the time-domain error.

    With a single speed group, falls back to leave-one-window-out.
    """
    observations = tuple(observations)
    groups = speed_groups(observations)
    if len(groups) < 2:
        groups = [[i] for i in range(len(observations))]
    errors: dict[str, list[float]] = {"base": [], "extended": [], "time_base": [], "time_extended": []}
    for group in groups:
        training = [o for i, o in enumerate(observations) if i not in group]
        held = [observations[i] for i in group]
        if len(training) < 2:
            continue
        fit = fit_cause(bicycle, cause, training)
        extended = with_cause(bicycle, cause, fit.values)
        measured = np.array([o.eigenvalue for o in held])
        for key, model in (("base", bicycle), ("extended", extended)):
            predicted = predicted_weave(model, held)
            errors[key].extend(np.abs(measured - predicted).tolist())
            if series is None:
                continue
            for index, eigenvalue in zip(group, predicted, strict=True):
                time, values, baseline = series[index]
                fitted = response_with_eigenvalue(time, values, complex(eigenvalue), baseline)
                values = np.atleast_2d(values)
                scale = np.sqrt(np.mean((values - values.mean(axis=1, keepdims=True)) ** 2))
                errors[f"time_{key}"].append(float(np.sqrt(np.mean((values - fitted) ** 2)) / scale))
    if not errors["base"]:
        raise AnalysisError("too few windows for a held-out comparison")

    # Medians: a few windows at very unstable speeds are fitted far off (see ROBUST_SCALE).
    def median(key: str) -> float | None:
        return float(np.median(errors[key])) if errors[key] else None

    return Gain("median |measured - predicted| weave eigenvalue on held-out speeds [1/s]",
                float(median("base") or 0.0), float(median("extended") or 0.0), True, len(groups),
                median("time_base"), median("time_extended"))
