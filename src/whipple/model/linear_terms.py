"""Terms added to the linear equations' matrices: effects that no physical extension describes.

``M q'' + (v (C1 + dC1) + D + dD) q' + (K0 + dK0 + v^2 (K2 + dK2)) q = f``. A term is one entry of
dC1, dD, dK0 or dK2, named ``<matrix>_<equation>_<coordinate>``: ``K0_steer_steer`` is a steer
torque per steer angle [N m/rad] (a steer spring), ``D_roll_roll`` a roll torque per roll rate
[N m s/rad] (roll damping). They let a diagnosis say which form the model's error has when no
physical cause explains it (:mod:`whipple.diagnosis.model_terms`); they exist in the linear model
only. The mass matrix has no terms: an added inertia is a body, and the physical causes hold it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: The matrices a term may enter, with the power of the speed that multiplies them.
TERM_MATRICES = {"C1": 1, "D": 0, "K0": 0, "K2": 2}
#: Units of a term of each matrix (roll and steer are both angles).
TERM_UNITS = {"C1": "N s^2/rad", "D": "N m s/rad", "K0": "N m/rad", "K2": "N s^2/(m rad)"}
COORDINATES = ("roll", "steer")
TERM_NAMES = tuple(f"{matrix}_{row}_{column}" for matrix in TERM_MATRICES for row in COORDINATES
                   for column in COORDINATES)
#: Largest magnitude of a term of anything like a bicycle (beyond it, a unit or typing error).
LARGEST_TERM = 1e6


def term_parts(name: str) -> tuple[str, str, str]:
    """Return the matrix, equation and coordinate of a term name (``K0_steer_steer``: K0, steer, steer)."""
    matrix, row, column = name.split("_")
    return matrix, row, column


@dataclass(frozen=True)
class LinearTerms:
    """Entries added to C1, D, K0 and K2 (TOML table ``[extensions.linear_terms]``).

    Attributes
    ----------
    entries : tuple of (str, float)
        Term name (one of ``TERM_NAMES``) and value, units ``TERM_UNITS`` of its matrix; sorted
        by name, zeros left out.
    """

    entries: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        unknown = [name for name, _ in self.entries if name not in TERM_NAMES]
        if unknown:
            raise ValueError(f"unknown linear term(s) {', '.join(unknown)}; known: {', '.join(TERM_NAMES)}")
        entries = tuple(sorted((name, float(value)) for name, value in self.entries if value != 0.0))
        object.__setattr__(self, "entries", entries)

    @classmethod
    def from_mapping(cls, values: Mapping[str, float]) -> LinearTerms:
        """Return the terms of a mapping of term name to value."""
        return cls(tuple(values.items()))

    def as_dict(self) -> dict[str, float]:
        """Return term name to value (the TOML table)."""
        return dict(self.entries)

    def matrix(self, name: str) -> NDArray[np.float64]:
        """Return the 2 x 2 matrix of terms added to ``name`` (C1, D, K0 or K2)."""
        added = np.zeros((2, 2))
        for term, value in self.entries:
            matrix, row, column = term_parts(term)
            if matrix == name:
                added[COORDINATES.index(row), COORDINATES.index(column)] += value
        return added

    def feedback_coefficients(self) -> list[NDArray[np.float64]]:
        """Return the same terms as state feedback ``f = sum_k v^k F_k [q, q']`` (F_k of shape (2, 4)).

        For models whose matrices are not assembled from M, C1, D, K0, K2 (tyre states, the
        CasADi expressions): the terms move to the right-hand side with their sign changed.
        """
        coefficients = [np.zeros((2, 4)) for _ in range(3)]
        for name, power in TERM_MATRICES.items():
            columns = slice(0, 2) if name.startswith("K") else slice(2, 4)
            coefficients[power][:, columns] -= self.matrix(name)
        return coefficients


def term_findings(terms: LinearTerms | None) -> list[tuple[bool, str]]:
    """Problems of a bicycle's linear terms, as ``(is_bad, text)`` (not finite, implausibly large)."""
    if terms is None:
        return []
    return [(not math.isfinite(value) or abs(value) > LARGEST_TERM,
             f"extension linear term {name} = {value:.6g} is not a finite number of magnitude up to "
             f"{LARGEST_TERM:g}")
            for name, value in terms.entries]


def added_feedback(first: list[NDArray[np.float64]], second: list[NDArray[np.float64]]) -> list[NDArray[np.float64]]:
    """Return the sum of two feedbacks given as coefficient matrices by power of the speed."""
    total = [np.zeros((2, 4)) for _ in range(max(len(first), len(second)))]
    for coefficients in (first, second):
        for power, gain in enumerate(coefficients):
            total[power] = total[power] + gain
    return total
