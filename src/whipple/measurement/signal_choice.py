"""Which signals a diagnosis fits jointly in every window: the roll rate, and the steer angle where it can."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from whipple.measurement.runs import Run

#: The signals a diagnosis fits jointly where the runs measure both (:func:`diagnosis_signals`).
JOINT_SIGNALS = ("roll_rate", "steer_angle")


def diagnosis_signals(runs: Sequence[Run]) -> tuple[str, ...]:
    """Return the signals a diagnosis fits jointly in every window of `runs`.

    The roll rate and the steer angle (:data:`JOINT_SIGNALS`) when every run measures a steer
    angle wherever it measures the roll rate; the roll rate alone, as in the seed paper, when
    any run lacks a steer angle, has one that never changes (:func:`steer_constant`) or has gaps
    in it that the roll rate has not (a joint fit would lose the windows across them). The steer
    angle's weave sharpens the shared eigenvalue: on the hidden-effect trials it gave more right
    names and fewer wrong ones (docs/diagnosis.md).

    Parameters
    ----------
    runs : sequence of Run
        The runs to be diagnosed together (their windows share one choice, so that every
        window is fitted alike).

    Returns
    -------
    tuple of str
        Run-file signal names, the reference of the mode shape first.
    """
    return JOINT_SIGNALS if runs and all(_steer_measured_alike(run) for run in runs) else JOINT_SIGNALS[:1]


def _steer_measured_alike(run: Run) -> bool:
    """Whether `run` measures a changing steer angle at every sample where it measures the roll rate."""
    steer = run.signals.get("steer_angle")
    return (steer is not None and not steer_constant(run)
            and bool(np.all(np.isfinite(steer) | ~np.isfinite(run.signals["roll_rate"]))))


def steer_constant(run: Run) -> bool:
    """Whether `run` has a steer angle column whose values never change (a sensor not connected, stuck)."""
    steer = run.signals.get("steer_angle")
    return steer is not None and constant_signal(steer)


def constant_signal(values: NDArray[np.float64]) -> bool:
    """Whether a signal's values (NaN for gaps) are all one number."""
    finite = values[np.isfinite(values)]
    return bool(finite.size) and float(np.ptp(finite)) == 0.0
