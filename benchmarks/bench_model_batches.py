"""Several models in one evaluation, and the nonlinear coasting in CasADi, each against its baseline in one run.

Run: ``python benchmarks/bench_model_batches.py [--windows 84] [--models 5] [--coasts 12]``

* **Models together** (:func:`whipple.diagnosis.fitting.models_residuals`): the residuals of
  ``--models`` payload models at ``--windows`` synthetic windows of the benchmark bicycle
  (2-8 m/s) in one evaluation, against the baseline of the same models one at a time
  (:func:`~whipple.diagnosis.fitting.model_residuals`), as a fit's finite-difference
  Jacobian evaluated them before 2026-11-28. Also a 3-value payload fitted with SciPy's own
  finite differences (the baseline) and with the points evaluated together, and the largest
  difference between the two routes.
* **Coasting** (:func:`whipple.simulation.nonlinear_bicycle.coast`, CVODES at rtol 1e-10): the
  nonlinear benchmark bicycle coasting from ``--coasts`` weave starts (roll rates 0.1-1 rad/s,
  4-7 m/s, 3 s at 100 Hz), against the baseline of SciPy's DOP853 calling the CasADi function
  from Python at rtol 1e-8, as the amplitude check did before 2026-11-28; each route's largest
  roll-rate error against DOP853 at rtol 1e-12.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares as scipy_least_squares

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from synthetic_windows import synthetic_observations  # noqa: E402

from whipple.diagnosis import fitting  # noqa: E402
from whipple.diagnosis.causes import candidate_causes  # noqa: E402
from whipple.diagnosis.fitting import fit_cause, model_residuals, models_residuals, window_whitening  # noqa: E402
from whipple.model.parameters import Payload, load_bicycle  # noqa: E402
from whipple.simulation.nonlinear_bicycle import ForcedBicycle, coast  # noqa: E402


def _best_time(function, repeat: int, rounds: int = 5) -> float:
    """Best time per call [s] over ``rounds`` rounds of ``repeat`` calls."""
    function()
    best = np.inf
    for _ in range(rounds):
        started = time.perf_counter()
        for _ in range(repeat):
            function()
        best = min(best, (time.perf_counter() - started) / repeat)
    return best


def _dop853(forced: ForcedBicycle, start, times, rtol: float, atol: float):
    return solve_ivp(lambda t, y: forced.free(y, np.zeros(2))[:10], (times[0], times[-1]), start, method="DOP853",
                     t_eval=times, rtol=rtol, atol=atol).y.T


def models_together(windows: int, count: int) -> None:
    base = load_bicycle("benchmark")
    truth = base.with_extensions(payload=Payload(8.0, 0.3, -0.8))
    observations = synthetic_observations(truth, 0, np.linspace(2.0, 8.0, windows))
    whitening = window_whitening(observations, base)
    payload = next(cause for cause in candidate_causes(base) if cause.name == "payload" and len(cause.parameters) == 3)
    models = [payload.apply(base, [4.0 + k, 0.2, -0.7]) for k in range(count)]
    together = _best_time(lambda: models_residuals(models, observations, whitening), 50)
    alone = _best_time(lambda: [model_residuals(model, observations, whitening) for model in models], 50)
    print(f"{count} models at {windows} windows: one at a time (baseline) {1e3 * alone:.2f} ms, "
          f"together {1e3 * together:.2f} ms: ratio {together / alone:.2f}")

    def fitted(serial: bool):
        if not serial:
            return fit_cause(base, payload, observations, whitening)
        original = fitting.least_squares
        fitting.least_squares = lambda *args, workers=None, **kwargs: scipy_least_squares(*args, **kwargs)
        try:
            return fit_cause(base, payload, observations, whitening)
        finally:
            fitting.least_squares = original

    serial_time = _best_time(lambda: fitted(True), 1, 3)
    batched_time = _best_time(lambda: fitted(False), 1, 3)
    difference = np.max(np.abs(np.subtract(fitted(True).values, fitted(False).values)))
    print(f"fit of a 3-value payload: SciPy's differences (baseline) {serial_time:.3f} s, points together "
          f"{batched_time:.3f} s: ratio {batched_time / serial_time:.2f}; largest difference of the values "
          f"{difference:.2g}")


def coasting(count: int) -> None:
    forced = ForcedBicycle(load_bicycle("benchmark"))
    times = np.linspace(0.0, 3.0, 301)
    starts = [forced.upright(speed, roll_rate=rate, steer_rate=-0.3 * rate)
              for speed, rate in zip(np.linspace(4.0, 7.0, count), np.linspace(0.1, 1.0, count), strict=True)]
    reference = [_dop853(forced, start, times, 1e-12, 1e-14)[:, 7] for start in starts]
    routes = {"DOP853 at 1e-8 from Python (baseline)": lambda start: _dop853(forced, start, times, 1e-8, 1e-10),
              "CVODES at 1e-10 in CasADi": lambda start: coast(forced, start, times, 1e-10, 1e-12)}
    seconds = {}
    for name, route in routes.items():
        started = time.perf_counter()
        states = [route(start) for start in starts]
        seconds[name] = time.perf_counter() - started
        error = max(np.max(np.abs(s[:, 7] - r)) for s, r in zip(states, reference, strict=True))
        print(f"{count} coasts, {name}: {seconds[name]:.2f} s, largest roll-rate error {error:.2g} rad/s")
    baseline, cvodes = seconds.values()
    print(f"coasting ratio (CVODES / baseline): {cvodes / baseline:.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--windows", type=int, default=84)
    parser.add_argument("--models", type=int, default=5)
    parser.add_argument("--coasts", type=int, default=12)
    args = parser.parse_args()
    models_together(args.windows, args.models)
    coasting(args.coasts)


if __name__ == "__main__":
    main()
