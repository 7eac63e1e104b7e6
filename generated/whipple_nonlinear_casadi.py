"""Whipple bicycle, nonlinear equations, Meijaard et al. (2007) parameters (CasADi).

GENERATED FILE - do not edit. Produced by ``whipple regenerate`` from the SymPy
derivation in derivation/ (model ``whipple_nonlinear``).

Derivation sources sha256: 85447a33b99f7a7cc45c28c4bf5678d54b6c5184e081d72ed53ff742e0d08074
SymPy version: 1.14.0

Equation form: M u' = F + C^T f, C u' = b (the front contact's velocity C u vanishes; f is the contact force on the front wheel, yaw-frame components [N]), u = [yaw_rate, roll_rate, pitch_rate, steer_rate, rear_wheel_rate, front_wheel_rate]; the pitch solves h(roll, pitch, steer) = 0; the rear contact moves at (x', y') = rear_contact_velocity.

Functions: contact_height, constraints, dynamics, energy, rear_contact_velocity.

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
    IByy: rear frame moment of inertia about y [kg m^2]
    IBzz: rear frame moment of inertia about z [kg m^2]
    IBxz: rear frame product of inertia xz [kg m^2]
    xH: front frame (fork and handlebar) mass centre, forward of the rear contact [m]
    zH: front frame mass centre, z down (negative above ground) [m]
    mH: front frame mass [kg]
    IHxx: front frame moment of inertia about x [kg m^2]
    IHyy: front frame moment of inertia about y [kg m^2]
    IHzz: front frame moment of inertia about z [kg m^2]
    IHxz: front frame product of inertia xz [kg m^2]
    rF: front wheel radius [m]
    mF: front wheel mass [kg]
    IFxx: front wheel moment of inertia about a diameter [kg m^2]
    IFyy: front wheel moment of inertia about its axle [kg m^2]

Variables:
    yaw: yaw angle of the rear frame [rad]
    roll: roll angle of the rear frame [rad]
    pitch: pitch angle of the rear frame [rad]
    steer: steer angle of the front frame relative to the rear frame [rad]
    yaw_rate: yaw rate [rad/s]
    roll_rate: roll rate [rad/s]
    pitch_rate: pitch rate [rad/s]
    steer_rate: steer rate [rad/s]
    rear_wheel_rate: rear wheel rate relative to the rear frame [rad/s]
    front_wheel_rate: front wheel rate relative to the front frame [rad/s]
    roll_torque: torque on the rear frame about the roll axis [N m]
    steer_torque: torque of the rear frame on the front frame about the steer axis [N m]
"""

import casadi

PARAMETERS = ('w', 'c', 'lam', 'g', 'rR', 'mR', 'IRxx', 'IRyy', 'xB', 'zB', 'mB', 'IBxx', 'IByy', 'IBzz', 'IBxz', 'xH', 'zH', 'mH', 'IHxx', 'IHyy', 'IHzz', 'IHxz', 'rF', 'mF', 'IFxx', 'IFyy')
VARIABLES = {'contact_height': ('roll', 'pitch', 'steer'), 'constraints': ('roll', 'pitch', 'steer'), 'dynamics': ('roll', 'pitch', 'steer', 'yaw_rate', 'roll_rate', 'pitch_rate', 'steer_rate', 'rear_wheel_rate', 'front_wheel_rate', 'roll_torque', 'steer_torque'), 'energy': ('roll', 'pitch', 'steer', 'yaw_rate', 'roll_rate', 'pitch_rate', 'steer_rate', 'rear_wheel_rate', 'front_wheel_rate'), 'rear_contact_velocity': ('yaw', 'pitch_rate', 'rear_wheel_rate')}
OUTPUTS = {'contact_height': ('height', 'height_gradient'), 'constraints': ('C',), 'dynamics': ('M', 'F', 'b'), 'energy': ('kinetic', 'potential'), 'rear_contact_velocity': ('velocity',)}


