"""Weave fit: estimator spread against the Cramer-Rao bound, and time per fit.

For damped sinusoids in white noise, the spread of the fitted (d, w) over many noise draws is
compared with the Cramer-Rao bound of the 5-parameter model ``c1 + exp(d t)[c2 cos wt + c3
sin wt]`` (Fisher information ``J^T J / sigma^2`` from the model's Jacobian at the true
parameters). The baseline, measured in the same run, is what the seed paper did: Nelder-Mead
(scipy.optimize.fmin, as Matlab's fminsearch) on all five parameters, started from the same
(d, w) as the variable-projection fit and the least-squares c's there.

Run: ``python benchmarks/bench_weavefit.py [draws]``.
"""

from __future__ import annotations

import sys
import time

import numpy as np
from scipy.optimize import fmin

from whipple.measurement.weave_starts import starting_values
from whipple.measurement.weavefit import fit_weave

#: (name, d [1/s], w [rad/s], sample rate [Hz], window [s], noise [signal units])
CASES = (
    ("seed run 1202 (stable, 100 Hz)", -1.32, 5.96, 100.0, 1.6, 0.02),
    ("unstable weave (500 Hz)", 1.4, 2.2, 500.0, 2.0, 0.02),
    ("lightly damped, long (500 Hz)", -0.3, 5.0, 500.0, 6.0, 0.05),
    ("short, under one period (100 Hz)", -2.0, 7.0, 100.0, 0.7, 0.02),
)
COEFFICIENTS = np.array([0.05, 0.5, -0.2])


def model(params, tau):
    c1, c2, c3, d, w = params
    return c1 + np.exp(d * tau) * (c2 * np.cos(w * tau) + c3 * np.sin(w * tau))


def cramer_rao(tau, d, w, sigma):
    c = COEFFICIENTS
    e = np.exp(d * tau)
    cos, sin = e * np.cos(w * tau), e * np.sin(w * tau)
    jacobian = np.column_stack([
        np.ones_like(tau), cos, sin, tau * (c[1] * cos + c[2] * sin), tau * (c[2] * cos - c[1] * sin)
    ])
    return np.sqrt(np.diag(np.linalg.inv(jacobian.T @ jacobian)))[3:] * sigma


def nelder_mead(tau, y):
    """The baseline: fminsearch-style simplex on all five parameters."""
    starts = starting_values(tau, y)

    def cost_of(dw):
        basis = np.column_stack([np.ones_like(tau), np.exp(dw[0] * tau) * np.cos(dw[1] * tau),
                                 np.exp(dw[0] * tau) * np.sin(dw[1] * tau)])
        c = np.linalg.lstsq(basis, y, rcond=None)[0]
        return float(np.sum((y - basis @ c) ** 2)), c

    d0, w0 = min(starts, key=lambda s: cost_of(s)[0])
    x0 = np.r_[cost_of((d0, w0))[1], d0, w0]
    best = fmin(lambda p: float(np.sum((y - model(p, tau)) ** 2)), x0, xtol=1e-8, ftol=1e-12,
                maxiter=20000, maxfun=40000, disp=False)
    return best[3], best[4]


def run_case(name, d, w, fs, duration, sigma, draws, rng):
    tau = np.arange(0, duration, 1 / fs)
    clean = model(np.r_[COEFFICIENTS, d, w], tau)
    noisy = [clean + sigma * rng.standard_normal(tau.size) for _ in range(draws)]
    crb = cramer_rao(tau, d, w, sigma)

    started = time.perf_counter()
    fits = [fit_weave(tau, y) for y in noisy]
    varpro_time = (time.perf_counter() - started) / draws
    varpro = np.array([(f.damping, f.frequency) for f in fits])
    coverage = (np.abs(varpro - (d, w)) < 2 * np.array([f.eigenvalue_std for f in fits])).mean(0)

    started = time.perf_counter()
    simplex = np.array([nelder_mead(tau, y) for y in noisy])
    simplex_time = (time.perf_counter() - started) / draws

    print(f"\n{name}: lambda = {d:+.2f} + {w:.2f}i, {tau.size} samples, sigma = {sigma}")
    print(f"  {'method':<26}{'std(d)/CRB':>11}{'std(w)/CRB':>11}{'bias d':>9}{'bias w':>9}"
          f"{'ms/fit':>9}")
    for label, estimates, seconds in (("variable projection", varpro, varpro_time),
                                      ("Nelder-Mead, 5 params", simplex, simplex_time)):
        ratio = estimates.std(axis=0) / crb
        bias = estimates.mean(axis=0) - (d, w)
        print(f"  {label:<26}{ratio[0]:>11.3f}{ratio[1]:>11.3f}{bias[0]:>+9.4f}{bias[1]:>+9.4f}"
              f"{1e3 * seconds:>9.2f}")
    print(f"  2-sigma coverage of the reported std (d, w): {coverage[0]:.3f}, {coverage[1]:.3f}")
    print(f"  time ratio variable projection / Nelder-Mead: {varpro_time / simplex_time:.3f}")
    return varpro.std(axis=0) / crb


def main(draws: int = 300) -> int:
    rng = np.random.default_rng(2009)
    worst = np.zeros(2)
    for case in CASES:
        worst = np.maximum(worst, run_case(*case, draws=draws, rng=rng))
    verdict = "within" if (worst <= 1.5).all() else "NOT within"
    print(f"\nlargest std/CRB of variable projection: d {worst[0]:.3f}, w {worst[1]:.3f} "
          f"({verdict} 1.5)")
    return 0 if (worst <= 1.5).all() else 1


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1]) if len(sys.argv) > 1 else 300))
