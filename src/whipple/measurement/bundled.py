"""Data shipped with whipple: the measured runs of the steer-by-wire treadmill bicycle.

See ``whipple/data/sbw_treadmill/README.md`` for provenance and licence (MIT, kept beside the
files).
"""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable

_FOLDER = "sbw_treadmill"


def bundled_folder() -> Traversable:
    """Return the folder holding the bundled runs, their reference windows, README and LICENCE."""
    return resources.files("whipple.data").joinpath(_FOLDER)


def bundled_runs() -> list[Traversable]:
    """Return the bundled run files (``*.log.gz``), sorted by belt speed.

    Each can be passed to :func:`whipple.measurement.runs.read_run`.
    """
    logs = [entry for entry in bundled_folder().iterdir() if entry.name.endswith(".log.gz")]
    return sorted(logs, key=lambda entry: _belt_speed(entry.name))


def bundled_reference_windows() -> Traversable:
    """Return the hand-picked reference windows of the bundled runs (CSV, rows as in the logs).

    Read them with :func:`whipple.measurement.reference_windows.read_windows`.
    """
    return bundled_folder().joinpath("reference_windows.csv")


def _belt_speed(name: str) -> float:
    # Names end in "_<speed>kph.log.gz"; unknown names sort last.
    token = name.split("_")[-1].split("kph")[0]
    try:
        return float(token)
    except ValueError:
        return float("inf")
