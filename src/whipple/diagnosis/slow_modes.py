"""The modes a window fits: as many as the bicycle has mechanical states, the slowest.

A window holds free coasting some time after its push. A model with more states than the
bicycle's four (roll, steer and their rates) starts each window on its slowest modes, so that
every model compared with a window's samples fits as many modal amplitudes
(:mod:`whipple.diagnosis.samples`) and none is charged for more.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["FITTED_MODES", "slowest_modes"]

#: Modes whose amplitudes each window fits: as many as the bicycle has mechanical states (roll,
#: steer and their rates).
FITTED_MODES = 4


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
