"""The model offered: by evidence where a candidate explains the windows, by prediction where none does.

Synthetic observations (the model's own weave eigenvalues and mode shapes plus Gaussian noise,
tests/synthetic_windows.py): scattered five times their stated uncertainty, no candidate
explains them (a dispersion near 25), which is the case the choice by prediction is for. The
one-standard-error rule of that choice is tested on constructed per-speed errors.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from synthetic_windows import STD, synthetic_observations

from whipple.diagnosis.admissible import inconsistencies, offer_of
from whipple.diagnosis.evaluation import rms
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.gain import held_out_gain
from whipple.diagnosis.observations import predicted_weave, speed_groups
from whipple.diagnosis.offer import excess_over_best, held_out_errors, offer, simplest_within
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import cause_by_name
from whipple.errors import InputError
from whipple.model.parameters import load_bicycle

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)
BICYCLE = load_bicycle("benchmark")
CAUSES = [cause_by_name(BICYCLE, name) for name in ("steer_damping", "steer_inertia", "speed_scale")]
TRUTH = BICYCLE.with_extensions(steer_damping=0.8)


def _diagnosis(std: float, seed: int = 1):
    return diagnose_observations(BICYCLE, synthetic_observations(TRUTH, seed, SPEEDS, std), CAUSES)


def test_where_no_candidate_explains_the_windows_the_choice_is_by_prediction():
    diagnosis = _diagnosis(5 * STD)
    assert max(diagnosis.typical_scales) > DiagnosisOptions().verdict.high_dispersion
    offered = offer(BICYCLE, diagnosis, CAUSES, DiagnosisOptions())
    assert offered.chosen_by == "prediction" and offered.standard_errors == 1.0
    scores = {p.name: p for p in offered.predictions}
    chosen = offered.fit.cause if offered.fit is not None else "none"
    best = min(scores.values(), key=lambda p: p.rms)
    # The offered model is within one standard error of the best predictor, and no simpler one is.
    assert scores[chosen].excess <= scores[chosen].standard_error
    assert best.excess == 0.0 and all(np.isclose(p.excess, p.rms ** 2 - best.rms ** 2) for p in scores.values())
    assert not any(p.values < scores[chosen].values and p.excess <= p.standard_error for p in scores.values())
    groups = speed_groups(diagnosis.observations)
    assert np.isclose(scores["none"].rms, rms(np.concatenate(held_out_errors(BICYCLE, None, None, diagnosis, groups))))
    for cause in CAUSES:
        fit = next((f for f in diagnosis.fits if f.cause == cause.name), None)
        if fit is not None and cause.name in scores:
            held_out = held_out_errors(BICYCLE, cause, fit, diagnosis, groups)
            assert np.isclose(scores[cause.name].rms, rms(np.concatenate(held_out)))
    if offered.fit is not None and offered.cause is not None:
        assert not inconsistencies(BICYCLE, offered.cause, offered.fit, diagnosis.observations)
    assert any("within 1 standard error of the best" in sentence for sentence in offered.sentences())


def test_with_no_standard_error_allowed_the_best_predictor_is_offered():
    diagnosis = _diagnosis(5 * STD)
    offered = offer(BICYCLE, diagnosis, CAUSES, DiagnosisOptions(prediction_standard_errors=0.0))
    scores = {p.name: p.rms for p in offered.predictions}
    # The choice before the rule: the smallest RMS, and a candidate only if it beats the base model.
    assert offered.fit is not None and scores[offered.fit.cause] == min(scores.values()) < scores["none"]


def test_the_base_models_errors_need_no_refit():
    diagnosis = _diagnosis(5 * STD)
    groups = speed_groups(diagnosis.observations)
    errors = held_out_errors(BICYCLE, None, None, diagnosis, groups)
    assert [len(e) for e in errors] == [len(g) for g in groups]
    assert np.allclose(np.concatenate(errors), np.abs([diagnosis.observations[i].eigenvalue for g in groups for i in g]
                                                      - predicted_weave(BICYCLE, [diagnosis.observations[i]
                                                                                 for g in groups for i in g])))


def _errors(per_group_rms, windows=4):
    """Per group, ``windows`` errors whose mean square is the group's given value squared."""
    return [np.full(windows, value) for value in per_group_rms]


