"""Bicycle with linear lateral tyre forces and relaxation (tyre compliance): linearized equation matrices (CasADi).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``tyre``).

Derivation sources sha256: 85447a33b99f7a7cc45c28c4bf5678d54b6c5184e081d72ed53ff742e0d08074
SymPy version: 1.14.0

Equation form: E x' = (A0 + v A1 + ...) x + B f, x = [roll, steer, roll_rate, steer_rate, lateral_speed, yaw_rate, rear_lateral_force, front_lateral_force], f = [roll torque, steer torque].

Parameters (SI units):
    w: wheelbase [m]
    c: trail [m]
    lam: steer axis tilt from vertical [rad]
    g: acceleration due to gravity [m/s^2]
    rR: rear wheel radius [m]
    mR: rear wheel mass [kg]
    IRxx: rear wheel moment of inertia about a diameter [kg m^2]
    IRyy: rear wheel moment of inertia about its axle [kg m^2]
    xB: rear frame mass centre, forward of the rear contact [m]
    zB: rear frame mass centre, z down (negative above ground) [m]
    mB: rear frame mass [kg]
    IBxx: rear frame moment of inertia about x [kg m^2]
    IBzz: rear frame moment of inertia about z [kg m^2]
    IBxz: rear frame product of inertia xz [kg m^2]
    xH: front frame (fork and handlebar) mass centre, forward of the rear contact [m]
    zH: front frame mass centre, z down (negative above ground) [m]
    mH: front frame mass [kg]
    IHxx: front frame moment of inertia about x [kg m^2]
    IHzz: front frame moment of inertia about z [kg m^2]
    IHxz: front frame product of inertia xz [kg m^2]
    rF: front wheel radius [m]
    mF: front wheel mass [kg]
    IFxx: front wheel moment of inertia about a diameter [kg m^2]
    IFyy: front wheel moment of inertia about its axle [kg m^2]
    payload_mass: point mass rigidly attached to the rear frame [kg]
    payload_x: payload position, forward of the rear contact [m]
    payload_z: payload position, z down (negative above ground) [m]
    steer_inertia: extra moment of inertia of the front frame about the steer axis [kg m^2]
    steer_damping: viscous damping torque about the steer axis per steer rate [N m s/rad]
    front_payload_mass: point mass rigidly attached to the front frame [kg]
    front_payload_x: front payload position, forward of the rear contact (steer angle zero) [m]
    front_payload_z: front payload position, z down (negative above ground) [m]
    reflected_steer_inertia: inertia of a rotor geared to the steer angle, reflected to the steer axis (N^2 J_rotor) [kg m^2]
    cornering_stiffness: lateral force per static wheel load per rad of slip angle [1/rad]
    camber_stiffness: lateral force per static wheel load per rad of camber [1/rad]
    relaxation_length: distance rolled for the lateral force to build up [m]
    pneumatic_trail: self-aligning moment arm of the lateral slip force [m]
"""

import casadi

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy', 'payload_mass', 'payload_x', 'payload_z', 'steer_inertia', 'steer_damping', 'front_payload_mass', 'front_payload_x', 'front_payload_z', 'reflected_steer_inertia', 'cornering_stiffness', 'camber_stiffness', 'relaxation_length', 'pneumatic_trail')
OUTPUTS = ('E', 'A0', 'A1', 'B')


