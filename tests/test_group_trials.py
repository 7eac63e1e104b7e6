"""Experiments of two groups (one bicycle, two controller gains) with one hidden effect.

A mechanical effect shows in both groups and is named as such, the controller not blamed; a
controller's error in one group is blamed on that group's controller (tests/group_trials.py).
Rates over many seeds: benchmarks/bench_group_trials.py.
"""

from __future__ import annotations

import pytest
from group_trials import GROUPS, group_experiment, run_group_trial

from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import candidate_causes
from whipple.errors import InputError
from whipple.model.fleet import Fleet


def test_a_fleet_has_a_controller_cause_per_group_and_shares_the_rest():
    experiment, _, _ = group_experiment("steer_damping", 0)
    fleet = Fleet(tuple((group.name, group.bicycle) for group in experiment.groups))
    names = [cause.name for cause in candidate_causes(fleet)]
    assert {f"controller_gain[{group}]" for group in GROUPS} <= set(names) and "controller_gain" not in names
    damped = next(c for c in candidate_causes(fleet) if c.name == "steer_damping").apply(fleet, [0.5])
    assert all(member.extensions.steer_damping == 0.5 for _, member in damped.members)
    gain = next(c for c in candidate_causes(fleet) if c.name == f"controller_gain[{GROUPS[1]}]").apply(fleet, [0.7])
    assert gain.member(GROUPS[1]).controller.gain_scale == 0.7 and gain.member(GROUPS[0]).controller.gain_scale == 1.0


def test_groups_must_share_the_physical_bicycle():
    experiment, _, _ = group_experiment("steer_damping", 0)
    first, second = experiment.groups
    with pytest.raises(InputError, match="share the bicycle's physical parameters"):
        Fleet(((first.name, first.bicycle), (second.name, second.bicycle.with_parameters(mB=30.0))))
    with pytest.raises(InputError, match="given twice"):
        Fleet(((first.name, first.bicycle), (first.name, second.bicycle)))


@pytest.mark.slow
@pytest.mark.parametrize("family", ["steer_damping", "payload"])
def test_a_mechanical_effect_is_named_and_no_controller_blamed(family):
    trial = run_group_trial(family, 0, options=DiagnosisOptions())
    assert trial.outcome == "right", (trial.diagnosis.verdict, trial.diagnosis.cause)
    assert not trial.blamed_controller


@pytest.mark.slow
@pytest.mark.parametrize("family", ["controller_gain", "controller_lag"])
def test_a_controller_error_in_one_group_is_blamed_on_that_group(family):
    trial = run_group_trial(family, 0)
    assert (trial.diagnosis.verdict, trial.diagnosis.cause) == ("named", f"{family}[{GROUPS[1]}]")
