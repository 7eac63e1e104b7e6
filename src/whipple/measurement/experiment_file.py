"""Experiment files: several groups of runs, each measured on its own bicycle and controller.

One bicycle measured under different controllers (or loads, or tyres) is one experiment of
several groups: the groups share the bicycle's physical properties, and each has its own
bicycle file carrying its own controller. An experiment file is TOML with one ``[[group]]``
table per group::

    description = "steer-by-wire bicycle, two controllers"   # optional

    [[group]]
    name = "mm_off"                      # a word: letters, digits, '_' and '-'
    bicycle = "sbw2024"                  # a built-in name, or a bicycle file with its controller
    runs = ["logs/eigen_normal_*.log.gz"]  # run files or glob patterns (one string or a list)
    layout = "sbw-treadmill"             # optional: a built-in layout name or a layout file
    windows = "windows-off.csv"          # optional: a windows file fitted instead of the finder's

    [[group]]
    name = "mm_on"
    bicycle = "sbw2024-mm.toml"
    runs = "logs/eigen_mm_*.log.gz"

Relative paths are relative to the experiment file's folder, absolute ones are taken as they
are; a built-in name (bicycle, layout) wins over a file of the same name, as on the command
line (write ``./name`` for the file). Patterns follow :mod:`glob` (``**`` spans folders); the
files a pattern matches are taken in natural order (``run9`` before ``run10``).

Reading checks everything a file can get wrong before any run is measured, each a one-line
:class:`~whipple.errors.ExperimentFileError` naming the experiment file, the group and the
problem: bad TOML, unknown keys, no groups, a name that is not a word or is given twice, a
pattern that matches nothing, a missing run, bicycle, layout or windows file, a run file in two
groups or twice in one, two runs of one group with one name, a bicycle or layout that cannot be
read.
"""

from __future__ import annotations

import glob
import os
import re
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from whipple.errors import ExperimentFileError, InputError
from whipple.measurement.bundled import bundled_experiment
from whipple.measurement.layouts import RunLayout, builtin_layouts, load_layout
from whipple.measurement.measure import MeasuredRuns, MeasurementOptions, Progress, measure_runs
from whipple.measurement.reference_windows import read_windows
from whipple.measurement.runs import Run, read_run, run_name
from whipple.measurement.windows import Window
from whipple.model.parameters import Bicycle, builtin_names, load_bicycle

__all__ = ["BUNDLED", "TOP_LEVEL_KEYS", "GROUP_KEYS", "Failure", "Group", "Experiment", "group_model_file",
           "read_group_models", "read_experiment"]

#: The word that names the experiment file of the bundled runs (:func:`.bundled.bundled_experiment`).
BUNDLED = "bundled"
#: Keys of the file's top level and of a ``[[group]]`` table.
TOP_LEVEL_KEYS = ("description", "group")
GROUP_KEYS = ("name", "bicycle", "runs", "layout", "windows")
#: How a group's reader reports a problem: the message, naming the file and the group.
Failure = Callable[[str], ExperimentFileError]
#: A group's name: it names files (``DIR/<name>.toml``) and report entries.
_WORD = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}")


@dataclass(frozen=True)
class Group:
    """One group of an experiment: runs measured on one bicycle with one controller.

    Attributes
    ----------
    name : str
        The group's name (a word).
    bicycle : Bicycle
        Its bicycle, with its controller, loaded and checked.
    runs : tuple of Path
        Its run files, patterns expanded.
    layout : RunLayout or None
        The layout its run files are read with (None: native, or recognised by the header).
    windows : Path or None
        A windows file fitted instead of the window finder's windows.
    bicycle_file, layout_file : Path or None
        The files the bicycle and the layout were read from (None: built-in or not given).
    """

    name: str
    bicycle: Bicycle
    runs: tuple[Path, ...]
    layout: RunLayout | None = None
    windows: Path | None = None
    bicycle_file: Path | None = None
    layout_file: Path | None = None

    def inputs(self) -> tuple[Path, ...]:
        """Return every file the group reads (outputs must never replace one)."""
        return (*self.runs, *(path for path in (self.bicycle_file, self.layout_file, self.windows)
                              if path is not None))

    def read_runs(self) -> list[Run]:
        """Read the group's run files (with its layout)."""
        return [read_run(path, self.layout) for path in self.runs]

    def measure(self, options: MeasurementOptions | None = None, *, progress: Progress | None = None
                ) -> MeasuredRuns:
        """Measure the group's runs on its own bicycle (:func:`~whipple.measurement.measure.measure_runs`).

        The windows file's windows where the group names one, else the window finder's; the
        steer signal's sign is checked against the group's bicycle, as ``whipple fit --bicycle``
        and ``whipple diagnose`` do.
        """
        runs = self.read_runs()
        windows: tuple[Window, ...] | None = None
        if self.windows is not None:
            windows = read_windows(self.windows, runs)
        return measure_runs(runs, options, windows=windows, bicycle=self.bicycle, progress=progress)


