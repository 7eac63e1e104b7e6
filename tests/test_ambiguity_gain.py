"""What the data cannot tell apart, pairs of causes, and the held-out gain.

Synthetic observations are the model's own weave eigenvalues and mode shapes (derived
equations) of a bicycle with known effects, plus Gaussian noise of the stated covariance.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from synthetic_windows import STD, synthetic_observations

from whipple.diagnosis import evidence
from whipple.diagnosis.causes import with_cause
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.families import (
    cause_pairs,
    combined_cause,
    common_family,
    components,
    describe_family,
    general_forms,
)
from whipple.diagnosis.fitting import CauseFit, fit_cause, pinned_values
from whipple.diagnosis.gain import cause_gains, held_out_gain
from whipple.diagnosis.gain_text import gain_json, gain_sentences
from whipple.diagnosis.observations import Observation, noise_free, speed_groups
from whipple.diagnosis.options import DiagnosisOptions, PairRules, VerdictRules
from whipple.diagnosis.registry import candidate_causes, cause_by_name, payload_causes
from whipple.model.parameters import Bicycle, load_bicycle

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)
#: The evidence's charge of ln(n)/2 per value, without the calibration: the pair and edge rules'
#: tests use it where the calibration would stand in for two effects (see the tests).
BIC = DiagnosisOptions(occam="bic")


def _observations(truth, seed, speeds=SPEEDS, std=STD):
    return synthetic_observations(truth, seed, speeds, std)


def test_family_words_and_combined_causes():
    assert describe_family(["steer_inertia", "parameter:IHzz"]) == (
        "extra inertia of the front assembly about the steer axis: steer_inertia or parameter:IHzz")
    assert common_family(["payload", "parameter:IBzz"]).key == "rear_mass"
    assert describe_family(["steer_damping", "speed_scale"]).startswith("causes that predict the observations alike")
    bicycle = load_bicycle("benchmark")
    pair = combined_cause(cause_by_name(bicycle, "steer_damping"), cause_by_name(bicycle, "parameter:c"))
    changed = pair.apply(bicycle, [0.5, 0.1])
    assert pair.name == "steer_damping + parameter:c" and pair.parameters == ("steer_damping", "c")
    assert changed.extensions.steer_damping == 0.5 and changed.parameters["c"] == 0.1
    assert np.isclose(pair.prior, cause_by_name(bicycle, "parameter:c").prior)


def test_causes_that_predict_alike_give_an_ambiguous_verdict_naming_the_family():
    # An extra steer inertia and a larger front-wheel diametral inertia IFxx move the weave's
    # eigenvalues and mode shape alike (their fits' predictions differ by 0.3 noise units in
    # total); IFxx's smaller prior alone would otherwise decide for steer_inertia.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name)
              for name in ("steer_inertia", "parameter:IFxx", "steer_damping", "speed_scale", "parameter:c")]
    diagnosis = diagnose_observations(bicycle, _observations(bicycle.with_extensions(steer_inertia=0.04), 0), causes)
    assert diagnosis.verdict == "ambiguous"
    assert {diagnosis.cause, *diagnosis.rivals} == {"steer_inertia", "parameter:IFxx"}
    assert diagnosis.family.startswith("extra inertia of the front assembly about the steer axis:")
    # The reason says how many times as many windows would separate the two beyond the noise;
    # windows that many times as many (noise-free, so that only their number changes) do.
    fit_of = {fit.cause: fit for fit in diagnosis.fits}
    apart = evidence.separation(fit_of["steer_inertia"], fit_of["parameter:IFxx"])
    factor = int(np.ceil(VerdictRules().separation / apart))
    assert f"about {factor} times as many windows at these speeds" in diagnosis.reasons[0]
    truth = bicycle.with_extensions(steer_inertia=0.04)
    more = diagnose_observations(bicycle, noise_free(truth, _observations(truth, 0, np.repeat(SPEEDS, factor))), causes)
    fit_of = {fit.cause: fit for fit in more.fits}
    assert evidence.separation(fit_of["steer_inertia"], fit_of["parameter:IFxx"]) > 0.8 * VerdictRules().separation
    # Without the mimic among the candidates, the same data name steer inertia.
    alone = diagnose_observations(bicycle, _observations(bicycle.with_extensions(steer_inertia=0.04), 0),
                                  [c for c in causes if c.name != "parameter:IFxx"])
    assert alone.verdict == "named" and alone.cause == "steer_inertia"


def test_high_dispersion_is_never_a_confident_name():
    # Scatter five times the stated uncertainty: every candidate leaves a reduced chi-square
    # near 25, so the leading cause is a guess, said as such.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "steer_inertia", "speed_scale")]
    truth = bicycle.with_extensions(steer_damping=0.8)
    diagnosis = diagnose_observations(bicycle, _observations(truth, 1, std=5 * STD), causes)
    assert diagnosis.scale > 3.0 and diagnosis.typical_scales[0] > 3.0
    assert diagnosis.verdict == "ambiguous" and diagnosis.cause.startswith("steer_damping")
    assert any("no candidate explains the data" in reason for reason in diagnosis.reasons)


def test_two_hidden_effects_are_found_as_a_pair():
    # Steer damping with a 35% larger rear-frame roll inertia: the best single cause leaves a
    # reduced chi-square above 2 (eigenvalues or mode shapes), so pairs are tried; the pair,
    # fitted jointly and charged for its extra value, explains the data to the noise and
    # recovers both values. It leads, but is not named outright: one effect outside the
    # candidates could fit two causes' freedom as well (docs/diagnosis.md, the rates).
    # Under the BIC's charge: with priors (the default) the calibration, every parameter within
    # its uncertainty, stands in for the pair at a dispersion near 1 and no pair is tried.
    bicycle = load_bicycle("benchmark")
    truth = bicycle.with_extensions(steer_damping=0.5).with_parameters(IBxx=1.35 * bicycle.parameters["IBxx"])
    diagnosis = diagnose_observations(bicycle, _observations(truth, 0), options=BIC)
    assert max(diagnosis.single_scales) > 2.0 and diagnosis.combinations
    assert diagnosis.verdict == "ambiguous" and diagnosis.cause == "steer_damping + parameter:IBxx"
    assert any("two causes together" in reason for reason in diagnosis.reasons)
    assert diagnosis.scale < 1.5
    for value, true, std in zip(diagnosis.best.values, (0.5, truth.parameters["IBxx"]), diagnosis.best.std,
                                strict=True):
        assert abs(value - true) < 3 * std


# Slow (every pair of a controlled bicycle fitted): run with `pytest -m slow`.
@pytest.mark.slow
def test_a_payload_off_the_frame_with_a_controller_delay_is_found_as_a_pair():
    # A rear load 10 kg well ahead of and below the rear frame's mass centre, with a 30 ms
    # controller delay, on the controlled sbw2024: the payload's position does nothing at zero
    # mass, so a screen linearised only at the base model cannot place it, and the leading
    # single causes (stand-ins) did not hold the pair (this test failed so); the screen
    # linearised away from the base model finds it (benchmarks/bench_prediction_choice.py
    # measured the effect over seeds).
    bicycle = load_bicycle("sbw2024")
    forms = {cause.name: cause for cause in general_forms(candidate_causes(bicycle), refinements=False)}
    pair = combined_cause(forms["payload"], forms["controller_delay"])
    true_values = (10.0, 0.6, -0.35, 0.03)
    truth = pair.apply(bicycle, true_values)
    diagnosis = diagnose_observations(bicycle, _observations(truth, 0, np.repeat([1.5, 2.5, 3.5, 4.5, 5.5], 4)))
    assert max(diagnosis.single_scales) > 2.0
    assert diagnosis.verdict == "ambiguous" and diagnosis.cause == "payload + controller_delay"
    assert diagnosis.best.parameters == pair.parameters
    for value, true, std in zip(diagnosis.best.values, true_values, diagnosis.best.std, strict=True):
        assert abs(value - true) < 3 * std


def _damping_and_roll_inertia() -> tuple[Bicycle, list[Observation]]:
    """The benchmark, and windows at 4-8 m/s of it with steer damping and a 40% larger IBxx."""
    bicycle = load_bicycle("benchmark")
    truth = bicycle.with_extensions(steer_damping=0.8).with_parameters(IBxx=1.4 * bicycle.parameters["IBxx"])
    return bicycle, _observations(truth, 0, np.repeat([4.0, 5.0, 6.0, 7.0, 8.0], 4))


def test_a_cause_stretched_to_the_edge_of_its_physical_range_is_not_named():
    # Two effects: the best single cause is a front payload of 0.7 kg ahead of the front wheel
    # at the height of the ground (the bound of its heights), within a dispersion of 2 of the
    # data. With pairs not tried (as for a single cause with fewer values), the edge alone
    # must keep it from a confident name: a load cannot sit lower, the data ask for more.
    bicycle, observations = _damping_and_roll_inertia()
    never_paired = DiagnosisOptions(pairs=PairRules(flexible_values=99), occam="bic")
    diagnosis = diagnose_observations(bicycle, observations, options=never_paired)
    assert diagnosis.cause == "front_payload" and diagnosis.best.pinned == (("front_payload_z", 0.0),)
    assert diagnosis.verdict == "ambiguous"
    # The edge of the range is the only reason given: without it the verdict would be "named".
    assert len(diagnosis.reasons) == 1 and "edge of its physical range" in diagnosis.reasons[0]


# Slow (pairs fitted on five speeds): run with `pytest -m slow`.
@pytest.mark.slow
def test_a_payload_free_to_stand_in_for_two_effects_is_checked_against_pairs():
    # The same two effects: a front payload with a fitted position fits them within the noise,
    # so pairs are tried although the dispersion is low, and the true pair leads (never named).
    bicycle, observations = _damping_and_roll_inertia()
    diagnosis = diagnose_observations(bicycle, observations)
    assert diagnosis.combinations  # tried although the best single cause fitted
    assert diagnosis.cause == "steer_damping + parameter:IBxx" and diagnosis.verdict == "ambiguous"
    truth = {"steer_damping": 0.8, "IBxx": 1.4 * bicycle.parameters["IBxx"]}
    best = diagnosis.best
    for name, value, std in zip(best.parameters, best.values, best.std, strict=True):
        assert abs(value - truth[name]) < 3 * std, (name, value, std)


def test_only_bounds_other_than_the_no_effect_values_pin_a_fit():
    bicycle = load_bicycle("benchmark")
    load = next(form for form in payload_causes(bicycle, "front_payload") if len(form.parameters) == 3)
    (_, heaviest), (nearest, farthest), (lowest, highest) = load.bounds
    middle = 0.5 * (nearest + farthest)
    assert pinned_values(load, [0.0, middle, -0.5]) == ()  # a mass of 0: no load, not a stretched one
    assert pinned_values(load, [heaviest, farthest, highest]) == (
        ("front_payload_mass", heaviest), ("front_payload_x", farthest), ("front_payload_z", highest))
    assert pinned_values(load, [1.0, middle, lowest + 0.01]) == ()
    assert pinned_values(load, [1.0, nearest, -0.5]) == (("front_payload_x", nearest),)
    mass = cause_by_name(bicycle, "parameter:mB")
    assert pinned_values(mass, [bicycle.parameters["mB"] / 3.0]) == (("mB", bicycle.parameters["mB"] / 3.0),)


def test_held_out_gain_never_sees_the_held_out_speed():
    # Whatever the held-out speed's measurements, the model that predicts it is the same: the
    # fold's choice and fit see only the other speeds.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "steer_inertia", "speed_scale")]
    observations = _observations(bicycle.with_extensions(steer_damping=0.6), 2)
    held = speed_groups(observations)[-1]
    spoiled = [replace(o, eigenvalue=o.eigenvalue + 1.5j) if i in held else o for i, o in enumerate(observations)]
    honest, leaked = (held_out_gain(bicycle, obs, causes) for obs in (observations, spoiled))
    assert honest.speeds[-1].cause == leaked.speeds[-1].cause == "steer_damping"
    assert honest.speeds[-1].values == leaked.speeds[-1].values
    training = [o for i, o in enumerate(observations) if i not in held]
    direct = fit_cause(bicycle, causes[0], training)
    assert np.allclose(honest.speeds[-1].values, direct.values, rtol=1e-3)
    # The spoiled speed is predicted no better: its error grows by the offset for both models.
    assert leaked.speeds[-1].extended_rms > honest.speeds[-1].extended_rms + 1.0
    # On clean data the extended model helps at every held-out speed, and says so.
    assert honest.cut > 0.5 and not honest.not_helped()
    assert len(honest.speeds) == 5 and all(s.windows == 4 for s in honest.speeds)


def test_held_out_gain_of_one_speed_says_it_is_over_windows():
    # Windows of one speed only: each window is left out in turn, and the words must not claim
    # a prediction of unseen speeds.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "speed_scale")]
    observations = _observations(bicycle.with_extensions(steer_damping=0.6), 5, speeds=np.full(6, 5.0))
    gain = held_out_gain(bicycle, observations, causes)
    assert gain.held_out_by == "window" and gain.folds == 6 and "held-out windows" in gain.metric
    (sentence,) = gain_sentences(gain)
    assert sentence.startswith("one speed only") and "not over speeds" in sentence
    assert gain_json(gain)["held_out_by"] == "window"
    several = held_out_gain(bicycle, _observations(bicycle.with_extensions(steer_damping=0.6), 5), causes)
    assert several.held_out_by == "speed" and gain_sentences(several)[0].startswith("overall on 5 held-out speeds")


def test_held_out_gain_reports_where_the_model_does_not_help():
    # Effect only at the two highest speeds (observations there from a damped bicycle): the
    # model extended on the other speeds cannot predict it, and the gain says so per speed.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "speed_scale")]
    plain = _observations(bicycle, 3)
    damped = _observations(with_cause(bicycle, causes[0], [0.6]), 3)
    mixed = [d if o.speed > 6.0 else o for o, d in zip(plain, damped, strict=True)]
    gain = held_out_gain(bicycle, mixed, causes)
    assert {round(s.speed, 1) for s in gain.not_helped()} >= {3.5, 4.5, 5.5}


def test_held_out_folds_on_a_local_dask_cluster_give_the_serial_gain():
    # Each fold is a whole diagnosis of the other speeds; run on worker processes (the causes
    # travel by cloudpickle, closures included) they must give exactly the serial figures.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "payload", "parameter:IFyy")]
    observations = _observations(bicycle.with_extensions(steer_damping=0.6), 4)
    serial = held_out_gain(bicycle, observations, causes)
    parallel = held_out_gain(bicycle, observations, causes, workers=2)
    assert parallel == serial
    assert len(serial.speeds) == 5 and serial.speeds[0].cause == "steer_damping"


def test_every_candidates_gain_is_its_own_refit_on_each_fold():
    # No choice is made: each candidate's figures are exactly those of refitting it alone on
    # every fold, and the hidden cause predicts the held-out speeds best.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("speed_scale", "steer_damping", "parameter:IFyy")]
    observations = _observations(bicycle.with_extensions(steer_damping=0.6), 5)
    gains = cause_gains(bicycle, observations, causes)
    assert [g.cause for g in gains] == [c.name for c in causes]
    for cause, result in zip(causes, gains, strict=True):
        assert result.gain == held_out_gain(bicycle, observations, fixed=cause)
        assert not result.gain.reselected and result.at_bound == 0
    best = min(gains, key=lambda g: g.gain.extended_rms)
    assert best.cause == "steer_damping" and best.gain.cut > 0.5


def test_values_at_a_bound_other_than_no_effect_are_counted():
    # A steer damping bounded below the truth sits at its upper bound in every fold; fitted to
    # an undamped bicycle it sits at 0, its no-effect value, which is no stand-in.
    bicycle = load_bicycle("benchmark")
    damping = cause_by_name(bicycle, "steer_damping")
    narrow = replace(damping, bounds=((0.0, 0.3),))
    damped = _observations(bicycle.with_extensions(steer_damping=0.6), 6, std=0.0)
    plain = _observations(bicycle, 6, std=0.0)
    assert cause_gains(bicycle, damped, [narrow])[0].at_bound == 5
    assert cause_gains(bicycle, plain, [damping])[0].at_bound == 0


def test_a_choice_by_prediction_never_sees_the_held_out_speed():
    # The nested choice (each candidate's refits predicting the fold's own training speeds)
    # sees only the other speeds, like the choice by evidence.
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "speed_scale")]
    observations = _observations(bicycle.with_extensions(steer_damping=0.6), 7)
    held = speed_groups(observations)[0]
    spoiled = [replace(o, eigenvalue=o.eigenvalue - 2.0j) if i in held else o for i, o in enumerate(observations)]
    honest, leaked = (held_out_gain(bicycle, obs, causes, choose="prediction") for obs in (observations, spoiled))
    assert all(s.cause == "steer_damping" and s.verdict == "chosen by prediction" for s in honest.speeds)
    assert honest.speeds[0].values == leaked.speeds[0].values
    assert honest.cut > 0.5


def test_pairs_of_candidates_are_every_two_names_in_their_most_general_form():
    bicycle = load_bicycle("benchmark")
    causes = [cause_by_name(bicycle, name) for name in ("steer_damping", "speed_scale")]
    forms = general_forms([*causes, *payload_causes(bicycle, "payload", rigid=True)])
    assert [c.name for c in forms] == ["steer_damping", "speed_scale", "payload"]
    assert len(forms[-1].parameters) == 5  # a rigid load at any position
    # Pairs take the point mass at any position: a rigid load's own inertia would trade against
    # the second cause's.
    pairs = cause_pairs([*causes, *payload_causes(bicycle, "payload", rigid=True)])
    assert [p.name for p in pairs] == ["steer_damping + speed_scale", "steer_damping + payload",
                                       "speed_scale + payload"]
    assert len(pairs[-1].parameters) == 4



def test_the_pair_screen_ranks_pairs_by_the_evidence_not_by_their_freedom():
    # A geared motor's reflected inertia with steer damping on the seed's bicycle: a rear
    # payload with a fitted position (three values) stands in for them. Ranked by the linearised
    # misfit alone, pairs of payloads (six values) led the screen and the true pair of two
    # one-value causes was never fitted: the payload was named (this test failed so). Ranked
    # by the evidence's own measure, the true pair is fitted and leads.
    bicycle = load_bicycle("kooijman2008")
    forms = {cause.name: cause for cause in general_forms(candidate_causes(bicycle), refinements=False)}
    pair = combined_cause(forms["reflected_steer_inertia"], forms["steer_damping"])
    diagnosis = diagnose_observations(bicycle, _observations(pair.apply(bicycle, [0.25, 1.0]), 2))
    assert diagnosis.verdict == "ambiguous"
    assert set(components(diagnosis.cause)) == {"reflected_steer_inertia", "steer_damping"}


def _fit(cause: str, evidence: float) -> CauseFit:
    return CauseFit(cause, (), (), (), (), 0.0, evidence=evidence)


def test_two_other_causes_ahead_of_the_best_single_one_make_it_ambiguous():
    # A pair ahead of the best single cause by less than the margin is not kept as the leader
    # (it is not clearly better), but unless it holds that cause, it is a rival: two effects
    # together would explain the windows as well (the wrong names among the hidden-effect
    # trials with two effects, docs/diagnosis.md).
    scored = [_fit("front_payload + tyre_compliance", 101.0), _fit("parameter:IFyy + reflected_steer_inertia", 100.7),
              _fit("front_payload", 100.0), _fit("payload + parameter:xH", 99.0), _fit("speed_scale", 90.0)]
    kept, rivals = evidence._clearly_better_pairs(scored, VerdictRules().margin)
    assert [fit.cause for fit in kept] == ["front_payload", "speed_scale"]
    # The pair holding the best adds a second cause to it; a pair behind the best is no rival
    # (among many pairs tried, one comes close by chance).
    assert [fit.cause for fit in rivals] == ["parameter:IFyy + reflected_steer_inertia"]
    verdict, name, contenders, reasons = evidence._verdict(kept, (1.0, 1.0), VerdictRules(), rivals)
    assert (verdict, name) == ("ambiguous", "front_payload")
    assert contenders == ("parameter:IFyy + reflected_steer_inertia",)
    assert "two causes together" in reasons[0] and "more evidence than front_payload" in reasons[0]
    # Without the rival pair the same ranking names the single cause.
    assert evidence._verdict(kept, (1.0, 1.0), VerdictRules())[0] == "named"
