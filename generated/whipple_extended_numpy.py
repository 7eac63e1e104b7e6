"""Whipple bicycle with rear- and front-frame payload point masses, extra steer inertia, reflected steer inertia and steer damping: linearized equation matrices (NumPy).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``whipple_extended``).

Derivation sources sha256: 85447a33b99f7a7cc45c28c4bf5678d54b6c5184e081d72ed53ff742e0d08074
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
    front_payload_mass: point mass rigidly attached to the front frame [kg]
    front_payload_x: front payload position, forward of the rear contact (steer angle zero) [m]
    front_payload_z: front payload position, z down (negative above ground) [m]
    reflected_steer_inertia: inertia of a rotor geared to the steer angle, reflected to the steer axis (N^2 J_rotor) [kg m^2]
"""

import numpy

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy', 'payload_mass', 'payload_x', 'payload_z', 'steer_inertia', 'steer_damping', 'front_payload_mass', 'front_payload_x', 'front_payload_z', 'reflected_steer_inertia')
OUTPUTS = ('M', 'C1', 'D', 'K0', 'K2')


def matrices(w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, front_payload_mass, front_payload_x, front_payload_z, reflected_steer_inertia):
    """Evaluate the matrices; parameters are arrays broadcast against each other.

    Returns a tuple M, C1, D, K0, K2 of arrays of shape broadcast_shape + their matrix shape.
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, front_payload_mass, front_payload_x, front_payload_z, reflected_steer_inertia, = numpy.broadcast_arrays(numpy.asarray(w, dtype=float), numpy.asarray(c, dtype=float), numpy.asarray(lam, dtype=float), numpy.asarray(g, dtype=float), numpy.asarray(rR, dtype=float), numpy.asarray(mR, dtype=float), numpy.asarray(IRxx, dtype=float), numpy.asarray(IRyy, dtype=float), numpy.asarray(xB, dtype=float), numpy.asarray(zB, dtype=float), numpy.asarray(mB, dtype=float), numpy.asarray(IBxx, dtype=float), numpy.asarray(IBzz, dtype=float), numpy.asarray(IBxz, dtype=float), numpy.asarray(xH, dtype=float), numpy.asarray(zH, dtype=float), numpy.asarray(mH, dtype=float), numpy.asarray(IHxx, dtype=float), numpy.asarray(IHzz, dtype=float), numpy.asarray(IHxz, dtype=float), numpy.asarray(rF, dtype=float), numpy.asarray(mF, dtype=float), numpy.asarray(IFxx, dtype=float), numpy.asarray(IFyy, dtype=float), numpy.asarray(payload_mass, dtype=float), numpy.asarray(payload_x, dtype=float), numpy.asarray(payload_z, dtype=float), numpy.asarray(steer_inertia, dtype=float), numpy.asarray(steer_damping, dtype=float), numpy.asarray(front_payload_mass, dtype=float), numpy.asarray(front_payload_x, dtype=float), numpy.asarray(front_payload_z, dtype=float), numpy.asarray(reflected_steer_inertia, dtype=float))
    shape = w.shape
    if not shape:
        w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, front_payload_mass, front_payload_x, front_payload_z, reflected_steer_inertia, = (value[()] for value in (w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, payload_mass, payload_x, payload_z, steer_inertia, steer_damping, front_payload_mass, front_payload_x, front_payload_z, reflected_steer_inertia,))
    x0 = front_payload_mass*front_payload_z*front_payload_z
    x1 = mF*rF*rF
    x2 = mH*zH*zH
    x3 = mR*rR*rR
    x4 = numpy.sin(lam)
    x5 = x4*x4
    x6 = steer_inertia*x5
    x7 = 1/(w)
    x8 = numpy.cos(lam)
    x9 = c*x8
    x10 = IFxx*w
    x11 = w*x4
    x12 = IHxz*x9
    x13 = w*x8
    x14 = c*steer_inertia
    x15 = front_payload_mass*front_payload_z
    x16 = w*x9
    x17 = mH*zH
    x18 = x4*x4*x4
    x19 = w*w
    x20 = x19*x8
    x21 = x15*x20
    x22 = x1*x11
    x23 = x17*x20
    x24 = front_payload_x*x15
    x25 = mB*zB
    x26 = x25*xB
    x27 = x17*xH
    x28 = payload_mass*payload_z
    x29 = payload_x*x28
    x30 = x7*(IBxz*x9 + IHxx*x11 + IHxz*x13 + steer_inertia*w*x4 + x0*x11 + x10*x4 + x11*x2 + x12 - x13*x24 - x13*x27 - x14*x18 + x14*x4 + x15*x16 + x16*x17 + x21 + x22 + x23 - x24*x9 - x26*x9 - x27*x9 - x29*x9)
    x31 = 1/(x19)
    x32 = c*c
    x33 = IBzz*x32
    x34 = IFxx*x32
    x35 = IHzz*x32
    x36 = IHzz*x19
    x37 = IRxx*x32
    x38 = steer_inertia*x32
    x39 = w*w*w*w
    x40 = front_payload_mass*x39
    x41 = mH*x39
    x42 = IFxx*c
    x43 = 2*w
    x44 = IHzz*c
    x45 = 2*w*w*w
    x46 = c*front_payload_mass
    x47 = x45*x46
    x48 = mH*x45
    x49 = c*x48
    x50 = front_payload_mass*front_payload_x
    x51 = x45*x50
    x52 = x48*xH
    x53 = front_payload_x*front_payload_x
    x54 = front_payload_mass*x32
    x55 = x53*x54
    x56 = xB*xB
    x57 = mB*x56
    x58 = x32*x57
    x59 = mH*x32
    x60 = xH*xH
    x61 = x59*x60
    x62 = payload_x*payload_x
    x63 = payload_mass*x62
    x64 = x32*x63
    x65 = front_payload_mass*x53
    x66 = mH*x60
    x67 = c*x19
    x68 = front_payload_mass*x67
    x69 = c*x65
    x70 = c*x66
    x71 = mH*x67
    x72 = 4*xH
    x73 = front_payload_x*x54
    x74 = x59*xH
    x75 = x19*x5
    x76 = x4*x4*x4*x4
    x77 = x42*x5
    x78 = x44*x5
    x79 = w*x6
    x80 = 2*x6
    x81 = x15*x4
    x82 = x45*x8
    x83 = x17*x4
    x84 = x11*x15*x9
    x85 = x11*x17*x9
    x86 = x5*x69
    x87 = x5*x70
    x88 = mH*x75
    x89 = x5*x73
    x90 = x5*x74
    x91 = 2*x19*x9
    x92 = 2*x4
    x93 = rF*rR
    x94 = x8*x93
    x95 = IFyy*rR
    x96 = IRyy*rF
    x97 = steer_inertia*x93
    x98 = rR*x1
    x99 = rF*x3
    x100 = x15*x93
    x101 = x25*x93
    x102 = x17*x93
    x103 = x28*x93
    x104 = 1/(rF)
    x105 = x104*x7/rR
    x106 = x105*x8
    x107 = front_payload_mass*x19
    x108 = mH*x19
    x109 = x11*x8
    x110 = mB*xB
    x111 = payload_mass*payload_x
    x112 = mF*rF
    x113 = mH*xH
    x114 = g*x7*(c*front_payload_mass*w*x8 + c*mH*w*x8 + front_payload_mass*front_payload_z*w*x4 + front_payload_mass*x19*x8 + mH*w*x4*zH + mH*x19*x8 - x11*x112 - x110*x9 - x111*x9 - x113*x13 - x113*x9 - x13*x50 - x50*x9)
    x115 = c*rF
    x116 = x115*x50
    x117 = x110*x115
    x118 = x113*x115
    x119 = x111*x115
    x120 = rF*w
    x121 = x120*x50
    x122 = x113*x120
    x123 = x120*x46
    x124 = mH*w*x115
    x125 = rF*x109
    M = numpy.zeros(shape + (2, 2))
    M[..., 0, 0] = IBxx + IFxx + IHxx + IRxx + mB*zB*zB + payload_mass*payload_z*payload_z + x0 + x1 + x2 + x3 + x6
    M[..., 0, 1] = x30
    M[..., 1, 0] = x30
    M[..., 1, 1] = x31*(IFxx*x19 + IHxx*x75 + 2*IHxz*x20*x4 + 4*c*x50*x75 + c*x72*x88 - 2*c*x79 - front_payload_x*x21*x92 - 4*front_payload_x*x68 - 2*front_payload_x*x84 + reflected_steer_inertia*x19 + steer_inertia*x19 + x0*x75 + x1*x75 + 2*x11*x12 + x14*x43 + x19*x54 + x19*x59 + x19*x65 + x19*x66 + x2*x75 - x23*x92*xH - x32*x80 - x33*x5 + x33 - x34*x5 + x34 - x35*x5 + x35 - x36*x5 + x36 - x37*x5 + x37 + x38*x76 + x38 - x40*x5 + x40 - x41*x5 + x41 + x42*x43 + x43*x44 + x43*x69 + x43*x70 - x43*x73 - x43*x74 - x43*x77 - x43*x78 - x43*x86 - x43*x87 + x43*x89 + x43*x90 - x47*x5 + x47 - x49*x5 + x49 + x5*x51 + x5*x52 - x5*x55 - x5*x58 - x5*x61 - x5*x64 - x51 - x52 - x54*x75 + x55 + x58 - x59*x75 + x61 + x64 - x65*x75 - x66*x75 - x71*x72 + x81*x82 + x81*x91 + x82*x83 + x83*x91 - 2*x85*xH)
    C1 = numpy.zeros(shape + (2, 2))
    C1[..., 0, 1] = x105*(IBxz*x94 + IHxz*x94 - x100*x9 - x101*x9 - x102*x9 - x103*x9 + x13*x95 + x13*x98 - x18*x97 - x24*x94 - x26*x94 - x27*x94 - x29*x94 + x4*x97 + x9*x95 + x9*x96 + x9*x98 + x9*x99)
    C1[..., 1, 0] = -x106*(c*x95 + c*x96 + w*x95)
    C1[..., 1, 1] = x31*(-IBzz*c*x5 + IBzz*c + IFxx*c + IFxx*w + IHxz*w*x4*x8 + IHzz*c - IHzz*w*x5 + IHzz*w - IRxx*c*x5 + IRxx*c + c*front_payload_mass*x19*x5 + c*front_payload_mass*x53 + c*mB*x56 + c*mF*rF*w*x4*x8 + c*mH*x19*x5 + c*mH*x60 + c*payload_mass*x62 + c*steer_inertia*x76 + c*steer_inertia - c*x5*x57 - c*x5*x63 - c*x80 + front_payload_mass*front_payload_x*x19*x5 + front_payload_mass*front_payload_x*x32 + front_payload_mass*w*x32*x5 + front_payload_mass*w*x53 - front_payload_x*x107 + mB*x32*xB + mF*rF*x19*x4*x8 + mH*w*x32*x5 + mH*w*x60 + mH*x19*x5*xH + mH*x32*xH + payload_mass*payload_x*x32 + steer_inertia*w - w*x5*x65 - w*x5*x66 - w*x54 - w*x59 - x10*x5 - x108*xH - x109*x24 - x109*x27 - x110*x32*x5 - x111*x32*x5 - x68 - x71 - x77 - x78 - x79 - x84 - x85 - x86 - x87 - x89 - x90)
    D = numpy.zeros(shape + (2, 2))
    D[..., 1, 1] = steer_damping
    K0 = numpy.zeros(shape + (2, 2))
    K0[..., 0, 0] = g*(-mR*rR - x112 + x15 + x17 + x25 + x28)
    K0[..., 0, 1] = x114
    K0[..., 1, 0] = x114
    K0[..., 1, 1] = x114*x4
    K2 = numpy.zeros(shape + (2, 2))
    K2[..., 0, 1] = x106*(-x100 - x101 - x102 - x103 + x95 + x96 + x98 + x99)
    K2[..., 1, 1] = x104*x31*(IFyy*x109 + front_payload_mass*rF*x75 - rF*x107 - rF*x108 + rF*x88 - x116*x5 + x116 - x117*x5 + x117 - x118*x5 + x118 - x119*x5 + x119 - x121*x5 + x121 - x122*x5 + x122 + x123*x5 - x123 + x124*x5 - x124 - x125*x15 - x125*x17 + x22*x8)
    return M, C1, D, K0, K2
