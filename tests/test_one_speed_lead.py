"""A cause is not named when its lead over a rival rests on the windows of one speed.

The evidence sums over windows. Where one speed's windows carry most of a lead (one window's
defect, or the one speed at which a flexible cause can bend towards an error no candidate has),
the data as a whole do not single out the leader: the verdict is ``ambiguous`` with that rival.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_speed_dependence import _observations

from whipple.diagnosis.consistency import lead_of_one_speed
from whipple.diagnosis.evidence import diagnose_observations
from whipple.diagnosis.fitting import ROBUST_SCALE, CauseFit, robust_squares, window_whitening
from whipple.diagnosis.observations import speed_groups
from whipple.diagnosis.options import DiagnosisOptions, VerdictRules


def _fit(name: str, residuals: np.ndarray, evidence: float) -> CauseFit:
    return CauseFit(name, ("x",), ("",), (0.0,), (1.0,), float(np.sum(robust_squares(residuals))),
                    evidence=evidence, residuals=residuals)


def test_a_lead_one_speed_carries_is_found_and_an_even_one_is_not():
    bicycle, observations = _observations(lambda v: 0.8)
    whitening = window_whitening(observations, bicycle)
    windows, _ = whitening.residual_layout()
    first_speed = np.isin(windows, speed_groups(observations)[0])
    best = np.full(windows.size, 0.5)
    # Two rivals trail the best by as much: one by misfitting the first speed's windows
    # only, the other by misfitting every window a little.
    carried = np.where(first_speed, 2.0, 0.5)
    # The same sum of robust squares, evenly over the windows (the soft-L1 loss inverted).
    share = np.mean(robust_squares(carried))
    spread = np.full(windows.size, ROBUST_SCALE * np.sqrt((share / (2 * ROBUST_SCALE**2) + 1) ** 2 - 1))
    leader = _fit("leader", best, 50.0)
    scored = [leader] + [_fit(name, residuals, 50.0 - (_fit("", residuals, 0.0).chi2 - leader.chi2) / 2)
                         for name, residuals in (("spread", spread), ("carried", carried))]
    assert scored[1].evidence == pytest.approx(scored[2].evidence, rel=1e-9)
    found = lead_of_one_speed(scored, whitening, observations, VerdictRules().one_speed_lead)
    assert found is not None
    rivals, reason = found
    assert rivals == ("carried",)
    assert "3.00 m/s" in reason


def test_a_true_cause_that_leads_at_every_speed_is_still_named_with_one_speed_off():
    """A steer damping of 0.8 N m s/rad, the windows at 3 m/s as if it were 1.6 there: still named."""
    bicycle, observations = _observations(lambda v: 1.6 if v == 3.0 else 0.8)
    diagnosis = diagnose_observations(bicycle, observations)
    assert (diagnosis.verdict, diagnosis.cause) == ("named", "steer_damping")


def test_the_check_can_be_switched_off():
    bicycle, observations = _observations(lambda v: 0.8)
    options = DiagnosisOptions(verdict=dataclasses.replace(VerdictRules(), one_speed_lead=0.0))
    assert diagnose_observations(bicycle, observations, options=options).verdict == "named"


@pytest.mark.slow
def test_a_front_payload_bending_towards_one_speed_is_not_named():
    """Twice the size of a steer spring (no candidate has it): a front payload led its own form by one window."""
    from hidden_effects import run_trial

    trial = run_trial("steer_spring", 1, "benchmark", scale=2.0)
    diagnosis = trial.diagnosis
    assert diagnosis.verdict != "named"
    assert "term:K0_steer_steer" in (diagnosis.cause, *diagnosis.rivals)
