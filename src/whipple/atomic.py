"""Atomic output files: write to a temporary file beside the target, then rename.

A reader never sees a half-written file, and an interrupted run never leaves one behind.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from whipple.errors import InputError


@contextmanager
def atomic_path(target: str | Path, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; rename it onto `target` on success.

    Parameters
    ----------
    target : str or Path
        The file to create or replace.
    suffix : str, optional
        Suffix of the temporary file (defaults to the target's, so that tools which infer the
        format from the name, such as matplotlib's ``savefig``, keep working).
    """
    target = Path(target)
    folder = target.parent if str(target.parent) else Path(".")
    folder.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(
        prefix=f".{target.name}.", suffix=target.suffix if suffix is None else suffix, dir=folder
    )
    os.close(handle)
    temporary = Path(name)
    # mkstemp creates the file readable by its owner only; outputs get the usual permissions.
    umask = os.umask(0)
    os.umask(umask)
    try:
        yield temporary
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, target)
    finally:
        if temporary.exists():
            temporary.unlink()


def write_text_atomic(target: str | Path, text: str) -> None:
    """Write `text` (UTF-8) to `target` atomically."""
    with atomic_path(target) as temporary:
        temporary.write_text(text, encoding="utf-8")


def refuse_input_overwrite(output: str | Path, inputs: Iterable[str | Path]) -> None:
    """Raise InputError if `output` is the same file as one of `inputs`.

    Outputs must never replace the data they were computed from.
    """
    output_path = Path(output).resolve()
    for source in inputs:
        source_path = Path(source)
        if source_path.exists() and source_path.resolve() == output_path:
            raise InputError(f"refusing to write output over input file {source}", output)