def contact_height(p, variables):
    """The holonomic constraint h = 0 that fixes the pitch.

    p: the parameters (order PARAMETERS); variables: roll, pitch, steer.
    Returns a tuple of CasADi expressions:

    height (): z of the front contact relative to the rear contact [m], z down (0 on the ground)
    height_gradient (3,): dh/d(roll, pitch, steer) [m/rad]
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy, = casadi.vertsplit(p)
    roll, pitch, steer, = casadi.vertsplit(variables)
    x0 = casadi.cos(roll)
    x1 = rR*x0
    x2 = casadi.cos(pitch)
    x3 = casadi.sin(pitch)
    x4 = c + w
    x5 = x3*x4
    x6 = casadi.cos(lam)
    x7 = casadi.sin(roll)
    x8 = casadi.sin(steer)
    x9 = x7*x8
    x10 = casadi.sin(lam)
    x11 = x10**2
    x12 = casadi.cos(steer)
    x13 = x6**2
    x14 = x11 + x12*x13
    x15 = x10*x6
    x16 = x10*x6 - x12*x15
    x17 = x16*x2
    x18 = -x14*x3 + x17
    x19 = x11*x12 + x13
    x20 = x16*x3
    x21 = x19*x2 - x20
    x22 = x12*x7
    x23 = x10*x8
    x24 = x2*x23 + x3*x6*x8
    x25 = x0*x24 + x22
    x26 = -x25
    x27 = x25*x26
    x28 = x26**2 + 2*x27 + 1
    x29 = 1/casadi.sqrt(x28)
    x30 = rR*x7
    x31 = rF*x29
    x32 = x0*x12
    x33 = x24*x7
    x34 = -x32 + x33
    x35 = x25*x34
    x36 = -x26*x34
    x37 = (1/2)*x26
    x38 = x28**(-3/2)
    x39 = rF*x38
    x40 = x39*(-x35 - x36 - x37*(-2*x32 + 2*x33))
    x41 = x2*x6*x8 - x23*x3
    x42 = x3*x8
    x43 = x2*x8
    x44 = x0*(x10*x12*x2 + x12*x3*x6)
    x45 = x44 - x9
    x46 = -x25*x45
    x47 = x26*x45
    x48 = x39*(-x37*(-2*x44 + 2*x7*x8) - x46 - x47)
    height = -c*(x0*x18 + x6*x9) + rF*x25*x26*x29 + rF*x29 - rF*(x0*x21 - x10*x9) + rR*x0*x2 - x0*x5 - x1
    height_gradient = casadi.vertcat(-c*(x0*x6*x8 - x18*x7) - rF*(-x0*x23 - x21*x7) - x2*x30 + x27*x40 + x30 + x31*x35 + x31*x36 + x40 + x5*x7, -c*x0*(-x14*x2 - x20) + rF*x0*x25**2*x26*x38*x41 + rF*x0*x25*x38*x41 + rF*x0*x26*x29*x41 - rF*x0*(-x17 - x19*x3) - x0*x2*x4 - x0*x25*x31*x41 - x1*x3, -c*(x0*(x13*x42 + x15*x43) + x22*x6) - rF*(x0*(-x11*x43 - x15*x42) - x10*x22) + x27*x48 + x31*x46 + x31*x47 + x48)
    return height, height_gradient


def constraints(p, variables):
    """The front contact's velocity C u (yaw-frame components).

    p: the parameters (order PARAMETERS); variables: roll, pitch, steer.
    Returns a tuple of CasADi expressions:

    C (3, 6): velocity of the front contact per rate in u [m/rad]
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy, = casadi.vertsplit(p)
    roll, pitch, steer, = casadi.vertsplit(variables)
    x0 = casadi.sin(roll)
    x1 = rR*x0
    x2 = casadi.cos(pitch)
    x3 = casadi.sin(pitch)
    x4 = c + w
    x5 = x3*x4
    x6 = casadi.sin(lam)
    x7 = casadi.sin(steer)
    x8 = x6*x7
    x9 = casadi.cos(lam)
    x10 = x7*x9
    x11 = -x10*x2 + x3*x8
    x12 = x0*x7
    x13 = casadi.cos(roll)
    x14 = x9**2
    x15 = casadi.cos(steer)
    x16 = x6**2
    x17 = x14 + x15*x16
    x18 = -x15*x6*x9 + x6*x9
    x19 = x18*x3
    x20 = x17*x2 - x19
    x21 = -x12*x6 + x13*x20
    x22 = x14*x15 + x16
    x23 = x18*x2
    x24 = -x22*x3 + x23
    x25 = x12*x9 + x13*x24
    x26 = -c*x21 + rF*x25
    x27 = x17*x3 + x23
    x28 = x2*x6
    x29 = x3*x9
    x30 = x28*x7 + x29*x7
    x31 = x0*x15 + x13*x30
    x32 = -x31
    x33 = 1/casadi.sqrt(2*x31*x32 + x32**2 + 1)
    x34 = x32*x33
    x35 = rF*x25*x34
    x36 = c*x31 + x35
    x37 = x19 + x2*x22
    x38 = rF*x33
    x39 = x32*x38
    x40 = -rF*x31 - x21*x39
    x41 = -c*x27 + rF*x37
    x42 = rF*x34*x37
    x43 = c*x11 + x42
    x44 = rF*x11
    x45 = -x27*x39 - x44
    x46 = -rR
    x47 = c*x15 + x10*x39
    x48 = rF*x34*x6
    x49 = -rF*x15 + x48*x7
    x50 = c*x8 + rF*x10
    x51 = rR*x2 - x5
    x52 = -c*x9 + rF*x6
    x53 = x0*x2
    x54 = -x0*x30 + x13*x15
    x55 = x0**2
    x56 = x2*x4
    x57 = rR*x13
    x58 = x3*x57
    x59 = x13*x56
    x60 = x58 + x59
    x61 = -x0*x20 - x13*x8
    x62 = -x0*x24 + x13*x7*x9
    x63 = -x51
    x64 = x1*x3
    x65 = x4*x53
    C = casadi.blockcat([[-x0*x5 + x1*x2 - x1 + x11*x26 + x27*x36 + x37*x40, x11*x41 + x27*x43 + x37*x45, x11*x50 + x13*x38 + x27*x47 + x37*x49 + x46 + x51, x11*x52 + x27*x48 + x38*(x0*x3*x6 - x53*x9) - x42*x9, x46, x38*x54], [rR*x3*x55 + x13*x60 + x26*x54 + x36*x61 + x40*x62 + x55*x56, x13*x63 - x38 + x41*x54 + x43*x61 + x45*x62 + x57, x47*x61 + x49*x62 + x50*x54 + x64 + x65, -x38*(x28 + x29) - x39*x62*x9 + x48*x61 + x52*x54, 0, -x33*x44], [x0*x60 - x13*x64 - x13*x65 + x21*x36 + x25*x40 + x26*x31, x0*x63 + x1 + x21*x43 + x25*x45 + x31*x41, x21*x47 + x25*x49 + x31*x50 - x58 - x59, x21*x48 + x31*x52 - x35*x9, 0, 0]])
    return (C,)


