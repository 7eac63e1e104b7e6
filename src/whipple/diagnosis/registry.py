"""The candidate causes, each declared in one place: how it changes the bicycle, its values, its family.

A :class:`CauseDeclaration` says everything the diagnosis needs of a cause: its vocabulary name;
how its fitted values change a bicycle, with their units, bounds, starting and no-effect values
and prior (its *forms*, :class:`~whipple.diagnosis.causes.Cause` objects built for a given
bicycle, since bounds depend on the bicycle's own masses and lengths); the physical families it
belongs to, whose words describe it when the data cannot tell it from its relatives
(:class:`Family`); and the model terms it is (a steer damping is the term ``D_steer_steer``,
which then does not compete as a term of its own).

:data:`REGISTRY` holds the package's causes. A cause that existing extensions or
:class:`~whipple.model.linear_terms.LinearTerms` can express is one more declaration, e.g. a
roll damping (docs: "Add a candidate cause")::

    roll_damping = declare(
        "roll_damping", Value("roll_damping", "N m s/rad", (0.0, 50.0)),
        apply=lambda bicycle, values: add_terms(bicycle, D_roll_roll=values[0]),
        families=(Family("roll_damping", "a roll torque resisting the roll rate (air, the tyres)"),),
        terms=("D_roll_roll",))
    whipple.diagnose(runs, bicycle, DiagnosisOptions(causes=(roll_damping,)))

A cause that needs new physics is derived in ``derivation/`` first (a new extension of the
equations), then declared here.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from whipple.diagnosis.causes import (
    BLAMEABLE_PARAMETERS,
    DEFAULT_CAMBER_STIFFNESS,
    Cause,
    parameter_cause,
    payload_form,
)
from whipple.diagnosis.priors import Prior, parameter_prior
from whipple.model.fleet import Fleet, Model
from whipple.model.linear_terms import TERM_NAMES, LinearTerms
from whipple.model.parameters import Bicycle, TyreCompliance

__all__ = ["KINDS", "Family", "FormChoices", "CauseDeclaration", "Value", "declare", "add_terms", "FAMILIES",
           "GROUP_SUFFIX", "ungrouped", "TYRE_PRIORS", "payload_causes", "PARAMETER_FAMILIES", "CALIBRATION",
           "REGISTRY", "declarations", "candidate_causes", "cause_by_name", "claimed_terms"]

#: Kinds of declaration: ``physical`` causes, ``controller`` causes (a bicycle with a controller
#: only; each group of an experiment has its own), ``parameter`` (one wrong benchmark parameter),
#: ``calibration`` (every measured parameter off within its uncertainty; only with priors).
KINDS = ("physical", "controller", "parameter", "calibration")


@dataclass(frozen=True)
class Family:
    """Causes acting through one physical quantity.

    Attributes
    ----------
    key : str
        Short identifier, e.g. ``"steer_axis_inertia"``.
    words : str
        The quantity in physical words, e.g. "extra inertia of the front assembly about the
        steer axis": how a verdict describes the causes the data cannot tell apart.
    """

    key: str
    words: str


@dataclass(frozen=True)
class FormChoices:
    """What a diagnosis' options choose among a cause's forms.

    Attributes
    ----------
    rigid_loads : bool
        Include the payloads' rigid-load form (a load with its own radii of gyration).
    priors : bool
        Give every value its physical prior (:mod:`whipple.diagnosis.priors`), and offer the
        calibration of every measured parameter within its uncertainty.
    """

    rigid_loads: bool = True
    priors: bool = False


@dataclass(frozen=True)
class CauseDeclaration:
    """One candidate cause, declared in one place.

    Attributes
    ----------
    name : str
        Vocabulary name (``parameter:<key>`` for a wrong parameter).
    forms : callable
        ``forms(bicycle, choices) -> list of Cause``: the cause's forms for a bicycle (values,
        units, bounds, starts, no-effect values, prior shared by the forms), none where the
        cause does not apply (a controller cause of a bicycle without one).
    families : tuple of Family or str
        The families it belongs to, most specific first (a str names a family of
        :data:`FAMILIES`); at least one, so that a verdict can say in physical words what it is.
    kind : str
        One of :data:`KINDS`.
    terms : tuple of str
        The model terms (:data:`~whipple.model.linear_terms.TERM_NAMES`) the cause is exactly:
        they do not compete as terms of their own.
    """

    name: str
    forms: Callable[[Model, FormChoices], Sequence[Cause]]
    families: tuple[Family | str, ...]
    kind: str = "physical"
    terms: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        problems = []
        if not self.name or not isinstance(self.name, str) or " + " in self.name or self.name.startswith("term:"):
            problems.append(f"a cause needs a name without ' + ' or 'term:', got {self.name!r}")
        if not self.families:
            problems.append(f"cause {self.name!r} names no family: a verdict could not say what it changes")
        known = {family.key for family in FAMILIES}
        unknown = [family for family in self.families if isinstance(family, str) and family not in known]
        if unknown:
            problems.append(f"cause {self.name!r}: unknown family {', '.join(unknown)} (known: {', '.join(known)})")
        if self.kind not in KINDS:
            problems.append(f"cause {self.name!r}: kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        bad_terms = [term for term in self.terms if term not in TERM_NAMES]
        if bad_terms:
            problems.append(f"cause {self.name!r}: unknown model term {', '.join(bad_terms)}")
        if problems:
            raise ValueError("; ".join(problems))

    @property
    def family_objects(self) -> tuple[Family, ...]:
        """The cause's families as :class:`Family` objects."""
        table = {family.key: family for family in FAMILIES}
        return tuple(table[family] if isinstance(family, str) else family for family in self.families)


