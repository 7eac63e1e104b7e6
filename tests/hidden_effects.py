"""Hidden-effect trials: simulate runs of a "true" bicycle with one effect, diagnose blind.

Used by tests/test_hidden_effects.py (a fast subset) and benchmarks/bench_diagnosis.py (rates
over many seeds). Effect sizes are drawn at random per seed from realistic ranges (tyre values
from shared spec tyre-model.md; the others chosen as plausible hardware effects), large enough
to be identifiable; the diagnosis is never told the effect or its size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from whipple.diagnosis.causes import cause_by_name
from whipple.diagnosis.evidence import Diagnosis, diagnose_observations
from whipple.diagnosis.observations import observations
from whipple.measurement.experiment import measure_run
from whipple.measurement.runs import run_from_simulation
from whipple.model.parameters import Bicycle, Payload, TyreCompliance, load_bicycle
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run

#: Causes with a hidden-effect generator, and "none" (no effect).
CAUSES = ("none", "steer_damping", "steer_inertia", "speed_scale", "payload", "tyre_compliance", "parameter:c",
          "parameter:IBxx", "parameter:IFyy")
#: Speeds of the simulated runs [m/s] (several runs across 2-8 m/s).
SPEEDS = (2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0)
#: Pushes per run (the bundled treadmill logs hold 7 to 20 per file).
PUSHES = 3


@dataclass(frozen=True)
class Trial:
    cause: str
    seed: int
    truth: dict[str, float]
    diagnosis: Diagnosis

    @property
    def named_correctly(self) -> bool:
        return self.diagnosis.verdict == "named" and self.diagnosis.cause == self.cause

    @property
    def said_none(self) -> bool:
        return self.diagnosis.verdict == "none"

    def covers(self, sigmas: float = 2.0) -> bool:
        """The named cause's interval (value +/- sigmas std) covers every true value."""
        best = self.diagnosis.best
        if best is None or best.cause != self.cause:
            return False
        return all(abs(value - self.truth[name]) <= sigmas * std
                   for name, value, std in zip(best.parameters, best.values, best.std, strict=True)
                   if name in self.truth)


def hidden_bicycle(base: Bicycle, cause: str, rng: np.random.Generator) -> tuple[Bicycle, dict[str, float]]:
    """The true bicycle: ``base`` with one effect of a random realistic size."""
    if cause == "none":
        return base, {}
    if cause == "steer_damping":
        value = rng.uniform(0.4, 1.2)
        return base.with_extensions(steer_damping=value), {"steer_damping": value}
    if cause == "steer_inertia":
        value = rng.uniform(0.03, 0.08)
        return base.with_extensions(steer_inertia=value), {"steer_inertia": value}
    if cause == "speed_scale":
        value = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.10) + 1.0
        return base.with_extensions(speed_scale=value), {"speed_scale": value}
    if cause == "payload":
        mass = rng.uniform(10.0, 25.0)
        x, z = cause_payload_position(base, rng)
        # Only the mass is an estimate the diagnosis must cover (position: if identifiable).
        return base.with_extensions(payload=Payload(mass, x, z)), {"payload_mass": mass}
    if cause == "tyre_compliance":
        stiffness, relaxation = rng.uniform(8.0, 16.0), rng.uniform(0.1, 0.25)
        tyres = TyreCompliance(stiffness, 0.57, relaxation)
        return base.with_extensions(tyre_compliance=tyres), {"cornering_stiffness": stiffness,
                                                            "relaxation_length": relaxation}
    if cause.startswith("parameter:"):
        # Trail and the inertias are the parameters most often estimated rather than measured
        # (a 25-50% error is plausible); the same rule applies to any other key asked for.
        key = cause.split(":", 1)[1]
        value = base.parameters[key] * (1.0 + rng.choice([-1.0, 1.0]) * rng.uniform(0.25, 0.5))
        return base.with_parameters(**{key: value}), {key: value}
    raise ValueError(cause)


def cause_payload_position(base: Bicycle, rng: np.random.Generator) -> tuple[float, float]:
    """A payload near the rear frame's mass centre (luggage on a rack, instruments)."""
    return (base.parameters["xB"] + rng.uniform(-0.1, 0.1), base.parameters["zB"] + rng.uniform(-0.1, 0.1))


def run_trial(cause: str, seed: int, base_name: str = "benchmark", speeds=SPEEDS) -> Trial:
    """Simulate runs of a hidden effect and diagnose them against the base bicycle."""
    rng = np.random.default_rng([seed, CAUSES.index(cause) if cause in CAUSES else 99])
    base = load_bicycle(base_name)
    truth_bicycle, truth = hidden_bicycle(base, cause, rng)
    measurements = []
    for k, speed in enumerate(speeds):
        scenario = RunScenario(speed=speed, seed=int(rng.integers(1 << 31)) + k, n_pushes=PUSHES)
        run = run_from_simulation(simulate_run(truth_bicycle, scenario, name=f"run{k}"))
        measurements += measure_run(run, baseline="auto")
    diagnosis = diagnose_observations(base, observations(measurements))
    return Trial(cause, seed, truth, diagnosis)


__all__ = ["CAUSES", "Trial", "cause_by_name", "hidden_bicycle", "run_trial"]
