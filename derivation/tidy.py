"""Canonical, compact forms of the derived coefficients.

The kinematics produce polynomials in sin(lam) and cos(lam) that hide the identity
sin^2 + cos^2 = 1. Reducing each numerator modulo that identity (a Groebner-basis division,
with cos above sin) gives every expression at most linear in cos(lam): exact, canonical and
fast, where ``trigsimp`` would take tens of seconds and still not be canonical.
"""

from __future__ import annotations

import sympy as sm


def tidy(expr: sm.Expr, angle: sm.Symbol) -> sm.Expr:
    """Rewrite ``expr`` with sin/cos of ``angle`` reduced modulo sin^2 + cos^2 = 1."""
    sine, cosine = sm.symbols("_sin_angle _cos_angle", real=True)
    polynomial = sm.together(expr.xreplace({sm.sin(angle): sine, sm.cos(angle): cosine}))
    numerator, denominator = sm.fraction(polynomial)
    identity = [cosine**2 + sine**2 - 1]
    _, numerator = sm.reduced(sm.expand(numerator), identity, cosine, sine, order="lex")
    _, denominator = sm.reduced(sm.expand(denominator), identity, cosine, sine, order="lex")
    result = sm.factor_terms(sm.cancel(numerator / denominator))
    return result.xreplace({sine: sm.sin(angle), cosine: sm.cos(angle)})
