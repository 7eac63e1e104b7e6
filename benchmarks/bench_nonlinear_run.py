"""Benchmark: simulated runs with the nonlinear model, and the amplitude check of the diagnosis.

Run on demand: ``python benchmarks/bench_nonlinear_run.py [--speeds 2,4]``. Every timing is
printed beside a baseline measured in the same run:

- ``simulate_nonlinear_run`` against ``simulate_run`` (the linear model, exact discretisation)
  for the same scenario of sbw2024 (three pushes, about 20 s of run), with the evaluations
  of the equations and the time per evaluation;
- the diagnosis of the bundled runs (``assemble``) with and without the amplitude check
  (:mod:`whipple.diagnosis.amplitude`), after measuring the windows (also timed).
"""

from __future__ import annotations

import argparse
import time

from whipple.diagnosis.report import assemble
from whipple.measurement.bundled import bundled_runs
from whipple.measurement.experiment import FitOptions, measure_run
from whipple.measurement.runs import read_run
from whipple.model.parameters import load_bicycle
from whipple.simulation.nonlinear_run import simulate_nonlinear_run
from whipple.simulation.scenario import RunScenario
from whipple.simulation.simulator import simulate_run


def seconds(function, *arguments, **keywords) -> tuple[float, object]:
    """Seconds one call takes, and its result."""
    started = time.perf_counter()
    result = function(*arguments, **keywords)
    return time.perf_counter() - started, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", default="2,4,5", help="speeds of the simulated runs [m/s]")
    args = parser.parse_args()
    bicycle = load_bicycle("sbw2024")
    for speed in map(float, args.speeds.split(",")):
        scenario = RunScenario(speed=speed)
        linear, _ = seconds(simulate_run, bicycle, scenario)
        nonlinear, run = seconds(simulate_nonlinear_run, bicycle, scenario)
        checks = run.checks
        print(f"{speed:g} m/s, {run.time[-1]:.1f} s of run: linear (baseline) {linear:.3f} s, nonlinear "
              f"{nonlinear:.2f} s ({nonlinear / linear:.0f}x), {checks.evaluations} evaluations, "
              f"{1e6 * nonlinear / checks.evaluations:.0f} us each; energy balance error {checks.energy_error:.2g} J")

    measuring, measurements = seconds(lambda: [m for source in bundled_runs()
                                               for m in measure_run(read_run(source), options=FitOptions(
                                                   baseline="auto"))])
    without, _ = seconds(assemble, bicycle, measurements, amplitude=False)
    with_check, report = seconds(assemble, bicycle, measurements)
    windows = len(report.used)
    print(f"bundled runs: measuring the windows {measuring:.2f} s; diagnosis without the amplitude check "
          f"(baseline) {without:.2f} s, with it {with_check:.2f} s (+{with_check - without:.2f} s for {windows} "
          f"windows, {1e3 * (with_check - without) / windows:.0f} ms each)")


if __name__ == "__main__":
    main()
