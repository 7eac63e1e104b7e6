"""Everything ``whipple check`` reports about one bicycle, as plain data.

Validation, the matrices of the (extended) model, the critical speeds and stable speed ranges
found by root finding, their standard deviations when the bicycle file has an uncertainty
table, and the eigenvalues with mode labels at a few speeds.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from whipple.errors import AnalysisError
from whipple.model.assembly import EXTENDED_PARAMETERS, extended_matrices, linear_model
from whipple.model.bodies import folded_parameters
from whipple.model.casadi_model import casadi_state_function
from whipple.model.parameters import Bicycle, check_physical
from whipple.stability.critical import CriticalSpeeds, critical_speeds
from whipple.stability.eigen import EigenResult, eigen_analysis
from whipple.stability.uncertainty import critical_speed_uncertainty

__all__ = ["REPORT_SPEEDS", "BicycleReport", "analyse_bicycle"]

#: Speeds [m/s] at which the report lists eigenvalues (those inside the searched range).
REPORT_SPEEDS = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0)


@dataclass(frozen=True)
class BicycleReport:
    """The analysis of one bicycle over a speed range."""

    bicycle: Bicycle
    warnings: tuple[str, ...]
    matrices: dict[str, list[list[float]]]
    critical: CriticalSpeeds
    speed_std: dict[str, float | None]
    uncertainty_notes: tuple[str, ...]
    eigen: EigenResult

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``matrices``, ``weave_speed``, ``capsize_speed``, ``stable_speed_ranges``, ..."""
        critical = self.critical.to_dict()
        return {
            "bicycle": self.bicycle.name,
            "source": self.bicycle.source,
            "validation": {"ok": True, "warnings": list(self.warnings)},
            "matrices": self.matrices,
            "speed_range": critical.pop("speed_range"),
            "weave_speed": critical.pop("weave_speed"),
            "capsize_speed": critical.pop("capsize_speed"),
            "weave_speed_std": self.speed_std.get("weave"),
            "capsize_speed_std": self.speed_std.get("capsize"),
            "uncertainty_notes": list(self.uncertainty_notes),
            **critical,
            "eigenvalues": [{"speed": float(speed),
                             "values": [[float(z.real), float(z.imag)] for z in self.eigen.eigenvalues[i]],
                             "modes": [str(label) for label in self.eigen.labels[i]]}
                            for i, speed in enumerate(self.eigen.speeds)],
        }

    def summary_lines(self) -> list[str]:
        """Human-readable lines for the CLI."""
        lines = self.critical.summary(self.speed_std)
        lines.extend(f"note: {note}" for note in self.uncertainty_notes)
        lines.append("eigenvalues (1/s):")
        for i, speed in enumerate(self.eigen.speeds):
            values = "  ".join(f"{z.real:+.4f}{z.imag:+.4f}i ({label})"
                               for z, label in zip(self.eigen.eigenvalues[i], self.eigen.labels[i], strict=True))
            lines.append(f"  v = {speed:5.2f} m/s: {values}")
        return lines


def _uncertainty(bicycle: Bicycle, critical: CriticalSpeeds) -> tuple[dict[str, float | None], tuple[str, ...]]:
    if not bicycle.uncertainty:
        return {}, ()
    folded = folded_parameters(bicycle.parameters)
    keys = [key for key, std in bicycle.uncertainty.items()
            if key in EXTENDED_PARAMETERS and std > 0 and key not in folded]
    skipped = [key for key in bicycle.uncertainty if key not in EXTENDED_PARAMETERS]
    notes = [f"uncertainty of {', '.join(skipped)} ignored: not in the linear model"] if skipped else []
    merged = [key for key in bicycle.uncertainty if key in folded]
    if merged:
        notes.append(f"uncertainty of {', '.join(merged)} ignored: a point wheel is folded into its frame")
    stds: dict[str, float | None] = {}
    if not keys:  # every stated uncertainty is zero (or outside the model): no spread
        for kind, speed in (("weave", critical.weave_speed), ("capsize", critical.capsize_speed)):
            if speed is not None:
                stds[kind] = 0.0
        return stds, tuple(notes)
    function, p0 = casadi_state_function(bicycle, keys)
    spread = np.array([bicycle.uncertainty[key] for key in keys])
    for kind, speed in (("weave", critical.weave_speed), ("capsize", critical.capsize_speed)):
        if speed is None:
            continue
        try:
            stds[kind] = critical_speed_uncertainty(function, p0, spread, speed, kind).std
        except AnalysisError as error:
            notes.append(f"no standard deviation for the {kind} speed: {error}")
    return stds, tuple(notes)


def analyse_bicycle(bicycle: Bicycle, speed_range: tuple[float, float] = (0.0, 10.0)) -> BicycleReport:
    """Validate a bicycle and analyse its stability between ``speed_range`` [m/s].

    Parameters
    ----------
    bicycle : Bicycle
        The bicycle.
    speed_range : tuple of float
        Lowest and highest forward speed [m/s] searched for critical speeds.

    Returns
    -------
    BicycleReport
        Validation warnings, matrices, critical speeds with their standard deviations (from the
        bicycle's ``[uncertainty]``) and eigenvalues over the range: what ``whipple check`` prints.
    """
    report = check_physical(bicycle)
    low, high = speed_range
    matrices = extended_matrices(bicycle.parameters, bicycle.extensions)
    shown = {"M": matrices.M, "C1": matrices.C1, "K0": matrices.K0, "K2": matrices.K2}
    if np.any(matrices.D != 0):
        shown["D"] = matrices.D
    model = linear_model(bicycle)
    critical = critical_speeds(model, low, high)
    speed_std, notes = _uncertainty(bicycle, critical)
    speeds = [v for v in REPORT_SPEEDS if low <= v <= high] or [low, high]
    return BicycleReport(bicycle, tuple(report.warnings), {k: m.tolist() for k, m in shown.items()},
                         critical, speed_std, notes, eigen_analysis(model, speeds, vectors=False))
