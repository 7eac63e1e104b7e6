"""Families of causes that change the same physics, and causes combined in pairs.

A family groups candidate causes that act on the bicycle through the same physical quantity
(the front assembly's inertia about the steer axis, the rear frame's mass distribution, ...).
Weave eigenvalues and mode shapes often cannot tell the members of a family apart; when the
diagnosis cannot, it names the family in physical words rather than one member
(:func:`describe_family`). The table lists causes by name, including some a given bicycle or
branch may not offer (controller causes exist only for bicycles with a controller); names not
in the table fall back to a generic description.

A combination is two causes fitted jointly (:func:`combined_cause`): the diagnosis tries the
few leading pairs when no single cause explains the data within its uncertainty.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.model_terms import is_term, term_words
from whipple.model.parameters import Bicycle

#: Separator of the two causes in a combination's name, e.g. ``"steer_damping + speed_scale"``.
COMBINATION = " + "


@dataclass(frozen=True)
class Family:
    """Causes acting through one physical quantity.

    Attributes
    ----------
    key : str
        Short identifier, e.g. ``"steer_axis_inertia"``.
    words : str
        The quantity in physical words, e.g. "extra inertia of the front assembly about the
        steer axis".
    members : tuple of str
        Cause names (``parameter:<key>`` for a wrong benchmark parameter).
    """

    key: str
    words: str
    members: tuple[str, ...]


#: The families, most specific first: a cause may belong to several (a front-frame inertia
#: parameter changes both the steer-axis inertia and the front assembly's mass distribution);
#: :func:`common_family` takes the first family holding all the causes it is given.
FAMILIES: tuple[Family, ...] = (
    Family("steer_axis_inertia", "extra inertia of the front assembly about the steer axis",
           ("steer_inertia", "reflected_steer_inertia", "parameter:IHzz", "parameter:IHxx", "parameter:IHxz",
            "parameter:IFxx")),
    Family("steer_torque_dynamics", "a steer torque that resists or lags the steer motion (steer damping, "
           "actuator or controller dynamics)",
           ("steer_damping", "controller_lag", "controller_delay", "controller_gain")),
    Family("controller", "the steer controller's strength or timing",
           ("controller_gain", "controller_delay", "controller_lag")),
    Family("front_mass", "the front assembly's mass distribution (a load on the front frame)",
           ("front_payload", "parameter:mH", "parameter:xH", "parameter:zH", "parameter:IHxx", "parameter:IHzz",
            "parameter:IHxz", "parameter:mF", "parameter:IFxx", "steer_inertia")),
    Family("rear_mass", "the rear frame's mass distribution (a load on the rear frame)",
           ("payload", "parameter:mB", "parameter:xB", "parameter:zB", "parameter:IBxx", "parameter:IBzz",
            "parameter:IBxz", "parameter:mR", "parameter:IRxx")),
    Family("wheel_spin", "the wheels' spin angular momentum (gyroscopic coupling)",
           ("parameter:IFyy", "parameter:IRyy", "parameter:rF", "parameter:rR")),
    Family("geometry", "the steering geometry (wheelbase, trail, head angle)",
           ("parameter:w", "parameter:c", "parameter:lam", "parameter:xH", "parameter:zH")),
    Family("speed", "the speed measurement", ("speed_scale",)),
    Family("tyre", "the tyre-road contact (lateral tyre compliance)", ("tyre_compliance",)),
)


def components(name: str) -> tuple[str, ...]:
    """Return the single causes of a name: one, or two for a combination."""
    return tuple(name.split(COMBINATION))


def families_of(name: str) -> tuple[Family, ...]:
    """Return the families a single cause belongs to (empty for one not in the table)."""
    return tuple(family for family in FAMILIES if name in family.members)


def common_family(names: Sequence[str]) -> Family | None:
    """Return the first family holding every single cause of every name, or None."""
    singles = {single for name in names for single in components(name)}
    for family in FAMILIES:
        if singles <= set(family.members):
            return family
    return None


def _listing(names: Sequence[str]) -> str:
    names = list(dict.fromkeys(names))
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def describe_family(names: Sequence[str]) -> str:
    """Say in physical words what causes the data cannot tell apart have in common.

    For example "extra inertia of the front assembly about the steer axis: steer_inertia or
    parameter:IHzz"; "causes that predict the observations alike: A or B" when they share no
    family of the table.
    """
    if not names:
        return ""
    family = common_family(names)
    if family is not None:
        words = family.words
    elif len(set(names)) == 1:
        words = describe_cause(names[0])
    else:
        words = "causes that predict the observations alike"
    return f"{words}: {_listing(names)}"


def describe_cause(name: str) -> str:
    """Say in physical words what a cause (or each cause of a combination) changes."""
    parts = []
    for single in components(name):
        found = families_of(single)
        parts.append(found[0].words if found else term_words(single) if is_term(single) else single)
    return " together with ".join(parts)


def combined_cause(first: Cause, second: Cause) -> Cause:
    """Return the two causes fitted jointly: values of the first, then of the second.

    The prior is the product of the two priors (two independent errors); the evidence charges
    the combination for all its fitted values.
    """
    split = len(first.parameters)

    def apply(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
        return second.apply(first.apply(bicycle, values[:split]), values[split:])

    null = None if first.null is None or second.null is None else first.null + second.null
    return Cause(first.name + COMBINATION + second.name, first.parameters + second.parameters,
                 first.units + second.units, first.start + second.start, first.bounds + second.bounds, apply,
                 prior=first.prior * second.prior, null=null)


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
