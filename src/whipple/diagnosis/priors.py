"""What is known of a cause's values before the data: their physical priors.

Every fitted value of a candidate cause has a prior (:class:`Prior`): what such a quantity
physically is on bicycles, from measurements published or from the bicycle's own measurement
uncertainty. The evidence is then a marginal likelihood (:func:`laplace_evidence`, the Laplace
approximation about the values' maximum a posteriori): a value that the data press far beyond
what is physically plausible pays the prior's density there, and a value the data barely inform
costs only what its prior's width leaves open.

A benchmark parameter's prior is its measurement uncertainty: the bicycle file's
``[uncertainty]`` table or BicycleParameters' ``+/-``, else :func:`default_uncertainty`, a
typical measurement error of its kind (documented there).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

#: Kinds of prior: normal in the value; normal in its logarithm (a positive scale quantity);
#: normal about 0 truncated to positive values (an added quantity that may well be absent).
KINDS = ("normal", "lognormal", "halfnormal")


@dataclass(frozen=True)
class Prior:
    """A value's prior density.

    Attributes
    ----------
    kind : {"normal", "lognormal", "halfnormal"}
        Normal in the value (centre: its mean); normal in the value's logarithm (centre: its
        median, scale: the standard deviation of the logarithm); or half-normal on values >= 0
        (centre 0).
    centre : float
        Mean, or median for ``lognormal``, in the value's unit.
    scale : float
        Standard deviation in the value's unit (of its logarithm for ``lognormal``).
    source : str
        Where it comes from, in words.
    """

    kind: str
    centre: float
    scale: float
    source: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"prior kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        if not (math.isfinite(self.scale) and self.scale > 0 and math.isfinite(self.centre)):
            raise ValueError(f"a prior needs a finite centre and a positive scale, got {self.centre}, {self.scale}")
        if self.kind == "lognormal" and self.centre <= 0:
            raise ValueError(f"a lognormal prior needs a positive median, got {self.centre}")

    def residual(self, value: float) -> float:
        """Return the whitened residual r of a value: -ln density = r^2 / 2 + const."""
        if self.kind == "lognormal":
            return (math.log(max(value, 1e-300)) - math.log(self.centre)) / self.scale
        return (value - (0.0 if self.kind == "halfnormal" else self.centre)) / self.scale

    def slope(self, value: float) -> float:
        """Return d(residual)/d(value) [1/unit]."""
        return 1.0 / (max(value, 1e-300) * self.scale) if self.kind == "lognormal" else 1.0 / self.scale

    def log_density(self, value: float) -> float:
        """Return the log prior density at ``value`` [ln(1/unit)]."""
        r = self.residual(value)
        normaliser = -math.log(self.scale * math.sqrt(2.0 * math.pi))
        if self.kind == "lognormal":
            normaliser -= math.log(max(value, 1e-300))
        if self.kind == "halfnormal":
            normaliser += math.log(2.0)
        return -0.5 * r * r + normaliser

    def describe(self) -> str:
        """Say the prior in words, e.g. "normal 1 +/- 0.05"."""
        if self.kind == "lognormal":
            return f"lognormal, median {self.centre:.4g}, factor {math.exp(self.scale):.3g}"
        if self.kind == "halfnormal":
            return f"half-normal, scale {self.scale:.4g}"
        return f"normal {self.centre:.6g} +/- {self.scale:.4g}"


def robust_prior_residuals(priors: Sequence[Prior], values: Sequence[float], f_scale: float) -> NDArray[np.float64]:
    """Return the prior residuals transformed so that a soft-L1 loss of scale ``f_scale`` costs r^2 / 2 each.

    The fits minimise a soft-L1 loss over all residuals (robust to outlying windows); a prior
    must not be robustified. The soft-L1 cost of ``r'`` equals ``r^2 / 2`` for
    ``r' = f sign(r) sqrt(q + q^2 / 4)``, ``q = (r / f)^2``.
    """
    r = np.array([prior.residual(float(v)) for prior, v in zip(priors, values, strict=True)])
    q = (r / f_scale) ** 2
    return np.sign(r) * f_scale * np.sqrt(q + q * q / 4.0)


def laplace_evidence(priors: Sequence[Prior], values: Sequence[float], jacobian: NDArray[np.float64]) -> float:
    """Return a cause's log Occam factor with priors: ln prior(values) + (k/2) ln 2 pi - ln det(H) / 2.

    The Laplace approximation of the marginal likelihood about the maximum a posteriori
    ``values``, less the data's likelihood there: with ``H = J^T J + D^2`` the Hessian of the
    negative log posterior (``J`` the whitened data residuals' Jacobian, a row per residual and a
    column per value; ``D`` the prior residuals' slopes), the evidence against the base model is
    ``(chi2_base - chi2_data) / 2`` plus this. For normal priors and residuals linear in the
    values it is exact: ``-r_p^2 / 2 - ln det(I + S J^T J S) / 2`` with ``S`` the priors' widths.
    """
    k = len(values)
    if k == 0:
        return 0.0
    slopes = np.array([prior.slope(float(v)) for prior, v in zip(priors, values, strict=True)])
    jacobian = np.asarray(jacobian, dtype=float)
    if jacobian.ndim != 2 or jacobian.shape[1] != k or not np.all(np.isfinite(jacobian)):
        jacobian = np.zeros((0, k))
    hessian = jacobian.T @ jacobian + np.diag(slopes**2)
    sign, log_det = np.linalg.slogdet(hessian)
    if sign <= 0 or not np.isfinite(log_det):
        return float("-inf")
    log_prior = sum(prior.log_density(float(v)) for prior, v in zip(priors, values, strict=True))
    return float(log_prior + 0.5 * k * math.log(2.0 * math.pi) - 0.5 * log_det)


#: Relative standard deviation [-] of a benchmark parameter measured as BicycleParameters
#: measures it, by kind, where a bicycle states none: masses weighed (2%), wheel inertias from a
#: pendulum (5%), frame inertias from a compound pendulum and a fit of several axes (10%).
RELATIVE_UNCERTAINTY = {"mass": 0.02, "wheel_inertia": 0.05, "frame_inertia": 0.10}
#: Absolute standard deviations of lengths [m] and the head angle [rad] where none is stated:
#: lengths by tape or calliper (5 mm), the mass centres' coordinates from hanging the frame
#: (20 mm), the steer axis tilt by inclinometer (0.5 degree).
ABSOLUTE_UNCERTAINTY = {"length": 0.005, "mass_centre": 0.02, "lam": math.radians(0.5)}
_KIND = {"w": "length", "c": "length", "rR": "length", "rF": "length", "lam": "lam",
         "mR": "mass", "mB": "mass", "mH": "mass", "mF": "mass",
         "xB": "mass_centre", "zB": "mass_centre", "xH": "mass_centre", "zH": "mass_centre",
         "IRxx": "wheel_inertia", "IRyy": "wheel_inertia", "IFxx": "wheel_inertia", "IFyy": "wheel_inertia",
         "IBxx": "frame_inertia", "IBzz": "frame_inertia", "IBxz": "frame_inertia",
         "IHxx": "frame_inertia", "IHzz": "frame_inertia", "IHxz": "frame_inertia"}


def default_uncertainty(key: str, parameters: Mapping[str, float]) -> float:
    """Return a typical measurement standard deviation of parameter ``key`` (its unit).

    For a product of inertia, 10% of the geometric mean of the two principal inertias beside it
    (a product's own value may be near 0).
    """
    kind = _KIND[key]
    if kind in ABSOLUTE_UNCERTAINTY:
        return ABSOLUTE_UNCERTAINTY[kind]
    value = abs(float(parameters[key]))
    if key.endswith("xz"):
        frame = key[1]
        value = math.sqrt(abs(float(parameters[f"I{frame}xx"])) * abs(float(parameters[f"I{frame}zz"])))
    return RELATIVE_UNCERTAINTY[kind] * max(value, 1e-6)


def parameter_prior(key: str, parameters: Mapping[str, float], uncertainty: Mapping[str, float]) -> Prior:
    """Return a benchmark parameter's prior: normal about its value with its measurement uncertainty.

    The bicycle's own stated uncertainty where it has one, else :func:`default_uncertainty`.
    """
    value = float(parameters[key])
    stated = uncertainty.get(key)
    if stated is not None and stated > 0:
        return Prior("normal", value, float(stated), "the bicycle's stated measurement uncertainty")
    return Prior("normal", value, default_uncertainty(key, parameters), "a typical measurement error of its kind")


#: The relative standard deviation [-] of one grossly wrong parameter (a typing error, a value
#: estimated from another bicycle): errors of 25-50% are the ones seen.
GROSS_ERROR = 0.3


def gross_error_prior(key: str, parameters: Mapping[str, float], uncertainty: Mapping[str, float]) -> Prior:
    """Return the prior of one grossly wrong parameter (``parameter:<key>``): normal about its value, wide.

    Not a measurement error (that is the calibration's, :func:`parameter_prior`): one value
    wrong by a share of itself, :data:`GROSS_ERROR`, and at least three times its measurement
    uncertainty.
    """
    value = float(parameters[key])
    measured = parameter_prior(key, parameters, uncertainty).scale
    scale = max(GROSS_ERROR * abs(value), 3.0 * measured)
    return Prior("normal", value, scale, "one value grossly wrong (an error or an estimate from another bicycle)")


def prior_shifts(names: Sequence[str], priors: Sequence[Prior], values: Sequence[float], units: Sequence[str],
                 least: float = 1.0) -> list[dict[str, float | str]]:
    """Return the values that moved from their priors' centres by at least ``least`` standard deviations.

    Parameters
    ----------
    names, priors, values, units : sequences
        A fit's value names, their priors, fitted values and units.
    least : float
        Smallest shift reported [prior standard deviations].

    Returns
    -------
    list of dict
        ``name``, ``prior`` (centre), ``value``, ``unit`` and ``sigmas`` (the shift in standard
        deviations of the prior, signed), largest first: what a calibration changed.
    """
    moved: list[dict[str, float | str]] = []
    for name, prior, value, unit in zip(names, priors, values, units, strict=True):
        sigmas = prior.residual(float(value)) - (prior.residual(prior.centre) if prior.kind != "halfnormal" else 0.0)
        if abs(sigmas) >= least:
            moved.append({"name": name, "prior": prior.centre, "value": float(value), "unit": unit,
                          "sigmas": float(sigmas)})
    return sorted(moved, key=lambda entry: -abs(float(entry["sigmas"])))


def shift_sentence(moved: Sequence[Mapping[str, float | str]]) -> str:
    """Say which values moved and by how many standard deviations ("" where none moved)."""
    return ", ".join(f"{m['name']} {float(m['prior']):.4g} -> {float(m['value']):.4g}"
                     f"{' ' + str(m['unit']) if m['unit'] else ''} ({float(m['sigmas']):+.1f} std)" for m in moved)
