"""How a fitted value is said: with its standard deviation, or as not determined by the data.

A load's mass, position and radii trade off: the data can fix the load's effect on the weave
sharply while each value alone spreads over more than its physical bounds. A "+/-" wider than
the bounds is no uncertainty a user can read, so such a value is said with its bounds instead.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["determined", "bounds_text", "estimate_text"]


def determined(std: float, bounds: tuple[float, float]) -> bool:
    """Whether the data determine a value (its standard deviation below its bounds' evenly spread).

    Determined: the standard deviation (the fit's, or the jackknife's over speed groups) is
    below that of a value spread evenly over its physical bounds, range / sqrt(12). Above it the
    data say no more of the value than its bounds do (a load's mass where mass, position and
    radii trade off): a "+/-" larger than the whole range is no uncertainty a user can read.
    """
    low, high = bounds
    return bool(np.isfinite(std) and (not np.isfinite(high - low) or std < (high - low) / np.sqrt(12.0)))


def bounds_text(estimate: dict[str, Any]) -> str:
    """Say an estimate's physical bounds, e.g. "its bounds 0 to 20 kg" (an entry of ``report_json``'s ``estimate``)."""
    low, high = estimate["bounds"]
    unit = f" {estimate['unit']}" if estimate["unit"] else ""
    return f"its bounds {low:.4g} to {high:.4g}{unit}"


def estimate_text(estimate: dict[str, Any]) -> str:
    """Say an estimate: "value +/- std unit", or the value and that the data do not determine it."""
    unit = f" {estimate['unit']}" if estimate["unit"] else ""
    if estimate["determined"]:
        return f"{estimate['value']:.6g} +/- {estimate['std']:.3g}{unit}"
    return (f"{estimate['value']:.6g}{unit}, not determined by the data (standard deviation {estimate['std']:.3g}, "
            f"more than a value spread evenly over {bounds_text(estimate)} has)")
