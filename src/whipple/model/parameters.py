"""Bicycle parameter sets: names, data objects, physical checks, and bicycle files.

This is the public entry point; the parameter set and its checks are defined in
:mod:`whipple.model.parameter_set`, the file formats in :mod:`whipple.model.bicycle_file`.

Examples
--------
>>> from whipple.model.parameters import load_bicycle, validate
>>> bicycle = load_bicycle("benchmark")
>>> bicycle.parameters["c"]
0.08
>>> validate(bicycle).ok
True
"""

from __future__ import annotations

import os
from pathlib import Path

import whipple.data
from whipple.errors import BicycleFileError
from whipple.model.benchmark_text import read_benchmark_txt
from whipple.model.bicycle_file import (
    bicycle_from_toml,
    parse_toml,
    read_bicycle_toml,
    write_bicycle_toml,
)
from whipple.model.parameter_set import (
    CONTROLLER_STATES,
    OPTIONAL_PARAMETERS,
    PARAMETER_DESCRIPTIONS,
    PARAMETER_NAMES,
    PARAMETER_UNITS,
    Bicycle,
    Controller,
    Extensions,
    Payload,
    TyreCompliance,
    ValidationReport,
    check_physical,
    validate,
    validate_rows,
)
from whipple.model.rider import Rider, add_rider, read_rider_txt

__all__ = [
    "CONTROLLER_STATES",
    "OPTIONAL_PARAMETERS",
    "PARAMETER_DESCRIPTIONS",
    "PARAMETER_NAMES",
    "PARAMETER_UNITS",
    "Bicycle",
    "Controller",
    "Extensions",
    "Payload",
    "Rider",
    "TyreCompliance",
    "ValidationReport",
    "add_rider",
    "builtin_names",
    "check_physical",
    "load_bicycle",
    "read_benchmark_txt",
    "read_bicycle_toml",
    "read_rider_txt",
    "validate",
    "validate_rows",
    "write_bicycle_toml",
]

#: Bicycles shipped with whipple, as files whipple/data/<name>.toml.
_BUILTIN = ("benchmark", "kooijman2008", "sbw2024", "sbw2024-mm")


def builtin_names() -> tuple[str, ...]:
    """Names of the bicycles shipped with whipple.

    Returns
    -------
    tuple of str
        The names :func:`load_bicycle` accepts in place of a file (``benchmark``, ...).
    """
    return _BUILTIN


def load_bicycle(spec: str | os.PathLike[str], rider: str | os.PathLike[str] | None = None) -> Bicycle:
    """Load a built-in bicycle, a TOML file, or a BicycleParameters text file.

    Parameters
    ----------
    spec : str or path
        A built-in name (see :func:`builtin_names`), or a path: ``*.txt`` is read as
        BicycleParameters text, anything else as TOML. A built-in name wins over a file of the
        same name in the working folder (write ``./benchmark`` for the file).
    rider : str or path, optional
        A BicycleParameters rider file (``<Rider><Bicycle>Benchmark.txt``) whose rigid rider is
        joined to the rear frame (:func:`whipple.model.rider.add_rider`).

    Returns
    -------
    Bicycle
        A bicycle that has passed :func:`check_physical`.

    Raises
    ------
    BicycleFileError
        Neither a built-in name nor a file, or a file that cannot be read.
    ParameterError
        Physically impossible values.
    """
    bicycle = _load(os.fspath(spec))
    if rider is None:
        return bicycle
    return add_rider(bicycle, read_rider_txt(rider))


def _load(text: str) -> Bicycle:
    if text in _BUILTIN:
        # The package's own data folder (an installed package is files on disk); importlib's
        # resource readers would add ~7 ms to every command's start.
        resource = Path(whipple.data.__file__).parent / f"{text}.toml"
        return bicycle_from_toml(parse_toml(resource.read_text(encoding="utf-8"), text), text)
    path = Path(text)
    if path.exists() and not path.is_file():
        raise BicycleFileError("not a regular file (a folder, a device or a pipe?)", text)
    if not path.is_file():
        raise BicycleFileError(
            f"no such file or built-in bicycle (built-in: {', '.join(_BUILTIN)})", text
        )
    if path.suffix.lower() == ".txt":
        return read_benchmark_txt(path)
    return read_bicycle_toml(path)