@dataclass(frozen=True)
class Value:
    """One fitted value of a cause with a single form.

    Attributes
    ----------
    name : str
        The value's name (reported with its estimate).
    unit : str
        Its unit ("" for a factor).
    bounds : tuple of float
        Its physical bounds, in ``unit``.
    null : float
        The value at which the cause changes nothing (also the fit's start).
    prior : Prior or None
        What the value physically is on bicycles, before the data (:class:`~whipple.diagnosis.priors.Prior`);
        None: no prior (the evidence then charges the value the BIC's ln(n)/2).
    """

    name: str
    unit: str
    bounds: tuple[float, float]
    null: float = 0.0
    prior: Prior | None = None


def declare(name: str, value: Value, apply: Callable[[Model, Sequence[float]], Model], *,
            families: tuple[Family | str, ...], kind: str = "physical", terms: tuple[str, ...] = (),
            applies: Callable[[Model], bool] | None = None) -> CauseDeclaration:
    """Return the declaration of a cause with one value and one form, the commonest kind.

    Parameters
    ----------
    name : str
        Vocabulary name.
    value : Value
        Its fitted value, unit, bounds and no-effect value.
    apply : callable
        ``apply(bicycle, values) -> Bicycle``: the bicycle with the cause at ``values[0]``.
    families, kind, terms
        As in :class:`CauseDeclaration`.
    applies : callable, optional
        ``applies(bicycle) -> bool``: whether the cause exists for a bicycle (default: always).

    Returns
    -------
    CauseDeclaration
    """
    def forms(bicycle: Model, choices: FormChoices) -> list[Cause]:
        if applies is not None and not applies(bicycle):
            return []
        priors = (value.prior,) if choices.priors and value.prior is not None else None
        return [Cause(name, (value.name,), (value.unit,), (value.null,), (value.bounds,), apply, null=(value.null,),
                      value_priors=priors)]

    return CauseDeclaration(name, forms, families, kind, terms)


def add_terms(bicycle: Model, **terms: float) -> Model:
    """Return the bicycle with values added to its model terms (``D_roll_roll=0.8``, units of each term)."""
    total = (bicycle.extensions.linear_terms or LinearTerms()).as_dict()
    for name, value in terms.items():
        total[name] = total.get(name, 0.0) + float(value)
    return bicycle.with_extensions(linear_terms=LinearTerms.from_mapping(total))


