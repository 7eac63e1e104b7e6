"""Test oracle: the closed-form benchmark matrices of Meijaard et al. (2007), Appendix A.

Meijaard, Papadopoulos, Ruina & Schwab (2007), "Linearized dynamics equations for the balance
and steer of a bicycle: a benchmark and review", Proc. R. Soc. A 463, 1955-1982, Appendix A,
written out independently of the SymPy derivation so that the generated code can be checked
against it. Equation form::

    M q'' + v C1 q' + (K0 + v^2 K2) q = f,    q = [roll, steer],

with K0 INCLUDING g (the paper's K0 multiplied by g).

This module is for tests and benchmarks only; nothing in src/ or derivation/ may import it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

Matrices = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def _matrix(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike) -> NDArray[np.float64]:
    """[[a, b], [c, d]] with the 2 x 2 block last, broadcasting the entries."""
    entries = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (a, b, c, d)))
    return np.stack(entries, axis=-1).reshape(*entries[0].shape, 2, 2)


def _spin_ratio(inertia: NDArray[np.float64], radius: NDArray[np.float64]) -> NDArray[np.float64]:
    """I / r, taken as 0 for a point wheel (r = 0 needs I = 0)."""
    inertia, radius = np.broadcast_arrays(inertia, radius)
    return np.divide(inertia, radius, out=np.zeros(radius.shape), where=radius != 0)


def meijaard_matrices(p: Mapping[str, ArrayLike]) -> Matrices:
    """M, C1, K0 (including g) and K2 from the 26 benchmark parameters.

    Parameters
    ----------
    p : mapping
        Benchmark parameters by name (IByy and IHyy are not needed); floats or arrays that
        broadcast together.

    Returns
    -------
    M, C1, K0, K2 : ndarray, shape (..., 2, 2)
        Mass [kg m^2], velocity-damping [kg m], stiffness at zero speed [N m/rad, includes g]
        and velocity-squared stiffness [kg] matrices; leading axes are the broadcast shape.
    """
    q = {key: np.asarray(value, dtype=float) for key, value in p.items()}
    w, c, lam, g = q["w"], q["c"], q["lam"], q["g"]
    rR, mR, IRxx, IRyy = q["rR"], q["mR"], q["IRxx"], q["IRyy"]
    xB, zB, mB = q["xB"], q["zB"], q["mB"]
    IBxx, IBzz, IBxz = q["IBxx"], q["IBzz"], q["IBxz"]
    xH, zH, mH = q["xH"], q["zH"], q["mH"]
    IHxx, IHzz, IHxz = q["IHxx"], q["IHzz"], q["IHxz"]
    rF, mF, IFxx, IFyy = q["rF"], q["mF"], q["IFxx"], q["IFyy"]
    sin, cos = np.sin(lam), np.cos(lam)

    # Whole bicycle (T): mass, mass centre, inertia about the rear contact point.
    mT = mR + mB + mH + mF
    xT = (xB * mB + xH * mH + w * mF) / mT
    zT = (-rR * mR + zB * mB + zH * mH - rF * mF) / mT
    ITxx = IRxx + IBxx + IHxx + IFxx + mR * rR**2 + mB * zB**2 + mH * zH**2 + mF * rF**2
    ITxz = IBxz + IHxz - mB * xB * zB - mH * xH * zH + mF * w * rF
    # Wheels are symmetric: IRzz = IRxx, IFzz = IFxx.
    ITzz = IRxx + IBzz + IHzz + IFxx + mB * xB**2 + mH * xH**2 + mF * w**2

    # Front assembly (A = front frame + front wheel) about its own mass centre.
    mA = mH + mF
    xA = (xH * mH + w * mF) / mA
    zA = (zH * mH - rF * mF) / mA
    IAxx = IHxx + IFxx + mH * (zH - zA) ** 2 + mF * (rF + zA) ** 2
    IAxz = IHxz - mH * (xH - xA) * (zH - zA) + mF * (w - xA) * (rF + zA)
    IAzz = IHzz + IFxx + mH * (xH - xA) ** 2 + mF * (w - xA) ** 2

    # Steer axis: offset of A's mass centre from the axis, inertias about it.
    uA = (xA - w - c) * cos - zA * sin
    IAll = mA * uA**2 + IAxx * sin**2 + 2 * IAxz * sin * cos + IAzz * cos**2
    IAlx = -mA * uA * zA + IAxx * sin + IAxz * cos
    IAlz = mA * uA * xA + IAxz * sin + IAzz * cos

    mu = c / w * cos  # trail ratio
    # Gyrostatic coefficients; a point wheel (radius 0, no spin inertia) has none: the limit
    # of I/r as both vanish (Kooijman et al. 2011, the two-mass-skate bicycle).
    SR, SF = _spin_ratio(IRyy, rR), _spin_ratio(IFyy, rF)
    ST = SR + SF
    SA = mA * uA + mu * mT * xT  # static moment term

    M = _matrix(ITxx, IAlx + mu * ITxz, IAlx + mu * ITxz, IAll + 2 * mu * IAlz + mu**2 * ITzz)
    K0 = _matrix(g * mT * zT, -g * SA, -g * SA, -g * SA * sin)
    K2 = _matrix(0.0, (ST - mT * zT) / w * cos, 0.0, (SA + SF * sin) / w * cos)
    C1 = _matrix(
        0.0,
        mu * ST + SF * cos + ITxz / w * cos - mu * mT * zT,
        -(mu * ST + SF * cos),
        IAlz / w * cos + mu * (SA + ITzz / w * cos),
    )
    return M, C1, K0, K2


def meijaard_matrices_scalar(p: Mapping[str, float]) -> Matrices:
    """The same matrices for one parameter set, with Python floats and :mod:`math`.

    This is the per-set baseline a benchmark times against vectorised code: the way a
    parameter set is usually evaluated one at a time, building 2 x 2 arrays at the end.
    """
    w, c, lam, g = p["w"], p["c"], p["lam"], p["g"]
    rR, mR, IRxx, IRyy = p["rR"], p["mR"], p["IRxx"], p["IRyy"]
    xB, zB, mB, IBxx, IBzz, IBxz = p["xB"], p["zB"], p["mB"], p["IBxx"], p["IBzz"], p["IBxz"]
    xH, zH, mH, IHxx, IHzz, IHxz = p["xH"], p["zH"], p["mH"], p["IHxx"], p["IHzz"], p["IHxz"]
    rF, mF, IFxx, IFyy = p["rF"], p["mF"], p["IFxx"], p["IFyy"]
    sin, cos = math.sin(lam), math.cos(lam)

    mT = mR + mB + mH + mF
    xT = (xB * mB + xH * mH + w * mF) / mT
    zT = (-rR * mR + zB * mB + zH * mH - rF * mF) / mT
    ITxx = IRxx + IBxx + IHxx + IFxx + mR * rR * rR + mB * zB * zB + mH * zH * zH + mF * rF * rF
    ITxz = IBxz + IHxz - mB * xB * zB - mH * xH * zH + mF * w * rF
    ITzz = IRxx + IBzz + IHzz + IFxx + mB * xB * xB + mH * xH * xH + mF * w * w

    mA = mH + mF
    xA = (xH * mH + w * mF) / mA
    zA = (zH * mH - rF * mF) / mA
    IAxx = IHxx + IFxx + mH * (zH - zA) ** 2 + mF * (rF + zA) ** 2
    IAxz = IHxz - mH * (xH - xA) * (zH - zA) + mF * (w - xA) * (rF + zA)
    IAzz = IHzz + IFxx + mH * (xH - xA) ** 2 + mF * (w - xA) ** 2

    uA = (xA - w - c) * cos - zA * sin
    IAll = mA * uA * uA + IAxx * sin * sin + 2 * IAxz * sin * cos + IAzz * cos * cos
    IAlx = -mA * uA * zA + IAxx * sin + IAxz * cos
    IAlz = mA * uA * xA + IAxz * sin + IAzz * cos

    mu = c / w * cos
    SR, SF = IRyy / rR, IFyy / rF
    ST = SR + SF
    SA = mA * uA + mu * mT * xT

    M_rd = IAlx + mu * ITxz
    M = np.array([[ITxx, M_rd], [M_rd, IAll + 2 * mu * IAlz + mu * mu * ITzz]])
    K0 = np.array([[g * mT * zT, -g * SA], [-g * SA, -g * SA * sin]])
    K2 = np.array([[0.0, (ST - mT * zT) / w * cos], [0.0, (SA + SF * sin) / w * cos]])
    C1 = np.array(
        [
            [0.0, mu * ST + SF * cos + ITxz / w * cos - mu * mT * zT],
            [-(mu * ST + SF * cos), IAlz / w * cos + mu * (SA + ITzz / w * cos)],
        ]
    )
    return M, C1, K0, K2


def _rigid_body_inertia(
    rng: np.random.Generator, mass: NDArray[np.float64], spread: tuple[float, float]
) -> dict[str, NDArray[np.float64]]:
    """Ixx, Iyy, Izz, Ixz of bodies symmetric about the xz plane, physical by construction.

    Second moments of the mass distribution s_i = sum m x_i^2 > 0 along principal axes give
    principal moments s_j + s_k, which are positive and satisfy the triangle inequality; the
    principal axes in the xz plane are then turned by a random angle about y.
    """
    s = mass * rng.uniform(*spread, size=(3, mass.size))
    principal_x, principal_y, principal_z = s[1] + s[2], s[0] + s[2], s[0] + s[1]
    angle = rng.uniform(-np.pi / 2, np.pi / 2, size=mass.size)
    cos, sin = np.cos(angle), np.sin(angle)
    return {
        "xx": principal_x * cos**2 + principal_z * sin**2,
        "yy": principal_y,
        "zz": principal_x * sin**2 + principal_z * cos**2,
        "xz": (principal_x - principal_z) * sin * cos,
    }


def random_physical_parameters(rng: np.random.Generator, n: int) -> dict[str, NDArray[np.float64]]:
    """Draw n physically valid benchmark parameter sets around real bicycles.

    Ranges span riderless bicycles to a bicycle with a rigid rider (benchmark-like), trail
    from negative to large, steer axis tilt within +/- 0.6 rad, wheels between a disc and a
    ring. All 26 parameters are returned, each an array of shape (n,).
    """
    u = rng.uniform
    w = u(0.8, 1.3, n)
    p: dict[str, NDArray[np.float64]] = {
        "w": w,
        "c": u(-0.05, 0.2, n),
        "lam": u(-0.6, 0.6, n),
        "g": u(9.78, 9.83, n),
    }
    for wheel in ("R", "F"):
        radius, mass = u(0.25, 0.4, n), u(1.0, 6.0, n)
        # About the axle: mass * radius^2 times 1/2 (disc) to 1 (ring); about a diameter:
        # half of that for a thin wheel, a little more for a wide one.
        axial = mass * radius**2 * u(0.5, 1.0, n)
        p |= {
            f"r{wheel}": radius,
            f"m{wheel}": mass,
            f"I{wheel}yy": axial,
            f"I{wheel}xx": axial / 2 * u(1.0, 1.2, n),
        }
    for body, mass, spread, x, z in (
        ("B", u(5.0, 100.0, n), (0.01, 0.15), w * u(0.1, 0.6, n), u(-1.2, -0.4, n)),
        ("H", u(0.5, 6.0, n), (0.002, 0.03), w * u(0.75, 1.0, n), u(-1.0, -0.5, n)),
    ):
        inertia = _rigid_body_inertia(rng, mass, spread)
        p |= {f"x{body}": x, f"z{body}": z, f"m{body}": mass}
        p |= {f"I{body}{axes}": value for axes, value in inertia.items()}
    return p