# Constructed per-speed errors [1/s], five speeds of four windows: the base model (0 values), a
# one-value candidate and a three-value candidate.
BASE = _errors([2.0, 2.4, 1.8, 2.2, 2.1])
CLOSE_RMS = [1.45, 1.45, 1.55, 1.40, 1.50]   # one value: a little worse than FLEXIBLE, not beyond noise
FLEXIBLE_RMS = [1.40, 1.50, 1.40, 1.45, 1.45]
CLOSE, FLEXIBLE = _errors(CLOSE_RMS), _errors(FLEXIBLE_RMS)
SIZES = [0, 1, 3]


def test_a_simpler_candidate_within_one_standard_error_is_offered():
    excess, error = excess_over_best([BASE, CLOSE, FLEXIBLE])
    assert excess[2] == 0.0 and 0.0 < excess[1] <= error[1]
    assert simplest_within(SIZES, excess, error, 1.0) == 1
    # Without the rule the smaller error wins.
    assert simplest_within(SIZES, excess, error, 0.0) == 2


def test_a_candidate_better_beyond_one_standard_error_wins_over_a_simpler_one():
    clearly = _errors([0.6, 0.7, 0.5, 0.6, 0.65])
    excess, error = excess_over_best([BASE, CLOSE, clearly])
    assert excess[1] > error[1] and excess[0] > error[0]
    assert simplest_within(SIZES, excess, error, 1.0) == 2


def test_the_base_model_is_offered_when_no_candidate_beats_it_beyond_one_standard_error():
    # A candidate better at some speeds and worse at others: on average a little better, not beyond the spread.
    mixed = _errors([1.2, 2.8, 1.0, 2.7, 1.9])
    excess, error = excess_over_best([BASE, mixed])
    assert excess[1] == 0.0 and 0.0 < excess[0] <= error[0]
    assert simplest_within([0, 2], excess, error, 1.0) == 0
    assert simplest_within([0, 2], excess, error, 0.0) == 1


def test_the_standard_error_takes_the_speeds_as_units():
    excess, error = excess_over_best([CLOSE, FLEXIBLE])
    differences = np.array(CLOSE_RMS) ** 2 - np.array(FLEXIBLE_RMS) ** 2
    # Groups of equal size: the standard deviation of the per-speed differences over sqrt(5).
    assert np.isclose(error[0], np.std(differences, ddof=1) / np.sqrt(5)) and np.isclose(excess[0], differences.mean())
    # More windows of the same errors per speed do not make the speeds more independent.
    assert np.allclose(excess_over_best([_errors(CLOSE_RMS, 40), _errors(FLEXIBLE_RMS, 40)])[1], error)
    # Groups of unequal size: the excess is the pooled one, over every window.
    uneven = [[np.array([1.0, 3.0]), np.array([2.0])], [np.array([1.0, 1.0]), np.array([1.0])]]
    excess, error = excess_over_best(uneven)
    assert np.isclose(excess[0], (1 + 9 + 4) / 3 - 1) and excess[1] == 0.0
    # Per-speed differences 4 and 3, weighted 2/3 and 1/3 (their windows): deviations from 11/3
    # of 1/3 and -2/3, weighted 2/9 and -2/9; sqrt(2/1 * 2 * (2/9)^2) = 4/9.
    assert np.isclose(error[0], 4 / 9) and error[1] == 0.0


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


def test_the_rules_multiplier_is_a_number_from_0():
    for bad in (-1.0, float("nan"), True, "1"):
        with pytest.raises(InputError, match="prediction_standard_errors"):
            DiagnosisOptions(prediction_standard_errors=bad)
    assert DiagnosisOptions().to_dict()["prediction_standard_errors"] == 1.0


def test_the_reports_prediction_table_names_the_best_predictor_and_the_choice():
    from whipple.diagnosis.markdown import _prediction_table

    diagnosis = _diagnosis(5 * STD)
    offered = offer(BICYCLE, diagnosis, CAUSES, DiagnosisOptions())
    chosen = offered.fit.cause if offered.fit is not None else "none"
    table = _prediction_table({p.name: p.to_dict() for p in offered.predictions}, 1.0, chosen)
    rows = {line.split("|")[1].strip(): line for line in table if line.startswith("| ") and "---" not in line}
    best = min(offered.predictions, key=lambda p: p.rms)
    # The best predictor's row says so rather than "0 +/- 0"; the chosen model's row is marked.
    assert "the best predictor" in next(line for name, line in rows.items() if best.name in name)
    assert sum("(chosen)" in name for name in rows) == 1 and f"**{chosen}** (chosen)" in rows
    assert not any("0 +/- 0 |" in line for line in table)
