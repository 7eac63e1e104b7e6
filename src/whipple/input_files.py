"""Reading input files in bounded memory: size caps, line caps, standard input.

Every file a user can name may be endless or huge (``/dev/zero``, ``/dev/urandom``, a pipe that
never closes, a log of days): whipple never reads one whole into memory without a cap. Small
files (bicycle, rider, layout and windows files) are read up to :data:`MAX_SMALL_FILE_BYTES`;
tables (run files, parameter tables) are read as text in blocks of lines, each line at most
:data:`MAX_LINE_CHARACTERS` long, with NUL characters and invalid UTF-8 refused at the first
block that holds them. The readers of each format add their own caps (rows of a run file).

``-`` names standard input (:data:`STANDARD_STREAM`) where a command reads one table.
"""

from __future__ import annotations

import codecs
import os
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from whipple.errors import InputError

#: Largest bicycle, rider, layout or windows file [bytes]: the largest real one is a few kB.
MAX_SMALL_FILE_BYTES = 16 << 20
#: Longest line of a table [characters]: a run file's longest line is a metadata line listing
#: its windows (about 60 kB for the longest run whipple simulates).
MAX_LINE_CHARACTERS = 1 << 20
#: Bytes read from a table at a time.
BLOCK_BYTES = 1 << 20
#: The file name that means standard input (for inputs) or standard output (for outputs).
STANDARD_STREAM = "-"

#: Builds the error of a reader: ``error(problem, source)``.
ErrorFactory = Callable[[str, str], InputError]


def is_standard_stream(path: str | os.PathLike[str] | None) -> bool:
    """Return True if `path` is ``-`` (standard input or output)."""
    return path is not None and os.fspath(path) == STANDARD_STREAM


def _mebibytes(size: int) -> str:
    return f"{size / (1 << 20):g} MiB"


def read_small_file(path: str | os.PathLike[str], what: str, error: ErrorFactory = InputError,
                    limit: int = MAX_SMALL_FILE_BYTES) -> bytes:
    """Return the bytes of a small input file, refusing one larger than `limit` without reading it all.

    Parameters
    ----------
    path : str or path
        The file (a device or a pipe is read up to the limit too).
    what : str
        What the file should be (``"bicycle file"``), for the message.
    error : callable
        ``error(problem, source)`` builds the exception to raise.
    limit : int
        Largest size accepted [bytes].

    Raises
    ------
    InputError
        (from `error`) If the file cannot be read or holds more than `limit` bytes (said to be
        no text if it holds NUL bytes: ``/dev/zero``).
    """
    source = os.fspath(path)
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)
    except OSError as failure:
        raise error(f"cannot read file: {failure.strerror or failure}", source) from None
    if len(data) > limit:
        if b"\x00" in data:  # /dev/zero, or a binary file named by mistake
            raise error("not a text file (it holds NUL bytes)", source)
        raise error(f"more than {_mebibytes(limit)}: too large for a {what}", source)
    return data


def open_binary(path: Any) -> IO[bytes]:
    """Open `path` (a path, ``-`` for standard input, or an importlib Traversable) for reading bytes."""
    if is_standard_stream(path):
        return os.fdopen(os.dup(sys.stdin.fileno()), "rb")
    if isinstance(path, str | os.PathLike):
        return open(path, "rb")
    return path.open("rb")


def text_lines(handle: IO[bytes], source: str, error: ErrorFactory = InputError,
               max_line: int = MAX_LINE_CHARACTERS, block_bytes: int = BLOCK_BYTES) -> Iterator[list[str]]:
    """Yield the lines of a UTF-8 text stream in blocks, without line ends, in bounded memory.

    A byte-order mark is dropped; lines end in LF, CR LF or CR. Each block
    holds the complete lines of about `block_bytes` bytes.

    Raises
    ------
    InputError
        (from `error`) At the first block that is not UTF-8 text, holds a NUL character
        (binary data, ``/dev/zero``), or a line longer than `max_line` characters.
    """
    decoder = codecs.getincrementaldecoder("utf-8-sig")()
    carry = ""
    number = 0  # lines yielded so far

    def checked(lines: list[str]) -> list[str]:
        if lines and max(map(len, lines)) > max_line:
            too_long = next(k for k, line in enumerate(lines) if len(line) > max_line)
            raise error(f"line {number + too_long + 1} is longer than {max_line} characters: not a table",
                        source)
        return lines

    while True:
        try:
            chunk = handle.read(block_bytes)
        except OSError as failure:
            raise error(f"cannot read file: {failure.strerror or failure}", source) from None
        try:
            text = carry + decoder.decode(chunk, final=not chunk)
        except UnicodeDecodeError:
            raise error(_not_utf8(chunk if number == 0 and not carry else b""), source) from None
        if "\x00" in text:
            raise error("not a text file (it holds NUL bytes)", source)
        if not chunk:
            break
        # A "\r" at the end may be the first half of "\r\n": keep it for the next block.
        held = text.endswith("\r")
        if "\r" in text:
            text = text[:-1] if held else text
            text = text.replace("\r\n", "\n").replace("\r", "\n")
        lines = text.split("\n")
        carry = lines.pop() + ("\r" if held else "")
        if len(carry) > max_line:
            raise error(f"line {number + len(lines) + 1} is longer than {max_line} characters: not a table",
                        source)
        if lines:
            yield checked(lines)
            number += len(lines)
    if carry:
        yield checked(carry.replace("\r\n", "\n").replace("\r", "\n").split("\n"))


def _not_utf8(start: bytes) -> str:
    """Return the problem of a table that is not UTF-8; `start` is its first block (empty if past it)."""
    if start.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "not UTF-8 text but UTF-16 (invalid UTF-8): save it as UTF-8"
    return "not a text file (invalid UTF-8), or text in another encoding (Latin-1?): save it as UTF-8"


def is_regular_file(path: Any) -> bool:
    """Return True if `path` names a regular file (not ``-``, a device, a pipe or a folder)."""
    if is_standard_stream(path) or not isinstance(path, str | os.PathLike):
        return False
    try:
        return Path(path).is_file()
    except OSError:
        return False
