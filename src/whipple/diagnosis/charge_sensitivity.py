"""Whether a named cause depends on how a model's extra modal amplitudes are charged.

Compared with the windows' samples, a model with more states than the base model (a tyre's
lateral slip, a controller's actuator) has that many more modal amplitudes fitted to every
window, and the evidence charges them (:meth:`~whipple.diagnosis.samples.SampleComparison.amplitude_charge`):
as fitted values, ln(n_w)/2 each (``"bic"``), or as what an amplitude fitted to pure noise
gains, 1/2 each (``"noise"``). Both are defensible and neither is right everywhere: the BIC's
charge took a true tyre compliance's name away on the ground (a front load named instead),
the noise charge named a tyre compliance in 7 of 30 effect-free trials of the controlled
bicycles, where the fast extra modes absorb what starts each window
(``benchmarks/results/diagnosis-log.md``). Where the two charges rank the causes differently,
the data do not decide between them: the verdict should not be a confident name, and an
ambiguous verdict should list the cause the other charge puts first among its rivals.

The check is symmetric: each fit's evidence is also computed under the charge the options do
not use (the other of :data:`~whipple.diagnosis.options.AMPLITUDE_CHARGES`). The BIC's charge
is the larger, so under the noise charge only a model with more states than the leader can
gain on it, and under the BIC's charge only one with fewer.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from whipple.diagnosis.families import components
from whipple.diagnosis.fitting import CauseFit
from whipple.diagnosis.options import VerdictRules

__all__ = ["other_charge", "charge_checked", "charge_rivals", "charge_reason"]

#: A verdict as :func:`whipple.diagnosis.evidence._verdict` returns it: verdict, leading cause, rivals, reasons.
Verdict = tuple[str, str, tuple[str, ...], tuple[str, ...]]

_WORDS = {"bic": "fitted values (ln(n)/2 each, n the window's residuals)",
          "noise": "what they gain on noise alone (1/2 each)"}


def other_charge(how: str) -> str:
    """Return the amplitude charge the options do not use (``"bic"`` <-> ``"noise"``)."""
    return "noise" if how == "bic" else "bic"


def charge_checked(verdict: Verdict, scored: Sequence[CauseFit], recharged: Sequence[CauseFit],
                   rules: VerdictRules, how: str) -> Verdict:
    """Return the verdict, made ``ambiguous`` (or given more rivals) where the leader depends on the amplitude charge.

    Parameters
    ----------
    verdict : tuple
        The verdict, leading cause, rivals and reasons under the options' charge.
    scored : sequence of CauseFit
        The causes by decreasing evidence under the options' charge, the leader first.
    recharged : sequence of CauseFit
        The same causes with their evidence under the other charge (:func:`other_charge`).
    rules : VerdictRules
        ``charge_sensitivity`` (False: the verdict unchanged) and ``margin``.
    how : str
        The charge the options use, ``"bic"`` or ``"noise"``.

    Returns
    -------
    tuple
        The verdict unchanged unless some cause with another number of states would lead or come
        within ``margin`` of the leader under the other charge (:func:`charge_rivals`): a
        ``named`` verdict then becomes ``ambiguous``, those causes its rivals, and why in words;
        an ``ambiguous`` one keeps its leader and reasons and gains those causes among its rivals
        (the ones not there yet) and the reason. ``none`` is left as it is.
    """
    state, name, rivals_before, reasons = verdict
    if state not in ("named", "ambiguous") or not rules.charge_sensitivity:
        return verdict
    other = {fit.cause: fit for fit in recharged}
    rivals = [fit for fit in charge_rivals(scored, other, rules.margin) if fit.cause not in rivals_before]
    if not rivals:
        return verdict
    reason = charge_reason(other[name], rivals, how)
    if state == "named":
        return "ambiguous", name, tuple(fit.cause for fit in rivals), (reason,)
    return "ambiguous", name, (*rivals_before, *(fit.cause for fit in rivals)), (*reasons, reason)


def charge_rivals(scored: Sequence[CauseFit], other: Mapping[str, CauseFit], margin: float) -> list[CauseFit]:
    """Return the causes that would rival the leader were the extra amplitudes charged the other way.

    Parameters
    ----------
    scored : sequence of CauseFit
        The causes by decreasing evidence under the options' charge, the leader first.
    other : mapping of str to CauseFit
        Each cause's fit with its evidence under the other charge (by cause name).
    margin : float
        The verdict rules' margin: a rival within it of the leader under the other charge counts.

    Returns
    -------
    list of CauseFit
        Their fits under the other charge, by decreasing evidence: causes with another number of
        states than the leader whose evidence there comes within ``margin`` of the leader's (a
        pair holding the leader is no rival: it only adds a second cause to it).
    """
    if not scored or scored[0].cause not in other:
        return []
    leader = other[scored[0].cause]
    rivals = [other[fit.cause] for fit in scored[1:] if fit.cause in other
              and leader.cause not in components(fit.cause)]
    rivals = [fit for fit in rivals if fit.states != leader.states and fit.evidence > leader.evidence - margin]
    return sorted(rivals, key=lambda fit: -fit.evidence)


def charge_reason(leader: CauseFit, rivals: Sequence[CauseFit], how: str) -> str:
    """Say in words why the leader depends on the charge ``how`` the options use.

    ``leader`` and ``rivals``: their fits under the other charge (:func:`charge_rivals`).
    """
    rival = rivals[0]
    extra = rival.states - leader.states
    fits = "fits the samples better" if rival.chi2 < leader.chi2 else "fits the samples"
    lead = "leads" if rival.evidence > leader.evidence else f"comes within the margin of {leader.cause}"
    others = f" (also {', '.join(fit.cause for fit in rivals[1:])})" if len(rivals) > 1 else ""
    whose = "its" if extra > 0 else f"{leader.cause}'s"
    return (f"{rival.cause}{others} {fits} (chi-square {rival.chi2:.4g} against {leader.cause}'s {leader.chi2:.4g}) "
            f"and {lead} when {whose} {abs(extra)} extra modal amplitudes per window are charged as "
            f"{_WORDS[other_charge(how)]} rather than as {_WORDS[how]}: the data do not decide between them")
