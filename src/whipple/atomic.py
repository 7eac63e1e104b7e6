"""Atomic output files: write to a temporary file beside the target, then rename.

A reader never sees a half-written file, and an interrupted run never leaves one behind. Any
failure to write (a read-only folder, a folder where the file should be, a full disk) is an
:class:`whipple.errors.OutputError` naming the target the user asked for, never the temporary
file.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path

from whipple.errors import InputError, OutputError


def _problem(error: OSError) -> str:
    """Return the reason of an OSError without the file name it may carry (a temporary one)."""
    return error.strerror or type(error).__name__


def prepare_folder(folder: str | Path, target: str | Path | None = None) -> Path:
    """Create `folder` (and its parents) if needed; OutputError if it cannot be a folder.

    The error names `target` (the file to be written into the folder) when given.
    """
    folder = Path(folder)
    named = folder if target is None else target
    which = "" if target is None else f" {folder}"
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"cannot write: folder{which} is a file", named)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        problem = _problem(error)
        if isinstance(error, FileExistsError | NotADirectoryError):
            problem = "a file on its path is not a folder"
        raise OutputError(f"cannot create folder{which}: {problem}", named) from None
    return folder


@contextmanager
def atomic_path(target: str | Path, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path in the target's folder; rename it onto `target` on success.

    Parameters
    ----------
    target : str or Path
        The file to create or replace.
    suffix : str, optional
        Suffix of the temporary file (defaults to the target's). Tools that infer a format
        from a file name should be given the format explicitly: the temporary file of a
        target without a suffix has none either.

    Raises
    ------
    OutputError
        If the folder cannot be created or written to, the target is a folder, or writing
        fails; it names `target`.
    """
    target = Path(target)
    if target.is_dir():
        raise OutputError("is a folder, not a file", target)
    # A symbolic link stays a link: its target is what gets replaced, as with the shell's `>`.
    real = Path(os.path.realpath(target))
    if real.exists() and not real.is_file():
        # A device or a pipe (/dev/null, /dev/stdout) cannot be replaced, only written to.
        try:
            yield real
        except OSError as error:
            raise OutputError(f"cannot write: {_problem(error)}", target) from None
        return
    folder = prepare_folder(real.parent, target)
    try:
        handle, name = tempfile.mkstemp(
            prefix=f".{real.name}.", suffix=target.suffix if suffix is None else suffix, dir=folder
        )
    except OSError as error:
        raise OutputError(f"cannot write: {_problem(error)}", target) from None
    os.close(handle)
    temporary = Path(name)
    # mkstemp creates the file readable by its owner only; outputs get the usual permissions.
    umask = os.umask(0)
    os.umask(umask)
    try:
        yield temporary
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, real)
    except OSError as error:
        raise OutputError(f"cannot write: {_problem(error)}", target) from None
    finally:
        if temporary.exists():
            temporary.unlink()


def check_writable(target: str | Path, is_folder: bool = False) -> None:
    """Raise OutputError now if `target` could not be written later (a probe file, removed).

    `target` is a file, or with `is_folder` a folder to write files into. The nearest
    existing folder on its path must take a new file; folders that do not exist yet are not
    created here.
    """
    target = Path(target)
    if not is_folder and target.is_dir():
        raise OutputError("is a folder, not a file", target)
    real = Path(os.path.realpath(target))
    if not is_folder and real.exists() and not real.is_file():
        # A device or a pipe is written to directly (see atomic_path).
        if not os.access(real, os.W_OK):
            raise OutputError("cannot write: permission denied", target)
        return
    folder = real if is_folder else real.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise OutputError(f"cannot write: {folder} is a file, not a folder", target)
    try:
        handle, name = tempfile.mkstemp(prefix=".whipple-probe.", dir=folder)
    except OSError as error:
        raise OutputError(f"cannot write: {_problem(error)}", target) from None
    os.close(handle)
    os.unlink(name)


def write_text_atomic(target: str | Path, text: str) -> None:
    """Write `text` (UTF-8) to `target` atomically (OutputError naming `target` on failure)."""
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


def refuse_shared_outputs(outputs: Mapping[str, str | Path | None]) -> None:
    """Raise InputError if two options name the same output file.

    Parameters
    ----------
    outputs : mapping of str to path or None
        Option name (e.g. ``"--json"``) to the file it names; None for options not given.
    """
    seen: dict[Path, str] = {}
    for option, path in outputs.items():
        if path is None:
            continue
        resolved = Path(path).resolve()
        if resolved in seen:
            raise InputError(f"{seen[resolved]} and {option} name the same file; one would replace "
                             "the other", path)
        seen[resolved] = option
