"""The worked example of docs/adding-a-cause.md: a roll damping declared as a candidate cause.

A viscous roll torque ``-c * roll_rate`` (air, the tyres, a rider's passive sway) is the model
term ``D_roll_roll`` = c [N m s/rad] of the linear equations, so one declaration adds it.
``tests/test_registry.py`` imports this declaration and checks that a hidden-effect trial finds
it; run this file to diagnose hidden-effect trials of a roll damping with it:

    python docs/examples/roll_damping.py [--seeds 3] [--bicycles benchmark browser]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.registry import Family, Value, add_terms, declare


def roll_damping_apply(bicycle, values):
    """The bicycle with a roll damping of ``values[0]`` [N m s/rad] added."""
    return add_terms(bicycle, D_roll_roll=values[0])


roll_damping = declare(
    "roll_damping",
    Value("roll_damping", "N m s/rad", bounds=(0.0, 500.0)),  # null value 0: no damping
    roll_damping_apply,
    families=(Family("roll_damping", "a roll torque resisting the roll rate (air, the tyres, a rider's sway)"),),
    terms=("D_roll_roll",),  # the cause is this term: it no longer competes as a term of its own
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--bicycles", nargs="+", default=["benchmark", "browser"])
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests"))
    from hidden_effects import run_trial  # the trial generator lives with the tests

    options = DiagnosisOptions(causes=(roll_damping,))
    for bicycle in args.bicycles:
        for seed in range(args.seeds):
            trial = run_trial("roll_damping", seed, bicycle, options=options)
            diagnosis, truth = trial.diagnosis, trial.truth["roll_damping"]
            value = diagnosis.best.values[0] if diagnosis.best is not None else float("nan")
            print(f"{bicycle} seed {seed}: true roll damping {truth:.4g} N m s/rad; verdict {diagnosis.verdict} "
                  f"({diagnosis.cause}), fitted {value:.4g} ({100 * (value / truth - 1):+.1f}%)")


if __name__ == "__main__":
    main()