#: The families, most specific first: a cause may belong to several (a front-frame inertia
#: parameter changes both the steer-axis inertia and the front assembly's mass distribution);
#: the first family holding every cause a verdict leaves open describes them.
FAMILIES: tuple[Family, ...] = (
    Family("steer_axis_inertia", "extra inertia of the front assembly about the steer axis"),
    Family("steer_torque_dynamics", "a steer torque that resists or lags the steer motion (steer damping, "
           "actuator or controller dynamics)"),
    Family("controller", "the steer controller's strength or timing"),
    Family("front_mass", "the front assembly's mass distribution (a load on the front frame)"),
    Family("rear_mass", "the rear frame's mass distribution (a load on the rear frame)"),
    Family("wheel_spin", "the wheels' spin angular momentum (gyroscopic coupling)"),
    Family("geometry", "the steering geometry (wheelbase, trail, head angle)"),
    Family("speed", "the speed measurement"),
    Family("tyre", "the tyre-road contact (lateral tyre compliance)"),
    Family("calibration", "the measured parameters, each off within its measurement uncertainty"),
)


def _steer_damping(bicycle: Model, values: Sequence[float]) -> Model:
    return bicycle.with_extensions(steer_damping=bicycle.extensions.steer_damping + float(values[0]))


def _steer_friction(bicycle: Model, values: Sequence[float]) -> Model:
    return bicycle.with_extensions(steer_friction=bicycle.extensions.steer_friction + float(values[0]))


def _steer_inertia(bicycle: Model, values: Sequence[float]) -> Model:
    return bicycle.with_extensions(steer_inertia=bicycle.extensions.steer_inertia + float(values[0]))


def _reflected_steer_inertia(bicycle: Model, values: Sequence[float]) -> Model:
    return bicycle.with_extensions(
        reflected_steer_inertia=bicycle.extensions.reflected_steer_inertia + float(values[0]))


def _speed_scale(bicycle: Model, values: Sequence[float]) -> Model:
    return bicycle.with_extensions(speed_scale=bicycle.extensions.speed_scale * float(values[0]))


def _controller_gain(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, gain_scale=controller.gain_scale * float(values[0])))


def _controller_delay(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, delay=controller.delay + float(values[0])))


def _controller_lag(bicycle: Bicycle, values: Sequence[float]) -> Bicycle:
    controller = bicycle.controller
    return bicycle.with_controller(replace(controller, lag=controller.lag + float(values[0])))


#: How a group-scoped cause's name holds its group: ``controller_gain[mm_on]``.
GROUP_SUFFIX = "[{group}]"


def _controller_forms(name: str, value: Value, apply: Callable[[Bicycle, Sequence[float]], Bicycle]
                      ) -> Callable[[Model, FormChoices], list[Cause]]:
    """Return the forms builder of a controller cause: one for a controlled bicycle, one per controlled group.

    The groups of an experiment share every physical property but each has its own controller,
    so that a controller's error is a cause of one group (``controller_gain[mm_on]``), never of
    the others.
    """
    def forms(model: Model, choices: FormChoices) -> list[Cause]:
        priors = (value.prior,) if choices.priors and value.prior is not None else None
        if isinstance(model, Bicycle):
            if model.controller.is_empty():
                return []
            return [Cause(name, (value.name,), (value.unit,), (value.null,), (value.bounds,), _alone(apply),
                          null=(value.null,), value_priors=priors)]
        return [Cause(name + GROUP_SUFFIX.format(group=group), (value.name + GROUP_SUFFIX.format(group=group),),
                      (value.unit,), (value.null,), (value.bounds,), _in_group(group, apply), null=(value.null,),
                      value_priors=priors)
                for group, member in model.members if not member.controller.is_empty()]

    return forms


def _alone(apply: Callable[[Bicycle, Sequence[float]], Bicycle]) -> Callable[[Model, Sequence[float]], Model]:
    def applied(model: Model, values: Sequence[float]) -> Model:
        if not isinstance(model, Bicycle):
            raise TypeError("a controller cause of a bicycle applies to that bicycle, not to an experiment's groups")
        return apply(model, values)

    return applied


def _in_group(group: str, apply: Callable[[Bicycle, Sequence[float]], Bicycle]
              ) -> Callable[[Model, Sequence[float]], Model]:
    def applied(model: Model, values: Sequence[float]) -> Model:
        if not isinstance(model, Fleet):
            raise TypeError(f"a cause of group {group!r} applies to the experiment's fleet of bicycles")
        return model.with_member(group, apply(model.member(group), values))

    return applied


def ungrouped(name: str) -> str:
    """Return a cause's name without its group (``controller_gain[mm_on]``: ``controller_gain``)."""
    return name.split("[", 1)[0] if name.endswith("]") else name


