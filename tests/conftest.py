"""Shared test fixtures."""

from __future__ import annotations

import importlib.resources
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest


def _read_reference(file_name: str) -> dict[str, Any]:
    text = (
        importlib.resources.files("whipple.data")
        .joinpath("reference", file_name)
        .read_text(encoding="utf-8")
    )
    return tomllib.loads(text)


@pytest.fixture(scope="session")
def meijaard2007() -> dict[str, Any]:
    """Published values for the benchmark bicycle, Meijaard et al. (2007).

    Package copy of the project's reference file: [parameters] Table 1, [matrices] with K0
    EXCLUDING g, [speeds] and [eigenvalues] Table 2.
    """
    return _read_reference("meijaard2007-benchmark.toml")


@pytest.fixture(scope="session")
def kooijman2008() -> dict[str, Any]:
    """Published values for the Kooijman et al. (2008) instrumented bicycle.

    [parameters] from BicycleParameters ("Silver"); [matrices] from Kooijman & Schwab (2009),
    eq. (2), printed to 5 decimals, K0 INCLUDING g.
    """
    return _read_reference("kooijman2008-instrumented-bicycle.toml")


@pytest.fixture()
def benchmark_file_text() -> str:
    """Text of the built-in benchmark bicycle file, a valid starting point for edits."""
    return (
        importlib.resources.files("whipple.data")
        .joinpath("benchmark.toml")
        .read_text(encoding="utf-8")
    )


@pytest.fixture()
def write_file(tmp_path: Path) -> Callable[[str, str], Path]:
    """Write text to a file of the given name in a fresh folder and return its path."""

    def write(name: str, text: str) -> Path:
        path = tmp_path / name
        path.write_text(text, encoding="utf-8")
        return path

    return write
