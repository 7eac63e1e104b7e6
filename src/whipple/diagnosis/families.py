"""Families of causes that change the same physics, and causes combined in pairs.

A family groups candidate causes that act on the bicycle through the same physical quantity
(the front assembly's inertia about the steer axis, the rear frame's mass distribution, ...).
Weave eigenvalues and mode shapes often cannot tell the members of a family apart; when the
diagnosis cannot, it names the family in physical words rather than one member
(:func:`describe_family`). Each cause declares its families (:mod:`whipple.diagnosis.registry`);
the table of families and their members is built from those declarations.

A combination is two causes fitted jointly (:func:`combined_cause`): the diagnosis tries the
few leading pairs when no single cause explains the data within its uncertainty.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.model_terms import is_term, term_words
from whipple.diagnosis.registry import FAMILIES, CauseDeclaration, Family, declarations, ungrouped
from whipple.model.fleet import Model

#: Separator of the two causes in a combination's name, e.g. ``"steer_damping + speed_scale"``.
COMBINATION = " + "


@dataclass(frozen=True)
class FamilyMembers:
    """A family with the causes declared in it.

    Attributes
    ----------
    family : Family
        Its key and words.
    members : tuple of str
        Cause names (``parameter:<key>`` for a wrong benchmark parameter).
    """

    family: Family
    members: tuple[str, ...]

    @property
    def key(self) -> str:
        """The family's short identifier."""
        return self.family.key

    @property
    def words(self) -> str:
        """The family's physical quantity in words."""
        return self.family.words


def family_table(extra: Sequence[CauseDeclaration] = ()) -> tuple[FamilyMembers, ...]:
    """Return every family with its members, most specific first.

    The package's families (:data:`~whipple.diagnosis.registry.FAMILIES`) in their order, then
    families that ``extra`` declarations bring, in their order; members in declaration order.
    """
    every = declarations(extra)
    order = list(FAMILIES)
    for declaration in every:
        order += [family for family in declaration.family_objects if family.key not in {f.key for f in order}]
    return tuple(FamilyMembers(family, tuple(d.name for d in every
                                             if family.key in {f.key for f in d.family_objects}))
                 for family in order)


def components(name: str) -> tuple[str, ...]:
    """Return the single causes of a name: one, or two for a combination."""
    return tuple(name.split(COMBINATION))


def families_of(name: str, extra: Sequence[CauseDeclaration] = ()) -> tuple[FamilyMembers, ...]:
    """Return the families a single cause belongs to, most specific first (empty for an undeclared name).

    A cause of one group of an experiment (``controller_gain[mm_on]``) belongs to its cause's families.
    """
    return tuple(family for family in family_table(extra) if ungrouped(name) in family.members)


def common_family(names: Sequence[str], extra: Sequence[CauseDeclaration] = ()) -> FamilyMembers | None:
    """Return the first family holding every single cause of every name, or None."""
    singles = {ungrouped(single) for name in names for single in components(name)}
    for family in family_table(extra):
        if singles <= set(family.members):
            return family
    return None


def _listing(names: Sequence[str]) -> str:
    names = list(dict.fromkeys(names))
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def describe_family(names: Sequence[str], extra: Sequence[CauseDeclaration] = ()) -> str:
    """Say in physical words what causes the data cannot tell apart have in common.

    For example "extra inertia of the front assembly about the steer axis: steer_inertia or
    parameter:IHzz"; "causes that predict the observations alike: A or B" when they share no
    family.
    """
    if not names:
        return ""
    family = common_family(names, extra)
    if family is not None:
        words = family.words
    elif len(set(names)) == 1:
        words = describe_cause(names[0], extra)
    else:
        words = "causes that predict the observations alike"
    return f"{words}: {_listing(names)}"


def describe_cause(name: str, extra: Sequence[CauseDeclaration] = ()) -> str:
    """Say in physical words what a cause (or each cause of a combination) changes."""
    parts = []
    for single in components(name):
        found = families_of(single, extra)
        parts.append(found[0].words if found else term_words(single) if is_term(single) else single)
    return " together with ".join(parts)


def combined_cause(first: Cause, second: Cause) -> Cause:
    """Return the two causes fitted jointly: values of the first, then of the second.

    The prior is the product of the two priors (two independent errors); the evidence charges
    the combination for all its fitted values.
    """
    split = len(first.parameters)

    def apply(bicycle: Model, values: Sequence[float]) -> Model:
        return second.apply(first.apply(bicycle, values[:split]), values[split:])

    null = None if first.null is None or second.null is None else first.null + second.null
    priors = (None if first.value_priors is None or second.value_priors is None
              else first.value_priors + second.value_priors)
    return Cause(first.name + COMBINATION + second.name, first.parameters + second.parameters,
                 first.units + second.units, first.start + second.start, first.bounds + second.bounds, apply,
                 prior=first.prior * second.prior, null=null, value_priors=priors)


def general_forms(causes: Sequence[Cause], refinements: bool = True) -> list[Cause]:
    """One form per cause name, the one with the most fitted values (e.g. a payload at any position).

    ``refinements`` False: leave out the forms that refine another (``Cause.refines``; a rigid
    load, whose own inertia a second cause's inertia would trade against), unless a cause has no
    other form.
    """
    chosen: dict[str, Cause] = {}
    for cause in causes:
        if not refinements and cause.refines is not None and any(
                other.name == cause.name and other.refines is None for other in causes):
            continue
        if cause.name not in chosen or len(cause.parameters) > len(chosen[cause.name].parameters):
            chosen[cause.name] = cause
    return list(chosen.values())


def cause_pairs(causes: Sequence[Cause]) -> list[Cause]:
    """Every pair of distinct causes, fitted jointly.

    Each in its most general form that refines no other (a payload at any position, a point
    mass: a pair's second cause takes up what a rigid load's own inertia would, so the rigid
    form would only add values that trade against it).
    """
    forms = general_forms(causes, refinements=False)
    return [combined_cause(first, second) for k, first in enumerate(forms) for second in forms[k + 1:]]