@dataclass(frozen=True)
class Experiment:
    """An experiment file, read: its groups in file order.

    Attributes
    ----------
    source : Path
        The experiment file.
    groups : tuple of Group
        Its groups.
    description : str
        Free text ("" when not given).
    """

    source: Path
    groups: tuple[Group, ...]
    description: str = ""

    def group(self, name: str) -> Group:
        """Return the group called `name` (KeyError when there is none)."""
        for group in self.groups:
            if group.name == name:
                return group
        raise KeyError(name)

    def inputs(self) -> tuple[Path, ...]:
        """Return the experiment file and every file its groups read."""
        return (self.source, *(path for group in self.groups for path in group.inputs()))

    def bicycles(self) -> dict[str, Bicycle]:
        """Return each group's own bicycle (with its controller), by group name."""
        return {group.name: group.bicycle for group in self.groups}


def group_model_file(folder: str | os.PathLike[str], name: str) -> Path:
    """Return the file of a group's model in a models folder: ``<folder>/<name>.toml``."""
    return Path(os.fspath(folder)) / f"{name}.toml"


def read_group_models(folder: str | os.PathLike[str], experiment: Experiment) -> dict[str, Bicycle]:
    """Read one model per group of an experiment from a folder: ``<folder>/<group>.toml`` each.

    Parameters
    ----------
    folder : str or path
        A folder holding one bicycle file per group (other files are ignored), such as the
        extended models a diagnosis of the experiment saves.
    experiment : Experiment
        The experiment whose groups need a model.

    Returns
    -------
    dict
        Group name to its model, in the experiment's order.

    Raises
    ------
    InputError
        No such folder, a group without its file, or a file that is no bicycle (one line naming it).
    """
    where = Path(os.fspath(folder))
    if not where.is_dir():
        raise InputError("no such folder of models (one bicycle file <group>.toml per group)", where)
    models = {}
    for group in experiment.groups:
        path = group_model_file(where, group.name)
        if not path.is_file():
            raise InputError(f"no model for group {group.name!r} of {experiment.source} (a models folder holds one "
                             "bicycle file <group>.toml per group)", path)
        models[group.name] = load_bicycle(path)
    return models


def read_experiment(path: str | os.PathLike[str]) -> Experiment:
    """Read an experiment file: its groups, their bicycles loaded and their run patterns expanded.

    Parameters
    ----------
    path : str or path
        The experiment file, or the word ``"bundled"`` for the bundled runs' experiment
        (:func:`whipple.measurement.bundled.bundled_experiment`; ``./bundled`` for a file of
        that name).

    Returns
    -------
    Experiment
        The groups in file order.

    Raises
    ------
    ExperimentFileError
        Anything wrong with the file or what it names, in one line naming the file.
    """
    source = bundled_experiment() if os.fspath(path) == BUNDLED else Path(os.fspath(path))
    document = _document(source)
    _check_keys(document, TOP_LEVEL_KEYS, source, "the top level")
    description = document.get("description", "")
    if not isinstance(description, str):
        raise ExperimentFileError(f"'description' must be a string, got {_kind(description)}", source)
    tables = document.get("group")
    if tables is None or tables == []:
        raise ExperimentFileError("no groups: the file needs one [[group]] table per group of runs", source)
    if not isinstance(tables, list) or not all(isinstance(table, dict) for table in tables):
        raise ExperimentFileError("'group' must be [[group]] tables, one per group of runs", source)
    groups: list[Group] = []
    owners: dict[Path, str] = {}
    for number, table in enumerate(tables, 1):
        group = _group(table, number, source)
        twin = next((g.name for g in groups if g.name.lower() == group.name.lower()), None)
        if twin is not None:
            raise ExperimentFileError(f"group {number} ({group.name!r}): the name {group.name!r} is given twice "
                                      f"(as {twin!r} before; names must differ, also in case)", source)
        for run in group.runs:
            other = owners.setdefault(run.resolve(), group.name)
            if other != group.name:
                raise ExperimentFileError(f"run file {run} is in groups {other!r} and {group.name!r} (a run "
                                          "belongs to one group)", source)
        groups.append(group)
    return Experiment(source, tuple(groups), description)


def _document(source: Path) -> dict[str, Any]:
    """Return the parsed TOML of the experiment file."""
    try:
        text = source.read_bytes().decode("utf-8-sig")
    except IsADirectoryError:
        raise ExperimentFileError("not a file (a folder?)", source) from None
    except FileNotFoundError:
        raise ExperimentFileError("no such experiment file", source) from None
    except OSError as error:
        raise ExperimentFileError(f"cannot read experiment file ({error.strerror or error})", source) from None
    except UnicodeDecodeError:
        raise ExperimentFileError("not a UTF-8 text file", source) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ExperimentFileError(f"TOML syntax error: {error}", source) from None


