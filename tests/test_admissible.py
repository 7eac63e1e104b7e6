"""Only physically consistent models are offered: no value at a bound, none degenerate, a physical
bicycle, and a weave that decays wherever the measured weave clearly decays."""

from __future__ import annotations

from synthetic_windows import synthetic_observations

from whipple.diagnosis.admissible import inconsistencies, offered_model
from whipple.diagnosis.causes import payload_form
from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.registry import cause_by_name
from whipple.model.parameters import load_bicycle

BICYCLE = load_bicycle("benchmark")
#: Windows of the benchmark itself at 5-7 m/s, where its weave decays.
WINDOWS = synthetic_observations(BICYCLE, 0, [5.0, 5.5, 6.0, 6.5, 7.0])


def _fit(cause, values, evidence=10.0):
    return CauseFit(cause.name, cause.parameters, cause.units, tuple(values), (0.0,) * len(values), 0.0, evidence)


def test_a_plain_fit_inside_its_range_is_consistent():
    cause = cause_by_name(BICYCLE, "steer_damping")
    assert inconsistencies(BICYCLE, cause, _fit(cause, [0.5]), WINDOWS) == ()


def test_a_value_at_its_bound_and_a_massless_load_with_a_place_are_not():
    load = payload_form(BICYCLE, "payload", "mxz")
    low, high = load.bounds[0]
    at_bound = inconsistencies(BICYCLE, load, _fit(load, [high, 0.3, -0.9]), WINDOWS)
    assert any("payload_mass at the edge of its physical range" in text for text in at_bound)
    nothing = inconsistencies(BICYCLE, load, _fit(load, [low, 0.3, -0.9]), WINDOWS)
    assert any("payload_mass is nothing" in text and "x and z were fitted" in text for text in nothing)


def test_a_weave_that_grows_where_the_measured_weave_decays_is_not_offered():
    # Speeds read 1.5 times too high: the true speeds, 3.3-4.7 m/s, lie below the weave speed (4.3 m/s).
    damping = cause_by_name(BICYCLE, "steer_damping")
    fast = cause_by_name(BICYCLE, "speed_scale")
    grows = inconsistencies(BICYCLE, fast, _fit(fast, [1.5]), WINDOWS)
    assert any("grows where the measured weave decays" in text for text in grows)
    offer = offered_model(BICYCLE, [_fit(fast, [1.5], 30.0), _fit(damping, [0.4], 20.0)],
                          [fast, damping], WINDOWS, threshold=3.0)
    assert offer.fit is not None and offer.fit.cause == "steer_damping"
    assert offer.rejected[0][0] == "speed_scale"
    assert offer.sentences()[-1] == "offered instead: steer_damping"


def test_no_consistent_candidate_offers_the_base_model():
    fast = cause_by_name(BICYCLE, "speed_scale")
    offer = offered_model(BICYCLE, [_fit(fast, [1.5], 30.0)], [fast], WINDOWS, threshold=3.0)
    assert offer.cause is None and "the base model is offered" in offer.sentences()[-1]
