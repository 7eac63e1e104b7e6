"""Data shipped with whipple: the measured runs of the steer-by-wire treadmill bicycle.

Two experiments on the same bicycle, treadmill and day: model matching OFF (the steer-into-lean
law alone, bicycle ``sbw2024``; the default) and model matching ON (a full state feedback,
bicycle ``sbw2024-mm``). See ``whipple/data/sbw_treadmill/README.md`` for provenance and licence
(MIT, kept beside the files).
"""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

from whipple.errors import InputError

__all__ = ["BUNDLED_EXPERIMENTS", "DEFAULT_EXPERIMENT", "bundled_folder", "bundled_runs", "bundled_experiment_bicycle",
           "bundled_reference_windows", "bundled_experiment"]

_FOLDER = "sbw_treadmill"

#: The bundled experiments: name -> (file-name prefix of its runs, built-in bicycle with its controller).
BUNDLED_EXPERIMENTS: dict[str, tuple[str, str]] = {
    "model-matching-off": ("eigen_normal_", "sbw2024"),
    "model-matching-on": ("eigen_mm_", "sbw2024-mm"),
}
#: The experiment :func:`bundled_runs` returns unless told otherwise.
DEFAULT_EXPERIMENT = "model-matching-off"


def bundled_folder() -> Traversable:
    """Return the folder holding the bundled runs, their reference windows, README and LICENCE."""
    return resources.files("whipple.data").joinpath(_FOLDER)


def bundled_runs(experiment: str = DEFAULT_EXPERIMENT) -> list[Traversable]:
    """Return the bundled run files (``*.log.gz``) of one experiment, sorted by belt speed.

    Parameters
    ----------
    experiment : str
        ``"model-matching-off"`` (default: the steer-into-lean law alone, bicycle ``sbw2024``)
        or ``"model-matching-on"`` (the full state feedback, bicycle ``sbw2024-mm``).

    Returns
    -------
    list of Traversable
        Each can be passed to :func:`whipple.measurement.runs.read_run`.

    Raises
    ------
    InputError
        An unknown experiment name.
    """
    prefix, _ = _experiment(experiment)
    logs = [entry for entry in bundled_folder().iterdir()
            if entry.name.endswith(".log.gz") and entry.name.startswith(prefix)]
    return sorted(logs, key=lambda entry: _belt_speed(entry.name))


def bundled_experiment_bicycle(experiment: str) -> str:
    """Return the built-in bicycle (with its controller) of a bundled experiment.

    Raises
    ------
    InputError
        An unknown experiment name.
    """
    return _experiment(experiment)[1]


def _experiment(name: str) -> tuple[str, str]:
    if name not in BUNDLED_EXPERIMENTS:
        raise InputError(f"no bundled experiment {name!r} (bundled: {', '.join(BUNDLED_EXPERIMENTS)})")
    return BUNDLED_EXPERIMENTS[name]


def bundled_reference_windows() -> Traversable:
    """Return the hand-picked reference windows of the bundled runs (CSV, rows as in the logs).

    One file for both experiments. Read them with
    :func:`whipple.measurement.reference_windows.read_windows`, which keeps the windows of the
    runs it is given.

    Returns
    -------
    Traversable
        The CSV file, a package resource.
    """
    return bundled_folder().joinpath("reference_windows.csv")


def bundled_experiment() -> Path:
    """Return the experiment file of both bundled experiments (groups ``mm_off`` and ``mm_on``).

    Read it with :func:`whipple.measurement.experiment_file.read_experiment`; its runs are the
    files beside it.

    Returns
    -------
    Path
        The experiment file (TOML).
    """
    # An installed package is files on disk, and the experiment file names its runs by paths
    # relative to itself.
    return Path(str(bundled_folder().joinpath("experiment.toml")))


def _belt_speed(name: str) -> float:
    # Names end in "_<speed>kph.log.gz"; unknown names sort last.
    token = name.split("_")[-1].split("kph")[0]
    try:
        return float(token)
    except ValueError:
        return float("inf")
