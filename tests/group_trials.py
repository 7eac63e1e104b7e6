"""Trials of experiments of two groups: one bicycle under two controller gains, an effect hidden.

An experiment that measures one bicycle under two controllers separates a controller's error
from a mechanical one: a mechanical effect shows in both groups, a controller's error in its
group only. A trial draws a hidden effect as :func:`hidden_effects.hidden_bicycle` does and
puts it

- for a mechanical family (steer damping, a payload, a wrong parameter, ...): into the shared
  bicycle of both groups;
- for a controller family (``controller_gain``, ``controller_delay``, ``controller_lag``): into
  the controller of the second group only;

then simulates each group's runs at the controlled bicycles' speeds and diagnoses both groups as
one experiment (:func:`whipple.diagnose` with an experiment). The right answer is the mechanical
cause, or the second group's controller cause (``controller_gain[<group>]``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from hidden_effects import (
    CONTROLLED_SPEEDS,
    CONTROLLER,
    PUSHES,
    cause_of_truth,
    hidden_bicycle,
    trial_bicycle,
    trial_diagnosis_options,
    trial_rng,
)

from whipple.diagnosis.evidence import Diagnosis
from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.pipeline import diagnose
from whipple.measurement.runs import Run, run_from_simulation
from whipple.model.parameters import Bicycle, Controller
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

#: The two groups: the controlled bicycle's own controller, and its roll-rate gains halved.
GROUPS = ("full", "half")
#: Mechanical families tried in two-group experiments.
MECHANICAL = ("steer_damping", "steer_inertia", "payload", "speed_scale", "parameter", "basket")


@dataclass
class Group:
    """One group of an experiment (what :func:`whipple.diagnose` takes)."""

    name: str
    bicycle: Bicycle
    runs: list[Run]
    layout: None = None
    windows: None = None


@dataclass
class Experiment:
    """Groups of one bicycle under different controllers."""

    groups: list[Group]
    name: str = "two gains"


@dataclass(frozen=True)
class GroupTrial:
    """A trial of two groups: the family, the true values, the expected cause, the diagnosis."""

    family: str
    seed: int
    bicycle: str
    truth: dict[str, float]
    expected: str
    diagnosis: Diagnosis = field(repr=False)

    @property
    def outcome(self) -> str:
        """``right`` (named the expected cause), ``ambiguous_truth``, ``ambiguous``, ``none`` or ``wrong``."""
        verdict, cause = self.diagnosis.verdict, self.diagnosis.cause
        if verdict == "named":
            return "right" if cause == self.expected else "wrong"
        if verdict == "ambiguous":
            contenders = {part for name in (cause, *self.diagnosis.rivals) for part in name.split(" + ")}
            return "ambiguous_truth" if self.expected in contenders else "ambiguous"
        return "none"

    @property
    def blamed_controller(self) -> bool:
        """Whether a controller cause was named for a mechanical effect."""
        return (self.family not in CONTROLLER and self.diagnosis.verdict == "named"
                and self.diagnosis.cause.startswith("controller_"))


def halved(controller: Controller) -> Controller:
    """The controller with its roll-rate gains halved (a second experiment's gain)."""
    steer = dict(controller.steer)
    steer["roll_rate"] = tuple(0.5 * value for value in steer["roll_rate"])
    return replace(controller, steer=steer)


def group_experiment(family: str, seed: int, base_name: str = "sbw2024", scale: float = 1.0
                     ) -> tuple[Experiment, dict[str, float], str]:
    """Return the experiment of a trial, the hidden effect's true values and the cause a right diagnosis names."""
    rng = trial_rng(family, seed)
    base = trial_bicycle(base_name)
    members = {GROUPS[0]: base, GROUPS[1]: base.with_controller(halved(base.controller))}
    if family in CONTROLLER:
        truth_bicycle, truth, _ = hidden_bicycle(members[GROUPS[1]], family, rng, scale)
        truths = {GROUPS[0]: members[GROUPS[0]], GROUPS[1]: truth_bicycle}
        expected = f"{family}[{GROUPS[1]}]"
    else:
        changed, truth, model = hidden_bicycle(base, family, rng, scale)
        if model is not None:
            raise ValueError(f"{family}: an effect outside the bicycle's model cannot be shared by two controllers")
        # The same physical change under each group's controller.
        truths = {name: changed.with_controller(member.controller) for name, member in members.items()}
        expected = cause_of_truth(next(iter(truth))) or "none"
    groups = []
    for g, name in enumerate(GROUPS):
        runs = []
        for k, speed in enumerate(CONTROLLED_SPEEDS):
            scenario = RunScenario(speed=speed, seed=int(rng.integers(1 << 31)) + 100 * g + k, n_pushes=PUSHES)
            runs.append(run_from_simulation(simulate_run(truths[name], scenario, name=f"{name}{k}")))
        groups.append(Group(name, members[name], runs))
    return Experiment(groups), truth, expected


def run_group_trial(family: str, seed: int, base_name: str = "sbw2024", scale: float = 1.0,
                    options: DiagnosisOptions | None = None) -> GroupTrial:
    """Simulate a two-group experiment with a hidden effect and diagnose it blind."""
    experiment, truth, expected = group_experiment(family, seed, base_name, scale)
    report = diagnose(experiment, options=trial_diagnosis_options(experiment.groups[0].bicycle, options))
    return GroupTrial(family, seed, base_name, truth, expected, report.diagnosis)


__all__ = ["GROUPS", "MECHANICAL", "Experiment", "Group", "GroupTrial", "group_experiment", "halved",
           "run_group_trial"]
