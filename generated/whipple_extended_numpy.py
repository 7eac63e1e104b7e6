"""Whipple bicycle with a rear-frame payload point mass, extra steer inertia and steer damping: linearized equation matrices (NumPy).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``whipple_extended``).

Derivation sources sha256: 89cb387b60f1a280ad0a5759cc931682670b1c8feb0fcfe1572b0f91b3219384
SymPy version: 1.14.0

Equation form: M q'' + (v C1 + D) q' + (K0 + v**2 K2) q = f, q = [roll, steer], f = [roll torque, steer torque]; K0 includes gravity.

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
"""

import numpy

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy', 'payload_mass', 'payload_x', 'payload_z', 'steer_inertia', 'steer_damping')
OUTPUTS = ('M', 'C1', 'D', 'K0', 'K2')


def matrices(w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping):
    """Evaluate the matrices; parameters are arrays broadcast against each other.

    Returns a tuple M, C1, D, K0, K2 of arrays of shape broadcast_shape + their matrix shape.
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, = numpy.broadcast_arrays(numpy.asarray(w, dtype=float), numpy.asarray(c, dtype=float), numpy.asarray(lam, dtype=float), numpy.asarray(g, dtype=float), numpy.asarray(rR, dtype=float), numpy.asarray(mR, dtype=float), numpy.asarray(IRxx, dtype=float), numpy.asarray(IRyy, dtype=float), numpy.asarray(xB, dtype=float), numpy.asarray(zB, dtype=float), numpy.asarray(mB, dtype=float), numpy.asarray(IBxx, dtype=float), numpy.asarray(IBzz, dtype=float), numpy.asarray(IBxz, dtype=float), numpy.asarray(xH, dtype=float), numpy.asarray(zH, dtype=float), numpy.asarray(mH, dtype=float), numpy.asarray(IHxx, dtype=float), numpy.asarray(IHzz, dtype=float), numpy.asarray(IHxz, dtype=float), numpy.asarray(rF, dtype=float), numpy.asarray(mF, dtype=float), numpy.asarray(IFxx, dtype=float), numpy.asarray(IFyy, dtype=float), numpy.asarray(payload_mass, dtype=float), numpy.asarray(payload_x, dtype=float), numpy.asarray(payload_z, dtype=float), numpy.asarray(steer_inertia, dtype=float), numpy.asarray(steer_damping, dtype=float))
    shape = w.shape
    x0 = mF*rF*rF
    x1 = mH*zH*zH
    x2 = mR*rR*rR
    x3 = numpy.sin(lam)
    x4 = x3*x3
    x5 = steer_inertia*x4
    x6 = 1/(w)
    x7 = numpy.cos(lam)
    x8 = c*x7
    x9 = IFxx*w
    x10 = w*x3
    x11 = IHxz*x8
    x12 = w*x7
    x13 = c*steer_inertia
    x14 = steer_inertia*w
    x15 = mH*zH
    x16 = x3*x3*x3
    x17 = x0*x10
    x18 = w*w
    x19 = x18*x7
    x20 = x15*x19
    x21 = mB*zB
    x22 = x21*xB
    x23 = x15*xH
    x24 = payload_mass*payload_z
    x25 = payload_x*x24
    x26 = x6*(IBxz*x8 + IHxx*x10 + IHxz*x12 + w*x15*x8 + x1*x10 + x11 - x12*x23 - x13*x16 + x13*x3 + x14*x3 + x17 + x20 - x22*x8 - x23*x8 - x25*x8 + x3*x9)
    x27 = 1/(x18)
    x28 = c*c
    x29 = IBzz*x28
    x30 = IFxx*x28
    x31 = IHzz*x28
    x32 = IHzz*x18
    x33 = IRxx*x28
    x34 = steer_inertia*x28
    x35 = mH*w*w*w*w
    x36 = IFxx*c
    x37 = 2*w
    x38 = IHzz*c
    x39 = 2*w*w*w
    x40 = c*mH
    x41 = x39*x40
    x42 = mH*xH
    x43 = x39*x42
    x44 = mB*xB*xB
    x45 = x28*x44
    x46 = mH*x28
    x47 = xH*xH
    x48 = x46*x47
    x49 = payload_mass*payload_x*payload_x
    x50 = x28*x49
    x51 = mH*x47
    x52 = c*x51
    x53 = mH*x18
    x54 = c*x53
    x55 = x46*xH
    x56 = x18*x4
    x57 = x3*x3*x3*x3
    x58 = x36*x4
    x59 = x38*x4
    x60 = w*x5
    x61 = 2*x5
    x62 = x19*x3
    x63 = x15*x3
    x64 = x10*x15*x8
    x65 = 2*xH
    x66 = x4*x52
    x67 = x42*x56
    x68 = x4*x55
    x69 = rF*rR
    x70 = x69*x7
    x71 = IFyy*rR
    x72 = IRyy*rF
    x73 = steer_inertia*x69
    x74 = rR*x0
    x75 = rF*x2
    x76 = x21*x69
    x77 = x15*x69
    x78 = x24*x69
    x79 = 1/(rF)
    x80 = x6*x79/rR
    x81 = x7*x80
    x82 = IBzz*c
    x83 = IHzz*w
    x84 = IRxx*c
    x85 = c*x44
    x86 = c*x49
    x87 = mB*xB
    x88 = x28*x87
    x89 = payload_mass*payload_x
    x90 = x28*x89
    x91 = w*x51
    x92 = w*x46
    x93 = x10*x7
    x94 = mF*rF
    x95 = x10*x94
    x96 = g*x6*(c*mH*w*x7 + mH*w*x3*zH + mH*x18*x7 - x12*x42 - x42*x8 - x8*x87 - x8*x89 - x95)
    x97 = c*rF
    x98 = x87*x97
    x99 = x42*x97
    x100 = x89*x97
    x101 = rF*w
    x102 = x101*x42
    x103 = x101*x40
    M = numpy.zeros(shape + (2, 2))
    M[..., 0, 0] = IBxx + IFxx + IHxx + IRxx + mB*zB*zB + payload_mass*payload_z*payload_z + x0 + x1 + x2 + x5
    M[..., 0, 1] = x26
    M[..., 1, 0] = x26
    M[..., 1, 1] = x27*(IFxx*x18 + IHxx*x56 + 2*IHxz*x62 - 2*c*x60 + 4*c*x67 + steer_inertia*x18 + x0*x56 + x1*x56 + 2*x10*x11 + x13*x37 + x18*x46 + x18*x51 + 2*x18*x63*x8 - x20*x3*x65 - x28*x61 - x29*x4 + x29 - x30*x4 + x30 - x31*x4 + x31 - x32*x4 + x32 - x33*x4 + x33 + x34*x57 + x34 - x35*x4 + x35 + x36*x37 + x37*x38 + x37*x52 - x37*x55 - x37*x58 - x37*x59 - x37*x66 + x37*x68 + x39*x63*x7 - x4*x41 + x4*x43 - x4*x45 - x4*x48 - x4*x50 + x41 - x43 + x45 - x46*x56 + x48 + x50 - x51*x56 - 4*x54*xH - x64*x65)
    C1 = numpy.zeros(shape + (2, 2))
    C1[..., 0, 1] = x80*(IBxz*x70 + IHxz*x70 + x12*x71 + x12*x74 - x16*x73 - x22*x70 - x23*x70 - x25*x70 + x3*x73 + x71*x8 + x72*x8 + x74*x8 + x75*x8 - x76*x8 - x77*x8 - x78*x8)
    C1[..., 1, 0] = -x81*(c*x71 + c*x72 + w*x71)
    C1[..., 1, 1] = x27*(IHxz*x93 - c*x61 + x13*x57 + x13 + x14 - x23*x93 + x36 + x38 - x4*x82 - x4*x83 - x4*x84 - x4*x85 - x4*x86 - x4*x88 - x4*x9 - x4*x90 - x4*x91 + x4*x92 + x40*x56 + x52 - x53*xH - x54 + x55 - x58 - x59 - x60 + x62*x94 - x64 - x66 + x67 - x68 + x8*x95 + x82 + x83 + x84 + x85 + x86 + x88 + x9 + x90 + x91 - x92)
    D = numpy.zeros(shape + (2, 2))
    D[..., 1, 1] = steer_damping
    K0 = numpy.zeros(shape + (2, 2))
    K0[..., 0, 0] = g*(-mR*rR + x15 + x21 + x24 - x94)
    K0[..., 0, 1] = x96
    K0[..., 1, 0] = x96
    K0[..., 1, 1] = x3*x96
    K2 = numpy.zeros(shape + (2, 2))
    K2[..., 0, 1] = x81*(x71 + x72 + x74 + x75 - x76 - x77 - x78)
    K2[..., 1, 1] = x27*x79*(IFyy*x93 + mH*rF*x56 - rF*x15*x93 - rF*x53 - x100*x4 + x100 - x102*x4 + x102 + x103*x4 - x103 + x17*x7 - x4*x98 - x4*x99 + x98 + x99)
    return M, C1, D, K0, K2
