"""Benchmark: regeneration with the nonlinear model, and evaluations of its state derivative.

Run on demand: ``python benchmarks/bench_nonlinear.py [--repeat N] [--states N]``. Every timing
is printed beside a baseline measured in the same run:

- regeneration (derive + emit) of every model, split into the linear models (the baseline:
  what ``whipple regenerate`` did before the nonlinear model) and the nonlinear one; then
  ``generate()`` as ``whipple regenerate`` runs it (the budget is 90 s);
- one evaluation of the nonlinear state derivative (NumPy, and the CasADi function with its
  pitch rootfinder) against one evaluation of the linear model's derivative from the generated
  matrices (``x' = A(v) x``, NumPy), and N states at once with the NumPy code against N
  single evaluations.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from whipple.derivation.emit import emit_casadi, emit_casadi_functions, emit_numpy, emit_numpy_functions
from whipple.derivation.models import MODELS, DerivedFunctions
from whipple.derivation.regenerate import generate
from whipple.generated import whipple_numpy

from whipple.model.nonlinear import casadi_state_derivative, parameter_vector, state_derivative, upright_state
from whipple.model.parameters import load_bicycle


def time_models() -> dict[str, float]:
    """Seconds to derive and emit (NumPy and CasADi) each model."""
    seconds = {}
    for name, derive in MODELS.items():
        started = time.perf_counter()
        model = derive()
        if isinstance(model, DerivedFunctions):
            emit_numpy_functions(model, "0" * 64)
            emit_casadi_functions(model, "0" * 64)
        else:
            emit_numpy(model, "0" * 64)
            emit_casadi(model, "0" * 64)
        seconds[name] = time.perf_counter() - started
    return seconds


def per_call(function, repeat: int) -> float:
    """Median seconds per call over ``repeat`` calls, in five batches."""
    batches = []
    for _ in range(5):
        started = time.perf_counter()
        for _ in range(repeat):
            function()
        batches.append((time.perf_counter() - started) / repeat)
    return float(np.median(batches))


def linear_derivative(parameters: dict[str, float], speed: float):
    """x' = A(v) x of the linear model from the generated matrices, for one state."""
    M, C1, K0, K2 = whipple_numpy.matrices(*(parameters[name] for name in whipple_numpy.PARAMETERS))
    x = np.array([0.01, 0.02, 0.1, -0.1])

    def evaluate():
        lower = -np.linalg.solve(M, (K0 + speed**2 * K2) @ x[:2] + speed * C1 @ x[2:])
        return np.concatenate([x[2:], lower])

    return evaluate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=200, help="calls per timing batch")
    parser.add_argument("--states", type=int, default=10_000, help="states evaluated at once")
    args = parser.parse_args()

    seconds = time_models()
    linear = sum(value for name, value in seconds.items() if name != "whipple_nonlinear")
    nonlinear = seconds["whipple_nonlinear"]
    print(f"linear models, derive + emit (baseline): {linear:7.2f} s")
    print(f"nonlinear model, derive + emit:          {nonlinear:7.2f} s   ({nonlinear / linear:.2f}x the linear ones)")
    started = time.perf_counter()
    generate()
    total = time.perf_counter() - started
    print(f"whipple regenerate, all models:          {total:7.2f} s   (budget 90 s)")

    parameters = dict(load_bicycle("benchmark").parameters)
    state = upright_state(parameters, 5.0, roll=0.1, steer=0.05, roll_rate=0.3)
    baseline = per_call(linear_derivative(parameters, 5.0), args.repeat)
    numpy_one = per_call(lambda: state_derivative(parameters, state), args.repeat)
    function, vector = casadi_state_derivative(), parameter_vector(parameters)
    casadi_one = per_call(lambda: function(vector, state, np.zeros(2)), args.repeat)
    print(f"linear derivative, one state (baseline): {baseline * 1e6:9.1f} us")
    print(f"nonlinear derivative, NumPy, one state:  {numpy_one * 1e6:9.1f} us   ({numpy_one / baseline:.0f}x)")
    print(f"nonlinear derivative, CasADi, one state: {casadi_one * 1e6:9.1f} us   ({casadi_one / baseline:.0f}x)")
    states = np.tile(state, (args.states, 1))
    states[:, 3] += np.linspace(-0.1, 0.1, args.states)
    started = time.perf_counter()
    state_derivative(parameters, states)
    batch = (time.perf_counter() - started) / args.states
    print(f"nonlinear derivative, NumPy, {args.states} states at once: {batch * 1e6:7.2f} us per state   "
          f"({numpy_one / batch:.0f}x faster than one at a time)")


if __name__ == "__main__":
    main()
