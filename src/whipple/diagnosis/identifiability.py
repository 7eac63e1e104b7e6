"""What the data determine of a fitted cause, and the values they leave open.

A cause with several values (a payload's mass and position, a tyre's cornering stiffness and
relaxation length, a pair of causes) is often determined only in some combinations: a load's
mass and height may trade against each other while the weave eigenvalues and mode shapes stay
the same. The fit's covariance, widened to the reported standard deviations, says which:
along its least-determined direction (each value measured in its bounds' range) lies a family
of values that fit about as well. :func:`open_values` returns that family, linearised, from -2
to +2 standard deviations along the direction (stopped at the bounds), and how well every other
combination of the values is determined. A fit at its bounds may find that direction blocked
both ways (it would take a value past its bound either way); the family is then the one among
the other values with those at their bounds held there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.fitting import AT_BOUND, CauseFit

#: The family is reported when, from -2 to +2 standard deviations along the least-determined
#: direction, some value moves by more than this fraction of its bounds' range.
OPEN_FRACTION = 0.1
#: Standard deviations each way along the least-determined direction.
FAMILY_SIGMAS = 2.0


@dataclass(frozen=True)
class OpenValues:
    """The values a cause's fit leaves open, linearised.

    Attributes
    ----------
    cause : str
        The cause.
    parameters, units : tuple of str
        Its values' names and units.
    fitted, low, high : tuple of float
        The fitted values, and the family's two ends (-2 and +2 standard deviations along the
        least-determined direction, each stopped at the bounds).
    determined : float
        How far (2 standard deviations) any value moves along the next least-determined
        direction, as a fraction of its bounds' range: every combination of the values but the
        open one is determined at least this well.
    held : tuple of str
        Values held at their bounds, where the least-determined direction of all values would
        take one past its bound either way (empty otherwise).
    """

    cause: str
    parameters: tuple[str, ...]
    units: tuple[str, ...]
    fitted: tuple[float, ...]
    low: tuple[float, ...]
    high: tuple[float, ...]
    determined: float
    held: tuple[str, ...] = ()

    def sentence(self) -> str:
        """Return the family and how well the rest is determined, in one sentence."""
        def values(point: tuple[float, ...]) -> str:
            return ", ".join(f"{name} {value:.4g}{' ' + unit if unit else ''}"
                             for name, unit, value in zip(self.parameters, self.units, point, strict=True))

        held = f", {', '.join(self.held)} held at their bounds" if self.held else ""
        return (f"values that fit about as well (linearised, {FAMILY_SIGMAS:g} std each way along the least "
                f"determined direction{held}): from {values(self.low)} to {values(self.high)}; every other "
                f"combination of the values is determined to within ±{100 * self.determined:.2g}% of the bounds' "
                f"range")

    def to_dict(self) -> dict[str, object]:
        """Return the family as plain JSON data."""
        return {"cause": self.cause, "parameters": list(self.parameters), "units": list(self.units),
                "fitted": list(self.fitted), "low": list(self.low), "high": list(self.high),
                "determined_fraction": self.determined, "held_at_bounds": list(self.held)}


def open_values(cause: Cause, fit: CauseFit) -> OpenValues | None:
    """Return the family of values a fit leaves open, or None when every value is determined.

    Parameters
    ----------
    cause : Cause
        The fitted cause (its bounds scale the values).
    fit : CauseFit
        Its fit to all windows: ``values``, ``std`` (possibly widened, e.g. by the jackknife)
        and ``covariance`` (of the least-squares fit).

    Returns
    -------
    OpenValues or None
        None for a cause with one value, without a usable covariance, or when no value moves
        by ``OPEN_FRACTION`` of its range along the family.
    """
    k = len(fit.values)
    covariance = np.asarray(fit.covariance, dtype=float)
    if k < 2 or covariance.shape != (k, k):
        return None
    lower, upper = cause.limits
    span = upper - lower
    # Widened to the reported standard deviations, keeping the fit's correlations.
    own = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    std = np.asarray(fit.std, dtype=float)
    widen = np.where(own > 0.0, std / np.where(own > 0.0, own, 1.0), 1.0)
    scaled = (widen[:, None] * covariance * widen[None, :]) / np.outer(span, span)
    if not np.all(np.isfinite(scaled)):  # a covariance or std that is not finite: no direction to give
        return None
    fitted = np.array(fit.values, dtype=float)
    free = np.ones(k, dtype=bool)
    family = _family(scaled, span, fitted, lower, upper)
    if family is not None and np.max(np.abs(family[1] - family[0]) / span) < OPEN_FRACTION:
        # Blocked both ways by values at their bounds: hold those there and look among the rest,
        # whose spread with them held is the conditional covariance.
        free = ~((fitted <= lower + AT_BOUND * span) | (fitted >= upper - AT_BOUND * span))
        if not free.any() or free.all():
            return None
        held = ~free
        conditional = (scaled[np.ix_(free, free)] - scaled[np.ix_(free, held)]
                       @ np.linalg.pinv(scaled[np.ix_(held, held)]) @ scaled[np.ix_(held, free)])
        family = _family(conditional, span[free], fitted[free], lower[free], upper[free])
    if family is None:
        return None
    low, high = fitted.copy(), fitted.copy()
    low[free], high[free] = family[0], family[1]
    held_names = tuple(name for name, keep in zip(fit.parameters, free, strict=True) if not keep)
    return OpenValues(fit.cause, fit.parameters, fit.units, tuple(map(float, fitted)), tuple(map(float, low)),
                      tuple(map(float, high)), family[2], held_names)


def _family(scaled: NDArray[np.float64], span: NDArray[np.float64], fitted: NDArray[np.float64],
            lower: NDArray[np.float64], upper: NDArray[np.float64]
            ) -> tuple[NDArray[np.float64], NDArray[np.float64], float] | None:
    """Return the family's two ends and how well every other combination is determined.

    From the values' covariance scaled by their ranges; the third item is the next direction's
    2-std reach as a fraction of the range. None when no value moves by ``OPEN_FRACTION`` of its
    range along the family.
    """
    variances, directions = np.linalg.eigh(scaled)
    if variances[-1] <= 0.0:
        return None
    step = directions[:, -1] * np.sqrt(variances[-1]) * span
    if np.max(np.abs(2.0 * FAMILY_SIGMAS * step) / span) < OPEN_FRACTION:
        return None
    low, high = (_along(fitted, sign * step, lower, upper) for sign in (-1.0, 1.0))
    if len(variances) == 1:
        return low, high, 0.0
    next_reach = np.abs(directions[:, -2]) * np.sqrt(max(float(variances[-2]), 0.0))
    return low, high, float(FAMILY_SIGMAS * np.max(next_reach))

def _along(origin: NDArray[np.float64], step: NDArray[np.float64], lower: NDArray[np.float64],
           upper: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return origin + t step for the largest t <= FAMILY_SIGMAS inside the bounds (on the line)."""
    t = FAMILY_SIGMAS
    for start, delta, low, high in zip(origin, step, lower, upper, strict=True):
        if delta > 0.0:
            t = min(t, max(0.0, (high - start) / delta))
        elif delta < 0.0:
            t = min(t, max(0.0, (low - start) / delta))
    return origin + t * step