def _group(table: dict[str, Any], number: int, source: Path) -> Group:
    """Read one ``[[group]]`` table."""
    name = table.get("name")
    where = f"group {number}" + (f" ({name!r})" if isinstance(name, str) else "")

    def fail(problem: str) -> ExperimentFileError:
        return ExperimentFileError(f"{where}: {problem}", source)

    _check_keys(table, GROUP_KEYS, source, where)
    missing = [key for key in ("name", "bicycle", "runs") if key not in table]
    if missing:
        raise fail(f"missing key{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
    for key in ("name", "bicycle", "layout", "windows"):
        if key in table and not (isinstance(table[key], str) and table[key].strip()):
            raise fail(f"{key!r} must be a non-empty string, got {_kind(table[key])}")
    if not _WORD.fullmatch(name):  # type: ignore[arg-type]
        raise fail("the name must be a word of at most 64 letters, digits, '_' and '-' (it names files), "
                   f"got {name!r}")
    base = source.parent
    runs = _run_files(table["runs"], base, fail)
    bicycle_file = None if table["bicycle"] in builtin_names() else _existing(table["bicycle"], base, "bicycle", fail)
    try:
        bicycle = load_bicycle(table["bicycle"] if bicycle_file is None else bicycle_file)
    except InputError as error:
        raise fail(f"bicycle: {error}") from None
    layout, layout_file = None, None
    if "layout" in table:
        layout_file = None if table["layout"] in builtin_layouts() else _existing(table["layout"], base, "layout", fail)
        try:
            layout = load_layout(table["layout"] if layout_file is None else layout_file)
        except InputError as error:
            raise fail(f"layout: {error}") from None
    windows = _existing(table["windows"], base, "windows", fail) if "windows" in table else None
    return Group(name, bicycle, runs, layout, windows, bicycle_file, layout_file)  # type: ignore[arg-type]


def _run_files(value: Any, base: Path, fail: Failure) -> tuple[Path, ...]:
    """Return the run files of a group's ``runs``: files and patterns, expanded, each once."""
    patterns = [value] if isinstance(value, str) else value
    if not isinstance(patterns, list) or not patterns or not all(isinstance(p, str) and p.strip() for p in patterns):
        raise fail(f"'runs' must be a run file or pattern, or a non-empty list of them, got {_kind(value)}")
    files: list[Path] = []
    for pattern in patterns:
        if glob.has_magic(pattern):
            # The pattern alone is a pattern: brackets or stars in the experiment file's folder are not.
            found = (glob.glob(pattern, recursive=True) if Path(pattern).is_absolute()
                     else glob.glob(pattern, root_dir=base, recursive=True))
            matches = sorted((_resolved(match, base) for match in found if _resolved(match, base).is_file()),
                             key=_natural)
            if not matches:
                where = "" if Path(pattern).is_absolute() else f" (relative to {base.resolve()})"
                raise fail(f"runs pattern {pattern!r} matches no file{where}")
            files += matches
        else:
            files.append(_existing(pattern, base, "run", fail))
    seen: dict[Path, Path] = {}
    names: dict[str, Path] = {}
    for path in files:
        if path.resolve() in seen:
            raise fail(f"run file {path} is listed twice")
        seen[path.resolve()] = path
        other = names.setdefault(run_name(path.name), path)
        if other != path:
            raise fail(f"two runs are named {run_name(path.name)} ({other} and {path}; windows and figures go by "
                       "run name)")
    return tuple(files)


def _resolved(text: str, base: Path) -> Path:
    """Return a path of the file: relative to ``base``, absolute as it is."""
    path = Path(text)
    return path if path.is_absolute() else base / path


def _existing(text: str, base: Path, what: str, fail: Failure) -> Path:
    """Return the regular file that ``text`` names, or fail naming it."""
    path = _resolved(text, base)
    if not path.exists():
        raise fail(f"no such {what} file {text!r} ({path})")
    if not path.is_file():
        raise fail(f"{what} {text!r} is not a regular file ({path})")
    return path


def _natural(path: Path) -> list[Any]:
    """Sort key: the path's digit runs as numbers (``run9`` before ``run10``)."""
    return [(0, int(part), "") if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", str(path))]


def _check_keys(table: dict[str, Any], allowed: Sequence[str], source: Path, where: str) -> None:
    for key in table:
        if key not in allowed:
            raise ExperimentFileError(f"{where}: unknown key {key!r} (known: {', '.join(allowed)})", source)


def _kind(value: Any) -> str:
    """Name a TOML value's type for a message."""
    kinds = {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
             dict: "a table"}
    return next((text for kind, text in kinds.items() if isinstance(value, kind)), type(value).__name__)
