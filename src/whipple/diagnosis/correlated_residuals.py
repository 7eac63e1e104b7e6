"""Residuals correlated in time: the windows' samples say less than their number suggests.

Compared with the samples (:mod:`whipple.diagnosis.samples`), a model's evidence adds up the
squared residual of every bin as if each were independent, in units of the sensors' white
noise. No real bicycle coasts free of small random pushes (a road's or a belt's roughness,
gusts of wind: :mod:`whipple.simulation.disturbance`); its response to them is a slow, weave-like
wandering that no model's free response holds, and that gives a model able to bend towards it
differences of chi-square many times those the noise allows. On simulated runs of the benchmark
with no effect and random roll torques of 1-5 N m, leads of 3-130 in evidence were read from
them, and loads on the front and rear frames were named, each for the other.

Where the windows were moved so, the best model's residual shows it in the directions that a
changed model moves a window: a shifted weave eigenvalue changes each signal by ``e^{lambda t}``
and ``t e^{lambda t}`` (cosine and sine parts), ``lambda`` the window's fitted weave eigenvalue.
Projected on these columns, each signal's residual of each window has four degrees of freedom,
and for white noise their sum of squares, over the residual's mean square, is a chi-square
with as many. :func:`correlation_factor` takes its ratio to that expectation at a lower bound of
:data:`CONFIDENCE` (1 when the residual is no larger there than the noise allows): every
difference of chi-square between models, in those directions, is that many times what white
noise would give. The evidence and every comparison made in units of the samples' dispersion
divide by it (:func:`whipple.diagnosis.evidence.diagnose_observations`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from whipple.diagnosis.observations import Observation
from whipple.diagnosis.samples import OVERFLOW_MISFIT, SampleComparison

#: One-sided confidence of the lower bound on the residual's excess in the directions a changed
#: model moves the windows: white noise exceeds 1 there by chance in 1 run of 20 at most.
CONFIDENCE = 0.95
#: Columns per signal and window: ``e^{lambda t}`` and ``t e^{lambda t}``, each cosine and sine.
COLUMNS = 4


def model_change_columns(tau: NDArray[np.float64], eigenvalue: complex) -> NDArray[np.float64]:
    """Return the directions (L, 4) in which a changed weave eigenvalue moves a window's signal.

    ``tau`` (L,): the bins' times from the window's start [s]; ``eigenvalue``: the window's weave
    eigenvalue [1/s]. Time is measured in units of the window's length (conditioning only).
    """
    length = max(float(np.max(tau, initial=0.0)), 1e-9)
    growth = np.exp(eigenvalue * tau)
    ramp = tau / length
    return np.stack([growth.real, growth.imag, ramp * growth.real, ramp * growth.imag], axis=-1)


def correlation_factor(samples: SampleComparison, residuals: NDArray[np.float64],
                       observations: Sequence[Observation]) -> float:
    """Return how many times white noise the residual is in the directions a changed model moves the windows.

    Parameters
    ----------
    samples : SampleComparison
        The windows' samples.
    residuals : ndarray, shape (samples,)
        A model's residual on every sample, in units of the noise (the best model's).
    observations : sequence of Observation
        The windows, in the order of ``samples``: their fitted weave eigenvalues.

    Returns
    -------
    float
        At least 1: the residual's sum of squares in those directions (:func:`model_change_columns`,
        per window and signal) over its mean square, divided by the :data:`CONFIDENCE` quantile of
        a chi-square with as many degrees of freedom. Windows the model cannot hold
        (:data:`~whipple.diagnosis.samples.OVERFLOW_MISFIT`) are left out.
    """
    full = np.zeros(samples.targets.shape)
    mask = np.broadcast_to(samples.mask[:, None, :], full.shape)
    full[mask] = residuals
    projected, squares, count, freedom = 0.0, 0.0, 0, 0
    for window, observation in enumerate(observations):
        bins = samples.mask[window]
        values = full[window][:, bins]  # (k, L)
        if values.shape[-1] <= 2 * COLUMNS or np.any(np.abs(values) >= OVERFLOW_MISFIT):
            continue
        basis = np.linalg.qr(model_change_columns(samples.tau[window, bins], complex(observation.eigenvalue)))[0]
        projected += float(np.sum((values @ basis) ** 2))
        squares += float(np.sum(values**2))
        count += values.size
        freedom += values.shape[0] * COLUMNS
    if freedom == 0 or squares <= 0:
        return 1.0
    level = squares / count
    return max(1.0, projected / level / float(chi2.ppf(CONFIDENCE, freedom)))


def correlated(scales: tuple[float, float], residuals: NDArray[np.float64], samples: SampleComparison | None,
               observations: Sequence[Observation]) -> tuple[tuple[float, float], float]:
    """Return the dispersions with the samples' times the correlation factor of ``residuals``, and that factor.

    ``scales``: the dispersions of the eigenvalue (or samples) and mode-shape residuals;
    ``residuals``: the best model's (:func:`correlation_factor`). Without the samples (the
    eigenvalue comparisons) the dispersions stand and the factor is 1.
    """
    if samples is None:
        return scales, 1.0
    factor = correlation_factor(samples, residuals, observations)
    return (scales[0] * factor, scales[1]), factor


def correlation_notes(factor: float) -> list[str]:
    """Return the report's caveat on a correlation factor above 1 (none at 1)."""
    if factor <= 1.0:
        return []
    return [f"the best-fitting model's residual wanders slowly (a road's roughness, wind?): where a changed model "
            f"would move the windows it is {factor:.1f} times the noise's, and every difference of evidence is "
            "divided by that"]
