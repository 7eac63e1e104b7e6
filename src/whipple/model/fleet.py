"""One physical bicycle in several set-ups: the groups of an experiment, which differ only by their controllers.

An experiment may measure one bicycle under several controllers (a steer-by-wire bicycle with
model matching off and on, a balance-assist bicycle at three gains). Every physical property is
shared; only the controller differs between the groups. A :class:`Fleet` holds the group's
bicycles and behaves as one bicycle for every physical change (``with_parameters``,
``with_extensions``: applied to every member alike), while a change of one group's controller
is made with :meth:`Fleet.with_member`. A model that is a Fleet is evaluated window by window
with the member of the window's group (:func:`members_of`).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.model.parameter_set import Bicycle, Extensions


@dataclass(frozen=True)
class Fleet:
    """One physical bicycle in several groups, each with its own controller.

    Attributes
    ----------
    members : tuple of (str, Bicycle)
        Each group's name and bicycle (with that group's controller). The bicycles share every
        physical parameter and extension.
    name : str
        The experiment's name.
    description : str
        What was changed (a diagnosed cause notes itself here, as on a bicycle).
    """

    members: tuple[tuple[str, Bicycle], ...]
    name: str = ""
    description: str = ""

    def __post_init__(self) -> None:
        names = [name for name, _ in self.members]
        if not names:
            raise InputError("an experiment needs at least one group")
        twice = sorted({name for name in names if names.count(name) > 1})
        if twice:
            raise InputError(f"group {twice[0]!r} is given twice")
        first = self.members[0][1]
        for name, bicycle in self.members[1:]:
            differing = sorted(key for key in set(first.parameters) | set(bicycle.parameters)
                               if first.parameters.get(key) != bicycle.parameters.get(key))
            if differing:
                raise InputError(f"the groups of one experiment share the bicycle's physical parameters; group "
                                 f"{name!r} differs from {self.members[0][0]!r} in {', '.join(differing[:5])}")
            if bicycle.extensions != first.extensions:
                raise InputError(f"the groups of one experiment share the bicycle's extensions; group {name!r} "
                                 f"differs from {self.members[0][0]!r}")

    @property
    def names(self) -> tuple[str, ...]:
        """The groups' names, in order."""
        return tuple(name for name, _ in self.members)

    def member(self, name: str) -> Bicycle:
        """Return the bicycle of group ``name``."""
        for member, bicycle in self.members:
            if member == name:
                return bicycle
        raise KeyError(name)

    @property
    def parameters(self) -> dict[str, float]:
        """The shared physical parameters (SI units, as :attr:`Bicycle.parameters`)."""
        return self.members[0][1].parameters

    @property
    def extensions(self) -> Extensions:
        """The shared extensions."""
        return self.members[0][1].extensions

    @property
    def uncertainty(self) -> dict[str, float]:
        """The shared parameters' measurement standard deviations (as :attr:`Bicycle.uncertainty`)."""
        return self.members[0][1].uncertainty

    def with_parameters(self, **changes: float) -> Fleet:
        """Return the fleet with parameters changed in every group."""
        return self._each(lambda bicycle: bicycle.with_parameters(**changes))

    def with_extensions(self, **changes: Any) -> Fleet:
        """Return the fleet with extensions changed in every group."""
        return self._each(lambda bicycle: bicycle.with_extensions(**changes))

    def with_member(self, name: str, bicycle: Bicycle) -> Fleet:
        """Return the fleet with group ``name``'s bicycle replaced (its controller changed, say)."""
        self.member(name)
        return replace(self, members=tuple((member, bicycle if member == name else old)
                                           for member, old in self.members))

    def model_speed(self, measured: ArrayLike) -> NDArray[np.float64]:
        """Return the true speed [m/s] of measured speeds (the shared ``speed_scale``)."""
        return self.members[0][1].model_speed(measured)

    def _each(self, change: Any) -> Fleet:
        return replace(self, members=tuple((name, change(bicycle)) for name, bicycle in self.members))


#: A model the diagnosis evaluates: one bicycle, or one bicycle in several groups.
Model: TypeAlias = Bicycle | Fleet


def members_of(model: Model, groups: Sequence[str] | NDArray[Any] | None
               ) -> Iterator[tuple[Bicycle, NDArray[np.intp] | None]]:
    """Yield each bicycle of a model with the windows it is evaluated at.

    Parameters
    ----------
    model : Bicycle or Fleet
        The model.
    groups : sequence of str or None
        The group of each window (None: windows of no group).

    Yields
    ------
    (Bicycle, ndarray of int or None)
        A plain bicycle once, with None (every window); a fleet's members in turn, each with the
        indices of its group's windows (those with none are skipped).

    Raises
    ------
    InputError
        A fleet evaluated at windows of a group it does not have.
    """
    if isinstance(model, Bicycle):
        yield model, None
        return
    labels = np.array([str(group) for group in (groups if groups is not None else [])], dtype=object)
    unknown = sorted(set(labels) - set(model.names))
    if unknown:
        raise InputError(f"windows of group {unknown[0]!r}, which the experiment does not have "
                         f"(groups: {', '.join(model.names)})")
    for name, bicycle in model.members:
        index = np.flatnonzero(labels == name)
        if index.size:
            yield bicycle, index


def first_bicycle(model: Model) -> Bicycle:
    """Return the model's bicycle, or a fleet's first group's (for what all groups share)."""
    return model if isinstance(model, Bicycle) else model.members[0][1]
