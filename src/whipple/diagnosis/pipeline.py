"""The diagnosis as one call: :func:`diagnose`, from run files to the report.

``whipple diagnose`` is a thin layer over :func:`diagnose`; the hidden-effect trials, the
benchmarks and the documentation's scripts call it too, so that the command and the library do
the same analysis::

    >>> import whipple
    >>> report = whipple.diagnose(whipple.bundled_runs(), "sbw2024")      # doctest: +SKIP
    >>> report.diagnosis.verdict, report.diagnosis.cause                   # doctest: +SKIP
    >>> report.to_dict() == json.load(open("diagnosis.json"))              # doctest: +SKIP

from ``whipple diagnose --bundled --bicycle sbw2024 --json diagnosis.json``.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from importlib.resources.abc import Traversable
from pathlib import Path
from typing import Protocol

from whipple.diagnosis.options import DiagnosisOptions
from whipple.diagnosis.report import DiagnosisReport, assemble
from whipple.errors import InputError
from whipple.measurement.experiment import RunMeasurement, WindowMeasurement
from whipple.measurement.layouts import RunLayout
from whipple.measurement.measure import MeasuredRuns, Progress, measure_runs
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import Run, check_same_bicycle, read_run
from whipple.measurement.windows import Window
from whipple.model.fleet import Fleet
from whipple.model.parameters import Bicycle, load_bicycle

__all__ = ["RunSource", "Layout", "ExperimentGroup", "ExperimentLike", "diagnose"]

#: What :func:`diagnose` takes as one run: a file (path or package resource) or a read run.
RunSource = str | os.PathLike[str] | Traversable | Run
#: A layout as :func:`~whipple.measurement.runs.read_run` takes it.
Layout = str | os.PathLike[str] | RunLayout | None


class ExperimentGroup(Protocol):
    """One group of an experiment: runs of the bicycle under one controller."""

    @property
    def name(self) -> str: ...  # noqa: D102

    @property
    def bicycle(self) -> Bicycle: ...  # noqa: D102

    @property
    def runs(self) -> Sequence[RunSource]: ...  # noqa: D102

    @property
    def layout(self) -> Layout: ...  # noqa: D102

    @property
    def windows(self) -> str | os.PathLike[str] | Traversable | None: ...  # noqa: D102


class ExperimentLike(Protocol):
    """An experiment of several groups (:func:`whipple.measurement.experiment_file.read_experiment`)."""

    @property
    def groups(self) -> Sequence[ExperimentGroup]: ...  # noqa: D102


def diagnose(runs: Sequence[RunSource] | MeasuredRuns | Sequence[WindowMeasurement | RunMeasurement] | ExperimentLike,
             bicycle: Bicycle | str | os.PathLike[str] | None = None, options: DiagnosisOptions | None = None, *,
             layout: Layout = None, windows: str | os.PathLike[str] | Traversable | Sequence[Window] | None = None,
             progress: Progress | None = None, workers: int | None = None,
             scheduler: str | None = None) -> DiagnosisReport:
    """Diagnose measured runs: what the model gets wrong, the cause, the extended model and its gain.

    Parameters
    ----------
    runs : sequence of run files or Run, measured windows, or an experiment
        Run files (paths, or resources such as :func:`whipple.measurement.bundled.bundled_runs`)
        or runs already read (:func:`whipple.measurement.runs.read_run`); they are measured
        together (:func:`whipple.measurement.measure.measure_runs`). Or windows measured already:
        a :class:`~whipple.measurement.measure.MeasuredRuns`, or a sequence of
        :class:`~whipple.measurement.experiment.RunMeasurement` or
        :class:`~whipple.measurement.experiment.WindowMeasurement` (measured elsewhere: the
        options' measurement part is then not applied). Or an experiment of several groups, the
        runs of one bicycle under several controllers (an object with ``groups``, each with
        ``name``, ``bicycle``, ``runs``, ``layout`` and ``windows``): its groups share every
        physical cause and parameter, and each has its own controller causes
        (``controller_gain[<group>]``); ``bicycle`` is then not given.
    bicycle : Bicycle, str or path
        The base model: a :class:`~whipple.model.parameter_set.Bicycle`, a built-in name
        (``"benchmark"``, ``"sbw2024"``, ...) or a bicycle file, with its controller if any.
    options : DiagnosisOptions, optional
        Every choice of the diagnosis (default :class:`~whipple.diagnosis.options.DiagnosisOptions`,
        what ``whipple diagnose`` does without options).
    layout : str, path or RunLayout, optional
        Layout of the run files (as :func:`~whipple.measurement.runs.read_run` takes it).
    windows : path or sequence of Window, optional
        A windows file, or windows, to fit instead of the window finder's.
    progress : callable, optional
        Called as ``progress(stage, done, total)`` with stages ``"runs"`` (runs measured),
        ``"candidates"`` (causes fitted) and ``"folds"`` (held-out speeds diagnosed); the command
        line renders it as progress bars.
    workers, scheduler : optional
        Diagnose the held-out speeds on a local Dask cluster of ``workers`` processes, or on an
        existing one at ``scheduler``; the results are those of the serial run.

    Returns
    -------
    DiagnosisReport
        The report; :meth:`~whipple.diagnosis.report.DiagnosisReport.to_dict` is what
        ``whipple diagnose --json`` writes.

    Raises
    ------
    InputError
        Unreadable or inconsistent inputs (files, a bicycle, windows), or too few usable windows.
    """
    options = options or DiagnosisOptions()
    if not isinstance(options, DiagnosisOptions):
        raise InputError(f"options must be DiagnosisOptions, got {type(options).__name__}")
    if hasattr(runs, "groups"):
        if bicycle is not None:
            raise InputError("an experiment names each group's bicycle: give no bicycle beside it")
        fleet, measured = _measured_experiment(runs, options, progress)  # type: ignore[arg-type]
        return assemble(fleet, measured, options, scheduler=scheduler, workers=workers, progress=progress)
    if bicycle is None:
        raise InputError("no bicycle given (a file, a built-in name or a Bicycle)")
    model = bicycle if isinstance(bicycle, Bicycle) else load_bicycle(bicycle)
    given = _measured(runs, model, options, layout, windows, progress)  # type: ignore[arg-type]
    return assemble(model, given, options, scheduler=scheduler, workers=workers, progress=progress)


def _measured(runs: Sequence[RunSource] | MeasuredRuns | Sequence[WindowMeasurement | RunMeasurement],
              bicycle: Bicycle, options: DiagnosisOptions, layout: Layout,
              windows: str | os.PathLike[str] | Traversable | Sequence[Window] | None,
              progress: Progress | None) -> MeasuredRuns | list[WindowMeasurement]:
    """Return the windows to diagnose: measured here from run files or runs, or as given."""
    if isinstance(runs, MeasuredRuns):
        return runs
    items = list(runs)
    if not items:
        raise InputError("no runs to diagnose")
    measured = [item for item in items if isinstance(item, WindowMeasurement | RunMeasurement)]
    if measured and len(measured) < len(items):
        raise InputError("runs must be all run files or runs, or all measured windows, not a mixture")
    if measured:
        return [m for item in measured for m in (item if isinstance(item, RunMeasurement) else [item])]
    read = _read(items, layout)  # type: ignore[arg-type]
    chosen = None
    if windows is not None:
        chosen = (tuple(windows) if isinstance(windows, Sequence) and not isinstance(windows, str)
                  else read_windows(_path(windows), read))
    return measure_runs(read, options.measurement, windows=chosen, bicycle=bicycle, progress=progress)


def _measured_experiment(experiment: ExperimentLike, options: DiagnosisOptions, progress: Progress | None
                         ) -> tuple[Fleet, MeasuredRuns]:
    """Return the experiment's fleet of bicycles and every group's windows, measured together.

    The windows of all groups share one choice of signals, and the set-aside rule judges them
    against each other (one bicycle, one set of sensors); each group's steer signal is checked
    against its own bicycle.
    """
    groups = list(experiment.groups)
    if not groups:
        raise InputError("the experiment has no groups")
    fleet = Fleet(tuple((group.name, group.bicycle) for group in groups), name=str(getattr(experiment, "name", "")))
    runs: list[Run] = []
    labels: list[str] = []
    chosen: list[Window] = []
    for group in groups:
        read = _read(list(group.runs), group.layout)
        if not read:
            raise InputError(f"group {group.name!r} has no runs")
        runs += read
        labels += [group.name] * len(read)
        if group.windows is not None:
            chosen += list(read_windows(_path(group.windows), read))
    check_same_bicycle(runs)
    measured = measure_runs(runs, options.measurement, windows=chosen or None, bicycle=fleet, groups=labels,
                            progress=progress)
    return fleet, measured


def _read(sources: Sequence[RunSource], layout: Layout) -> list[Run]:
    """Return the runs of files (a run already read is taken as it is), all of one bicycle by their metadata."""
    given = Path(os.fspath(layout)) if isinstance(layout, os.PathLike) else layout
    runs = [source if isinstance(source, Run) else read_run(_path(source), given) for source in sources]
    check_same_bicycle(runs)
    return runs


def _path(source: str | os.PathLike[str] | Traversable) -> Path | Traversable:
    """Return a file given as a string or path-like object as a Path, a package resource as it is."""
    return Path(os.fspath(source)) if isinstance(source, str | os.PathLike) else source
