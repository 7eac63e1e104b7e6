"""Atomic output files: write to a temporary file beside the target, then rename.

A reader never sees a half-written file, and an interrupted run never leaves one behind (the
command line turns SIGTERM and SIGHUP into an exception, so that the temporary file is removed
as on Ctrl-C). Any failure to write (a read-only folder, a folder where the file should be, a
full disk) is an :class:`whipple.errors.OutputError` naming the target the user asked for,
never the temporary file.

``-`` and ``/dev/stdout`` name standard output: the text goes there (after what was printed
before); :func:`messages_to_standard_error` sends the command's own messages to standard error
meanwhile, so that standard output holds the data alone. A device or a pipe is written into,
never replaced.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import sys
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import TextIO

from whipple.errors import InputError, OutputError

#: Names of standard output as an output file.
STANDARD_OUTPUT_NAMES = ("-", "/dev/stdout", "/dev/fd/1", "/proc/self/fd/1")

#: Where text for standard output goes while the messages go to standard error.
_data_stream: ContextVar[TextIO | None] = ContextVar("data_stream", default=None)


def is_standard_output(target: str | os.PathLike[str] | None) -> bool:
    """Return True if `target` names standard output (``-``, ``/dev/stdout``)."""
    if target is None:
        return False
    text = os.fspath(target)
    return text == "-" or os.path.abspath(text) in STANDARD_OUTPUT_NAMES


def standard_output() -> TextIO:
    """Return the stream that outputs named ``-`` are written to."""
    return _data_stream.get() or sys.stdout


@contextmanager
def messages_to_standard_error() -> Iterator[None]:
    """Within the block, ``print`` goes to standard error and outputs named ``-`` to standard output."""
    token = _data_stream.set(sys.stdout)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        _data_stream.reset(token)


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
        The file to create or replace; ``-`` or ``/dev/stdout`` for standard output (the
        temporary file is then in the system's temporary folder and copied out on success).
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
    if is_standard_output(target):
        with tempfile.TemporaryDirectory(prefix="whipple-") as scratch:
            copied = Path(scratch) / f"output{Path(target).suffix if suffix is None else suffix}"
            yield copied
            _copy_out(copied, target)
        return
    target = Path(target)
    if target.is_dir():
        raise OutputError("is a folder, not a file", target)
    if _is_device(target):
        # A device or a pipe (/dev/null, /dev/stderr) cannot be replaced, only written to.
        try:
            yield target
        except OSError as error:
            raise OutputError(f"cannot write: {_problem(error)}", target) from None
        return
    # A symbolic link stays a link: its target is what gets replaced, as with the shell's `>`.
    real = Path(os.path.realpath(target))
    folder = prepare_folder(real.parent, target)
    umask = os.umask(0)
    os.umask(umask)
    temporary: Path | None = None
    try:
        handle, name = tempfile.mkstemp(
            prefix=f".{real.name}.", suffix=target.suffix if suffix is None else suffix, dir=folder
        )
        temporary = Path(name)
        os.close(handle)
        # mkstemp creates the file readable by its owner only; outputs get the usual permissions.
        yield temporary
        os.chmod(temporary, 0o666 & ~umask)
        os.replace(temporary, real)
    except OSError as error:
        raise OutputError(f"cannot write: {_problem(error)}", target) from None
    finally:
        # Also on KeyboardInterrupt and on the exception the command line raises for SIGTERM.
        if temporary is not None:
            with contextlib.suppress(OSError):
                temporary.unlink()


def _is_device(target: Path) -> bool:
    """Whether `target` exists and is no regular file or folder (a device, a pipe, a socket)."""
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _copy_out(temporary: Path, target: str | Path) -> None:
    """Copy a finished temporary file to standard output."""
    stream = standard_output()
    try:
        stream.flush()
        buffer = getattr(stream, "buffer", None)
        with temporary.open("rb") as source:
            if buffer is not None:
                shutil.copyfileobj(source, buffer)
                buffer.flush()
            else:  # a text stream without bytes underneath (a test's capture)
                stream.write(source.read().decode("utf-8", errors="replace"))
                stream.flush()
    except BrokenPipeError:
        raise
    except OSError as error:
        raise OutputError(f"cannot write: {_problem(error)}", target) from None


@contextmanager
def atomic_text(target: str | Path) -> Iterator[TextIO]:
    """Yield a text stream (UTF-8) whose content becomes `target` atomically, or goes to standard output.

    For standard output (``-``) the text is written as it comes (a long table streams); for
    a file as :func:`atomic_path`.
    """
    if is_standard_output(target):
        stream = standard_output()
        yield stream
        stream.flush()
        return
    with atomic_path(target) as temporary, temporary.open("w", encoding="utf-8", newline="") as handle:
        yield handle


def check_writable(target: str | Path, is_folder: bool = False) -> None:
    """Raise OutputError now if `target` could not be written later (a probe file, removed).

    `target` is a file, or with `is_folder` a folder to write files into. The nearest
    existing folder on its path must take a new file; folders that do not exist yet are not
    created here.
    """
    if is_standard_output(target):
        if is_folder:
            raise OutputError("standard output is no folder")
        return
    target = Path(target)
    if not is_folder and target.is_dir():
        raise OutputError("is a folder, not a file", target)
    real = Path(os.path.realpath(target))
    if not is_folder and _is_device(target):
        # A device or a pipe is written to directly (see atomic_path).
        if not os.access(target, os.W_OK):
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
    """Write `text` (UTF-8) to `target` atomically, or to standard output for ``-`` (OutputError naming `target`)."""
    with atomic_text(target) as stream:
        stream.write(text)


def refuse_input_overwrite(output: str | Path, inputs: Iterable[str | Path]) -> None:
    """Raise InputError if `output` is the same file as one of `inputs`.

    Outputs must never replace the data they were computed from. Standard output (``-``) and
    standard input (an input named ``-``) are no files.
    """
    if is_standard_output(output):
        return
    output_path = Path(output).resolve()
    for source in inputs:
        source_path = Path(source)
        if os.fspath(source) == "-" or not source_path.exists():
            continue
        # A hard link is the input under another name: the same file, though no path resolves to it.
        if source_path.resolve() == output_path or (output_path.exists() and os.path.samefile(source_path,
                                                                                             output_path)):
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
        resolved = Path("/dev/stdout") if is_standard_output(path) else Path(path).resolve()
        if resolved in seen:
            raise InputError(f"{seen[resolved]} and {option} name the same file; one would replace "
                             "the other", path)
        seen[resolved] = option
