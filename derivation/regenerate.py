"""Regenerate generated/ from the derivation, or check that it is up to date.

The output is a pure function of the derivation sources and the SymPy version: no dates, no
paths, so ``regenerate --check`` can compare byte for byte.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from pathlib import Path

import sympy as sm

from whipple.model import parameter_table

from .emit import emit_casadi, emit_casadi_functions, emit_numpy, emit_numpy_functions
from .models import MODELS, DerivedFunctions

DERIVATION_DIR = Path(__file__).resolve().parent
MANIFEST = "manifest.json"


def source_hashes() -> dict[str, str]:
    """sha256 of every derivation source file, and of the parameter table it reads, by file name."""
    sources = [*sorted(DERIVATION_DIR.glob("*.py")), Path(parameter_table.__file__)]
    return {path.name: hashlib.sha256(path.read_bytes()).hexdigest() for path in sources}


def combined_hash(hashes: dict[str, str]) -> str:
    """One sha256 over the sorted (name, hash) pairs."""
    digest = hashlib.sha256()
    for name, value in sorted(hashes.items()):
        digest.update(f"{name}:{value}\n".encode())
    return digest.hexdigest()


def generate(progress: Callable[[str], object] | None = None) -> dict[str, str]:
    """Derive every model and return the generated files' texts by file name.

    `progress`, if given, is called with each model's name when its derivation is done.
    """
    hashes = source_hashes()
    source_hash = combined_hash(hashes)
    files: dict[str, str] = {
        "__init__.py": '"""Generated code: see derivation/ and manifest.json. Do not edit."""\n'
    }
    for name, derive in MODELS.items():
        model = derive()
        if isinstance(model, DerivedFunctions):
            files[f"{name}_numpy.py"] = emit_numpy_functions(model, source_hash)
            files[f"{name}_casadi.py"] = emit_casadi_functions(model, source_hash)
        else:
            files[f"{name}_numpy.py"] = emit_numpy(model, source_hash)
            files[f"{name}_casadi.py"] = emit_casadi(model, source_hash)
        if progress is not None:
            progress(name)
    manifest = {
        "generator": "whipple regenerate (derivation/regenerate.py)",
        "sympy": sm.__version__,
        "derivation_sources_sha256": hashes,
        "models": sorted(MODELS),
        "files_sha256": {name: hashlib.sha256(text.encode()).hexdigest()
                         for name, text in sorted(files.items())},
    }
    files[MANIFEST] = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    return files


def differences(files: dict[str, str], directory: Path) -> list[str]:
    """Names of files in ``files`` that are missing from or differ in ``directory``."""
    changed = []
    for name, text in sorted(files.items()):
        path = directory / name
        if not path.exists() or path.read_bytes() != text.encode():
            changed.append(name)
    return changed
