"""Roots of batched monic cubics ``s^3 + b s^2 + c s + d`` in closed form.

Used where a cubic arises from a 4-state model: the eigenvalues left at a real crossing
(:mod:`whipple.stability.root_spectrum`, :mod:`whipple.stability.whipple_form`) and Ferrari's
resolvent (:mod:`whipple.stability.quartic`). One formula for both, so that the two cannot
drift apart in the arithmetic that decides which branch a rounding error falls into.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray


def real_cubic_root(b: NDArray[np.float64], c: NDArray[np.float64], d: NDArray[np.float64],
                    steps: int = 2) -> NDArray[np.float64]:
    """Return the largest real root of each cubic ``s^3 + b s^2 + c s + d`` (arrays broadcast).

    Cardano's formula on the depressed cubic ``t^3 + P t + Q`` (``s = t - b/3``); where all
    three roots are real, its trigonometric form, whose first branch is the largest. Then
    `steps` Newton steps on the cubic itself; a step that is not finite (a zero slope at a
    multiple root) is skipped. Multiple roots are found to about the cube root of rounding.
    """
    P = c - b * b / 3.0
    Q = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d
    disc = 0.25 * Q * Q + P * P * P / 27.0
    root_disc = np.sqrt(np.maximum(disc, 0.0))
    one = np.cbrt(root_disc - 0.5 * Q) - np.cbrt(root_disc + 0.5 * Q)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        radius = np.sqrt(np.maximum(-P / 3.0, 0.0))
        # Rounding may put the cosine just outside [-1, 1] at a double root; arccos would give NaN.
        cosine = np.clip(-0.5 * Q / (radius * radius * radius), -1.0, 1.0)
        three = 2.0 * radius * np.cos(np.arccos(cosine) / 3.0)
        # P = 0 with disc <= 0 is the triple root t = 0, which Cardano's form gives exactly.
        r = np.where((disc > 0) | (radius == 0), one, three) - b / 3.0
        for _ in range(steps):
            step = (((r + b) * r + c) * r + d) / ((3.0 * r + 2.0 * b) * r + c)
            r = r - np.where(np.isfinite(step), step, 0.0)
    return r


def cubic_roots(b: NDArray[np.float64], c: NDArray[np.float64], d: NDArray[np.float64]
                ) -> NDArray[np.complex128]:
    """Return the three roots of each cubic ``s^3 + b s^2 + c s + d``, shape (..., 3).

    The largest real root (:func:`real_cubic_root`) first, then the two roots of the quadratic
    left after dividing it out.
    """
    r = real_cubic_root(b, c, d)
    # s^3 + b s^2 + c s + d = (s - r)(s^2 + e s + f).
    e, f = b + r, c + r * (b + r)
    root = np.sqrt((e * e - 4.0 * f).astype(complex))
    return np.stack([r + 0j, 0.5 * (-e + root), 0.5 * (-e - root)], axis=-1)
