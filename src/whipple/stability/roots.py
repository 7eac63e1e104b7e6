"""Locating the zeros of the stability conditions over speed, for many models at once.

Used by :mod:`whipple.stability.critical`. For each model of a batch and each condition
(:mod:`whipple.stability.characteristic`: ``hopf`` or ``real``), the roots in ``[low, high]`` are found in
three vectorised stages:

1. **Brackets** from sign changes of the condition on a speed grid. A grid point where the
   condition is exactly zero is a root. Two roots in one grid cell leave no sign change, so
   every local minimum of ``|condition|`` without a sign change (a *dip*) is searched by a
   golden-section minimisation of ``sign * condition`` over its two neighbouring cells: a
   negative minimum gives two brackets, a minimum of zero within tolerance is a *tangential*
   root (the eigenvalue touches the axis and goes back; callers verify it on the
   eigenvalues), anything else is no root.
2. **Refinement** of all brackets at once with the Illinois variant of regula falsi (always
   bracketing, superlinear) to a width of about 1e-9 m/s.
3. **Polishing** with ``casadi.rootfinder`` (Newton, exact derivative in v) on the CasADi
   expression of the same condition, mapped over all roots in one call. A Newton result that
   leaves its bracket is rejected, and that root is bisected to machine precision instead.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from whipple.stability.characteristic import (
    condition_rootfinder,
    hopf_condition,
    real_condition,
    sparsity_pattern,
)

KINDS = ("hopf", "real")
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0
#: Bracket width [m/s, relative to 1 + |v|] after which Illinois hands over to Newton.
HANDOVER_WIDTH = 1e-9
#: Bracket width [relative to 1 + |v|] of a root bisected to machine precision.
MACHINE_WIDTH = 4 * np.finfo(float).eps


@dataclass(frozen=True)
class Roots:
    """Zeros of one condition for a batch of models (flat arrays, one entry per root).

    Attributes
    ----------
    model : ndarray of int
        Index of the model in the batch.
    speed : ndarray of float
        Root [m/s].
    method : ndarray of str
        ``casadi-newton``, ``bisection`` (Newton rejected), ``grid`` (exact zero on the grid)
        or ``touch`` (tangential root candidate from a dip, still to be verified).
    """

    model: NDArray[np.intp]
    speed: NDArray[np.float64]
    method: NDArray[np.str_]


def polynomial_matrices(coefficients: NDArray[np.float64], speeds: NDArray[np.float64]
                        ) -> NDArray[np.float64]:
    """``sum_k v_i^k C_ik`` for per-item coefficients (N, T, n, n) and speeds (N,) [m/s]."""
    total = np.zeros(coefficients.shape[:1] + coefficients.shape[2:])
    for power in range(coefficients.shape[1] - 1, -1, -1):
        total = total * speeds[:, None, None] + coefficients[:, power]
    return total


def condition(kind: str, eigenvalues: NDArray[Any]) -> NDArray[np.float64]:
    """Return the ``hopf`` or ``real`` condition from eigenvalues [1/s], shape (..., n)."""
    return hopf_condition(eigenvalues) if kind == "hopf" else real_condition(eigenvalues)


def _golden_minimum(function: Callable[[NDArray[np.float64]], NDArray[np.float64]],
                    low: NDArray[np.float64], high: NDArray[np.float64], iterations: int = 60
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Vectorised golden-section search of a minimum of `function` on [low, high]."""
    a, b = low.copy(), high.copy()
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = function(c), function(d)
    for _ in range(iterations):
        left = fc < fd
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        new = np.where(left, b - GOLDEN * (b - a), a + GOLDEN * (b - a))
        fnew = function(new)
        c, d, fc, fd = (np.where(left, new, d), np.where(left, c, new),
                        np.where(left, fnew, fd), np.where(left, fc, fnew))
    best = np.where(fc < fd, c, d)
    candidates = np.stack([low, best, high])
    values = np.stack([function(low), np.minimum(fc, fd), function(high)])
    pick = np.argmin(values, axis=0)
    return np.take_along_axis(candidates, pick[None], 0)[0], np.min(values, axis=0)