def _tyre(bicycle: Model, values: Sequence[float]) -> Model:
    camber = (bicycle.extensions.tyre_compliance.camber_stiffness
              if bicycle.extensions.tyre_compliance is not None else DEFAULT_CAMBER_STIFFNESS)
    return bicycle.with_extensions(tyre_compliance=TyreCompliance(
        cornering_stiffness=float(values[0]), camber_stiffness=camber, relaxation_length=float(values[1])))


def _tyre_forms(bicycle: Model, choices: FormChoices) -> list[Cause]:
    # Cornering stiffness [1/rad] from very soft to nearly rigid, relaxation length [m] from a
    # few millimetres to a metre; the fit starts at a typical bicycle tyre's (12 /rad, 0.15 m).
    return [Cause("tyre_compliance", ("cornering_stiffness", "relaxation_length"), ("1/rad", "m"), (12.0, 0.15),
                  ((1.0, 500.0), (0.005, 1.0)), _tyre, value_priors=TYRE_PRIORS if choices.priors else None)]


#: Priors of the tyres' values: bicycle tyres' cornering stiffness per load measured at about
#: 8-20 /rad (median 12, within a factor 2.5 at one standard deviation), relaxation lengths of
#: a few to 25 centimetres (median 0.1 m, factor 2.5).
TYRE_PRIORS = (Prior("lognormal", 12.0, math.log(2.5), "bicycle tyres' measured cornering stiffness"),
               Prior("lognormal", 0.1, math.log(2.5), "bicycle tyres' measured relaxation lengths"))


def _payload_forms(name: str) -> Callable[[Model, FormChoices], list[Cause]]:
    """Return the forms builder of a load on the rear (``payload``) or front frame (``front_payload``).

    The mass alone at the frame's mass centre; mass and height (height changes the roll inertia,
    which a mass alone cannot mimic); mass and full position (a rack behind the saddle, a basket
    ahead of the steer axis: without this form such loads were named right in 0% and 6% of
    hidden-effect trials, with it in most; its mimicry of steer inertia or trail is reported as
    ``ambiguous`` by the families); and, with ``rigid_loads``, the same load as a rigid body with
    its own radii of gyration (:func:`~whipple.diagnosis.causes.payload_form`). The forms share the
    cause's one unit of prior weight, so that taking the best of them is not a free extra chance.
    """
    def forms(bicycle: Model, choices: FormChoices) -> list[Cause]:
        free = ("m", "mz", "mxz", "mxzk") if choices.rigid_loads else ("m", "mz", "mxz")
        return [payload_form(bicycle, name, form, prior=1.0 / len(free), priors=choices.priors) for form in free]

    return forms


def payload_causes(bicycle: Model, name: str, rigid: bool = True) -> list[Cause]:
    """Return the forms of a payload cause, ``payload`` (rear frame) or ``front_payload`` (front frame)."""
    return _payload_forms(name)(bicycle, FormChoices(rigid_loads=rigid))


def _parameter_forms(key: str) -> Callable[[Model, FormChoices], list[Cause]]:
    def forms(bicycle: Model, choices: FormChoices) -> list[Cause]:
        if key not in bicycle.parameters:
            return []
        # A wrong parameter is one hypothesis, whichever parameter: the keys share one unit of prior.
        keys = [k for k in BLAMEABLE_PARAMETERS if k in bicycle.parameters]
        return [parameter_cause(bicycle, key, 1.0 / len(keys), priors=choices.priors)]

    return forms


#: The families of each blameable benchmark parameter, most specific first.
PARAMETER_FAMILIES: dict[str, tuple[str, ...]] = {
    "w": ("geometry",), "c": ("geometry",), "lam": ("geometry",),
    "rR": ("wheel_spin",), "mR": ("rear_mass",), "IRxx": ("rear_mass",), "IRyy": ("wheel_spin",),
    "xB": ("rear_mass",), "zB": ("rear_mass",), "mB": ("rear_mass",), "IBxx": ("rear_mass",),
    "IBzz": ("rear_mass",), "IBxz": ("rear_mass",),
    "xH": ("front_mass", "geometry"), "zH": ("front_mass", "geometry"), "mH": ("front_mass",),
    "IHxx": ("steer_axis_inertia", "front_mass"), "IHzz": ("steer_axis_inertia", "front_mass"),
    "IHxz": ("steer_axis_inertia", "front_mass"),
    "rF": ("wheel_spin",), "mF": ("front_mass",), "IFxx": ("steer_axis_inertia", "front_mass"),
    "IFyy": ("wheel_spin",),
}

