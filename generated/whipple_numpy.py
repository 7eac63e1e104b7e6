"""Whipple bicycle, Meijaard et al. (2007) parameters: linearized equation matrices (NumPy).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``whipple``).

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
"""

import numpy

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy')
OUTPUTS = ('M', 'C1', 'K0', 'K2')


def matrices(w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy):
    """Evaluate the matrices; parameters are arrays broadcast against each other.

    Returns a tuple M, C1, K0, K2 of arrays of shape broadcast_shape + their matrix shape.
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, = numpy.broadcast_arrays(numpy.asarray(w, dtype=float), numpy.asarray(c, dtype=float), numpy.asarray(lam, dtype=float), numpy.asarray(g, dtype=float), numpy.asarray(rR, dtype=float), numpy.asarray(mR, dtype=float), numpy.asarray(IRxx, dtype=float), numpy.asarray(IRyy, dtype=float), numpy.asarray(xB, dtype=float), numpy.asarray(zB, dtype=float), numpy.asarray(mB, dtype=float), numpy.asarray(IBxx, dtype=float), numpy.asarray(IBzz, dtype=float), numpy.asarray(IBxz, dtype=float), numpy.asarray(xH, dtype=float), numpy.asarray(zH, dtype=float), numpy.asarray(mH, dtype=float), numpy.asarray(IHxx, dtype=float), numpy.asarray(IHzz, dtype=float), numpy.asarray(IHxz, dtype=float), numpy.asarray(rF, dtype=float), numpy.asarray(mF, dtype=float), numpy.asarray(IFxx, dtype=float), numpy.asarray(IFyy, dtype=float))
    shape = w.shape
    if not shape:
        w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy, = (value[()] for value in (w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IBzz, IBxz, xH, zH, mH, IHxx, IHzz, IHxz, rF, mF, IFxx, IFyy,))
    x0 = mF*rF*rF
    x1 = mH*zH*zH
    x2 = mR*rR*rR
    x3 = 1/(w)
    x4 = numpy.cos(lam)
    x5 = c*x4
    x6 = numpy.sin(lam)
    x7 = IFxx*w
    x8 = w*x6
    x9 = IHxz*x5
    x10 = IHxz*x4
    x11 = mH*zH
    x12 = x0*x8
    x13 = w*w
    x14 = x11*x4
    x15 = x13*x14
    x16 = mB*zB
    x17 = x11*x5
    x18 = x14*xH
    x19 = x3*(IBxz*x5 + IHxx*x8 + w*x10 + w*x11*x5 - w*x18 + x1*x8 + x12 + x15 - x16*x5*xB - x17*xH + x6*x7 + x9)
    x20 = 1/(x13)
    x21 = c*c
    x22 = IBzz*x21
    x23 = IFxx*x21
    x24 = IHzz*x21
    x25 = IHzz*x13
    x26 = IRxx*x21
    x27 = mH*w*w*w*w
    x28 = IFxx*c
    x29 = 2*w
    x30 = IHzz*c
    x31 = 2*w*w*w
    x32 = c*mH
    x33 = x31*x32
    x34 = mH*xH
    x35 = x31*x34
    x36 = mB*xB*xB
    x37 = x21*x36
    x38 = mH*x21
    x39 = xH*xH
    x40 = x38*x39
    x41 = mH*x39
    x42 = c*x41
    x43 = mH*x13
    x44 = c*x43
    x45 = x38*xH
    x46 = x6*x6
    x47 = x13*x46
    x48 = x28*x46
    x49 = x30*x46
    x50 = x13*x6
    x51 = 2*x50
    x52 = x11*x5*x8
    x53 = 2*xH
    x54 = x42*x46
    x55 = x34*x47
    x56 = x45*x46
    x57 = rF*rR
    x58 = rR*x0
    x59 = rF*x2
    x60 = x16*x57
    x61 = x11*x57
    x62 = IFyy*rR
    x63 = IRyy*rF
    x64 = c*x62 + c*x63 + w*x62
    x65 = 1/(rF)
    x66 = x3*x4*x65/rR
    x67 = IBzz*c
    x68 = IHzz*w
    x69 = IRxx*c
    x70 = c*x36
    x71 = mB*xB
    x72 = x21*x71
    x73 = w*x41
    x74 = w*x38
    x75 = mF*rF
    x76 = x75*x8
    x77 = w*x34
    x78 = g*x3*(c*mH*w*x4 + mH*w*x6*zH + mH*x13*x4 - x34*x5 - x4*x77 - x5*x71 - x76)
    x79 = c*rF
    x80 = x71*x79
    x81 = x34*x79
    x82 = rF*x77
    x83 = rF*w*x32
    M = numpy.zeros(shape + (2, 2))
    M[..., 0, 0] = IBxx + IFxx + IHxx + IRxx + mB*zB*zB + x0 + x1 + x2
    M[..., 0, 1] = x19
    M[..., 1, 0] = x19
    M[..., 1, 1] = x20*(IFxx*x13 + IHxx*x47 + 4*c*x55 + x0*x47 + x1*x47 + x10*x51 + x13*x38 + x13*x41 + x14*x31*x6 - x15*x53*x6 + x17*x51 - x22*x46 + x22 - x23*x46 + x23 - x24*x46 + x24 - x25*x46 + x25 - x26*x46 + x26 - x27*x46 + x27 + x28*x29 + x29*x30 + x29*x42 - x29*x45 - x29*x48 - x29*x49 - x29*x54 + x29*x56 - x33*x46 + x33 + x35*x46 - x35 - x37*x46 + x37 - x38*x47 - x40*x46 + x40 - x41*x47 - 4*x44*xH - x52*x53 + 2*x8*x9)
    C1 = numpy.zeros(shape + (2, 2))
    C1[..., 0, 1] = x66*(IBxz*x57 + IHxz*x57 + c*x58 + c*x59 - c*x60 - c*x61 + w*x58 - x60*xB - x61*xH + x64)
    C1[..., 1, 0] = -x64*x66
    C1[..., 1, 1] = x20*(x10*x8 - x18*x8 + x28 + x30 + x32*x47 + x4*x50*x75 + x42 - x43*xH - x44 + x45 - x46*x67 - x46*x68 - x46*x69 - x46*x7 - x46*x70 - x46*x72 - x46*x73 + x46*x74 - x48 - x49 + x5*x76 - x52 - x54 + x55 - x56 + x67 + x68 + x69 + x7 + x70 + x72 + x73 - x74)
    K0 = numpy.zeros(shape + (2, 2))
    K0[..., 0, 0] = g*(-mR*rR + x11 + x16 - x75)
    K0[..., 0, 1] = x78
    K0[..., 1, 0] = x78
    K0[..., 1, 1] = x6*x78
    K2 = numpy.zeros(shape + (2, 2))
    K2[..., 0, 1] = x66*(x58 + x59 - x60 - x61 + x62 + x63)
    K2[..., 1, 1] = x20*x65*(IFyy*x4*x8 + mH*rF*x47 - rF*x14*x8 - rF*x43 + x12*x4 - x46*x80 - x46*x81 - x46*x82 + x46*x83 + x80 + x81 + x82 - x83)
    return M, C1, K0, K2
