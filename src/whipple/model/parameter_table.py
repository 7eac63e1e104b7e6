"""Every parameter of the package's models: name, SI unit and description, in one table.

The benchmark parameters follow Meijaard, Papadopoulos, Ruina & Schwab (2007), Table 1 (x forward
from the rear contact point, z down, inertias about each body's mass centre). The derivation
(``derivation/symbols.py``) names its symbols from this table, and the bicycle files and parameter
sets check against it, so a parameter has one description everywhere, including the generated code.

This module holds plain data only (no NumPy), so both sides can import it cheaply.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ParameterInfo:
    """One parameter.

    Attributes
    ----------
    name : str
        Name, as in bicycle files and the generated code.
    unit : str
        SI unit.
    description : str
        What it is, without the unit.
    group : str
        ``benchmark`` (Meijaard et al. 2007, Table 1), ``extension`` (payloads, steer inertia,
        reflected steer inertia and damping) or ``tyre`` (tyre compliance).
    """

    name: str
    unit: str
    description: str
    group: str

    @property
    def described(self) -> str:
        """The description with the unit in brackets, e.g. ``trail [m]``."""
        return f"{self.description} [{self.unit}]"


def _group(group: str, rows: tuple[tuple[str, str, str], ...]) -> tuple[ParameterInfo, ...]:
    return tuple(ParameterInfo(name, unit, description, group) for name, unit, description in rows)


PARAMETERS: tuple[ParameterInfo, ...] = (
    *_group("benchmark", (
        ("w", "m", "wheelbase"),
        ("c", "m", "trail"),
        ("lam", "rad", "steer axis tilt from vertical"),
        ("g", "m/s^2", "acceleration due to gravity"),
        ("rR", "m", "rear wheel radius"),
        ("mR", "kg", "rear wheel mass"),
        ("IRxx", "kg m^2", "rear wheel moment of inertia about a diameter"),
        ("IRyy", "kg m^2", "rear wheel moment of inertia about its axle"),
        ("xB", "m", "rear frame mass centre, forward of the rear contact"),
        ("zB", "m", "rear frame mass centre, z down (negative above ground)"),
        ("mB", "kg", "rear frame mass"),
        ("IBxx", "kg m^2", "rear frame moment of inertia about x"),
        ("IByy", "kg m^2", "rear frame moment of inertia about y"),
        ("IBzz", "kg m^2", "rear frame moment of inertia about z"),
        ("IBxz", "kg m^2", "rear frame product of inertia xz"),
        ("xH", "m", "front frame (fork and handlebar) mass centre, forward of the rear contact"),
        ("zH", "m", "front frame mass centre, z down (negative above ground)"),
        ("mH", "kg", "front frame mass"),
        ("IHxx", "kg m^2", "front frame moment of inertia about x"),
        ("IHyy", "kg m^2", "front frame moment of inertia about y"),
        ("IHzz", "kg m^2", "front frame moment of inertia about z"),
        ("IHxz", "kg m^2", "front frame product of inertia xz"),
        ("rF", "m", "front wheel radius"),
        ("mF", "kg", "front wheel mass"),
        ("IFxx", "kg m^2", "front wheel moment of inertia about a diameter"),
        ("IFyy", "kg m^2", "front wheel moment of inertia about its axle"),
    )),
    *_group("extension", (
        ("payload_mass", "kg", "point mass rigidly attached to the rear frame"),
        ("payload_x", "m", "payload position, forward of the rear contact"),
        ("payload_z", "m", "payload position, z down (negative above ground)"),
        ("steer_inertia", "kg m^2", "extra moment of inertia of the front frame about the steer axis"),
        ("steer_damping", "N m s/rad", "viscous damping torque about the steer axis per steer rate"),
        ("front_payload_mass", "kg", "point mass rigidly attached to the front frame"),
        ("front_payload_x", "m", "front payload position, forward of the rear contact (steer angle zero)"),
        ("front_payload_z", "m", "front payload position, z down (negative above ground)"),
        ("reflected_steer_inertia", "kg m^2",
         "inertia of a rotor geared to the steer angle, reflected to the steer axis (N^2 J_rotor)"),
    )),
    *_group("tyre", (
        ("cornering_stiffness", "1/rad", "lateral force per static wheel load per rad of slip angle"),
        ("camber_stiffness", "1/rad", "lateral force per static wheel load per rad of camber"),
        ("relaxation_length", "m", "distance rolled for the lateral force to build up"),
        ("pneumatic_trail", "m", "self-aligning moment arm of the lateral slip force"),
    )),
)

#: The table by name.
BY_NAME: dict[str, ParameterInfo] = {info.name: info for info in PARAMETERS}


def names(group: str) -> tuple[str, ...]:
    """Return the names of one group's parameters, in table order."""
    return tuple(info.name for info in PARAMETERS if info.group == group)