#: Name of the calibration candidate: every measured parameter fitted within its prior.
CALIBRATION = "calibration"


def _calibration_forms(model: Model, choices: FormChoices) -> list[Cause]:
    """Return the calibration's one form: every blameable parameter, each with its measurement prior.

    "The measured parameters are off": the parameters of a bicycle are measured (or estimated
    from other bicycles) with errors, and the data may be explained by all of them moving a
    little, each within its uncertainty, better than by any one named cause. Offered only where
    the evidence has priors (without them the many values would make it the best fit always).
    """
    if not choices.priors:
        return []
    keys = [key for key in BLAMEABLE_PARAMETERS if key in model.parameters]
    singles = [parameter_cause(model, key, 1.0) for key in keys]

    def apply(bicycle: Model, values: Sequence[float]) -> Model:
        return bicycle.with_parameters(**{key: float(value) for key, value in zip(keys, values, strict=True)})

    bounds = [_product_bounds(model, key) if key.endswith("xz") else single.bounds[0]
              for key, single in zip(keys, singles, strict=True)]
    return [Cause(CALIBRATION, tuple(keys), tuple(unit for single in singles for unit in single.units),
                  tuple(float(model.parameters[key]) for key in keys), tuple(bounds), apply,
                  null=tuple(float(model.parameters[key]) for key in keys),
                  value_priors=tuple(parameter_prior(key, model.parameters, model.uncertainty) for key in keys))]


def _product_bounds(model: Model, key: str) -> tuple[float, float]:
    """Return the bounds of a product of inertia, either sign.

    Its magnitude stays below the geometric mean of the two principal inertias beside it: the
    inertia tensor of a body is positive definite.
    """
    frame = key[1]
    limit = float(np.sqrt(abs(model.parameters[f"I{frame}xx"]) * abs(model.parameters[f"I{frame}zz"])))
    return -limit, limit


#: The package's candidate causes, in the order they are fitted and reported.
REGISTRY: tuple[CauseDeclaration, ...] = (
    # Viscous damping about the steer axis: bearings, cables, an actuator's back-EMF [N m s/rad].
    declare("steer_damping", Value("steer_damping", "N m s/rad", (0.0, 20.0),
                                   prior=Prior("halfnormal", 0.0, 1.0, "bearings, cables, a motor's back-EMF")),
            _steer_damping,
            families=("steer_torque_dynamics",), terms=("D_steer_steer",)),
    # Coulomb (dry) friction about the steer axis [N m]: headset seals and bearings, cables, a
    # motor's gears. Each window's model has its equivalent viscous damping at the window's
    # amplitude (whipple.model.steer_friction), so that only windows of different amplitudes
    # tell it from a steer damping. Prior: a half-normal of scale 0.5 N m, an engineering
    # estimate (tenths of a newton metre for sealed headsets), not a measured distribution.
    declare("steer_friction", Value("steer_friction", "N m", (0.0, 5.0),
                                    prior=Prior("halfnormal", 0.0, 0.5, "headset seals and bearings, cables, gears")),
            _steer_friction,
            families=("steer_torque_dynamics",)),
    # Rigid inertia about the steer axis not in the parameters: a motor's housing, a bag, a lamp.
    declare("steer_inertia", Value("steer_inertia", "kg m^2", (0.0, 2.0),
                                   prior=Prior("halfnormal", 0.0, 0.05, "a lamp, bag or motor housing")),
            _steer_inertia,
            families=("steer_axis_inertia", "front_mass")),
    # A geared motor's rotor inertia, reflected to the steer axis (steer equation only).
    declare("reflected_steer_inertia", Value("reflected_steer_inertia", "kg m^2", (0.0, 2.0),
                                             prior=Prior("halfnormal", 0.0, 0.15, "a geared motor's N^2 J")),
            _reflected_steer_inertia, families=("steer_axis_inertia",)),
    # The speed signal off by a factor (measured speed = factor x true speed).
    declare("speed_scale", Value("speed_scale", "", (0.5, 2.0), null=1.0,
                                 prior=Prior("lognormal", 1.0, 0.05, "speed sensors calibrated to a few percent")),
            _speed_scale, families=("speed",)),
    CauseDeclaration("payload", _payload_forms("payload"), ("rear_mass",)),
    CauseDeclaration("front_payload", _payload_forms("front_payload"), ("front_mass",)),
    CauseDeclaration("tyre_compliance", _tyre_forms, ("tyre",)),
    # The controller's commanded torque scaled [-], delayed [s] (Pade approximant in the linear
    # model) or passed through a first-order lag of that time constant [s].
    CauseDeclaration("controller_gain", _controller_forms("controller_gain", Value(
        "controller_gain", "", (0.2, 5.0), null=1.0,
        prior=Prior("lognormal", 1.0, 0.2, "an actuator's torque constant or amplifier gain")), _controller_gain),
                     ("steer_torque_dynamics", "controller"), kind="controller"),
    CauseDeclaration("controller_delay", _controller_forms("controller_delay", Value(
        "controller_delay", "s", (0.0, 0.3),
        prior=Prior("halfnormal", 0.0, 0.05, "sensing, computing and communication")), _controller_delay),
                     ("steer_torque_dynamics", "controller"), kind="controller"),
    CauseDeclaration("controller_lag", _controller_forms("controller_lag", Value(
        "controller_lag", "s", (0.0, 0.3), prior=Prior("halfnormal", 0.0, 0.05, "an actuator of a few Hz or more")),
        _controller_lag),
                     ("steer_torque_dynamics", "controller"), kind="controller"),
    *(CauseDeclaration(f"parameter:{key}", _parameter_forms(key), PARAMETER_FAMILIES[key], kind="parameter")
      for key in BLAMEABLE_PARAMETERS),
    CauseDeclaration(CALIBRATION, _calibration_forms, ("calibration",), kind="calibration"),
)


