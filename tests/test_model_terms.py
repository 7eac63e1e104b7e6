"""Model terms as candidates: a truth outside the physical causes is reported as its form.

Synthetic observations are the model's own weave eigenvalues and mode shapes plus noise
(tests/synthetic_windows.py). The true effects are given as state feedback (the controller's
path), not as terms, so that the candidate and the truth are built independently.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from synthetic_windows import synthetic_observations

from whipple.cli import main
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.families import describe_cause
from whipple.diagnosis.model_terms import is_term, term_causes
from whipple.diagnosis.registry import claimed_terms
from whipple.model.linear_terms import TERM_NAMES
from whipple.model.parameters import Controller, load_bicycle
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run, write_run_csv

SPEEDS = np.repeat([3.0, 4.0, 5.0, 6.0, 7.0], 4)


def test_a_steer_spring_is_reported_as_its_form_and_not_named():
    bicycle = load_bicycle("benchmark")
    spring = 1.5  # N m/rad, a steering stabiliser
    truth = bicycle.with_controller(Controller(steer={"steer": (-spring,)}))
    diagnosis = diagnose_observations(bicycle, synthetic_observations(truth, 0, SPEEDS))
    assert diagnosis.verdict == "ambiguous"
    assert diagnosis.cause == "term:K0_steer_steer"
    assert abs(diagnosis.best.values[0] - spring) < 3.0 * diagnosis.best.std[0]
    assert any("steer spring" in reason and "none of the physical" in reason for reason in diagnosis.reasons)


def test_a_physical_cause_is_still_named_with_the_terms_competing():
    # Steer damping is D[steer, steer]: that term is the candidate itself, not a rival.
    bicycle = load_bicycle("benchmark")
    diagnosis = diagnose_observations(bicycle, synthetic_observations(
        bicycle.with_extensions(steer_damping=0.8), 0, SPEEDS))
    assert (diagnosis.verdict, diagnosis.cause) == ("named", "steer_damping")


def test_the_terms_share_one_prior_have_symmetric_bounds_and_words():
    bicycle = load_bicycle("kooijman2008")
    causes = term_causes(bicycle)
    assert {cause.name.removeprefix("term:") for cause in causes} == set(TERM_NAMES) - set(claimed_terms())
    assert np.isclose(sum(cause.prior for cause in causes), 1.0)
    for cause in causes:
        (low, high), = cause.bounds
        assert is_term(cause.name) and high > 0 and low == -high and np.isfinite(high)
        assert cause.apply(bicycle, [0.0]).extensions.linear_terms.entries == ()
        assert describe_cause(cause.name) != cause.name


def test_entries_without_a_scale_offer_no_term():
    # A bicycle file with every mass zero (accepted, with warnings) has no stiffness: the terms
    # of those entries had bounds and a prior scale of 0, and whipple diagnose ended in a
    # traceback ("a prior needs a finite centre and a positive scale, got 0.0, 0.0").
    massless = load_bicycle("benchmark").with_parameters(mR=0.0, mB=0.0, mH=0.0, mF=0.0)
    causes = term_causes(massless, priors=True)
    assert 0 < len(causes) < len(TERM_NAMES)
    assert np.isclose(sum(cause.prior for cause in causes), 1.0)
    assert all(cause.bounds[0][1] > 0 for cause in causes)


# Slow (a whole diagnosis by the command): run with `pytest -m slow`.
@pytest.mark.slow
def test_the_command_reports_the_form_and_saves_it(tmp_path, capsys):
    # Simulated runs of the benchmark with a steer spring (as state feedback), diagnosed blind.
    truth = load_bicycle("benchmark").with_controller(Controller(steer={"steer": (-1.5,)}))
    runs = [str(write_run_csv(simulate_run(truth, RunScenario(speed=speed, seed=20 + k), name=f"run{k}"),
                              tmp_path / f"run{k}.csv"))
            for k, speed in enumerate((3.0, 4.0, 5.0, 6.0, 7.0))]
    out, model = tmp_path / "d.json", tmp_path / "extended.toml"
    assert main(["diagnose", *runs, "--bicycle", "benchmark", "--json", str(out), "--save-model", str(model)]) == 0
    printed = capsys.readouterr().out
    assert "verdict: ambiguous (term:K0_steer_steer)" in printed and "form of a steer spring" in printed
    data = json.loads(out.read_text())
    assert data["verdict"] == "ambiguous" and data["cause"] == "term:K0_steer_steer"
    assert abs(data["estimate"]["K0_steer_steer"]["value"] - 1.5) < 0.3
    # The extended model carries the term, and every command accepts it.
    saved = load_bicycle(str(model)).extensions.linear_terms.as_dict()
    assert saved["K0_steer_steer"] == pytest.approx(data["estimate"]["K0_steer_steer"]["value"])
    assert main(["check", str(model)]) == 0
