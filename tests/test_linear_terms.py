"""Terms added to the linear equations: where they enter, and the same model by every path.

A term must change exactly its entry of its matrix, and act in the first-order model (with or
without tyre states) and in the CasADi expressions exactly as the same torque given as a
speed-polynomial state feedback does (an independent path: the controller's).
"""

from __future__ import annotations

import numpy as np
import pytest

from whipple.errors import InputError
from whipple.model.assembly import linear_model, model_matrices
from whipple.model.casadi_model import casadi_state_function
from whipple.model.linear_terms import TERM_NAMES, LinearTerms
from whipple.model.parameters import Controller, TyreCompliance, load_bicycle, read_bicycle_toml, write_bicycle_toml
from whipple.simulation.nonlinear_bicycle import nonlinear_parameters

TERMS = {"K0_steer_steer": 1.5, "D_roll_roll": 3.0, "C1_roll_steer": 0.7, "K2_steer_roll": 0.2}
# The same torques as feedback f = -(added terms) x: roll torque -3 roll_rate - 0.7 v steer_rate,
# steer torque -1.5 steer - 0.2 v^2 roll.
SAME_FEEDBACK = Controller(roll={"roll_rate": (-3.0,), "steer_rate": (0.0, -0.7)},
                           steer={"steer": (-1.5,), "roll": (0.0, 0.0, -0.2)})


def _with_terms(bicycle):
    return bicycle.with_extensions(linear_terms=LinearTerms.from_mapping(TERMS))


def test_each_term_changes_its_own_entry_alone():
    bicycle = load_bicycle("benchmark")
    for name in TERM_NAMES:
        changed = bicycle.with_extensions(linear_terms=LinearTerms.from_mapping({name: 2.5}))
        before, after = model_matrices(bicycle.parameters), model_matrices(changed.parameters, changed.extensions)
        matrix, row, column = name.split("_")
        for other in ("M", "C1", "D", "K0", "K2"):
            expected = np.zeros((2, 2))
            if other == matrix:
                expected[("roll", "steer").index(row), ("roll", "steer").index(column)] = 2.5
            np.testing.assert_allclose(getattr(after, other) - getattr(before, other), expected, atol=1e-12)


@pytest.mark.parametrize("tyres", [None, TyreCompliance(12.0, 0.57, 0.15)])
def test_terms_act_as_the_same_torques_given_as_feedback(tyres):
    bicycle = load_bicycle("benchmark").with_extensions(tyre_compliance=tyres)
    speeds = np.array([1.0, 4.0, 7.5])
    by_terms = linear_model(_with_terms(bicycle)).state_matrix(speeds)
    by_feedback = linear_model(bicycle.with_controller(SAME_FEEDBACK)).state_matrix(speeds)
    np.testing.assert_allclose(by_terms, by_feedback, atol=1e-9)
    function, p0 = casadi_state_function(_with_terms(bicycle))
    for k, speed in enumerate(speeds):
        np.testing.assert_allclose(np.asarray(function(speed, p0)), by_terms[k], atol=1e-9)


def test_terms_stay_in_the_plant_under_a_lagging_controller():
    # A lag acts on the controller's torque only; the terms are passive torques of the plant.
    controlled = load_bicycle("benchmark").with_controller(Controller(steer={"roll_rate": (10.0,)}, lag=0.05))
    with_terms = _with_terms(controlled)
    plant_terms = _with_terms(load_bicycle("benchmark"))
    speed = 5.0
    a = linear_model(with_terms).state_matrix(speed)
    # The plant's rows (roll, steer accelerations) without the actuator state equal those of
    # the plant with terms; the actuator column comes on top.
    np.testing.assert_allclose(a[:4, :4], linear_model(plant_terms).state_matrix(speed), atol=1e-9)
    function, p0 = casadi_state_function(with_terms)
    np.testing.assert_allclose(np.asarray(function(speed, p0)), a, atol=1e-9)


def test_a_bicycle_file_keeps_its_terms(tmp_path):
    bicycle = _with_terms(load_bicycle("benchmark"))
    path = tmp_path / "terms.toml"
    write_bicycle_toml(bicycle, path)
    assert "[extensions.linear_terms]" in path.read_text()
    assert read_bicycle_toml(path).extensions == bicycle.extensions


def test_unknown_terms_and_the_nonlinear_model_are_refused():
    with pytest.raises(ValueError, match="unknown linear term"):
        LinearTerms.from_mapping({"M_roll_roll": 1.0})
    with pytest.raises(InputError, match="linear_terms"):
        nonlinear_parameters(_with_terms(load_bicycle("benchmark")))
