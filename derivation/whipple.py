"""The Whipple bicycle as a multibody system, built as in Meijaard et al. (2007).

Four rigid bodies (rear wheel R, rear frame B, front frame H, front wheel F) joined by three
revolute joints (rear hub, steer axis, front hub); knife-edge wheels on flat level ground.
The rear wheel's rolling constraint is built into the velocities (its contact point is at rest),
the front wheel's is returned as a velocity that must vanish.

The model is built in fixed stages, each relating only things that already exist:
frames (orientations), points (positions and velocities), bodies (mass and inertia), loads.
Axes follow the benchmark: x forward, y to the right, z down; the rear frame axes coincide with
the benchmark's global axes in the upright reference configuration.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sm
from sympy.physics.mechanics import Point, ReferenceFrame, dynamicsymbols, inertia
from sympy.physics.vector import Dyadic, Vector

from .symbols import lateral_speed, pitch, roll, spin_front, spin_rear, steer, yaw


@dataclass
class Body:
    """A rigid body (or a point mass) for Kane's method.

    mass_centre_velocity and angular_velocity are exact, in terms of the coordinates and their
    time derivatives; central_inertia is the inertia dyadic about the mass centre.
    """

    name: str
    mass: sm.Expr
    mass_centre: Point
    frame: ReferenceFrame
    central_inertia: Dyadic


@dataclass
class Load:
    """A force on a point (``point`` given) or a torque on a frame (``frame`` given)."""

    vector: Vector
    point: Point | None = None
    frame: ReferenceFrame | None = None


@dataclass
class BicycleSystem:
    """Everything Kane's method needs, plus the frames for extensions to attach to."""

    inertial: ReferenceFrame
    yaw_frame: ReferenceFrame
    rear_frame: ReferenceFrame
    front_frame: ReferenceFrame
    steer_axis: Vector
    bodies: list[Body]
    loads: list[Load]
    # Scalar velocity expressions that vanish (nonholonomic constraints and the time
    # derivative of the holonomic one), linear in the speeds.
    constraints: list[sm.Expr]
    # Position of the front contact relative to the rear contact, for the holonomic constraint.
    front_contact_position: Vector
    coordinates: tuple[sm.Expr, ...]
    generalized_speeds: tuple[sm.Expr, ...]
    independent_speeds: tuple[sm.Expr, ...]
    dependent_speeds: tuple[sm.Expr, ...]
    inputs: tuple[sm.Symbol, ...]
    points: dict[str, Point] = field(default_factory=dict)
    frames: dict[str, ReferenceFrame] = field(default_factory=dict)
    headings: dict[str, Vector] = field(default_factory=dict)


def build_frames(p: dict[str, sm.Symbol]):
    """Orientations: yaw, roll and pitch of the rear frame, steer about the tilted steer axis."""
    inertial = ReferenceFrame("N")
    yaw_frame = inertial.orientnew("A", "Axis", (yaw, inertial.z))
    roll_frame = yaw_frame.orientnew("Bphi", "Axis", (roll, yaw_frame.x))
    rear_frame = roll_frame.orientnew("B", "Axis", (pitch, roll_frame.y))
    # The steer axis frame S: the rear frame pitched forward by the tilt, so S.z is the steer
    # axis. The front frame H turns about it and is tilted back, so that H coincides with the
    # rear frame when the steer angle is zero (the benchmark's reference configuration).
    steer_axis_frame = rear_frame.orientnew("S", "Axis", (p["lam"], rear_frame.y))
    steered = steer_axis_frame.orientnew("Sdelta", "Axis", (steer, steer_axis_frame.z))
    front_frame = steered.orientnew("H", "Axis", (-p["lam"], steered.y))
    steer_axis = steer_axis_frame.z
    rear_wheel = rear_frame.orientnew("R", "Axis", (spin_rear, rear_frame.y))
    front_wheel = front_frame.orientnew("F", "Axis", (spin_front, front_frame.y))
    return inertial, yaw_frame, roll_frame, rear_frame, front_frame, rear_wheel, front_wheel, steer_axis


