"""The values a fit leaves open: the family along the least-determined direction.

Synthetic observations are the model's own weave eigenvalues and mode shapes (derived
equations) of a bicycle with a known point load, plus Gaussian noise of the stated covariance.
"""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
from synthetic_windows import synthetic_observations

from whipple.diagnosis.causes import payload_form
from whipple.diagnosis.fitting import fit_cause
from whipple.diagnosis.identifiability import FAMILY_SIGMAS, open_values
from whipple.diagnosis.registry import cause_by_name
from whipple.model.parameters import Payload, load_bicycle

SPEEDS = np.repeat([3.5, 4.5, 5.5, 6.5, 7.5], 4)


def _distance_to_line(point, low, high, span):
    """Distance of point from the line through low and high, and where along it (0 at low, 1 at high)."""
    p, a, b = (np.asarray(v, dtype=float) / span for v in (point, low, high))
    direction = b - a
    t = float(np.dot(p - a, direction) / np.dot(direction, direction))
    return float(np.linalg.norm(p - (a + t * direction))), t


def test_a_load_whose_mass_and_position_trade_off_is_reported_as_a_family_holding_the_truth():
    # A 1.5 kg load on the front frame ahead of and above the front axle, seen through weave
    # eigenvalues alone (20 windows at 3.5-7.5 m/s): mass and position trade against each
    # other (the mass's std near 20%), so the family is reported; in every seed the true load
    # lies on it, within the noise of the determined combinations.
    bicycle = load_bicycle("benchmark")
    truth = (1.5, bicycle.parameters["w"] + 0.1, -bicycle.parameters["rF"] - 0.35)
    cause = payload_form(bicycle, "front_payload", "mxz")
    lower, upper = cause.limits
    span = upper - lower
    for seed in range(5):
        observed = [replace(o, shape=None, shape_covariance=None) for o in synthetic_observations(
            bicycle.with_extensions(front_payload=Payload(*truth)), seed, SPEEDS)]
        family = open_values(cause, fit_cause(bicycle, cause, observed))
        assert family is not None and family.parameters == cause.parameters
        distance, along = _distance_to_line(truth, family.low, family.high, span)
        # Off the line by at most 3 std of the next direction (``determined`` is 2 std), and
        # between its ends.
        assert distance < 1.5 * family.determined
        assert 0.0 <= along <= 1.0
        # The open direction reaches far wider than the determined ones.
        reach = np.max(np.abs(np.subtract(family.high, family.low)) / span) / 2.0
        assert reach > 3.0 * family.determined
    # As the report gives it: one sentence, and plain JSON data.
    assert f"front_payload_mass {family.low[0]:.4g} kg" in family.sentence()
    assert json.loads(json.dumps(family.to_dict()))["high"] == list(family.high)


def test_a_single_value_or_a_determined_fit_leaves_nothing_open():
    bicycle = load_bicycle("benchmark")
    observed = synthetic_observations(bicycle.with_extensions(steer_damping=0.5), 0, SPEEDS)
    damping = cause_by_name(bicycle, "steer_damping")
    assert open_values(damping, fit_cause(bicycle, damping, observed)) is None
    load = payload_form(bicycle, "front_payload", "mxz")
    fit = fit_cause(bicycle, load, observed)
    tiny = replace(fit, covariance=np.eye(3) * 1e-12, std=(1e-6, 1e-6, 1e-6))
    assert open_values(load, tiny) is None
    assert open_values(load, replace(fit, std=(np.nan, 1.0, 1.0))) is None  # a failed spread: nothing to say


def test_the_family_stops_at_the_bounds_and_stays_on_its_line():
    bicycle = load_bicycle("benchmark")
    load = payload_form(bicycle, "front_payload", "mxz")
    lower, upper = load.limits
    fitted = np.array([0.5, 0.5 * (lower[1] + upper[1]), -0.6])
    # Mass and height strongly correlated, the mass's std wide enough to reach 0 kg.
    covariance = np.array([[4.0, 0.0, -0.19], [0.0, 1e-6, 0.0], [-0.19, 0.0, 0.01]])
    fit = replace(fit_cause(bicycle, load, synthetic_observations(bicycle, 0, SPEEDS[:8])),
                  values=tuple(fitted), std=tuple(np.sqrt(np.diag(covariance))), covariance=covariance)
    family = open_values(load, fit)
    assert family is not None
    assert np.all(np.array(family.low) >= lower - 1e-12) and np.all(np.array(family.high) <= upper + 1e-12)
    assert abs(min(family.low[0], family.high[0])) < 1e-12  # stopped at 0 kg, 1.75 std from the fit
    ends = np.array([family.low, family.high]) - fitted
    # Both ends on one line through the fitted values, the stopped end no farther than 2 std.
    assert abs(ends[0, 0] * ends[1, 2] - ends[0, 2] * ends[1, 0]) < 1e-9
    assert np.max(np.abs(ends[:, 0])) <= FAMILY_SIGMAS * 2.0 + 1e-9


def test_a_family_blocked_both_ways_at_the_bounds_holds_those_values_there():
    bicycle = load_bicycle("benchmark")
    load = payload_form(bicycle, "front_payload", "mxz")
    lower, upper = load.limits
    span = upper - lower
    # Mass at its upper bound and height at its lower bound, strongly correlated so that their
    # least-determined direction takes one of them past its bound either way; the fore-aft
    # position is free, loosely determined and correlated with the mass.
    fitted = np.array([upper[0], 0.5 * (lower[1] + upper[1]), lower[2]])
    std = np.array([0.5, 0.1, 0.3]) * span
    correlation = np.array([[1.0, 0.3, 0.99], [0.3, 1.0, 0.2], [0.99, 0.2, 1.0]])
    covariance = correlation * np.outer(std, std)
    fit = replace(fit_cause(bicycle, load, synthetic_observations(bicycle, 0, SPEEDS[:8])),
                  values=tuple(fitted), std=tuple(std), covariance=covariance)
    family = open_values(load, fit)
    assert family is not None
    assert family.held == (family.parameters[0], family.parameters[2])
    low, high = np.array(family.low), np.array(family.high)
    assert low[0] == high[0] == fitted[0] and low[2] == high[2] == fitted[2]
    # The position moves by its spread given the held values: 2 std of the conditional variance.
    held = [0, 2]
    conditional = covariance[1, 1] - covariance[1, held] @ np.linalg.solve(
        covariance[np.ix_(held, held)], covariance[held, 1])
    assert np.isclose(abs(high[1] - low[1]), 2 * FAMILY_SIGMAS * np.sqrt(conditional))
    assert "held at their bounds" in family.sentence()
    assert json.loads(json.dumps(family.to_dict()))["held_at_bounds"] == list(family.held)
