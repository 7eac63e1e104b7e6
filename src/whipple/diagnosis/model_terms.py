"""Model terms as candidates: the form of an error when no physical cause has it.

Each term is one entry added to C1, D, K0 or K2 of the linear equations
(:mod:`whipple.model.linear_terms`): a steer spring is ``K0_steer_steer``, roll damping
``D_roll_roll``. They are no physical explanation, but they compete with the physical causes
for the evidence: when the truth is none of the physical candidates, one of them often fits
nearly as well as the truth (in 150 hidden-effect trials of a steer spring, a physical cause
was named with confidence in 102, a front-frame load in 81), while the term of the truth's
form mostly fits better still (8 wrong names remained; docs/diagnosis.md, "Model terms"). A
leading term therefore turns a confident wrong name into the statement "the error has the form
of a steer spring, which no candidate cause has" (verdict ``ambiguous``,
:mod:`whipple.diagnosis.evidence`).

Left out: the terms a declared cause is exactly (``D_steer_steer`` is the candidate
``steer_damping``; :attr:`whipple.diagnosis.registry.CauseDeclaration.terms`), and the mass
matrix, whose changes are bodies (the payload and inertia causes).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.priors import Prior
from whipple.diagnosis.registry import CauseDeclaration, add_terms, candidate_causes, claimed_terms
from whipple.model.assembly import model_matrices
from whipple.model.fleet import Model
from whipple.model.linear_terms import COORDINATES, TERM_MATRICES, TERM_NAMES, TERM_UNITS, term_parts

#: Prefix of a term's cause name, e.g. ``term:K0_steer_steer``.
PREFIX = "term:"
#: Speed [m/s] at which a term's bounds are compared with the bicycle's own stiffness and damping.
REFERENCE_SPEED = 5.0
#: What each kind of term would be, in physical words (diagonal, then coupling terms).
_WORDS = {
    ("K0", True): "a {row} spring (a {row} stiffness independent of speed: e.g. {example})",
    ("K0", False): "a {row} torque per {column} angle independent of speed",
    ("K2", True): "a {row} stiffness growing with the speed squared",
    ("K2", False): "a {row} torque per {column} angle growing with the speed squared",
    ("D", True): "{row} damping (a {row} torque per {row} rate independent of speed: e.g. {example})",
    ("D", False): "a {row} torque per {column} rate independent of speed (a feedback of the {column} rate)",
    ("C1", True): "{row} damping growing with the speed",
    ("C1", False): "a {row} torque per {column} rate growing with the speed",
}
_EXAMPLES = {("K0", "roll"): "a harness or a rider's support", ("K0", "steer"): "a steering stabiliser or cables",
             ("D", "roll"): "air, the tyres or a rider's passive sway"}


def is_term(name: str) -> bool:
    """Return True for a model term's cause name (``term:<matrix>_<row>_<column>``)."""
    return name.startswith(PREFIX)


def term_words(name: str) -> str:
    """Say in physical words what a model term (cause name or term name) adds to the equations."""
    matrix, row, column = term_parts(name.removeprefix(PREFIX))
    words = _WORDS[(matrix, row == column)].format(row=row, column=column,
                                                   example=_EXAMPLES.get((matrix, row), "an effect not modelled"))
    return f"{words}, {matrix}[{row}, {column}]"


def term_causes(bicycle: Model, extra: Sequence[CauseDeclaration] = (), priors: bool = False) -> list[Cause]:
    """Return one cause per model term no declared cause is, sharing one unit of prior weight.

    ``extra``: declarations besides the package's (their terms are left out too); ``priors``:
    give each term a prior, normal about 0 with half its bound.

    Bounds: +/- the bicycle's own scale of that entry at ``REFERENCE_SPEED`` V (for
    stiffness S = |diag(K0 + V^2 K2)|, the geometric mean of its row's and column's entries;
    for damping the critical damping 2 sqrt(S M) likewise), divided by V^k for a term
    multiplied by v^k. Wide enough for a spring or damper as strong as the bicycle's own.
    """
    matrices = model_matrices(bicycle.parameters, bicycle.extensions)
    speed = REFERENCE_SPEED
    stiffness = np.abs(np.diagonal(matrices.K0 + speed**2 * matrices.K2))
    damping = 2.0 * np.sqrt(stiffness * np.abs(np.diagonal(matrices.M)))
    claimed = claimed_terms(extra)
    names = [name for name in TERM_NAMES if name not in claimed]
    bounds = {}
    for name in names:
        matrix, row, column = term_parts(name)
        i, j = COORDINATES.index(row), COORDINATES.index(column)
        own = stiffness if matrix.startswith("K") else damping
        bound = float(np.sqrt(own[i] * own[j])) / speed ** TERM_MATRICES[matrix]
        # An entry of no scale (a bicycle without mass has no stiffness) offers no term to fit.
        if bound > 0 and np.isfinite(bound):
            bounds[name] = bound
    causes = []
    for name, bound in bounds.items():
        matrix = term_parts(name)[0]
        # A term's prior: normal about 0 with half the bicycle's own scale of that entry.
        value_priors = (Prior("normal", 0.0, 0.5 * bound, "half the bicycle's own scale of the entry"),)
        causes.append(Cause(PREFIX + name, (name,), (TERM_UNITS[matrix],), (0.0,), ((-bound, bound),),
                            _adder(name), prior=1.0 / len(bounds), null=(0.0,),
                            value_priors=value_priors if priors else None))
    return causes


def candidates_with_terms(bicycle: Model, include_parameters: bool = True, *, rigid_loads: bool = True,
                          extra: Sequence[CauseDeclaration] = ()) -> list[Cause]:
    """Return the bicycle's candidate causes (:func:`~whipple.diagnosis.registry.candidate_causes`) and the terms."""
    return [*candidate_causes(bicycle, include_parameters, rigid_loads=rigid_loads, extra=extra),
            *term_causes(bicycle, extra)]


def _adder(name: str) -> Callable[[Model, Sequence[float]], Model]:
    def apply(bicycle: Model, values: Sequence[float]) -> Model:
        return add_terms(bicycle, **{name: float(values[0])})

    return apply