def build_bicycle(p: dict[str, sm.Symbol], lateral_slip: bool = False) -> BicycleSystem:
    """The Whipple bicycle in the benchmark parameters ``p`` (symbols keyed by name).

    ``p`` must also hold ``IByy`` and ``IHyy``: they are carried into the dynamics so that the
    derivation shows, rather than assumes, that they drop out of the linear equations.

    With ``lateral_slip`` the wheels keep their longitudinal rolling and normal contact
    conditions but may slip sideways: the lateral velocity of the rear wheel's contact point
    (``lateral_speed``) and the yaw rate become independent speeds. Lateral tyre forces are
    then added by :func:`whipple.derivation.tyre.add_tyre_forces`.
    """
    N, A, roll_frame, B, H, R, F, steer_axis = build_frames(p)

    # Points. The rear wheel rolls: its material contact point has no longitudinal or normal
    # velocity (and, without lateral slip, none at all), so the hub moves with the wheel's
    # angular velocity about that point plus the slip velocity.
    slip_velocity = lateral_speed * A.y if lateral_slip else Vector(0)
    rear_hub = Point("rear_hub")
    rear_hub.set_vel(N, slip_velocity + R.ang_vel_in(N).cross(-p["rR"] * roll_frame.z))
    rear_contact = rear_hub.locatenew("rear_contact", p["rR"] * roll_frame.z)
    rear_contact.set_vel(N, slip_velocity)
    rear_mass_centre = rear_hub.locatenew("rear_mass_centre", p["xB"] * B.x + (p["zB"] + p["rR"]) * B.z)
    rear_mass_centre.v2pt_theory(rear_hub, N, B)
    # The steer axis meets the ground at the trail's distance ahead of the front contact.
    steer_point = rear_hub.locatenew("steer_point", (p["w"] + p["c"]) * B.x + p["rR"] * B.z)
    steer_point.v2pt_theory(rear_hub, N, B)
    front_hub = steer_point.locatenew("front_hub", -p["c"] * H.x - p["rF"] * H.z)
    front_hub.v2pt_theory(steer_point, N, H)
    front_mass_centre = steer_point.locatenew(
        "front_mass_centre", (p["xH"] - p["w"] - p["c"]) * H.x + p["zH"] * H.z
    )
    front_mass_centre.v2pt_theory(steer_point, N, H)

    # The front contact lies in the wheel plane, straight "down" from the hub: along the
    # projection of the vertical onto the wheel plane.
    vertical_in_plane = A.z - A.z.dot(H.y) * H.y
    to_front_contact = p["rF"] * vertical_in_plane / vertical_in_plane.magnitude()
    front_contact_velocity = front_hub.vel(N) + F.ang_vel_in(N).cross(to_front_contact)
    front_contact = front_hub.locatenew("front_contact", to_front_contact)
    front_contact.set_vel(N, front_contact_velocity)
    # The front wheel's heading: where its plane meets the ground.
    front_heading = H.y.cross(A.z)
    front_heading = front_heading / front_heading.magnitude()
    front_contact_position = front_hub.pos_from(rear_hub) + to_front_contact - p["rR"] * roll_frame.z

    bodies = [
        Body("rear_wheel", p["mR"], rear_hub, R, inertia(B, p["IRxx"], p["IRyy"], p["IRxx"])),
        Body("rear_frame", p["mB"], rear_mass_centre, B,
             inertia(B, p["IBxx"], p["IByy"], p["IBzz"], 0, 0, p["IBxz"])),
        Body("front_frame", p["mH"], front_mass_centre, H,
             inertia(H, p["IHxx"], p["IHyy"], p["IHzz"], 0, 0, p["IHxz"])),
        Body("front_wheel", p["mF"], front_hub, F, inertia(H, p["IFxx"], p["IFyy"], p["IFxx"])),
    ]

    # Loads: gravity (z is down), and the two inputs of the benchmark: a roll torque on the
    # rear frame about the roll axis, and a steer torque between the rear and front frames.
    roll_torque, steer_torque = sm.symbols("T_phi T_delta", real=True)
    loads = [Load(body.mass * p["g"] * A.z, point=body.mass_centre) for body in bodies]
    loads += [
        Load(roll_torque * A.x, frame=B),
        Load(steer_torque * steer_axis, frame=H),
        Load(-steer_torque * steer_axis, frame=B),
    ]

    return BicycleSystem(
        inertial=N, yaw_frame=A, rear_frame=B, front_frame=H, steer_axis=steer_axis,
        bodies=bodies, loads=loads,
        constraints=([front_contact_velocity.dot(axis) for axis in (front_heading, A.z)] if lateral_slip
                     else [front_contact_velocity.dot(axis) for axis in (A.x, A.y, A.z)]),
        front_contact_position=front_contact_position,
        coordinates=(yaw, roll, pitch, steer, spin_rear, spin_front),
        generalized_speeds=(lateral_speed,) if lateral_slip else (),
        independent_speeds=((roll.diff(), steer.diff(), spin_rear.diff(), lateral_speed, yaw.diff())
                            if lateral_slip else (roll.diff(), steer.diff(), spin_rear.diff())),
        dependent_speeds=((pitch.diff(), spin_front.diff()) if lateral_slip
                          else (yaw.diff(), pitch.diff(), spin_front.diff())),
        inputs=(roll_torque, steer_torque),
        points={"rear_hub": rear_hub, "steer_point": steer_point, "front_hub": front_hub,
                "rear_contact": rear_contact, "front_contact": front_contact},
        frames={"roll": roll_frame, "rear_wheel": R, "front_wheel": F},
        headings={"rear": A.x, "front": front_heading},
    )


