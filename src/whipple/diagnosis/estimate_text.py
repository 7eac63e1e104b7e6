"""How a fitted value is said: with its standard deviation, or as not determined by the data.

A load's mass, position and radii trade off: the data can fix the load's effect on the weave
sharply while each value alone spreads over more than its physical bounds. A "+/-" wider than
the bounds is no uncertainty a user can read, so such a value is said with its bounds instead.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from whipple.diagnosis.evidence import Diagnosis

__all__ = ["determined", "estimates", "bounds_text", "estimate_text"]


def determined(std: float, bounds: tuple[float, float]) -> bool:
    """Whether the data determine a value (its standard deviation below its bounds' evenly spread).

    Determined: the standard deviation (the fit's, or the jackknife's over speed groups) is
    below that of a value spread evenly over its physical bounds, range / sqrt(12). Above it the
    data say no more of the value than its bounds do (a load's mass where mass, position and
    radii trade off): a "+/-" larger than the whole range is no uncertainty a user can read.
    """
    low, high = bounds
    return bool(np.isfinite(std) and (not np.isfinite(high - low) or std < (high - low) / np.sqrt(12.0)))


def estimates(diagnosis: Diagnosis) -> dict[str, dict[str, Any]]:
    """Return the leading cause's values by name: value, std, unit, bounds and whether determined.

    The entries of ``report_json``'s ``estimate`` (empty when no cause leads).
    """
    best, chosen = diagnosis.best, diagnosis.chosen
    # The leading cause and its fit are set together (a diagnosis without one has neither).
    if best is None or chosen is None:
        return {}
    return {name: {"value": value, "std": std, "unit": unit, "bounds": [float(low), float(high)],
                   "determined": determined(std, (low, high))}
            for name, value, std, unit, (low, high)
            in zip(best.parameters, best.values, best.std, best.units, chosen.bounds, strict=True)}


def bounds_text(estimate: dict[str, Any]) -> str:
    """Say an estimate's physical bounds, e.g. "its bounds 0 to 20 kg" (an entry of :func:`estimates`)."""
    low, high = estimate["bounds"]
    return f"its bounds {low:.4g} to {high:.4g}{_unit(estimate)}"


def estimate_text(estimate: dict[str, Any]) -> str:
    """Say an estimate: "value +/- std unit", or the value and that the data do not determine it."""
    unit = _unit(estimate)
    if estimate["determined"]:
        return f"{estimate['value']:.6g} +/- {estimate['std']:.3g}{unit}"
    return (f"{estimate['value']:.6g}{unit}, not determined by the data (standard deviation {estimate['std']:.3g}, "
            f"more than a value spread evenly over {bounds_text(estimate)} has)")


def _unit(estimate: dict[str, Any]) -> str:
    """Return the estimate's unit after a space, or nothing for a value without one."""
    return f" {estimate['unit']}" if estimate["unit"] else ""
