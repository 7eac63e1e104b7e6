"""Numbers written as text: what every reader of the package accepts as a number.

A number in a file or on the command line is ASCII decimal text: an optional sign, digits with
an optional decimal point, an optional exponent (``1.5``, ``-2e3``, ``.5``), and where a format
allows them ``nan`` and ``inf``. Python's :func:`float` and NumPy's parsers read more: other
scripts' digits (``'١٢'`` and ``'１２'`` are 12.0) and digit-group underscores (``'1_0'`` is
10.0). No logger, spreadsheet or tool of the field writes those as numbers, so a cell holding
them is a mistake, refused like any other text, by the bicycle files' reader, the run files',
layouts' and window lists' readers, the sweep's parameter tables and the command line.
"""

from __future__ import annotations

import re

#: An unsigned decimal number (digits, optional point, optional exponent), to embed in a
#: reader's own pattern; with ``re.ASCII`` or as written, ``[0-9]`` is ASCII only.
UNSIGNED_DECIMAL = r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"

_NUMBER = re.compile(rf"[+-]?(?:{UNSIGNED_DECIMAL}|inf|infinity|nan)", re.ASCII | re.IGNORECASE)
_INTEGER = re.compile(r"[+-]?[0-9]+", re.ASCII)


def parse_number(text: str) -> float:
    """Read a number written as ASCII decimal text (surrounding white space allowed).

    Accepts what :func:`float` accepts (``1.5``, ``-2e3``, ``.5``, ``nan``, ``inf``) except
    other scripts' digits and underscores, which :func:`float` also reads.

    Parameters
    ----------
    text : str
        The text of a cell, a value or a command-line item.

    Raises
    ------
    ValueError
        If `text` is not such a number.
    """
    stripped = text.strip()
    if not _NUMBER.fullmatch(stripped):
        raise ValueError(f"not a number: {text!r}")
    return float(stripped)


def parse_integer(text: str) -> int:
    """Read an integer written in ASCII digits, with an optional sign (surrounding white space allowed).

    Raises
    ------
    ValueError
        If `text` is not such an integer (:func:`int` also reads other scripts' digits and
        underscores).
    """
    stripped = text.strip()
    if not _INTEGER.fullmatch(stripped):
        raise ValueError(f"not an integer: {text!r}")
    return int(stripped)


def may_hold_other_numbers(text: str) -> bool:
    """Return True if `text` may hold numbers :func:`float` reads and :func:`parse_number` refuses.

    For readers that parse a whole block with a fast parser first: text without non-ASCII
    characters and underscores reads the same either way.
    """
    return not text.isascii() or "_" in text
