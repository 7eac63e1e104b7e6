"""Hidden effects: simulate runs of a bicycle with one effect, diagnose without telling.

The fast subset (run in CI) takes three seeds per cause and requires the cause to be named in
at least two of them, and ``none`` to be said for all three effect-free seeds. The slow test
runs 50 seeds per cause and checks the rates the issue asks for: each cause named correctly
in at least 90% of seeds, ``none`` wrongly named (a cause named without an effect) in at most
5%. Interval coverage is measured and reported by benchmarks/bench_diagnosis.py and in
docs/diagnosis.md.
"""

from __future__ import annotations

import pytest
from hidden_effects import CAUSES, run_trial

EFFECTS = [cause for cause in CAUSES if cause != "none"]


def _identified(trial) -> bool:
    """Named right, or ambiguous with the hidden cause leading and in the family the verdict names.

    Some causes cannot be told apart by weave eigenvalues and mode shapes: a steer inertia is
    predicted within the noise by a front-wheel diametral inertia IFxx or a front payload (issue
    12: the verdict is then ``ambiguous``, naming the family, rather than a name decided by a
    prior alone).
    """
    diagnosis = trial.diagnosis
    return trial.named_correctly or (diagnosis.verdict == "ambiguous" and diagnosis.cause == trial.cause
                                     and trial.cause in diagnosis.family)


@pytest.mark.parametrize("cause", EFFECTS)
def test_hidden_cause_is_named_fast_subset(cause):
    trials = [run_trial(cause, seed) for seed in range(3)]
    identified = sum(_identified(trial) for trial in trials)
    verdicts = [(trial.diagnosis.verdict, trial.diagnosis.cause, trial.diagnosis.family) for trial in trials]
    assert identified >= 2, verdicts
    assert not any(trial.diagnosis.verdict == "named" and trial.diagnosis.cause != cause for trial in trials), verdicts


def test_no_effect_says_none_fast_subset():
    trials = [run_trial("none", seed) for seed in range(3)]
    assert all(trial.said_none for trial in trials), [trial.diagnosis.ranking()[:3] for trial in trials]


@pytest.mark.slow
@pytest.mark.parametrize("cause", list(CAUSES))
def test_hidden_effect_rates(cause):
    trials = [run_trial(cause, seed) for seed in range(50)]
    if cause == "none":
        false_alarms = sum(trial.diagnosis.verdict == "named" for trial in trials)
        assert false_alarms <= 0.05 * len(trials)
    else:
        named = sum(trial.named_correctly for trial in trials)
        assert named >= 0.9 * len(trials), f"{cause}: named in {named} of {len(trials)}"
