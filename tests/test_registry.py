"""The cause registry: each candidate cause declared in one place, a new one in one declaration.

The worked example of docs/adding-a-cause.md, a roll damping expressed through the model term
``D_roll_roll``, is declared here as the how-to declares it and found by a hidden-effect trial
that hides a roll damping; without the declaration the same trial names no cause (the truth is
none of the package's candidates).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from hidden_effects import run_trial

from whipple.diagnosis.families import describe_cause, describe_family, family_table
from whipple.diagnosis.model_terms import term_causes
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import (
    FAMILIES,
    REGISTRY,
    CauseDeclaration,
    Value,
    add_terms,
    candidate_causes,
    declare,
)
from whipple.model.parameters import load_bicycle

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs" / "examples"))
from roll_damping import roll_damping as ROLL_DAMPING  # noqa: E402  (the how-to's declaration)


def _roll_damping(bicycle, values):
    return add_terms(bicycle, D_roll_roll=values[0])


def test_every_package_cause_has_a_family_with_words():
    bicycle = load_bicycle("sbw2024")
    names = {cause.name for cause in candidate_causes(bicycle)}
    for declaration in REGISTRY:
        assert declaration.family_objects and all(family.words for family in declaration.family_objects)
    for name in names:
        assert describe_cause(name) != name, f"{name} has no words of its own"
    assert {family.key for family in FAMILIES} == {row.key for row in family_table()}


def test_a_cause_without_a_family_or_declared_twice_is_refused():
    with pytest.raises(ValueError, match="names no family"):
        declare("wobble", Value("w", "", (0.0, 1.0)), _roll_damping, families=())
    with pytest.raises(ValueError, match="unknown family"):
        declare("wobble", Value("w", "", (0.0, 1.0)), _roll_damping, families=("nonsense",))
    with pytest.raises(ValueError, match="unknown model term"):
        declare("wobble", Value("w", "", (0.0, 1.0)), _roll_damping, families=("tyre",), terms=("X_roll",))
    with pytest.raises(ValueError, match="declared twice"):
        candidate_causes(load_bicycle("benchmark"), extra=[ROLL_DAMPING, ROLL_DAMPING])
    with pytest.raises(ValueError, match="declared twice"):
        candidate_causes(load_bicycle("benchmark"),
                         extra=[declare("steer_damping", Value("c", "", (0.0, 1.0)), _roll_damping,
                                        families=("tyre",))])


def test_one_declaration_adds_a_candidate_with_its_family_and_takes_its_term_out():
    bicycle = load_bicycle("benchmark")
    options = DiagnosisOptions(causes=(ROLL_DAMPING,))
    names = [cause.name for cause in options.candidates(bicycle)]
    assert "roll_damping" in names and "term:D_roll_roll" not in names
    assert "term:D_roll_roll" in [cause.name for cause in term_causes(bicycle)]
    assert describe_cause("roll_damping", (ROLL_DAMPING,)).startswith("a roll torque resisting")
    assert describe_family(["roll_damping"], (ROLL_DAMPING,)).endswith(": roll_damping")
    changed = next(c for c in options.candidates(bicycle) if c.name == "roll_damping").apply(bicycle, [7.0])
    assert changed.extensions.linear_terms.as_dict() == {"D_roll_roll": 7.0}
    assert isinstance(ROLL_DAMPING, CauseDeclaration) and options.to_dict()["causes"] == ["roll_damping"]


def test_the_howto_example_is_found_by_a_hidden_effect_trial():
    declared = run_trial("roll_damping", 0, "benchmark", options=DiagnosisOptions(causes=(ROLL_DAMPING,)))
    assert (declared.diagnosis.verdict, declared.diagnosis.cause) == ("named", "roll_damping")
    value, std = declared.diagnosis.best.values[0], declared.diagnosis.best.std[0]
    assert abs(value - declared.truth["roll_damping"]) < 3 * std
    undeclared = run_trial("roll_damping", 0, "benchmark")
    assert undeclared.diagnosis.verdict != "named"
