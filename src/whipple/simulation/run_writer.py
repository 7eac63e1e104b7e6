"""Writing runs as native run files (the CSV of the run-file spec), and the true-window key.

Anything with ``time``, ``signals`` and ``metadata`` can be written: a simulated run, or a
:class:`whipple.measurement.runs.Run` read through a layout (converting it to the native format).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from whipple.atomic import write_text_atomic
from whipple.errors import InputError


class Writable(Protocol):
    """A run: sample times [s], signals by run-file column name (SI units), metadata."""

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times [s]."""

    @property
    def signals(self) -> Mapping[str, NDArray[np.float64]]:
        """Signals by run-file column name, SI units."""

    @property
    def metadata(self) -> Mapping[str, str]:
        """Metadata lines."""


def write_run_csv(run: Writable, path: str | Path) -> Path:
    """Write a run as a native run file that ``whipple.measurement.runs.read_run`` reads back.

    The file holds one ``# key: value`` line per metadata entry (readers ignore keys they do
    not know, such as ``true_windows``), the header ``time,<signals>`` and one line per sample
    (10 significant digits for time, 9 for signals). It is written atomically.

    Parameters
    ----------
    run : SimulatedRun or Run
        The run to write.
    path : str or Path
        The file to write.

    Returns
    -------
    Path
        The file written.
    """
    target = Path(path)
    for key, value in run.metadata.items():
        if "\n" in f"{key}{value}" or ":" in key:
            raise InputError(f"metadata key {key!r} cannot be written on one line", target)
    lines = [f"# {key}: {value}" for key, value in run.metadata.items()]
    names = [name for name in run.signals if name != "time"]
    lines.append(",".join(["time", *names]))
    table = np.column_stack([run.time, *(run.signals[name] for name in names)])
    formats = ["%.10g"] + ["%.9g"] * len(names)
    lines.extend(",".join(f % value for f, value in zip(formats, row, strict=True))
                 for row in table)
    write_text_atomic(target, "\n".join(lines) + "\n")
    return target


def format_true_windows(segments: tuple[tuple[float, float], ...]) -> str:
    """``start:stop`` pairs [s] separated by ``; `` (empty when there are none)."""
    return "; ".join(f"{start:.9g}:{stop:.9g}" for start, stop in segments)


def parse_true_windows(text: str) -> tuple[tuple[float, float], ...]:
    """Read a ``true_windows`` metadata value (see :func:`format_true_windows`).

    Raises
    ------
    InputError
        If the text is not ``start:stop`` pairs [s] separated by semicolons.
    """
    windows = []
    for part in filter(None, (item.strip() for item in text.split(";"))):
        try:
            start, stop = (float(x) for x in part.split(":"))
        except ValueError:
            raise InputError(f"true_windows: expected start:stop, got {part!r}") from None
        if not start < stop:
            raise InputError(f"true_windows: window {part!r} does not end after it starts")
        windows.append((start, stop))
    return tuple(windows)
