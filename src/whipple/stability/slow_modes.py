"""The modes a window fits: as many as the bicycle has mechanical states, the slowest.

A window holds free coasting some time after its push. A model with more states than the
bicycle's four (roll, steer and their rates) starts each window on its slowest modes, so that
every model compared with a window's samples fits as many modal amplitudes
(:mod:`whipple.diagnosis.samples`) and none is charged for more.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["FITTED_MODES", "REAL_MODE", "dropped_modes", "lower_members", "slowest_modes", "unseen_growth"]

#: Modes whose amplitudes each window fits: as many as the bicycle has mechanical states (roll,
#: steer and their rates).
FITTED_MODES = 4
#: Eigenvalues whose imaginary part is below this fraction of their magnitude are real modes.
REAL_MODE = 1e-9


def lower_members(values: NDArray[np.complex128]) -> NDArray[np.bool_]:
    """Return which eigenvalues (...) are a complex pair's lower member (its real response: the imaginary part)."""
    return np.asarray(values.imag < -REAL_MODE * np.maximum(np.abs(values), np.finfo(float).tiny), dtype=bool)


def slowest_modes(values: NDArray[np.complex128], count: int = FITTED_MODES) -> NDArray[np.intp]:
    """Return the indices (..., count) of the ``count`` slowest modes: the smallest eigenvalues in magnitude.

    A window holds free coasting some time after its push, and a model's fastest modes have
    died out by its first sample or are beyond what its samples resolve: a tyre's relaxation
    (oscillations of 50-80 rad/s, decaying at 10-20 1/s, beside a weave of 4-8 rad/s), a
    controller's delay and lag (tens of 1/s). Its state lies on its slowest modes, as many as the
    bicycle has mechanical states, and each window fits their amplitudes alone, as many as the
    Whipple model's (its castering mode among them). Fitted freely, the fast modes' amplitudes
    would fit some of the noise of every window's first samples, whatever the model's values.
    Slow means a long time scale, ``1/|lambda|``: by the real part alone a lightly damped tyre
    oscillation would count as slower than the castering mode. ``values`` (..., n):
    eigenvalues [1/s], a complex pair's members next to each other (as
    :func:`numpy.linalg.eig` gives them): a stable sort keeps them together unless ``count``
    falls between them, when one real response of the pair is kept.
    """
    return np.argsort(np.abs(values), axis=-1, kind="stable")[..., :count]


def unseen_growth(values: NDArray[np.complex128], count: int = FITTED_MODES) -> NDArray[np.bool_]:
    """Return where (...) a mode beyond the ``count`` slowest grows: one the window must show.

    A window starts such a mode at rest (:func:`slowest_modes`), which a free response can only
    do if it decays: a growing mode, however fast, is excited by the least disturbance and
    would be in the window. A model with one (a tyre whose relaxation is unstable at the
    window's speed) holds a window only where the window shows the mode, whose amplitudes it
    then fits too (:mod:`whipple.diagnosis.growing_modes`). ``values`` (..., n): eigenvalues [1/s].
    """
    return np.asarray(dropped_modes(values, count)[1] > 0, dtype=bool)


def dropped_modes(values: NDArray[np.complex128], count: int = FITTED_MODES
                  ) -> tuple[NDArray[np.intp], NDArray[np.int_]]:
    """Return the modes beyond the ``count`` slowest, the fastest-growing first, and how many grow.

    ``values`` (..., n): eigenvalues [1/s]. Returns the indices (..., n - count), ordered by
    decreasing real part (a complex pair's members stay next to each other), and the number of
    them whose real part is positive (...). A window that shows such a growing mode fits its
    amplitudes too (:mod:`whipple.diagnosis.growing_modes`).
    """
    dropped = np.argsort(np.abs(values), axis=-1, kind="stable")[..., count:]
    real = np.take_along_axis(values, dropped, axis=-1).real
    order = np.argsort(-real, axis=-1, kind="stable")
    return np.take_along_axis(dropped, order, axis=-1), np.sum(real > 0, axis=-1)
