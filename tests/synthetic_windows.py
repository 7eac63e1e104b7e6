"""Synthetic window observations: a model's own weave eigenvalues and mode shapes, plus noise.

Used by the tests of the held-out gain and by ``benchmarks/bench_prediction_choice.py``: no
simulated runs and no window fits, so that what is tested is the choice and the gain alone.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from whipple.diagnosis.observations import Observation, predicted_modes
from whipple.model.parameters import Bicycle

STD, SHAPE_STD = 0.05, 0.004  # stated uncertainty of both parts: eigenvalue [1/s], mode shape [s]


def synthetic_observations(truth: Bicycle, seed: int, speeds: Sequence[float], std: float = STD
                           ) -> list[Observation]:
    """Observations of ``truth`` at ``speeds`` [m/s] with noise ``std`` [1/s] and stated uncertainty STD.

    Each window's eigenvalue is the weave of ``truth`` (the mode nearest -1 + 5i 1/s) plus
    Gaussian noise of ``std`` in each part; its mode shape gets noise scaled alike.
    """
    rng = np.random.default_rng(seed)
    covariance, shape_covariance = np.eye(2) * STD**2, np.eye(2) * SHAPE_STD**2
    guesses = [Observation("r", 0.0, 1.0, v, (v, v), complex(-1.0, 5.0), covariance, 0.0j, shape_covariance)
               for v in speeds]
    eigenvalues, shapes = predicted_modes(truth, guesses)
    return [Observation("r", 0.0, 1.0, v, (v, v), lam + complex(*rng.normal(0.0, std, 2)), covariance,
                        shape + complex(*rng.normal(0.0, SHAPE_STD * std / STD, 2)), shape_covariance)
            for v, lam, shape in zip(speeds, eigenvalues, shapes, strict=True)]
