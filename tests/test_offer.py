"""The model offered: by evidence where a candidate explains the windows, by prediction where none does.

Synthetic observations (the model's own weave eigenvalues and mode shapes plus Gaussian noise,
tests/synthetic_windows.py): scattered five times their stated uncertainty, no candidate
explains them (a dispersion near 25), which is the case the choice by prediction is for.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from synthetic_windows import STD, synthetic_observations

from whipple.diagnosis.admissible import inconsistencies, offer_of
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.gain import held_out_gain
from whipple.diagnosis.observations import speed_groups
from whipple.diagnosis.offer import offer, prediction_rms
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import cause_by_name
from whipple.model.parameters import load_bicycle

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)
BICYCLE = load_bicycle("benchmark")
CAUSES = [cause_by_name(BICYCLE, name) for name in ("steer_damping", "steer_inertia", "speed_scale")]
TRUTH = BICYCLE.with_extensions(steer_damping=0.8)


def _diagnosis(std: float, seed: int = 1):
    return diagnose_observations(BICYCLE, synthetic_observations(TRUTH, seed, SPEEDS, std), CAUSES)


def test_where_no_candidate_explains_the_windows_the_best_predictor_is_offered():
    diagnosis = _diagnosis(5 * STD)
    assert max(diagnosis.typical_scales) > DiagnosisOptions().verdict.high_dispersion
    offered = offer(BICYCLE, diagnosis, CAUSES, DiagnosisOptions())
    assert offered.chosen_by == "prediction" and offered.fit is not None and offered.cause is not None
    scores = dict(offered.predictions)
    # The offered candidate predicts the left-out speeds best, and better than the base model.
    assert scores[offered.fit.cause] == min(scores.values()) < scores["none"]
    groups = speed_groups(diagnosis.observations)
    assert np.isclose(scores[offered.fit.cause], prediction_rms(BICYCLE, offered.cause, offered.fit, diagnosis, groups))
    assert not inconsistencies(BICYCLE, offered.cause, offered.fit, diagnosis.observations)
    assert any("best predicts each speed left out" in sentence for sentence in offered.sentences())


def test_where_a_candidate_explains_the_windows_the_evidence_chooses():
    diagnosis = _diagnosis(STD)
    assert max(diagnosis.typical_scales) < DiagnosisOptions().verdict.high_dispersion
    offered = offer(BICYCLE, diagnosis, CAUSES, DiagnosisOptions())
    assert offered == offer_of(BICYCLE, diagnosis, CAUSES, DiagnosisOptions().verdict.named_threshold)
    assert offered.chosen_by == "evidence" and offered.fit is not None and offered.fit.cause == "steer_damping"


def test_no_shortlist_means_the_evidence_chooses():
    diagnosis = _diagnosis(5 * STD)
    options = DiagnosisOptions(prediction_shortlist=0)
    assert offer(BICYCLE, diagnosis, CAUSES, options) == offer_of(BICYCLE, diagnosis, CAUSES,
                                                                 options.verdict.named_threshold)


def test_a_folds_choice_by_prediction_never_sees_its_held_out_speed():
    # The held-out gain's folds choose as the diagnosis does, on their own training speeds: the
    # model predicting a left-out speed is the same whatever that speed's measurements are.
    observations = synthetic_observations(TRUTH, 2, SPEEDS, 5 * STD)
    held = speed_groups(observations)[-1]
    spoiled = [replace(o, eigenvalue=o.eigenvalue + 1.5j) if i in held else o for i, o in enumerate(observations)]
    honest, leaked = (held_out_gain(BICYCLE, obs, CAUSES) for obs in (observations, spoiled))
    assert honest.speeds[-1].cause == leaked.speeds[-1].cause
    assert honest.speeds[-1].values == leaked.speeds[-1].values