def matrices(p):
    """The matrices as CasADi expressions of the parameter vector p (order PARAMETERS)."""
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, front_payload_mass, front_payload_x, front_payload_z, reflected_steer_inertia, cornering_stiffness, camber_stiffness, relaxation_length, pneumatic_trail, = casadi.vertsplit(p)
    x0 = front_payload_mass*front_payload_z**2
    x1 = mF*rF**2
    x2 = mH*zH**2
    x3 = mR*rR**2
    x4 = casadi.sin(lam)
    x5 = x4**2
    x6 = steer_inertia*x5
    x7 = IFxx + IRxx
    x8 = casadi.cos(lam)
    x9 = IHxz*x8
    x10 = steer_inertia*x4
    x11 = front_payload_mass*front_payload_z
    x12 = c*x8
    x13 = mH*zH
    x14 = w*x8
    x15 = x1*x4
    x16 = mF*rF
    x17 = x12*x16
    x18 = front_payload_x*x11
    x19 = x18*x8
    x20 = x13*xH
    x21 = x20*x8
    x22 = IFxx*x4 + IHxx*x4 + x0*x4 + x10 + x11*x12 + x11*x14 + x12*x13 + x13*x14 + x15 - x17 - x19 + x2*x4 - x21 + x9
    x23 = mB*zB
    x24 = payload_mass*payload_z
    x25 = mF*rF + mR*rR - x11 - x13 - x23 - x24
    x26 = w*x16
    x27 = IBxz + IHxz - payload_x*x24 + x10*x8 - x18 - x20 - x23*xB + x26
    x28 = c**2
    x29 = front_payload_mass*x28
    x30 = w**2
    x31 = front_payload_mass*x30
    x32 = mF*x28
    x33 = mH*x28
    x34 = mH*x30
    x35 = front_payload_mass*front_payload_x**2
    x36 = mH*xH**2
    x37 = front_payload_mass*front_payload_x
    x38 = 2*c
    x39 = x37*x38
    x40 = mH*xH
    x41 = x38*x40
    x42 = 2*w
    x43 = x37*x42
    x44 = x40*x42
    x45 = 2*x4
    x46 = front_payload_mass*w
    x47 = x38*x46
    x48 = mH*w
    x49 = x38*x48
    x50 = 2*x12
    x51 = x11*x4
    x52 = x13*x4
    x53 = 2*x14
    x54 = IHzz + steer_inertia + x35 + x36
    x55 = front_payload_mass*x12
    x56 = mH*x12
    x57 = x46*x8
    x58 = x48*x8
    x59 = front_payload_mass*front_payload_x*x8 + mF*rF*x4 - mF*x12 + mH*x8*xH - x51 - x52 - x55 - x56 - x57 - x58
    x60 = x26*x4
    x61 = x37*x8
    x62 = c*x61
    x63 = mF*w
    x64 = x40*x8
    x65 = c*x64
    x66 = w*x61
    x67 = w*x64
    x68 = IFxx*x8 + IHxz*x4 + IHzz*x8 + steer_inertia*x8 - x12*x63 - x18*x4 - x20*x4 + x35*x8 + x36*x8 + x60 - x62 - x65 - x66 - x67
    x69 = front_payload_mass + mB + mF + mH + mR + payload_mass
    x70 = mB*xB
    x71 = payload_mass*payload_x
    x72 = x37 + x40 + x63 + x70 + x71
    x73 = -w*x51 - w*x52 - x12*x46 - x12*x48 + x12*x70 + x12*x71 - x31*x8 - x34*x8 + x60 + x62 + x65 + x66 + x67
    x74 = g/w
    x75 = camber_stiffness*pneumatic_trail
    x76 = x75*x8
    x77 = x74*(x61*x75 + x63*x76 + x64*x75 + x70*x76 + x71*x76 + x73)
    x78 = -front_payload_mass*front_payload_x + mB*w - mB*xB - mH*xH + mR*w - payload_mass*payload_x + payload_mass*w + x46 + x48
    x79 = 1/relaxation_length
    x80 = cornering_stiffness*x79
    x81 = x72*x80
    x82 = x74*x81
    x83 = 1/rF
    x84 = IFyy*x8*x83
    x85 = IFyy*rR + IRyy*rF
    x86 = x83/rR
    x87 = IFyy*x4
    x88 = x74*x79
    x89 = camber_stiffness*x88
    x90 = -x79
    x91 = camber_stiffness*x4
    x92 = cornering_stiffness*x8
    E = casadi.blockcat([[1, 0, 0, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0, 0, 0], [0, 0, IBxx + IHxx + mB*zB**2 + payload_mass*payload_z**2 + x0 + x1 + x2 + x3 + x6 + x7, x22, x25, x27, 0, 0], [0, 0, x22, IFxx + IHxx*x5 - IHzz*x5 + reflected_steer_inertia + x0*x5 + x1*x5 - x16*x4*x50 - x19*x45 + x2*x5 - x21*x45 - x29*x5 + x29 - x31*x5 + x31 - x32*x5 + x32 - x33*x5 + x33 - x34*x5 + x34 - x35*x5 - x36*x5 + x39*x5 - x39 + x41*x5 - x41 + x43*x5 - x43 + x44*x5 - x44 + x45*x9 - x47*x5 + x47 - x49*x5 + x49 + x50*x51 + x50*x52 + x51*x53 + x52*x53 + x54, x59, x68, 0, 0], [0, 0, x25, x59, x69, x72, 0, 0], [0, 0, x27, x68, x72, IBzz + mB*xB**2 + mF*x30 + payload_mass*payload_x**2 + x54 - x6 + x7, 0, 0], [0, 0, 0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 0, 0, 1]])
    A0 = casadi.blockcat([[0, 0, 1, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0, 0, 0], [g*x25, x73*x74, 0, 0, 0, 0, 0, 0], [x77, x4*x77, 0, -steer_damping, 0, 0, 0, -x8*(c + pneumatic_trail)], [0, 0, 0, 0, 0, 0, 1, 1], [g*x69*x75, x4*x72*x74*x75, 0, 0, 0, 0, -pneumatic_trail, -pneumatic_trail + w], [0, 0, 0, 0, -x74*x78*x80, 0, 0, 0], [0, 0, 0, x12*x82, -x82, -g*x81, 0, 0]])
    A1 = casadi.blockcat([[0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, -x84, 0, x86*(front_payload_mass*front_payload_z*rF*rR + mB*rF*rR*zB + mH*rF*rR*zH + payload_mass*payload_z*rF*rR - rF*x3 - rR*x1 - x85), 0, 0], [0, 0, x84, 0, 0, x83*(rF*x51 + rF*x52 + rF*x55 + rF*x56 + rF*x57 + rF*x58 - rF*x61 - rF*x64 - x15 + x17 - x87), 0, 0], [0, 0, 0, 0, 0, -x69, 0, 0], [0, 0, x85*x86, x83*x87, 0, -x72, 0, 0], [x78*x89, 0, 0, 0, 0, 0, x90, 0], [x72*x89, x88*(cornering_stiffness*x61 + cornering_stiffness*x64 + x37*x91 + x40*x91 + x63*x91 + x63*x92 + x70*x91 + x70*x92 + x71*x91 + x71*x92), 0, 0, 0, 0, 0, x90]])
    B = casadi.blockcat([[0, 0], [0, 0], [1, 0], [0, 1], [0, 0], [0, 0], [0, 0], [0, 0]])
    return E, A0, A1, B


def function(symbol_type=casadi.SX):
    """casadi.Function p -> (E, A0, A1, B), p of length 37."""
    p = symbol_type.sym('p', 37)
    return casadi.Function('tyre', [p], list(matrices(p)), ['p'], list(OUTPUTS))
