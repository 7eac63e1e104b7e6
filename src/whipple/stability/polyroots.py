"""All real roots in ``[low, high]`` of many polynomials in the speed at once.

Used by :mod:`whipple.stability.critical` on the Hopf and real conditions
(:mod:`whipple.stability.polynomial`). Per polynomial ``p(v)`` (a row of coefficients):

1. **Reduction.** When every odd coefficient is exactly zero (the Whipple model and any model
   symmetric in v: the structure makes them vanish exactly in the arithmetic), p is solved as a
   polynomial in ``u = v^2`` and each root gives ``v = +/- sqrt(u)``. Exactly vanishing low and
   high coefficients are stripped (a factor ``v^m`` gives the root 0).
2. **Roots.** Degree 1 and 2 in closed form (the cancellation-free quadratic formula: the
   Whipple model's conditions are quadratics in u); higher degrees from the eigenvalues of
   companion matrices, one batched ``numpy.linalg.eigvals`` call per degree.
3. **Candidates.** Real roots, and complex ones within :data:`NEAR_REAL` of the real axis
   (a double root, where an eigenvalue touches the axis, splits into such a pair in rounding);
   those are *touch* candidates. Around a companion pair up to :data:`SPLIT_PAIR` off the
   axis (two close real roots can come out so), the polynomial is scanned for sign changes
   over a window set by the pair, and each change bisected (method ``companion+scan``).
4. **Polishing.** Newton's method on p itself (on ``p'`` for touch candidates), accepted step by
   step only while ``|p|`` (``|p'|``) decreases.

The cost does not depend on the interval: nothing is sampled. Callers verify every root on the
eigenvalues (a root of the Hopf condition may be a pair of opposite real eigenvalues).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.stability.polynomial import evaluate

#: Relative imaginary part [-] below which a complex root is a candidate (double-root splitting
#: in rounding is of order sqrt(machine epsilon) = 1.5e-8).
NEAR_REAL = 1e-6
#: Newton steps of the polishing.
NEWTON_STEPS = 6
#: Relative imaginary part [-] up to which a complex pair from a companion matrix may be two
#: close real roots split by the eigenvalue solver's error (high-degree conditions span many
#: orders of magnitude in their coefficients): the neighbourhood is scanned for sign changes.
SPLIT_PAIR = 0.2
#: Points of that scan, over the real part +/- SCAN_WIDTH times the imaginary part.
SCAN_POINTS = 64
SCAN_WIDTH = 4.0
#: Bisection steps on each sign change of the scan (to below rounding).
BISECTIONS = 60


@dataclass(frozen=True)
class PolynomialRoots:
    """Real roots of a batch of polynomials, as flat arrays (one entry per root).

    Attributes
    ----------
    model : ndarray of int
        Row of the polynomial in the batch.
    speed : ndarray of float
        Root [m/s], sorted by (model, speed).
    near : ndarray of bool
        True for a candidate from a complex pair close to the axis (a possible touch).
    method : ndarray of str
        ``closed-form``, ``companion`` or ``companion+scan``, with ``+newton`` when the polishing
        moved the root.
    """

    model: NDArray[np.intp]
    speed: NDArray[np.float64]
    near: NDArray[np.bool_]
    method: NDArray[np.str_]


def _reduce(polys: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Polynomials in ``u = v^2`` where every odd coefficient is exactly zero."""
    even = np.all(polys[:, 1::2] == 0, axis=-1)
    working = np.where(even[:, None], pad_to(polys[:, 0::2], polys.shape[1]), polys)
    return working, even


def pad_to(p: NDArray[np.float64], length: int) -> NDArray[np.float64]:
    """Rows of p padded with zeros (or cut) to `length` columns."""
    if p.shape[1] >= length:
        return p[:, :length]
    return np.pad(p, ((0, 0), (0, length - p.shape[1])))