def add_payload(system: BicycleSystem, p: dict[str, sm.Symbol]) -> None:
    """A point mass rigidly on the rear frame at (payload_x, 0, payload_z) in benchmark axes."""
    B = system.rear_frame
    rear_hub = system.points["rear_hub"]
    position = p["payload_x"] * B.x + (p["payload_z"] + p["rR"]) * B.z
    payload = rear_hub.locatenew("payload", position)
    payload.v2pt_theory(rear_hub, system.inertial, B)
    system.bodies.append(Body("payload", p["payload_mass"], payload, B, Dyadic(0)))
    system.loads.append(Load(p["payload_mass"] * p["g"] * system.yaw_frame.z, point=payload))


def add_front_payload(system: BicycleSystem, p: dict[str, sm.Symbol]) -> None:
    """A point mass rigidly on the front frame at (front_payload_x, 0, front_payload_z).

    The position is in benchmark axes in the reference configuration (steer angle zero), like
    the front frame's own mass centre (xH, zH); the mass turns with the front frame.
    """
    H = system.front_frame
    steer_point = system.points["steer_point"]
    position = (p["front_payload_x"] - p["w"] - p["c"]) * H.x + p["front_payload_z"] * H.z
    payload = steer_point.locatenew("front_payload", position)
    payload.v2pt_theory(steer_point, system.inertial, H)
    system.bodies.append(Body("front_payload", p["front_payload_mass"], payload, H, Dyadic(0)))
    system.loads.append(Load(p["front_payload_mass"] * p["g"] * system.yaw_frame.z, point=payload))


def add_reflected_steer_inertia(system: BicycleSystem, p: dict[str, sm.Symbol]) -> None:
    """A rotor geared to the steer angle (a steer motor), in the limit of a high gear ratio.

    A rotor of axial inertia J_rotor turning at N times the steer rate relative to its carrier
    has angular velocity ``omega_carrier + N steer_rate s`` about the steer axis s. Its kinetic
    energy ``J_rotor (N steer_rate + omega_carrier . s)^2 / 2`` holds the reflected inertia
    ``N^2 J_rotor`` of the steer equation, a coupling ``N J_rotor`` of the steer rate with the
    carrier's rotation (roll and yaw rates), and ``J_rotor`` added to the carrier's inertia. The
    parameter ``reflected_steer_inertia`` is ``N^2 J_rotor``; the two smaller terms are of
    relative order 1/N and 1/N^2 and are neglected, as are the rotor's transverse inertia and
    its mass (counted in the frame carrying it). The rotor's gyroscopic torques are products of
    first-order rates and vanish in the linear model anyway. The rotor is therefore a massless
    body whose angular velocity is ``steer_rate s`` and whose inertia is
    ``reflected_steer_inertia s s^T``: it adds exactly ``reflected_steer_inertia`` to M[steer,
    steer] and nothing else (the derivation checks this).
    """
    s = system.steer_axis
    rotor = ReferenceFrame("rotor")
    rotor.set_ang_vel(system.inertial, steer.diff() * s)
    system.bodies.append(Body("steer_rotor", sm.S.Zero, system.points["steer_point"], rotor,
                              p["reflected_steer_inertia"] * (s | s)))


def add_steer_inertia(system: BicycleSystem, p: dict[str, sm.Symbol]) -> None:
    """Extra inertia of the front frame about the steer axis (a motor, a lamp, a bag)."""
    s = system.steer_axis
    front = next(body for body in system.bodies if body.name == "front_frame")
    front.central_inertia = front.central_inertia + p["steer_inertia"] * (s | s)


def add_steer_damping(system: BicycleSystem, damping: sm.Symbol) -> None:
    """Viscous damping torque about the steer axis, between the rear and front frames."""
    rate = steer.diff()
    s = system.steer_axis
    system.loads.append(Load(-damping * rate * s, frame=system.front_frame))
    system.loads.append(Load(damping * rate * s, frame=system.rear_frame))


__all__ = ["BicycleSystem", "Body", "Load", "build_bicycle", "add_payload", "add_front_payload",
           "add_reflected_steer_inertia", "add_steer_inertia",
           "add_steer_damping", "dynamicsymbols"]
