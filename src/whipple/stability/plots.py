"""Eigenvalues versus speed, in the style of the seed paper's Figure 6.

Real parts are solid lines, imaginary parts (of the member with positive imaginary part of
each complex pair) dashed, one colour per mode; critical speeds are marked by vertical lines
and the stable speed ranges shaded. The figure is returned, never shown or saved here (the CLI
saves it atomically). The matching table of numbers is
:func:`whipple.stability.eigen.eigenvalue_table`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from numpy.typing import NDArray

from whipple.stability import modes
from whipple.stability.critical import CriticalSpeeds
from whipple.stability.eigen import EigenResult

#: Colour and legend text of each named mode; other modes cycle through grey shades.
STYLES = {
    modes.WEAVE: ("tab:blue", "weave"),
    modes.WEAVE_UPPER: ("tab:purple", "weave-forming (upper)"),
    modes.WEAVE_LOWER: ("tab:cyan", "weave-forming (lower)"),
    modes.CAPSIZE: ("tab:red", "capsize"),
    modes.CASTERING: ("tab:green", "castering"),
}
OTHER_COLOURS = ("0.35", "0.55", "0.7", "tab:olive", "tab:brown", "tab:pink")


def _widen(mask: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Extend each run of True by one sample each way, so consecutive segments join."""
    wide = mask.copy()
    wide[1:] |= mask[:-1]
    wide[:-1] |= mask[1:]
    return wide


def _style(name: str, others: dict[str, str]) -> tuple[str, str]:
    if name in STYLES:
        return STYLES[name]
    colour = others.setdefault(name, OTHER_COLOURS[len(others) % len(OTHER_COLOURS)])
    return colour, name.replace("_", " ")


def plot_eigenvalues(
    result: EigenResult,
    critical: CriticalSpeeds | None = None,
    *,
    title: str | None = None,
    ylim: tuple[float, float] | None = None,
    measured: Sequence[tuple[float, float, complex]] | None = None,
) -> Figure:
    """Figure of eigenvalues [1/s] against forward speed [m/s].

    Parameters
    ----------
    result : EigenResult
        Analysis of a single model (:func:`whipple.stability.eigen.eigen_analysis`) on an
        increasing, reasonably fine speed grid.
    critical : CriticalSpeeds, optional
        Crossings to mark (vertical lines; weave and capsize speeds annotated) and stable
        ranges to shade.
    title : str, optional
        Axes title.
    ylim : (float, float), optional
        Vertical range [1/s]; by default symmetric, large enough for the weave and capsize
        modes and at least +/- 10 1/s (fast modes may leave the axes, as in the seed paper).
    measured : sequence of (float, float, complex), optional
        Measured eigenvalues as (lowest speed [m/s], highest speed [m/s], eigenvalue [1/s]),
        drawn as horizontal bars at the real (solid) and imaginary (dashed) parts.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if result.eigenvalues.ndim != 2:
        raise ValueError("plot_eigenvalues needs the analysis of a single model, not a batch")
    order = np.argsort(result.speeds)
    speeds = result.speeds[order]
    values = result.eigenvalues[order]
    labels = result.labels[order]
    figure = Figure(figsize=(9.0, 4.8))
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()

    others: dict[str, str] = {}
    handles: dict[str, Line2D] = {}
    for name in sorted(set(labels.ravel().tolist()), key=lambda n: (n not in STYLES, n)):
        colour, text = _style(name, others)
        for column in range(values.shape[1]):
            mask = labels[:, column] == name
            if not np.any(mask):
                continue
            wide = _widen(mask)
            axes.plot(speeds, np.where(wide, values[:, column].real, np.nan), color=colour,
                      lw=1.8)
            upper = wide & (values[:, column].imag > 0)
            if np.any(upper):
                axes.plot(speeds, np.where(upper, values[:, column].imag, np.nan),
                          color=colour, lw=1.4, ls="--")
        handles[name] = Line2D([], [], color=colour, lw=1.8, label=text)

    legend: list[Artist] = [
        *handles.values(),
        Line2D([], [], color="black", lw=1.4, label="real part"),
        Line2D([], [], color="black", lw=1.4, ls="--", label="imaginary part"),
    ]
    if critical is not None:
        _mark_critical(axes, critical)
        if critical.stable_speed_ranges:
            legend.append(Patch(color="tab:green", alpha=0.15, label="stable speed range"))
        if critical.crossings:
            legend.append(Line2D([], [], color="0.3", lw=0.9, ls="-.", label="critical speed"))
    if measured:
        for low, high, value in measured:
            axes.plot([low, high], [value.real] * 2, color="black", lw=1.8, alpha=0.8)
            axes.plot([low, high], [abs(value.imag)] * 2, color="black", lw=1.8, ls=":", alpha=0.8)
        legend.append(Line2D([], [], color="black", lw=1.8,
                             label="measured weave, a window's\nspeed range (re; im dotted)"))

    if ylim is None:
        main = np.isin(labels, [modes.WEAVE, modes.WEAVE_UPPER, modes.WEAVE_LOWER,
                                modes.CAPSIZE])
        reach = np.max(np.abs(np.concatenate([values[main].real, values[main].imag])),
                       initial=0.0)
        ylim = (-max(10.0, 1.1 * reach), max(10.0, 1.1 * reach))
    axes.set_ylim(*ylim)
    axes.set_xlim(speeds[0], speeds[-1])
    axes.axhline(0.0, color="black", lw=0.6)
    axes.set_xlabel("forward speed v [m/s]")
    axes.set_ylabel("eigenvalue λ [1/s]")
    axes.set_title(title or "Eigenvalues of the linear model against forward speed")
    axes.legend(handles=legend, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes.grid(alpha=0.3)
    figure.tight_layout()
    return figure


def _mark_critical(axes: Axes, critical: CriticalSpeeds) -> None:
    """Vertical lines at the crossings, annotations at weave/capsize speeds, stable bands."""
    for low, high in critical.stable_speed_ranges:
        axes.axvspan(low, high, color="tab:green", alpha=0.15, lw=0)
    for crossing in critical.crossings:
        style = ":" if crossing.direction == "touch" else "-."
        axes.axvline(crossing.speed, color="0.3", lw=0.9, ls=style)
    for speed, text in ((critical.weave_speed, "v_weave"), (critical.capsize_speed, "v_capsize")):
        if speed is not None:
            axes.annotate(
                f"{text} = {speed:.3f} m/s", xy=(speed, 1.0), xycoords=("data", "axes fraction"),
                xytext=(3, -12), textcoords="offset points", fontsize=8, rotation=90,
                va="top", bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.8})