def _roots_by_degree(working: NDArray[np.float64]
                     ) -> tuple[NDArray[np.intp], NDArray[np.complex128], NDArray[np.str_]]:
    """All roots of every row (exact zeros stripped); flat (row, root, method)."""
    nonzero = working != 0
    has = np.any(nonzero, axis=-1)
    width = working.shape[1]
    low_index = np.where(has, np.argmax(nonzero, axis=-1), 0)
    high_index = np.where(has, width - 1 - np.argmax(nonzero[:, ::-1], axis=-1), 0)
    degree = high_index - low_index
    rows_out, roots_out, methods_out = [], [], []
    # A factor u^m or v^m: the root 0.
    zero_rows = np.nonzero(has & (low_index > 0))[0]
    rows_out.append(zero_rows)
    roots_out.append(np.zeros(zero_rows.size, dtype=complex))
    methods_out.append(np.full(zero_rows.size, "closed-form"))
    # (Not np.unique: its first call imports numpy.ma, 15 ms of a sweep's start.)
    for d in sorted(set(degree[has & (degree > 0)].tolist())):
        rows = np.nonzero(has & (degree == d))[0]
        base = low_index[rows]
        coefficient = np.stack([working[rows, base + j] for j in range(d + 1)], axis=-1)
        if d == 1:
            roots = (-coefficient[:, 0] / coefficient[:, 1])[:, None].astype(complex)
            method = "closed-form"
        elif d == 2:
            c, b, a = coefficient[:, 0], coefficient[:, 1], coefficient[:, 2]
            disc = b * b - 4.0 * a * c
            root_disc = np.sqrt(np.abs(disc))
            sign = np.where(b >= 0, 1.0, -1.0)
            q = -0.5 * (b + sign * np.where(disc >= 0, root_disc, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                real_pair = np.stack([q / a, c / q], axis=-1)
                vertex = -b / (2.0 * a)
                imag = 0.5 * root_disc / np.abs(a)
            complex_pair = np.stack([vertex + 1j * imag, vertex - 1j * imag], axis=-1)
            roots = np.where((disc >= 0)[:, None], real_pair + 0j, complex_pair)
            method = "closed-form"
        else:
            companion = np.zeros((rows.size, d, d))
            companion[:, 0, :] = -coefficient[:, d - 1::-1] / coefficient[:, d:d + 1]
            companion[:, np.arange(1, d), np.arange(d - 1)] = 1.0
            roots = np.linalg.eigvals(companion).astype(complex)
            method = "companion"
        rows_out.append(np.repeat(rows, roots.shape[1]))
        roots_out.append(roots.ravel())
        methods_out.append(np.full(roots.size, method))
    return (np.concatenate(rows_out).astype(np.intp), np.concatenate(roots_out),
            np.concatenate(methods_out).astype("<U20"))


def _split_pairs(working: NDArray[np.float64], row: NDArray[np.intp], root: NDArray[np.complex128],
                 method: NDArray[np.str_]) -> tuple[NDArray[np.intp], NDArray[np.complex128]]:
    """Real roots near complex companion pairs that may be split close real roots.

    The eigenvalues of a companion matrix are exact for a nearby polynomial, not for this one:
    two close real roots of a badly scaled high-degree polynomial can come out as a complex
    pair (the tyre model's Hopf condition: two roots 1 % apart in speed, one a crossing, returned as a
    pair 2.6 % off the axis). Around each such pair (one member per pair, relative imaginary
    part between NEAR_REAL and SPLIT_PAIR) the polynomial itself is scanned for sign changes
    over a window set by the pair, not by the speed interval, and each is bisected.
    """
    size = np.maximum(np.abs(root), 1e-300)
    ratio = np.abs(root.imag) / size
    pick = np.nonzero((method == "companion") & (root.imag > 0) & (ratio > NEAR_REAL)
                      & (ratio <= SPLIT_PAIR))[0]
    if pick.size == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=complex)
    centre, half = root[pick].real, SCAN_WIDTH * root[pick].imag
    grid = centre[:, None] + half[:, None] * np.linspace(-1.0, 1.0, SCAN_POINTS)[None, :]
    polys = working[row[pick]]
    values = evaluate(polys[:, None, :], grid)[0]
    change = np.nonzero(np.sign(values[:, :-1]) * np.sign(values[:, 1:]) < 0)
    owner = change[0]
    a, b = grid[change], grid[change[0], change[1] + 1]
    fa = values[change]
    own = polys[owner]
    for _ in range(BISECTIONS):
        middle = 0.5 * (a + b)
        fm = evaluate(own, middle)[0]
        left = np.sign(fm) == np.sign(fa)
        a, fa = np.where(left, middle, a), np.where(left, fm, fa)
        b = np.where(left, b, middle)
    return row[pick][owner], (0.5 * (a + b)).astype(complex)


def _polish(polys: NDArray[np.float64], model: NDArray[np.intp], speed: NDArray[np.float64],
            near: NDArray[np.bool_]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Newton on p (on p' for touch candidates), each step kept only if it reduces the residual."""
    derivative = polys[:, 1:] * np.arange(1, polys.shape[1])
    second = derivative[:, 1:] * np.arange(1, derivative.shape[1]) if derivative.shape[1] > 1 \
        else np.zeros((polys.shape[0], 1))
    length = polys.shape[1]
    own, first, bend = polys[model], pad_to(derivative, length)[model], pad_to(second, length)[model]
    target = np.where(near[:, None], first, own)
    slope_poly = np.where(near[:, None], bend, first)
    moved = np.zeros(speed.shape, dtype=bool)
    with np.errstate(all="ignore"):
        value, _ = evaluate(target, speed)
        for _ in range(NEWTON_STEPS):
            slope, _ = evaluate(slope_poly, speed)
            step = value / slope
            trial = speed - step
            trial_value, _ = evaluate(target, trial)
            better = np.isfinite(trial) & (np.abs(trial_value) < np.abs(value))
            if not np.any(better):
                break
            moved |= better & (trial != speed)
            speed = np.where(better, trial, speed)
            value = np.where(better, trial_value, value)
    return speed, moved


def real_roots(polys: NDArray[np.float64], low: float, high: float, polish: bool = True
               ) -> PolynomialRoots:
    """Real roots in ``[low, high]`` [m/s] of a batch of polynomials in v.

    Parameters
    ----------
    polys : ndarray, shape (N, L)
        Coefficients of ``v^0 .. v^(L-1)`` of each polynomial.
    low, high : float
        The interval [m/s].
    polish : bool
        Polish the roots by Newton's method (see the module docstring).

    Returns
    -------
    PolynomialRoots
    """
    nonzero = np.nonzero(np.any(polys != 0, axis=0))[0]
    polys = polys[:, :nonzero[-1] + 1] if nonzero.size else polys[:, :1]
    working, even = _reduce(polys)
    row, root, method = _roots_by_degree(working)
    split_row, split_root = _split_pairs(working, row, root, method)
    row = np.concatenate([row, split_row])
    root = np.concatenate([root, split_root])
    method = np.concatenate([method, np.full(split_row.size, "companion+scan")]).astype("<U20")
    scale = np.maximum(np.abs(root), 1e-300)
    near = np.abs(root.imag) > 0
    keep = np.abs(root.imag) <= NEAR_REAL * scale
    # Of a conjugate pair, one member.
    keep &= root.imag >= 0
    row, root, method, near = row[keep], root[keep], method[keep], near[keep]
    in_u = even[row]
    # A root u of the reduced polynomial gives v = +/- sqrt(u) (u < 0: no real speed; a
    # touch candidate slightly below zero is the double root 0).
    u = root.real
    positive = np.where(in_u, np.sqrt(np.maximum(u, 0.0)), u)
    usable = ~in_u | (u >= 0) | near
    row, positive, method, near, in_u = (row[usable], positive[usable], method[usable],
                                         near[usable], in_u[usable])
    mirror = in_u & (positive > 0)
    model = np.concatenate([row, row[mirror]])
    speed = np.concatenate([positive, -positive[mirror]])
    method = np.concatenate([method, method[mirror]])
    near = np.concatenate([near, near[mirror]])
    margin = 1e-9 * (1.0 + np.abs(speed))
    inside = (speed >= low - margin) & (speed <= high + margin)
    model, speed, method, near = model[inside], speed[inside], method[inside], near[inside]
    if polish and speed.size:
        speed, moved = _polish(polys, model, speed, near)
        method = np.where(moved, np.char.add(method, "+newton"), method)
    inside = (speed >= low) & (speed <= high)
    model, speed, method, near = model[inside], speed[inside], method[inside], near[inside]
    order = np.lexsort((speed, model))
    return PolynomialRoots(model[order], speed[order], near[order], method[order].astype(str))
