"""Check the generated equations against published matrices.

The published sets ship with the package (``whipple/data/reference``). Each entry is compared
with the value computed through the CasADi functions, with an absolute tolerance set by how
the reference was printed: the benchmark (Meijaard et al. 2007) to 14 decimals, so 1e-12
leaves room only for floating-point evaluation; the seed paper (Kooijman & Schwab 2009) to 5
decimals, so half a unit of the fifth decimal. The NumPy code is cross-checked against CasADi.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib import resources

import numpy as np

from whipple.model.assembly import MODEL_PARAMETERS, whipple_matrices
from whipple.model.casadi_model import casadi_matrices

__all__ = ["MATRIX_NAMES", "ReferenceSet", "EntryCheck", "VerificationResult", "reference_sets", "verify"]

MATRIX_NAMES = ("M", "C1", "K0", "K2")


@dataclass(frozen=True)
class ReferenceSet:
    """A published parameter set with its matrices (K0 including gravity)."""

    name: str
    citation: str
    parameters: dict[str, float]
    matrices: dict[str, np.ndarray]
    tolerance: float
    tolerance_reason: str


@dataclass(frozen=True)
class EntryCheck:
    """One matrix entry: published value, computed value, absolute error, tolerance."""

    matrix: str
    row: int
    column: int
    published: float
    computed: float
    error: float
    tolerance: float

    @property
    def passed(self) -> bool:
        """Whether the error is within the tolerance."""
        return self.error <= self.tolerance


@dataclass(frozen=True)
class VerificationResult:
    """All entries of one reference set, and the NumPy-versus-CasADi discrepancy."""

    reference: ReferenceSet
    entries: tuple[EntryCheck, ...]
    numpy_casadi_difference: float

    @property
    def passed(self) -> bool:
        """Whether every entry passes and NumPy agrees with CasADi."""
        # NumPy and CasADi evaluate the same expressions: they may differ by rounding only.
        return all(entry.passed for entry in self.entries) and self.numpy_casadi_difference < 1e-12

    def to_dict(self) -> dict:
        """Return the result as JSON-ready data."""
        return {
            "reference": self.reference.name,
            "citation": self.reference.citation,
            "tolerance": self.reference.tolerance,
            "tolerance_reason": self.reference.tolerance_reason,
            "passed": self.passed,
            "numpy_casadi_max_difference": self.numpy_casadi_difference,
            "entries": [
                {"matrix": e.matrix, "row": e.row, "column": e.column, "published": e.published,
                 "computed": e.computed, "error": e.error, "tolerance": e.tolerance,
                 "passed": e.passed}
                for e in self.entries
            ],
        }


def _load(file_name: str) -> dict:
    text = resources.files("whipple.data").joinpath("reference", file_name).read_text("utf-8")
    return tomllib.loads(text)


def reference_sets() -> tuple[ReferenceSet, ...]:
    """Return the published sets shipped with the package.

    Returns
    -------
    tuple of ReferenceSet
        The benchmark of Meijaard et al. (2007) and the bicycle of Kooijman & Schwab (2009), each
        with its parameters and published matrices.
    """
    benchmark = _load("meijaard2007-benchmark.toml")
    g = benchmark["parameters"]["g"]
    # The benchmark prints K0 without gravity; the package's K0 includes it.
    benchmark_matrices = {name: np.array(benchmark["matrices"][name], dtype=float) for name in MATRIX_NAMES}
    benchmark_matrices["K0"] = benchmark_matrices["K0"] * g
    seed = _load("kooijman2008-instrumented-bicycle.toml")
    return (
        ReferenceSet(
            "benchmark",
            "Meijaard, Papadopoulos, Ruina & Schwab (2007), Proc. R. Soc. A 463, Table 1 and section 4",
            dict(benchmark["parameters"]), benchmark_matrices, 1e-12,
            "printed to 14 decimals; K0 multiplied by g"),
        ReferenceSet(
            "kooijman2008",
            "Kooijman & Schwab (2009), DETC2009-86965, equation (2)",
            dict(seed["parameters"]),
            {name: np.array(seed["matrices"][name], dtype=float) for name in MATRIX_NAMES},
            0.5e-5 + 1e-12, "printed to 5 decimals: half a unit of the fifth decimal"),
    )


def verify(reference: ReferenceSet) -> VerificationResult:
    """Evaluate the generated CasADi and NumPy code at a reference set and compare.

    Parameters
    ----------
    reference : ReferenceSet
        A published set (:func:`reference_sets`).

    Returns
    -------
    VerificationResult
        Every published entry compared with the generated CasADi code, and the largest
        difference between the NumPy and CasADi code; ``passed`` says whether all agree.
    """
    vector = np.array([reference.parameters[name] for name in MODEL_PARAMETERS])
    computed = {name: np.array(value, dtype=float)
                for name, value in zip(MATRIX_NAMES, casadi_matrices(vector), strict=True)}
    numeric = whipple_matrices(reference.parameters)
    difference = max(float(np.max(np.abs(getattr(numeric, name) - computed[name])))
                     for name in MATRIX_NAMES)
    entries = []
    for name in MATRIX_NAMES:
        for row in range(2):
            for column in range(2):
                published = float(reference.matrices[name][row, column])
                value = float(computed[name][row, column])
                entries.append(EntryCheck(name, row, column, published, value,
                                          abs(value - published), reference.tolerance))
    return VerificationResult(reference, tuple(entries), difference)