def _illinois(function: Callable[[NDArray[np.float64], NDArray[np.bool_]], NDArray[np.float64]],
              a: NDArray[np.float64], b: NDArray[np.float64],
              fa: NDArray[np.float64], fb: NDArray[np.float64], width: float,
              iterations: int = 200) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Shrink sign-change brackets [a, b] until ``|b - a| <= width (1 + |b|)`` or f = 0.

    Illinois: regula falsi, halving the function value kept at an end that survives twice.
    Falls back to bisection when the secant point is not strictly inside the bracket.
    """
    a, b, fa, fb = a.copy(), b.copy(), fa.copy(), fb.copy()
    for _ in range(iterations):
        active = (np.abs(b - a) > width * (1.0 + np.abs(b))) & (fb != 0)
        if not np.any(active):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            c = b - fb * (b - a) / (fb - fa)
        lower, upper = np.minimum(a, b), np.maximum(a, b)
        c = np.where((c > lower) & (c < upper), c, 0.5 * (a + b))
        fc = function(c, active)
        switch = fc * fb < 0
        a = np.where(active & switch, b, a)
        fa = np.where(active & switch, fb, np.where(active, 0.5 * fa, fa))
        b = np.where(active, c, b)
        fb = np.where(active, fc, fb)
    return np.minimum(a, b), np.maximum(a, b)


def find_roots(kind: str, coefficients: NDArray[np.float64], scale: NDArray[np.float64],
               grid: NDArray[np.float64], values: NDArray[np.float64], polish: bool) -> Roots:
    """All zeros of one condition for B models, from its values on a speed grid.

    Parameters
    ----------
    kind : {'hopf', 'real'}
        The condition (see :mod:`whipple.stability.characteristic`).
    coefficients : ndarray, shape (B, T, n, n)
        Polynomial coefficients of the state matrices, constant term first.
    scale : ndarray, shape (B,)
        Positive factor [1/s] dividing A in every evaluation (a power of two, so exact), to
        keep the conditions away from overflow and the residuals of order one; it does not
        move the roots.
    grid : ndarray, shape (G,)
        Increasing speeds [m/s] covering the searched interval, its ends included.
    values : ndarray, shape (B, G)
        The condition of ``A / scale`` on the grid (from its eigenvalues).
    polish : bool
        Polish with ``casadi.rootfinder`` (otherwise bisect to machine precision).
    """
    def evaluate(model: NDArray[np.intp], speed: NDArray[np.float64]) -> NDArray[np.float64]:
        matrices = polynomial_matrices(coefficients[model], speed) / scale[model, None, None]
        return condition(kind, np.linalg.eigvals(matrices))

    sign = np.sign(values)
    magnitude = np.abs(values)
    model_z, index_z = np.nonzero(sign == 0)
    model_c, index_c = np.nonzero(sign[:, :-1] * sign[:, 1:] < 0)
    a, b = grid[index_c], grid[index_c + 1]
    fa, fb = values[model_c, index_c], values[model_c, index_c + 1]

    padded = np.pad(magnitude, ((0, 0), (1, 1)), constant_values=np.inf)
    padded_sign = np.pad(sign, ((0, 0), (1, 1)), mode="edge")
    dip = ((magnitude < padded[:, :-2]) & (magnitude <= padded[:, 2:]) & (sign != 0)
           & (padded_sign[:, :-2] == sign) & (padded_sign[:, 2:] == sign))
    model_d, index_d = np.nonzero(dip)
    touch_model = np.zeros(0, dtype=np.intp)
    touch_speed = np.zeros(0)
    if model_d.size:
        low = grid[np.maximum(index_d - 1, 0)]
        high = grid[np.minimum(index_d + 1, grid.size - 1)]
        dip_sign = sign[model_d, index_d]
        where, lowest = _golden_minimum(lambda v: dip_sign * evaluate(model_d, v), low, high)
        split = lowest < 0
        # A negative minimum means two roots, one on each side of it.
        model_c = np.concatenate([model_c, model_d[split], model_d[split]])
        a = np.concatenate([a, low[split], where[split]])
        b = np.concatenate([b, where[split], high[split]])
        at_low = evaluate(model_d[split], low[split])
        at_high = evaluate(model_d[split], high[split])
        at_minimum = dip_sign[split] * lowest[split]
        fa = np.concatenate([fa, at_low, at_minimum])
        fb = np.concatenate([fb, at_minimum, at_high])
        touch_model, touch_speed = model_d[~split], where[~split]

    def shrinker(models: NDArray[np.intp]
                 ) -> Callable[[NDArray[np.float64], NDArray[np.bool_]], NDArray[np.float64]]:
        def shrink(c: NDArray[np.float64], active: NDArray[np.bool_]) -> NDArray[np.float64]:
            out = np.zeros_like(c)
            out[active] = evaluate(models[active], c[active])
            return out
        return shrink

    # Refine every bracket to the hand-over width, then polish.
    lower, upper = _illinois(shrinker(model_c), a, b, fa, fb,
                             HANDOVER_WIDTH if polish else MACHINE_WIDTH)
    speed = 0.5 * (lower + upper)
    method = np.full(speed.shape, "bisection", dtype="<U13")
    if polish and speed.size:
        start_value = np.abs(evaluate(model_c, speed))
        flat = (coefficients[model_c] / scale[model_c, None, None, None]).reshape(speed.size, -1)
        solver = condition_rootfinder(sparsity_pattern(coefficients), kind, speed.size)
        polished = np.asarray(solver(speed[None, :], flat.T,
                                     np.maximum(start_value, 1e-300)[None, :])).ravel()
        # Illinois often ends on a bracket much narrower than the hand-over width; the CasADi
        # root may differ from it by rounding, so only a jump away (to another root or
        # nowhere) is rejected.
        margin = HANDOVER_WIDTH * (1.0 + np.abs(speed))
        accepted = (np.isfinite(polished) & (polished >= lower - margin)
                    & (polished <= upper + margin))
        speed = np.where(accepted, polished, speed)
        method[accepted] = "casadi-newton"
        rejected = ~accepted
        if np.any(rejected):
            sub = model_c[rejected]
            refined = _illinois(shrinker(sub), lower[rejected], upper[rejected],
                                evaluate(sub, lower[rejected]), evaluate(sub, upper[rejected]),
                                MACHINE_WIDTH)
            speed[rejected] = 0.5 * (refined[0] + refined[1])

    models = np.concatenate([model_c, model_z, touch_model]).astype(np.intp)
    speeds = np.concatenate([speed, grid[index_z], touch_speed])
    methods = np.concatenate([method, np.full(index_z.shape, "grid"),
                              np.full(touch_speed.shape, "touch")])
    order = np.lexsort((speeds, models))
    return Roots(models[order], speeds[order], methods[order].astype(str))
