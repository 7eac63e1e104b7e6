"""Re-derive the linearized equations with SymPy and rewrite generated/ (or check it).

With --check nothing is written: the command exits 1 and names every file of generated/ that
differs from a fresh derivation, and 0 when all match byte for byte.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import sympy

import whipple.generated
from whipple.atomic import check_writable, is_standard_output, write_text_atomic
from whipple.cli.progress import Progress
from whipple.derivation.models import MODELS
from whipple.derivation.regenerate import MANIFEST, differences, generate
from whipple.errors import InputError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    parser.add_argument("--check", action="store_true",
                        help="compare with a fresh derivation instead of writing; exit 1 on any difference")
    parser.add_argument("--output", type=Path, default=None,
                        help="folder to write to or check (default: the package's generated/ folder)")


def _default_folder() -> Path:
    return Path(whipple.generated.__file__).resolve().parent


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    folder = args.output or _default_folder()
    if is_standard_output(folder):
        raise InputError("--output needs a folder, not standard output", folder)
    if folder.exists() and not folder.is_dir():
        raise InputError("--output needs a folder; this is a file", folder)
    if args.check and not folder.is_dir():
        raise InputError("--check: no such folder, nothing to compare with", folder)
    if args.check and not (folder / MANIFEST).is_file():
        raise InputError(f"--check: the folder holds no generated code (no {MANIFEST})", folder)
    if not args.check:
        check_writable(folder, is_folder=True)
    started = time.perf_counter()
    with Progress(len(MODELS), "model", "deriving") as progress:
        files = generate(progress=progress.finished)
    elapsed = time.perf_counter() - started
    if args.check:
        changed = differences(files, folder)
        if not changed:
            print(f"generated code in {folder} matches a fresh derivation ({elapsed:.1f} s)")
            return 0
        manifest = folder / MANIFEST
        if manifest.exists():
            recorded = json.loads(manifest.read_text()).get("sympy")
            if recorded and recorded != sympy.__version__:
                print(f"note: generated with SymPy {recorded}, this is SymPy {sympy.__version__}",
                      file=sys.stderr)
        print(f"generated code in {folder} differs from a fresh derivation: {', '.join(changed)}",
              file=sys.stderr)
        return 1
    for name, text in files.items():
        write_text_atomic(folder / name, text)
    print(f"wrote {len(files)} files to {folder} ({elapsed:.1f} s)")
    return 0
