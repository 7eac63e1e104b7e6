"""A fast mode that grows, fitted where a window shows it.

Compared with a window's samples, a model with more states than the bicycle's four starts the
window on its four slowest modes (:func:`~whipple.stability.slow_modes.slowest_modes`): its fast
modes (a tyre's relaxation, a controller's lag) have died out by the window's first sample. A
fast mode that grows has not: the least disturbance starts it, and it would be in the window.
Either the window shows it, and its amplitudes are fitted with the slow modes', or the model
cannot have produced the window. A tyre softer than the bicycle's own can make such a mode, a
lightly damped tyre oscillation of some 28 rad/s (4.5 Hz) that grows at the higher speeds (a
shimmy); where the runs show it, the true model holds its windows only so (on a simulated trial
of the benchmark with such tyres at 6-8 m/s, the true model left its eight windows at a
chi-square per sample of 0.3-2.0 with the mode fitted, where the base model left them at
17-2,118).

A window shows the mode where fitting its amplitudes gains at least :data:`GROWTH_EVIDENCE` in
log-likelihood over the slow modes alone (two amplitudes gain a unit or so on noise alone) and
the mode's part of the fit stands out of the noise (:func:`shown_growth`). A model holds the
windows where it grows only if some window shows the mode: the runs then hold it, and a window
where it stays within the noise started it small (on a simulated trial, one window of four at
8 m/s, where the mode grows at 1.35 1/s), and is fitted without its amplitudes. A model whose
growing mode no window shows (a tyre at the edge of its range where every measured weave
decays) is no model of the windows where it grows.

The windows are compared in bins (:data:`~whipple.diagnosis.window_bins.BIN_DURATION`), which
cannot show an oscillation faster than half their rate (:func:`resolved`): averaged over bins
of 0.04 s, a mode of 153 rad/s (24 Hz) is a faint oscillation of about 4 rad/s, at the weave's
own frequency, which fitted freely in each window soaks up whatever the windows hold there. A
stiff tyre's relaxation mode is that fast; where it grows, the tyre model took up, with those
free amplitudes, the response to random road torques of a bicycle with no effect at all
(simulated, the benchmark at 3-7 m/s), and was named with an evidence of 778. No window shows
such a mode: a model whose growing mode the bins cannot resolve holds no window where it grows.
The soft tyres whose shimmy the runs show grow at 34 rad/s at most (trial tyres on the
benchmark, the Kooijman bicycle and the Browser, 2-8 m/s).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from whipple.stability.slow_modes import FITTED_MODES, dropped_modes, slowest_modes

#: Log-likelihood ratio of a window fitted with a growing fast mode against the slow modes alone
#: that shows the mode (as a catch's tail needs, :data:`whipple.measurement.catches.TAIL_EVIDENCE`:
#: chance gives a few units).
GROWTH_EVIDENCE = 20.0
#: Mean square of a growing mode's part of a window's fit, in units of the noise, that shows the
#: mode: at least the noise's own.
GROWTH_VISIBLE = 1.0


def fitted_modes(values: NDArray[np.complex128], growing: NDArray[np.int_] | None = None
                 ) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """Return the modes a window fits (..., 4 + g), and which of them are real columns (..., 4 + g).

    ``values`` (..., n): eigenvalues [1/s]. The four slowest modes, then the growing modes beyond
    them, g the most of any window: a window with fewer has the rest padded (False), columns of
    zeros in its design. ``growing`` (...): how many modes beyond the slowest grow (default:
    those of ``values``; along a speed profile, the most of any piece, taken from the first
    piece's modes in order of their real parts). Fewer than five states: the slowest alone.
    """
    slowest = slowest_modes(values)
    if values.shape[-1] <= FITTED_MODES:
        return slowest, np.ones(slowest.shape, dtype=bool)
    dropped, own = dropped_modes(values)
    growing = own if growing is None else growing
    extra = int(np.max(growing, initial=0))
    kept = np.concatenate([slowest, dropped[..., :extra]], axis=-1)
    real = np.concatenate([np.ones(slowest.shape, dtype=bool), np.arange(extra) < growing[..., None]], axis=-1)
    return kept, real


def resolved(values: NDArray[np.complex128], steps: NDArray[np.float64] | None,
             bins: NDArray[np.int_] | None) -> NDArray[np.bool_]:
    """Return where (..., W, m) a window's bins resolve a mode's oscillation: below half their rate.

    ``values`` (..., W, m): eigenvalues [1/s]; ``steps`` (W,): each window's sampling interval
    [s] and ``bins`` (W,) its samples per bin (None: every mode resolved; one sample a bin).
    """
    if steps is None:
        return np.ones(values.shape, dtype=bool)
    interval = steps * (1 if bins is None else bins)
    return np.asarray(np.abs(values.imag) * interval[:, None] < np.pi, dtype=bool)


def orthonormal_columns(matrix: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return an orthonormal basis of each matrix's column space, and the factor of its pseudo-inverse.

    ``matrix`` (..., s, c): returns ``q`` (..., s, c) and ``p`` (..., c, c) with
    ``pinv(matrix) = p @ q^T``. By QR; a matrix with a column of zeros (a padded growing mode,
    :func:`fitted_modes`) by its singular value decomposition, whose basis leaves that column
    out where QR would put an arbitrary direction in its place.
    """
    q, r = np.linalg.qr(matrix)
    inverse = np.linalg.pinv(r)
    padded = ~np.all(np.any(matrix != 0, axis=-2), axis=-1)
    if np.any(padded):
        u, singular, vt = np.linalg.svd(matrix[padded], full_matrices=False)
        tolerance = np.max(singular, axis=-1, keepdims=True) * max(matrix.shape[-2:]) * np.finfo(float).eps
        kept = singular > tolerance
        scale = np.where(kept, 1.0 / np.where(kept, singular, 1.0), 0.0)
        q[padded], inverse[padded] = u * kept[..., None, :], np.swapaxes(vt, -1, -2) * scale[..., None, :]
    return q, inverse


def shown_growth(growing: NDArray[np.bool_], extended: NDArray[np.float64], plain: NDArray[np.float64],
                 samples: NDArray[np.int_]) -> NDArray[np.bool_]:
    """Return where (models, W) a window shows its model's growing fast mode.

    ``growing`` (models, W): where a mode beyond the slowest grows; ``extended`` and ``plain``
    (models, W, k, L): the windows' residuals in units of the noise with that mode's amplitudes
    fitted and without; ``samples`` (W,): each window's residuals (bins times signals). A window
    shows the mode where (1) fitting it gains :data:`GROWTH_EVIDENCE` or more in
    log-likelihood, times the window's dispersion (its residual's mean square with the mode, at
    least 1: a model that leaves the window off gains on its own misfit too), and (2) the mode's
    part of the fit has a mean square of at least :data:`GROWTH_VISIBLE` (the gain's share per
    sample): an oscillation that stands out of the noise, as a shimmy does, and not a column
    that takes up a little of a misfit the model leaves spread over the window (on a simulated
    no-effect ground trial with sensor faults, a stiff tyre's growing mode gained 29.8 on one
    window of 3.8 m/s, 1.1 times its dispersion of 1.14 times 20, and had a mean square of 0.5).
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        left = np.sum(extended**2, axis=(-2, -1))
        gain = 0.5 * (np.sum(plain**2, axis=(-2, -1)) - left)
        count = np.maximum(samples, 1)
        dispersion = np.maximum(left / count, 1.0)
        visible = 2.0 * gain / count >= GROWTH_VISIBLE
    return np.asarray(growing & (gain >= GROWTH_EVIDENCE * dispersion) & visible, dtype=bool)
