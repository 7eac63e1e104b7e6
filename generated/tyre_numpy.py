"""Bicycle with linear lateral tyre forces and relaxation (tyre compliance): linearized equation matrices (NumPy).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``tyre``).

Derivation sources sha256: 89cb387b60f1a280ad0a5759cc931682670b1c8feb0fcfe1572b0f91b3219384
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
    cornering_stiffness: lateral force per static wheel load per rad of slip angle [1/rad]
    camber_stiffness: lateral force per static wheel load per rad of camber [1/rad]
    relaxation_length: distance rolled for the lateral force to build up [m]
    pneumatic_trail: self-aligning moment arm of the lateral slip force [m]
"""

import numpy

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy', 'payload_mass', 'payload_x', 'payload_z', 'steer_inertia', 'steer_damping', 'cornering_stiffness', 'camber_stiffness', 'relaxation_length', 'pneumatic_trail')
OUTPUTS = ('E', 'A0', 'A1', 'B')


def matrices(w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, cornering_stiffness, camber_stiffness, relaxation_length, pneumatic_trail):
    """Evaluate the matrices; parameters are arrays broadcast against each other.

    Returns a tuple E, A0, A1, B of arrays of shape broadcast_shape + their matrix shape.
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, cornering_stiffness, camber_stiffness, relaxation_length, pneumatic_trail, = numpy.broadcast_arrays(numpy.asarray(w, dtype=float), numpy.asarray(c, dtype=float), numpy.asarray(lam, dtype=float), numpy.asarray(g, dtype=float), numpy.asarray(rR, dtype=float), numpy.asarray(mR, dtype=float), numpy.asarray(IRxx, dtype=float), numpy.asarray(IRyy, dtype=float), numpy.asarray(xB, dtype=float), numpy.asarray(zB, dtype=float), numpy.asarray(mB, dtype=float), numpy.asarray(IBxx, dtype=float), numpy.asarray(IBzz, dtype=float), numpy.asarray(IBxz, dtype=float), numpy.asarray(xH, dtype=float), numpy.asarray(zH, dtype=float), numpy.asarray(mH, dtype=float), numpy.asarray(IHxx, dtype=float), numpy.asarray(IHzz, dtype=float), numpy.asarray(IHxz, dtype=float), numpy.asarray(rF, dtype=float), numpy.asarray(mF, dtype=float), numpy.asarray(IFxx, dtype=float), numpy.asarray(IFyy, dtype=float), numpy.asarray(payload_mass, dtype=float), numpy.asarray(payload_x, dtype=float), numpy.asarray(payload_z, dtype=float), numpy.asarray(steer_inertia, dtype=float), numpy.asarray(steer_damping, dtype=float), numpy.asarray(cornering_stiffness, dtype=float), numpy.asarray(camber_stiffness, dtype=float), numpy.asarray(relaxation_length, dtype=float), numpy.asarray(pneumatic_trail, dtype=float))
    shape = w.shape
    x0 = mF*rF*rF
    x1 = mH*zH*zH
    x2 = mR*rR*rR
    x3 = numpy.sin(lam)
    x4 = x3*x3
    x5 = steer_inertia*x4
    x6 = IFxx + IRxx
    x7 = numpy.cos(lam)
    x8 = IHxz*x7
    x9 = steer_inertia*x3
    x10 = mH*zH
    x11 = c*x7
    x12 = w*x7
    x13 = x0*x3
    x14 = mF*rF
    x15 = x11*x14
    x16 = x10*xH
    x17 = x16*x7
    x18 = IFxx*x3 + IHxx*x3 + x1*x3 + x10*x11 + x10*x12 + x13 - x15 - x17 + x8 + x9
    x19 = mB*zB
    x20 = payload_mass*payload_z
    x21 = mF*rF + mR*rR - x10 - x19 - x20
    x22 = w*x14
    x23 = IBxz + IHxz - payload_x*x20 - x16 - x19*xB + x22 + x7*x9
    x24 = c*c
    x25 = mF*x24
    x26 = mH*x24
    x27 = w*w
    x28 = mH*x27
    x29 = mH*xH*xH
    x30 = mH*xH
    x31 = 2*x30
    x32 = c*x31
    x33 = w*x31
    x34 = 2*x3
    x35 = mH*w
    x36 = 2*c*x35
    x37 = 2*x11
    x38 = x10*x3
    x39 = IHzz + steer_inertia + x29
    x40 = mH*x11
    x41 = x35*x7
    x42 = mF*rF*x3 - mF*x11 + mH*x7*xH - x38 - x40 - x41
    x43 = x22*x3
    x44 = mF*w
    x45 = x30*x7
    x46 = c*x45
    x47 = w*x45
    x48 = IFxx*x7 + IHxz*x3 + IHzz*x7 + steer_inertia*x7 - x11*x44 - x16*x3 + x29*x7 + x43 - x46 - x47
    x49 = mB + mF + mH + mR + payload_mass
    x50 = mB*xB
    x51 = payload_mass*payload_x
    x52 = x30 + x44 + x50 + x51
    x53 = -w*x38 - x11*x35 + x11*x50 + x11*x51 - x28*x7 + x43 + x46 + x47
    x54 = g/w
    x55 = camber_stiffness*pneumatic_trail
    x56 = x55*x7
    x57 = x54*(x44*x56 + x45*x55 + x50*x56 + x51*x56 + x53)
    x58 = mB*w - mB*xB - mH*xH + mR*w - payload_mass*payload_x + payload_mass*w + x35
    x59 = 1/(relaxation_length)
    x60 = cornering_stiffness*x59
    x61 = x52*x60
    x62 = x54*x61
    x63 = 1/(rF)
    x64 = IFyy*x63*x7
    x65 = IFyy*rR + IRyy*rF
    x66 = x63/rR
    x67 = IFyy*x3
    x68 = x54*x59
    x69 = camber_stiffness*x68
    x70 = -x59
    x71 = camber_stiffness*x3
    x72 = cornering_stiffness*x7
    E = numpy.zeros(shape + (8, 8))
    E[..., 0, 0] = 1
    E[..., 1, 1] = 1
    E[..., 2, 2] = IBxx + IHxx + mB*zB*zB + payload_mass*payload_z*payload_z + x0 + x1 + x2 + x5 + x6
    E[..., 2, 3] = x18
    E[..., 2, 4] = x21
    E[..., 2, 5] = x23
    E[..., 3, 2] = x18
    E[..., 3, 3] = IFxx + IHxx*x4 - IHzz*x4 + x0*x4 + x1*x4 + 2*x12*x38 - x14*x3*x37 - x17*x34 - x25*x4 + x25 - x26*x4 + x26 - x28*x4 + x28 - x29*x4 + x32*x4 - x32 + x33*x4 - x33 + x34*x8 - x36*x4 + x36 + x37*x38 + x39
    E[..., 3, 4] = x42
    E[..., 3, 5] = x48
    E[..., 4, 2] = x21
    E[..., 4, 3] = x42
    E[..., 4, 4] = x49
    E[..., 4, 5] = x52
    E[..., 5, 2] = x23
    E[..., 5, 3] = x48
    E[..., 5, 4] = x52
    E[..., 5, 5] = IBzz + mB*xB*xB + mF*x27 + payload_mass*payload_x*payload_x + x39 - x5 + x6
    E[..., 6, 6] = 1
    E[..., 7, 7] = 1
    A0 = numpy.zeros(shape + (8, 8))
    A0[..., 0, 2] = 1
    A0[..., 1, 3] = 1
    A0[..., 2, 0] = g*x21
    A0[..., 2, 1] = x53*x54
    A0[..., 3, 0] = x57
    A0[..., 3, 1] = x3*x57
    A0[..., 3, 3] = -steer_damping
    A0[..., 3, 7] = -x7*(c + pneumatic_trail)
    A0[..., 4, 6] = 1
    A0[..., 4, 7] = 1
    A0[..., 5, 0] = g*x49*x55
    A0[..., 5, 1] = x3*x52*x54*x55
    A0[..., 5, 6] = -pneumatic_trail
    A0[..., 5, 7] = -pneumatic_trail + w
    A0[..., 6, 4] = -x54*x58*x60
    A0[..., 7, 3] = x11*x62
    A0[..., 7, 4] = -x62
    A0[..., 7, 5] = -g*x61
    A1 = numpy.zeros(shape + (8, 8))
    A1[..., 2, 3] = -x64
    A1[..., 2, 5] = x66*(mB*rF*rR*zB + mH*rF*rR*zH + payload_mass*payload_z*rF*rR - rF*x2 - rR*x0 - x65)
    A1[..., 3, 2] = x64
    A1[..., 3, 5] = x63*(rF*x38 + rF*x40 + rF*x41 - rF*x45 - x13 + x15 - x67)
    A1[..., 4, 5] = -x49
    A1[..., 5, 2] = x65*x66
    A1[..., 5, 3] = x63*x67
    A1[..., 5, 5] = -x52
    A1[..., 6, 0] = x58*x69
    A1[..., 6, 6] = x70
    A1[..., 7, 0] = x52*x69
    A1[..., 7, 1] = x68*(cornering_stiffness*x45 + x30*x71 + x44*x71 + x44*x72 + x50*x71 + x50*x72 + x51*x71 + x51*x72)
    A1[..., 7, 7] = x70
    B = numpy.zeros(shape + (8, 2))
    B[..., 2, 0] = 1
    B[..., 3, 1] = 1
    return E, A0, A1, B
