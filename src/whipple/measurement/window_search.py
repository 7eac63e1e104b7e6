"""What the window finder returns: the windows of a run to fit, and the stretches it rejected.

:func:`whipple.measurement.windows.find_windows` finds them; the fits, the windows files and
the diagnosis take them as plain records.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Window", "WindowSearch"]


@dataclass(frozen=True)
class Window:
    """A stretch of a run to fit.

    Attributes
    ----------
    run : str
        Name of the run.
    start, stop : float
        First and last sample time [s].
    start_index, stop_index : int
        Sample indices: ``run.time[start_index:stop_index]`` (stop exclusive).
    reason : str
        Why the window starts and ends (or, for a rejected stretch, why it was rejected).
    notes : tuple of str
        Quality notes (growing oscillation, saturation, ...).
    """

    run: str
    start: float
    stop: float
    start_index: int
    stop_index: int
    reason: str = ""
    notes: tuple[str, ...] = ()

    @property
    def duration(self) -> float:
        """Length of the window [s]."""
        return self.stop - self.start


@dataclass(frozen=True)
class WindowSearch:
    """Result of :func:`find_windows`.

    Attributes
    ----------
    run : str
        Name of the run.
    windows : tuple of Window
        Accepted free-coasting windows, in time order.
    rejected : tuple of Window
        Candidate stretches that were rejected, with the reason.
    noise : float
        Standard deviation of the roll rate's noise [rad/s].
    background : float
        Median swing of the low-passed roll rate [rad/s].
    frequency : float
        Dominant frequency of the roll rate [Hz].
    stills : tuple of int
        Where each still stretch of the roll rate begins, with or without a wake (sample indices).
    """

    run: str
    windows: tuple[Window, ...]
    rejected: tuple[Window, ...]
    noise: float
    background: float
    frequency: float
    stills: tuple[int, ...] = ()