def dynamics(p, variables):
    """Kane's equations of the unconstrained speeds, and the constraint bias.

    p: the parameters (order PARAMETERS); variables: roll, pitch, steer, yaw_rate, roll_rate, pitch_rate, steer_rate, rear_wheel_rate, front_wheel_rate, roll_torque, steer_torque.
    Returns a tuple of CasADi expressions:

    M (6, 6): mass matrix [kg m^2]
    F (6,): generalized active minus velocity-dependent inertia forces [N m]
    b (3,): C u' = b along the motion [m/s^2]
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy, = casadi.vertsplit(p)
    roll, pitch, steer, yaw_rate, roll_rate, pitch_rate, steer_rate, rear_wheel_rate, front_wheel_rate, roll_torque, steer_torque, = casadi.vertsplit(variables)
    x0 = casadi.sin(roll)
    x1 = x0**2
    x2 = rR**2
    x3 = mR*x2
    x4 = x1*x3
    x5 = casadi.cos(roll)
    x6 = x5**2
    x7 = casadi.sin(pitch)
    x8 = IRxx*x7**2
    x9 = casadi.cos(pitch)
    x10 = IRxx*x9**2
    x11 = IBxz*x7
    x12 = IBzz*x5*x9 - x11*x5
    x13 = x5*x9
    x14 = x5*x7
    x15 = -IBxx*x14 + IBxz*x5*x9
    x16 = rR*x0
    x17 = x7*xB
    x18 = x0*x17
    x19 = rR + zB
    x20 = x0*x19*x9 - x16 - x18
    x21 = casadi.cos(steer)
    x22 = x0*x21
    x23 = casadi.sin(steer)
    x24 = casadi.sin(lam)
    x25 = x24*x9
    x26 = casadi.cos(lam)
    x27 = x26*x7
    x28 = x23*x25 + x23*x27
    x29 = x22 + x28*x5
    x30 = x29**2
    x31 = x9*xB
    x32 = x19*x7
    x33 = x31*x5
    x34 = x32*x5
    x35 = x33 + x34
    x36 = x1*x31 + x1*x32 + x35*x5
    x37 = -x0*x33 - x0*x34 + x0*x35
    x38 = x0*x23
    x39 = x24**2
    x40 = x26**2
    x41 = x21*x40 + x39
    x42 = x24*x26
    x43 = -x21*x42 + x24*x26
    x44 = x43*x9
    x45 = -x41*x7 + x44
    x46 = x26*x38 + x45*x5
    x47 = x21*x39 + x40
    x48 = x43*x7
    x49 = x47*x9 - x48
    x50 = -x24*x38 + x49*x5
    x51 = IHxx*x46 + IHxz*x50
    x52 = IHxz*x46 + IHzz*x50
    x53 = x24*x7
    x54 = x26*x9
    x55 = x23*x53 - x23*x54
    x56 = c*x50
    x57 = rF*x46 - x56
    x58 = x44 + x47*x7
    x59 = c*x58
    x60 = x41*x9 + x48
    x61 = rF*x60
    x62 = x16*x9
    x63 = c + w
    x64 = x63*x7
    x65 = x0*x64
    x66 = -x16 + x62 - x65
    x67 = x29*x59 - x29*x61 + x55*x57 + x66
    x68 = x46*zH
    x69 = -x63 + xH
    x70 = x50*x69 - x68
    x71 = x60*zH
    x72 = x58*x69
    x73 = x29*x71 - x29*x72 + x55*x70 + x66
    x74 = x14*x16
    x75 = x63*x9
    x76 = x5*x75
    x77 = x0*x76
    x78 = rR*x5
    x79 = x7*x78
    x80 = x76 + x79
    x81 = rF*x46
    x82 = x0*x80 + x29*x56 + x29*x57 - x29*x81 - x74 - x77
    x83 = x0*x28
    x84 = -x21*x5 + x83
    x85 = -x84
    x86 = x23*x5
    x87 = -x0*x49 - x24*x86
    x88 = x29*x87
    x89 = -x0*x45 + x23*x26*x5
    x90 = x29*x89
    x91 = rR*x7
    x92 = x1*x75 + x1*x91 + x5*x80
    x93 = c*x88 - rF*x90 + x57*x85 + x92
    x94 = x50*x69
    x95 = x0*x80 + x29*x46*zH + x29*x70 - x29*x94 - x74 - x77
    x96 = -x69*x88 + x70*x85 + x90*zH + x92
    x97 = IFxx*x50
    x98 = IFxx*x46
    x99 = IFyy*x29
    x100 = IHyy*x29
    x101 = x19*x9
    x102 = -x101 + x17
    x103 = x102*x5 + x78
    x104 = mB*x36
    x105 = x0*x102 + x16
    x106 = mB*x37
    x107 = rF*x60 - x59
    x108 = x107*x55 + x55*x59 - x55*x61
    x109 = mF*x67
    x110 = x55*x87
    x111 = x55*x89
    x112 = rR*x9
    x113 = x112 - x64
    x114 = -x113
    x115 = x114*x5 + x78
    x116 = c*x110 - rF*x111 + x107*x85 + x115
    x117 = mF*x93
    x118 = x0*x114 + x16
    x119 = x107*x29 + x118 + x55*x56 - x55*x81
    x120 = mF*x82
    x121 = x58*x69 - x71
    x122 = x121*x55 + x55*x71 - x55*x72
    x123 = mH*x73
    x124 = -x110*x69 + x111*zH + x115 + x121*x85
    x125 = mH*x96
    x126 = x118 + x121*x29 + x55*x68 - x55*x94
    x127 = mH*x95
    x128 = x100*x55 + x103*x104 + x105*x106 + x108*x109 + x116*x117 + x119*x120 + x122*x123 + x124*x125 + x126*x127 + x55*x99 + x58*x97 + x60*x98
    x129 = x23*x26
    x130 = x23*x24
    x131 = IRyy*x0
    x132 = x0*x31
    x133 = x0*x32
    x134 = x132 + x133
    x135 = -x35
    x136 = -rR - x102
    x137 = mB*x20
    x138 = c*x130 + rF*x129
    x139 = c*x21*x50 + x138*x29 - x21*x81 - x80
    x140 = x21*x87
    x141 = x21*x89
    x142 = x16*x7
    x143 = x0*x75
    x144 = x142 + x143
    x145 = c*x140 - rF*x141 + x138*x85 + x144
    x146 = -rR + x113
    x147 = x138*x55 + x146 + x21*x59 - x21*x61
    x148 = -x129*zH - x130*x69
    x149 = x148*x29 + x21*x46*zH - x21*x94 - x80
    x150 = -x140*x69 + x141*zH + x144 + x148*x85
    x151 = x146 + x148*x55 + x21*x71 - x21*x72
    x152 = x0*x3
    x153 = IByy*x0 + x100*x21 + x104*x134 + x106*x135 + x109*x147 + x117*x145 + x120*x139 + x123*x151 + x125*x150 + x127*x149 + x129*x98 - x130*x97 + x131 + x136*x137 + x152 + x21*x99
    x154 = -c*x26 + rF*x24
    x155 = x154*x29
    x156 = x154*x85
    x157 = x154*x55
    x158 = -x24*zH + x26*x69
    x159 = x158*x29
    x160 = x158*x85
    x161 = x158*x55
    x162 = x109*x157 + x117*x156 + x120*x155 + x123*x161 + x125*x160 + x127*x159 + x24*x98 + x26*x97
    x163 = IRyy*x0 + mR*x0*x2 - rR*x109 - rR*x123 - rR*x137
    x164 = IHxx*x60 + IHxz*x58
    x165 = IHxz*x60 + IHzz*x58
    x166 = IBxz*x9 + IBzz*x7
    x167 = IBxx*x9 + x11
    x168 = x55**2
    x169 = IFyy*x55
    x170 = mB*x103
    x171 = mB*x105
    x172 = mF*x108
    x173 = mF*x116
    x174 = mF*x119
    x175 = mH*x122
    x176 = mH*x124
    x177 = mH*x126
    x178 = IFxx*x60
    x179 = IFxx*x58
    x180 = IHyy*x21*x55 + x129*x178 - x130*x179 + x134*x170 + x135*x171 + x139*x174 + x145*x173 + x147*x172 + x149*x177 + x150*x176 + x151*x175 + x169*x21
    x181 = x155*x174 + x156*x173 + x157*x172 + x159*x177 + x160*x176 + x161*x175 + x178*x24 + x179*x26
    x182 = -rR*x172 - rR*x175
    x183 = IHxz*x26
    x184 = -IHzz*x130 + x183*x23
    x185 = IHxz*x24
    x186 = IHxx*x129 - x185*x23
    x187 = x21**2
    x188 = x23**2
    x189 = IFxx*x40
    x190 = IFxx*x39
    x191 = IRyy + x3
    x192 = mF*x139
    x193 = mF*x145
    x194 = mF*x147
    x195 = mH*x149
    x196 = mH*x150
    x197 = mH*x151
    x198 = x155*x192 + x156*x193 + x157*x194 + x159*x195 + x160*x196 + x161*x197
    x199 = mB*x136
    x200 = IRyy + mR*x2 - rR*x194 - rR*x197 - rR*x199
    x201 = IFyy*x21
    x202 = IHxx*x24 + x183
    x203 = IHzz*x26 + x185
    x204 = mF*x154**2
    x205 = mH*x158**2
    x206 = x85**2
    x207 = mF*rR
    x208 = mH*rR
    x209 = -x157*x207 - x161*x208
    x210 = x5*yaw_rate
    x211 = roll_rate*x210
    x212 = x0*yaw_rate
    x213 = 2*x3
    x214 = roll_rate*x7
    x215 = x13*yaw_rate + x214
    x216 = pitch_rate + x212
    x217 = x215*x216
    x218 = rear_wheel_rate + x216
    x219 = IRyy*x218
    x220 = -x215
    x221 = pitch_rate*x220 + x212*x214
    x222 = IRxx*x217 + IRxx*x221 - x215*x219
    x223 = roll_rate*x9
    x224 = x14*yaw_rate
    x225 = x223 - x224
    x226 = x216*x225
    x227 = pitch_rate*x225 - x212*x223
    x228 = -IRxx*x226 + IRxx*x227 + x219*x225
    x229 = IBxx*x225 + IBxz*x215
    x230 = IBxz*x225 + IBzz*x215
    x231 = IByy*x211 + x215*x229 - x225*x230
    x232 = IBxx*x221 + IBxz*x227 - IByy*x217 + x216*x230
    x233 = IBxz*x221 + IByy*x226 + IBzz*x227 - x216*x229
    x234 = x78*yaw_rate
    x235 = roll_rate*x78
    x236 = -x19*x225 + x215*xB
    x237 = x132*x216 + x133*x216 + x235 + x236*x5
    x238 = pitch_rate*(-x216*x31 - x216*x32) + roll_rate*(-x17*x210 + x19*x5*x9*yaw_rate - x234) - x237*yaw_rate
    x239 = roll_rate*yaw_rate
    x240 = -x55
    x241 = roll_rate*x28 + x210*x240
    x242 = pitch_rate*x23
    x243 = x21*x53 - x21*x54
    x244 = x21*x25 + x21*x27
    x245 = x244*x5
    x246 = x245 - x38
    x247 = roll_rate*x243 - x242 + x246*yaw_rate
    x248 = pitch_rate*x241 + steer_rate*x247 + x239*x85
    x249 = x17*x216
    x250 = -x19*x220 + x225*xB
    x251 = -x212*x31 - x212*x32
    x252 = x6*yaw_rate
    x253 = pitch_rate*(x0*x250 - x101*x216*x5 + x249*x5) + roll_rate*(x0*x251 + x237 - x252*x31 - x252*x32)
    x254 = rR*x218
    x255 = -roll_rate*x16
    x256 = pitch_rate*(x0*x101*x216 - x18*x216 + x250*x5) + roll_rate*(-x0*x236 + x212*x33 + x212*x34 + x216*x33 + x216*x34 + x251*x5 + x255) + yaw_rate*(x19*x216*x9 - x249 - x254)
    x257 = roll_rate*x58 + steer_rate*x26 - x24*x242 + x50*yaw_rate
    x258 = pitch_rate*x21
    x259 = roll_rate*x55 + x258 + x29*yaw_rate
    x260 = x257*x259
    x261 = IFyy*(front_wheel_rate + x259)
    x262 = x23*x42
    x263 = x262*x7
    x264 = x23*x40
    x265 = x263 - x264*x9
    x266 = x262*x9 + x264*x7
    x267 = x22*x26 + x266*x5
    x268 = roll_rate*x265 + x258*x26 + x267*yaw_rate
    x269 = -x60
    x270 = roll_rate*x45 + x210*x269
    x271 = pitch_rate*x270 + steer_rate*x268 + x239*x89
    x272 = IFxx*x260 + IFxx*x271 - x257*x261
    x273 = roll_rate*x60 + steer_rate*x24 + x242*x26 + x46*yaw_rate
    x274 = x259*x273
    x275 = x23*x39
    x276 = x23*x24*x26*x9 - x275*x7
    x277 = -x263 - x275*x9
    x278 = -x22*x24 + x277*x5
    x279 = roll_rate*x276 - x24*x258 + x278*yaw_rate
    x280 = -x58
    x281 = roll_rate*x49 + x210*x280
    x282 = pitch_rate*x281 + steer_rate*x279 + x239*x87
    x283 = -IFxx*x274 + IFxx*x282 + x261*x273
    x284 = IHxz*x273 + IHzz*x257
    x285 = IHxx*x273 + IHxz*x257
    x286 = IHyy*x248 + x257*x285 - x273*x284
    x287 = IHxz*x271 + IHyy*x274 + IHzz*x282 - x259*x285
    x288 = IHxx*x271 + IHxz*x282 - IHyy*x260 + x259*x284
    x289 = x85*yaw_rate
    x290 = x87*yaw_rate
    x291 = c*x290
    x292 = rF*x89*yaw_rate - x291
    x293 = -x210*x64 + x234*x9 - x234
    x294 = x292*x55 + x293
    x295 = c*x259
    x296 = rF*x259
    x297 = -c*x257 + rF*x273
    x298 = -rR*x225 + x215*x63
    x299 = x142*x216 + x143*x216 + x235 + x298*x5
    x300 = x297*x85 + x299
    x301 = x295*x87 - x296*x89 + x300
    x302 = -c*x279 + rF*x268
    x303 = x243*x297 + x302*x55
    x304 = -c*x281 + rF*x270
    x305 = x216*x91
    x306 = x216*x75
    x307 = x28*x297 + x304*x55 - x305 - x306
    x308 = pitch_rate*(x241*x59 - x241*x61 + x295*x49 - x296*x45 + x307) + roll_rate*(x289*x59 - x289*x61 + x294) + steer_rate*(x247*x59 - x247*x61 - x265*x296 + x276*x295 + x303) - x301*yaw_rate
    x309 = x89*yaw_rate
    x310 = x309*zH
    x311 = -x310 + x69*x87*yaw_rate
    x312 = x257*x69 - x273*zH
    x313 = x259*zH
    x314 = x259*x69
    x315 = x299 + x312*x85 + x313*x89 - x314*x87
    x316 = -x268*zH + x279*x69
    x317 = -x270*zH + x281*x69
    x318 = pitch_rate*(x241*x60*zH - x241*x72 + x259*x45*zH + x28*x312 - x305 - x306 - x314*x49 + x317*x55) + roll_rate*(x289*x71 - x289*x72 + x293 + x311*x55) + steer_rate*(x243*x312 + x247*x71 - x247*x72 + x265*x313 - x276*x314 + x316*x55) - x315*yaw_rate
    x319 = x246*x297 + x29*x302
    x320 = -x142*yaw_rate - x212*x75
    x321 = x0*x320 - x252*x75 - x252*x91
    x322 = x29*x292 + x321
    x323 = x280*x295
    x324 = x269*x296
    x325 = x240*x297
    x326 = -rR*x220 + x225*x63
    x327 = x216*x64
    x328 = x0*x326 - x216*x78*x9 + x327*x5
    x329 = x29*x304 + x325*x5 + x328
    x330 = pitch_rate*(x241*x56 - x241*x81 + x323*x5 - x324*x5 + x329) + roll_rate*(x289*x56 - x289*x81 + x301 + x322) + steer_rate*(x247*x56 - x247*x81 - x267*x296 + x278*x295 + x319)
    x331 = x240*x312
    x332 = x269*x313
    x333 = x280*x314
    x334 = pitch_rate*(x241*x68 - x241*x94 + x29*x317 + x328 + x331*x5 + x332*x5 - x333*x5) + roll_rate*(x289*x68 - x289*x94 + x29*x311 + x315 + x321) + steer_rate*(x246*x312 + x247*x68 - x247*x94 + x267*x313 - x278*x314 + x29*x316)
    x335 = x112*x216 - x254 - x327
    x336 = c*x247
    x337 = x21*x5
    x338 = -x0*x277 - x24*x337
    x339 = rF*x247
    x340 = -x0*x266 + x21*x26*x5
    x341 = -x0*x244 - x86
    x342 = x297*x341 + x302*x85
    x343 = -x50
    x344 = -x46
    x345 = rF*x309
    x346 = -x29
    x347 = -x0*x298 + x16*x224 + x212*x76 + x216*x76 + x216*x79 + x255 + x320*x5
    x348 = x292*x85 + x297*x346 + x347
    x349 = c*x241
    x350 = rF*x241
    x351 = x0*x325
    x352 = x216*x65
    x353 = x216*x62 + x326*x5 - x352
    x354 = pitch_rate*(-x0*x323 + x0*x324 + x304*x85 + x349*x87 - x350*x89 - x351 + x353) + roll_rate*(x291*x85 + x295*x343 - x296*x344 - x345*x85 + x348) + steer_rate*(x295*x338 - x296*x340 + x336*x87 - x339*x89 + x342) + yaw_rate*(x259*x59 - x259*x61 + x297*x55 + x335)
    x355 = x89*zH
    x356 = x69*x87
    x357 = pitch_rate*(-x0*x331 - x0*x332 + x0*x333 + x241*x355 - x241*x356 + x317*x85 + x353) + roll_rate*(-x290*x69*x85 + x310*x85 + x311*x85 + x312*x346 + x313*x344 - x314*x343 + x347) + steer_rate*(x247*x355 - x247*x356 + x312*x341 + x313*x340 - x314*x338 + x316*x85) + yaw_rate*(x259*x71 - x259*x72 + x312*x55 + x335)
    x358 = roll_rate**2
    x359 = IRyy*x211
    x360 = x211*x213
    x361 = x25 + x27
    x362 = x0*x53 - x0*x54
    x363 = -x26*x5*x9 + x5*x53
    x364 = x29*x346
    x365 = x346**2 + 2*x364 + 1
    x366 = 1/casadi.sqrt(x365)
    x367 = x346*x366
    x368 = rF*x273
    x369 = x366*x368
    x370 = (1/2)*x346
    x371 = -x29*x84 - x346*x85 - x370*(-2*x337 + 2*x83)
    x372 = x346*x371
    x373 = x365**(-3/2)
    x374 = x368*x373
    x375 = c*x289 + x345*x367 + x369*x84 + x372*x374
    x376 = rF*x366
    x377 = x346*x376
    x378 = x257*x376
    x379 = rF*x373
    x380 = x257*x379
    x381 = -rF*x289 - x290*x377 - x372*x380 - x378*x84
    x382 = x379*(front_wheel_rate*x85 + pitch_rate*x5 + steer_rate*x362)
    x383 = x295 + x367*x368
    x384 = x240*x5
    x385 = x364*x384
    x386 = rF*x270*x367 + x349 - x369*x384 + x374*x385
    x387 = rF*x240*x257*x366*x5 - x281*x377 - x350 - x380*x385
    x388 = -x257*x377 - x296
    x389 = x29*x384
    x390 = -x246
    x391 = -x246*x346 - x29*x390 - x370*(2*x0*x23 - 2*x245)
    x392 = x346*x391
    x393 = rF*x268*x367 + x336 + x369*x390 + x374*x392
    x394 = -x279*x377 - x339 - x378*x390 - x380*x392
    x395 = front_wheel_rate*x376
    x396 = x379*(front_wheel_rate*x55 + roll_rate + steer_rate*x361)
    x397 = x280*x383
    x398 = x269*x388
    M = casadi.blockcat([[IByy*x1 + IFxx*x46**2 + IFxx*x50**2 + IFyy*x30 + IHyy*x30 + IRyy*x1 + mB*x20**2 + mB*x36**2 + mB*x37**2 + mF*x67**2 + mF*x82**2 + mF*x93**2 + mH*x73**2 + mH*x95**2 + mH*x96**2 + x10*x6 + x12*x13 - x14*x15 + x4 + x46*x51 + x50*x52 + x6*x8, x12*x7 + x128 + x15*x9 + x51*x60 + x52*x58, x129*x51 - x130*x52 + x153, x162 + x24*x51 + x26*x52, x163, x99], [x128 + x13*x166 - x14*x167 + x164*x46 + x165*x50, IFxx*x58**2 + IFxx*x60**2 + IFyy*x168 + IHyy*x168 + mB*x103**2 + mB*x105**2 + mF*x108**2 + mF*x116**2 + mF*x119**2 + mH*x122**2 + mH*x124**2 + mH*x126**2 + x10 + x164*x60 + x165*x58 + x166*x7 + x167*x9 + x3*x6 + x4 + x8, x129*x164 - x130*x165 + x180, x164*x24 + x165*x26 + x181, x182, x169], [x153 + x184*x50 + x186*x46, x180 + x184*x58 + x186*x60, IByy + IFyy*x187 + IHyy*x187 + mB*x134**2 + mB*x135**2 + mB*x136**2 + mF*x139**2 + mF*x145**2 + mF*x147**2 + mH*x149**2 + mH*x150**2 + mH*x151**2 + x129*x186 - x130*x184 + x188*x189 + x188*x190 + x191, x184*x26 + x186*x24 + x198, x200, x201], [x162 + x202*x46 + x203*x50, x181 + x202*x60 + x203*x58, x129*x202 - x130*x203 + x198, x168*x204 + x168*x205 + x189 + x190 + x202*x24 + x203*x26 + x204*x206 + x204*x30 + x205*x206 + x205*x30, x209, 0], [x163, x182, x200, x209, mB*x2 + mF*x2 + mH*x2 + x191, 0], [x99, x169, x201, 0, 0, IFyy]])
    F = casadi.vertcat(g*mB*x37 + g*mF*x82 + g*mH*x95 - roll_rate*x212*x213*x5 - x0*x231 - x104*x256 - x106*x253 - x109*x308 - x117*x354 - x120*x330 - x123*x318 - x125*x357 - x127*x334 - x13*x228 - x13*x233 - x131*x211 - x137*x238 + x222*x5*x7 + x232*x5*x7 - x248*x99 - x272*x46 - x283*x50 - x286*x29 - x287*x50 - x288*x46, g*mB*x105 + g*mF*x119 + g*mH*x126 + g*mR*rR*x0 - mR*x78*(-x16*x358 - x254*yaw_rate) + roll_torque - x152*x358*x5 - x169*x248 - x170*x256 - x171*x253 - x172*x308 - x173*x354 - x174*x330 - x175*x318 - x176*x357 - x177*x334 - x222*x9 - x228*x7 - x232*x9 - x233*x7 - x272*x60 - x283*x58 - x286*x55 - x287*x58 - x288*x60, g*mB*x135 + g*mF*x139 + g*mH*x149 - mB*x134*x256 - mB*x135*x253 - x129*x272 - x129*x288 - x192*x330 - x193*x354 - x194*x308 - x195*x334 - x196*x357 - x197*x318 - x199*x238 - x201*x248 - x21*x286 + x23*x24*x283 + x23*x24*x287 - x231 - x359 - x360, g*mF*x154*x29 + g*mH*x158*x29 - mF*x155*x330 - mF*x156*x354 - mF*x157*x308 - mH*x159*x334 - mH*x160*x357 - mH*x161*x318 + steer_torque*x361**2 + steer_torque*x362**2 + steer_torque*x363**2 - x24*x272 - x24*x288 - x26*x283 - x26*x287, mB*rR*x238 + x207*x308 + x208*x318 - x359 - x360, -IFyy*x248)
    b = casadi.vertcat(-pitch_rate*(x307 + x376*(-front_wheel_rate*x0*x240 + steer_rate*(x0*x25 + x0*x27)) + x382*x389 + x383*x49 + x386*x58 + x387*x60 + x388*x45) - roll_rate*(x294 + x371*x382 + x375*x58 + x376*(front_wheel_rate*x346 - pitch_rate*x0 + steer_rate*x363) + x381*x60) - steer_rate*(x265*x388 + x276*x383 + x303 + x341*x395 + x382*x391 + x393*x58 + x394*x60), -pitch_rate*(rR*x0*x216*x9 - x0*x397 - x0*x398 + x304*x85 + x326*x5 - x351 - x352 - x376*(front_wheel_rate*x28 + steer_rate*(x26*x9 - x53)) + x386*x87 + x387*x89 - x389*x396) - roll_rate*(x343*x383 + x344*x388 + x348 - x371*x396 + x375*x87 + x381*x89) - steer_rate*(-x243*x395 + x338*x383 + x340*x388 + x342 - x391*x396 + x393*x87 + x394*x89), -pitch_rate*(x329 + x386*x50 + x387*x46 + x397*x5 + x398*x5) - roll_rate*(x300 + x322 + x375*x50 + x381*x46 + x383*x87 + x388*x89) - steer_rate*(x267*x388 + x278*x383 + x319 + x393*x50 + x394*x46))
    return M, F, b


def energy(p, variables):
    """Kinetic and potential energy.

    p: the parameters (order PARAMETERS); variables: roll, pitch, steer, yaw_rate, roll_rate, pitch_rate, steer_rate, rear_wheel_rate, front_wheel_rate.
    Returns a tuple of CasADi expressions:

    kinetic (): kinetic energy [J]
    potential (): potential energy of gravity, zero with the mass centres at ground level [J]
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy, = casadi.vertsplit(p)
    roll, pitch, steer, yaw_rate, roll_rate, pitch_rate, steer_rate, rear_wheel_rate, front_wheel_rate, = casadi.vertsplit(variables)
    x0 = (1/2)*pitch_rate
    x1 = casadi.sin(roll)
    x2 = pitch_rate + x1*yaw_rate
    x3 = IByy*x2
    x4 = rear_wheel_rate + x2
    x5 = IRyy*x4
    x6 = rR**2
    x7 = roll_rate**2*x6 + x4**2*x6
    x8 = casadi.sin(pitch)
    x9 = casadi.cos(pitch)
    x10 = casadi.cos(roll)
    x11 = x10*yaw_rate
    x12 = roll_rate*x8 + x11*x9
    x13 = IRxx*x8
    x14 = roll_rate*x9 - x11*x8
    x15 = IRxx*x9
    x16 = (1/2)*roll_rate
    x17 = (1/2)*yaw_rate
    x18 = casadi.cos(steer)
    x19 = casadi.sin(lam)
    x20 = casadi.sin(steer)
    x21 = x19*x20
    x22 = casadi.cos(lam)
    x23 = x20*x22
    x24 = x21*x8 - x23*x9
    x25 = x1*x18 + x10*(x21*x9 + x23*x8)
    x26 = pitch_rate*x18 + roll_rate*x24 + x25*yaw_rate
    x27 = IFyy*(front_wheel_rate + x26)
    x28 = IBxx*x14 + IBxz*x12
    x29 = IBxz*x14 + IBzz*x12
    x30 = x10*x8
    x31 = rR + zB
    x32 = x12*xB - x14*x31
    x33 = x2**2
    x34 = x2*x8
    x35 = x34*xB
    x36 = rR*x4
    x37 = rR*roll_rate
    x38 = 2*x37
    x39 = x2*x9
    x40 = x19**2
    x41 = x22**2
    x42 = x18*x41 + x40
    x43 = -x18*x19*x22 + x19*x22
    x44 = x43*x8
    x45 = x42*x9 + x44
    x46 = x43*x9
    x47 = x1*x23 + x10*(-x42*x8 + x46)
    x48 = pitch_rate*x23 + roll_rate*x45 + steer_rate*x19 + x47*yaw_rate
    x49 = IFxx*x48
    x50 = x18*x40 + x41
    x51 = x46 + x50*x8
    x52 = -x1*x21 + x10*(-x44 + x50*x9)
    x53 = -pitch_rate*x21 + roll_rate*x51 + steer_rate*x22 + x52*yaw_rate
    x54 = IFxx*x53
    x55 = (1/2)*steer_rate
    x56 = IHxx*x48 + IHxz*x53
    x57 = IHxz*x48 + IHzz*x53
    x58 = IHyy*x26
    x59 = -c*x53 + rF*x48
    x60 = x26**2
    x61 = x18*x37 - x24*x36
    x62 = rR*x2
    x63 = c + w
    x64 = x2*x63
    x65 = -rR*x14 + x12*x63
    x66 = x18*x65 - x21*x64 - x23*x62
    x67 = c*x26
    x68 = rF*x26
    x69 = x18*x59 - x21*x67 - x23*x68
    x70 = -x21*x37 - x36*x51
    x71 = rR*x2*x43 - x21*x65 - x50*x64
    x72 = x23*x37 - x36*x45
    x73 = x23*x65 + x42*x62 - x43*x64
    x74 = x34*x63
    x75 = x33*x6 + x33*x63**2 + x36*x74 - x36*(rR*x39 - x74) + x38*x65 - x39*x4*x6 + x65**2 + x7
    x76 = -x63 + xH
    x77 = -x48*zH + x53*x76
    x78 = x26*zH
    x79 = x26*x76
    x80 = x18*x77 + x21*x79 + x23*x78
    x81 = rR*x10
    x82 = x30*x63
    kinetic = (1/2)*front_wheel_rate*x27 + (1/2)*mB*(x31**2*x33 - x31*x36*x39 + x32**2 + x32*x38 + x33*xB**2 + x35*x36 - x36*(x2*x31*x9 - x35) + x7) + (1/2)*mF*(c**2*x60 + rF**2*x60 - x36*(x24*x59 - x45*x68 + x51*x67) + x37*x69 + x59**2 + x59*x61 + x59*x66 + x62*(c*x26*x43 - x23*x59 - x42*x68) - x64*(x21*x59 - x43*x68 + x50*x67) + x65*x69 + x67*x70 + x67*x71 - x68*x72 - x68*x73 + x75) + (1/2)*mH*(-x36*(x24*x77 + x45*x78 - x51*x79) + x37*x80 + x60*x76**2 + x60*zH**2 + x61*x77 + x62*(-x23*x77 + x26*x42*zH - x43*x79) - x64*(x21*x77 + x43*x78 - x50*x79) + x65*x80 + x66*x77 - x70*x79 - x71*x79 + x72*x78 + x73*x78 + x75 + x77**2) + (1/2)*mR*x7 + (1/2)*rear_wheel_rate*x5 + x0*x3 + x0*x5 + x0*(x18*x27 - x21*x54 + x23*x49) + x0*(x18*x58 - x21*x57 + x23*x56) + x16*(x12*x13 + x14*x15) + x16*(x28*x9 + x29*x8) + x16*(x24*x27 + x45*x49 + x51*x54) + x16*(x24*x58 + x45*x56 + x51*x57) + x17*(x1*x3 + x10*x29*x9 - x28*x30) + x17*(x1*x5 + x10*x12*x15 - x10*x13*x14) + x17*(x25*x27 + x47*x49 + x52*x54) + x17*(x25*x58 + x47*x56 + x52*x57) + x55*(x19*x49 + x22*x54) + x55*(x19*x56 + x22*x57)
    potential = -g*mB*(x10*x31*x9 - x30*xB - x81) - g*mF*(-c*x47 - rF*x52 + rR*x10*x9 - x81 - x82) - g*mH*(x47*x76 + x52*zH + x81*x9 - x81 - x82) + g*mR*rR*x10
    return kinetic, potential


def rear_contact_velocity(p, variables):
    """Velocity of the rear contact point along the ground.

    p: the parameters (order PARAMETERS); variables: yaw, pitch_rate, rear_wheel_rate.
    Returns a tuple of CasADi expressions:

    velocity (2,): (x', y') in the ground frame [m/s]
    """
    w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy, = casadi.vertsplit(p)
    yaw, pitch_rate, rear_wheel_rate, = casadi.vertsplit(variables)
    x0 = rR*(-pitch_rate - rear_wheel_rate)
    velocity = casadi.vertcat(x0*casadi.cos(yaw), x0*casadi.sin(yaw))
    return (velocity,)


def function(name, symbol_type=casadi.SX):
    """casadi.Function (p, variables) -> OUTPUTS[name] of the function called name."""
    p = symbol_type.sym('p', len(PARAMETERS))
    variables = symbol_type.sym('variables', len(VARIABLES[name]))
    outputs = list(globals()[name](p, variables))
    return casadi.Function(name, [p, variables], outputs, ['p', 'variables'], list(OUTPUTS[name]))