def declarations(extra: Sequence[CauseDeclaration] = ()) -> tuple[CauseDeclaration, ...]:
    """Return the package's declarations and ``extra`` ones (a name given twice is an error).

    Parameters
    ----------
    extra : sequence of CauseDeclaration
        Declarations added by the caller (e.g. ``DiagnosisOptions.causes``).

    Returns
    -------
    tuple of CauseDeclaration
        :data:`REGISTRY`, then ``extra``.
    """
    every = (*REGISTRY, *extra)
    names = [declaration.name for declaration in every]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice:
        raise ValueError(f"cause {twice[0]!r} is declared twice")
    return every


def candidate_causes(bicycle: Model, include_parameters: bool = True, *, rigid_loads: bool = True,
                     priors: bool = False, extra: Sequence[CauseDeclaration] = ()) -> list[Cause]:
    """Return every form of every declared cause for a bicycle, with starting values and bounds.

    Parameters
    ----------
    bicycle : Bicycle
        The base bicycle (bounds follow its masses and lengths; controller causes need a controller).
    include_parameters : bool
        Include ``parameter:<key>`` causes.
    rigid_loads : bool
        Include the payloads' rigid-load form.
    priors : bool
        Give every value its physical prior, and offer the calibration (:class:`FormChoices`).
    extra : sequence of CauseDeclaration
        More declarations (:func:`declarations`).

    Returns
    -------
    list of Cause
        In the order of the declarations.
    """
    choices = FormChoices(rigid_loads=rigid_loads, priors=priors)
    return [cause for declaration in declarations(extra)
            if include_parameters or declaration.kind not in ("parameter", "calibration")
            for cause in declaration.forms(bicycle, choices)]


def cause_by_name(bicycle: Model, name: str, extra: Sequence[CauseDeclaration] = ()) -> Cause:
    """Return the first form of the candidate cause called ``name`` (e.g. ``parameter:c``).

    Raises
    ------
    KeyError
        No declared cause has that name (or it does not apply to the bicycle).
    """
    forms = [cause for cause in candidate_causes(bicycle, extra=extra) if cause.name == name]
    if not forms:
        raise KeyError(name)
    return forms[0]


def claimed_terms(extra: Sequence[CauseDeclaration] = ()) -> dict[str, str]:
    """Return the model terms that declared causes are exactly, with the cause of each."""
    return {term: declaration.name for declaration in declarations(extra) for term in declaration.terms}
