"""A named cause must not depend on how a model's extra modal amplitudes are charged.

Compared with the samples, a tyre compliance (4 more states than the benchmark's model) pays
for 4 more modal amplitudes per window: ln(n_w)/2 each (the BIC's charge, the default) or 1/2
each (what an amplitude gains on noise alone). Where the two charges put different causes
first, the verdict is ``ambiguous`` (whipple.diagnosis.charge_sensitivity).
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from hidden_effects import run_trial

from whipple.diagnosis import evidence
from whipple.diagnosis.charge_sensitivity import charge_checked, other_charge
from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.options import DiagnosisOptions, VerdictRules
from whipple.diagnosis.samples import SampleComparison
from whipple.errors import InputError

#: Ten windows of 30 bins of 4 signals: the BIC charges ln(120)/2 = 2.4 per amplitude and window.
WINDOWS = SimpleNamespace(mask=np.ones((10, 30), dtype=bool), states=(0, 1, 2, 3))


class _Windows:
    """The windows' sizes, charged by SampleComparison's own rule (what _scored reads of the samples)."""

    mask, states = WINDOWS.mask, WINDOWS.states

    def amplitude_charge(self, extra_states: int, how: str = "bic") -> float:
        return SampleComparison.amplitude_charge(self, extra_states, how)  # type: ignore[arg-type]


def _fit(cause: str, chi2: float, values: int, states: int = 4) -> CauseFit:
    return CauseFit(cause, tuple(f"v{k}" for k in range(values)), ("",) * values, (0.0,) * values, (0.0,) * values,
                    chi2, states=states)


def _verdicts(tyre_chi2: float, how: str = "bic", rules: VerdictRules | None = None):
    """The verdict on a front load (4 states) against a tyre compliance (8 states), and the two scorings."""
    base = _fit("none", 1200.0, 0)
    fits = [_fit("front_payload", 1020.0, 5), _fit("tyre_compliance", tyre_chi2, 2, states=8)]
    causes = [SimpleNamespace(prior=1.0, value_priors=None)] * 2
    options = DiagnosisOptions(amplitude_charge=how)
    rules = rules or VerdictRules()

    def scored(charge: str) -> list[CauseFit]:
        ranked = evidence._scored(causes, base, fits, 40, _Windows(), replace(options, amplitude_charge=charge))
        return sorted(ranked, key=lambda fit: -fit.evidence)

    ranked, recharged = scored(how), scored(other_charge(how))
    return evidence._verdict(ranked, (1.0, 1.0), rules), ranked, recharged, rules


def test_the_other_charge_moves_the_evidence_by_the_difference_of_the_charges_for_the_extra_states():
    _, ranked, recharged, _ = _verdicts(951.0)
    moved = {fit.cause: fit.evidence for fit in recharged}
    bic, noise = (SampleComparison.amplitude_charge(_Windows(), 4, how)  # type: ignore[arg-type]
                  for how in ("bic", "noise"))
    assert bic == pytest.approx(4 * 0.5 * 10 * np.log(120)) and noise == pytest.approx(20.0)
    for fit in ranked:
        extra = bic - noise if fit.states == 8 else 0.0
        assert moved[fit.cause] == pytest.approx(fit.evidence + extra)


def test_a_rival_with_more_states_that_leads_under_the_noise_charge_leaves_the_name_open():
    # The BIC's charge of the tyre's 4 amplitudes in 10 windows (96) outweighs its better fit
    # (chi-square 951 against 1020): the front load leads; charged 1/2 each (20) the tyre leads.
    verdict, ranked, recharged, rules = _verdicts(951.0)
    assert verdict == ("named", "front_payload", (), ())
    checked = charge_checked(verdict, ranked, recharged, rules, "bic")
    assert checked[:3] == ("ambiguous", "front_payload", ("tyre_compliance",))
    reason = checked[3][0]
    assert "tyre_compliance fits the samples better (chi-square 951 against front_payload's 1020)" in reason
    assert "leads when its 4 extra modal amplitudes per window are charged as what they gain on noise" in reason
    assert "the data do not decide between them" in reason
    # False: the verdict of the options' charge alone.
    assert charge_checked(verdict, ranked, recharged, replace(rules, charge_sensitivity=False), "bic") == verdict


def test_a_rival_that_trails_under_either_charge_leaves_the_name():
    # A tyre fit barely better than the base model's (chi-square 1100) trails the front load
    # however its amplitudes are charged.
    verdict, ranked, recharged, rules = _verdicts(1100.0)
    assert verdict[0] == "named"
    assert charge_checked(verdict, ranked, recharged, rules, "bic") == verdict


def test_the_check_is_symmetric_when_the_options_charge_what_amplitudes_gain_on_noise():
    # Charged 1/2 each, the tyre leads and is named; charged as fitted values the front load
    # leads: the name depends on the choice all the same.
    verdict, ranked, recharged, rules = _verdicts(951.0, how="noise")
    assert verdict == ("named", "tyre_compliance", (), ())
    checked = charge_checked(verdict, ranked, recharged, rules, "noise")
    assert checked[:3] == ("ambiguous", "tyre_compliance", ("front_payload",))
    assert "when tyre_compliance's 4 extra modal amplitudes per window are charged as fitted values" in checked[3][0]


def test_none_stays_none_and_an_ambiguous_verdict_keeps_its_reasons():
    _, ranked, recharged, rules = _verdicts(951.0)
    strict = replace(rules, named_threshold=1e5)
    none = evidence._verdict(ranked, (1.0, 1.0), strict)
    assert none[0] == "none" and charge_checked(none, ranked, recharged, strict, "bic") == none
    wide = replace(rules, margin=100.0)
    open_verdict = evidence._verdict(ranked, (1.0, 1.0), wide)
    assert open_verdict[0] == "ambiguous"
    assert charge_checked(open_verdict, ranked, recharged, wide, "bic") == open_verdict


def test_an_ambiguous_verdict_gains_the_rival_the_other_charge_would_put_first():
    _, ranked, recharged, rules = _verdicts(951.0)
    # Ambiguous for another reason (no candidate explains the data), the tyre not among the rivals.
    open_verdict = evidence._verdict(ranked, (2 * rules.high_dispersion, 1.0), rules, samples=True)
    assert open_verdict[0] == "ambiguous" and "tyre_compliance" not in open_verdict[2]
    checked = charge_checked(open_verdict, ranked, recharged, rules, "bic")
    assert checked[:2] == open_verdict[:2]
    assert checked[2] == (*open_verdict[2], "tyre_compliance")
    assert checked[3][:-1] == open_verdict[3]
    assert checked[3][-1].startswith("tyre_compliance fits the samples better")


def test_charge_sensitivity_must_be_true_or_false():
    with pytest.raises(InputError, match="charge_sensitivity"):
        VerdictRules(charge_sensitivity="yes")  # type: ignore[arg-type]


# Slow: one trial on the ground (its runs simulated and every candidate fitted to the samples).
@pytest.mark.slow
def test_a_tyre_compliance_on_the_ground_is_not_named_a_front_load():
    """Benchmark, tyre compliance, seed 2, coasting on the ground: the tyre fits the samples best,
    a front load leads only by the BIC's charge of the tyre's extra amplitudes (named wrongly
    before the check). Now not a confident wrong name, the tyre among the rivals."""
    trial = run_trial("tyre_compliance", 2, "benchmark", conditions="ground")
    assert trial.outcome != "wrong"
    assert trial.diagnosis.verdict == "ambiguous" and "tyre_compliance" in trial.contenders
