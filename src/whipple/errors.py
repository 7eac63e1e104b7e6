"""Exceptions raised by whipple.

Every error a user can cause with bad input derives from :class:`InputError`, so that the CLI
can turn it into a one-line message and exit code 2. They also subclass :class:`ValueError`,
so callers may catch the broad builtin or the specific class.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["WhippleError", "InputError", "ParameterError", "BicycleFileError", "RunFileError", "ExperimentFileError",
           "OutputError", "AnalysisError"]


class WhippleError(Exception):
    """Base class of all whipple errors."""


class InputError(WhippleError, ValueError):
    """Bad input: a malformed file, a missing value, a non-physical parameter.

    Parameters
    ----------
    message : str
        What is wrong, in one line.
    source : str or Path, optional
        The file (or built-in name) the problem was found in; prefixed to the message.
    """

    def __init__(self, message: str, source: str | Path | None = None):
        self.source = None if source is None else str(source)
        self.problem = message
        super().__init__(message if source is None else f"{source}: {message}")


class ParameterError(InputError):
    """A parameter set is incomplete or physically implausible."""


class BicycleFileError(InputError):
    """A bicycle file (TOML or BicycleParameters text) cannot be read."""


class RunFileError(InputError):
    """A measured or simulated run file cannot be read or analysed."""


class ExperimentFileError(InputError):
    """An experiment file (groups of runs, each with its bicycle) cannot be read, or names what is not there."""


class OutputError(InputError):
    """An output file cannot be written (read-only folder, a folder in its place, a full disk).

    The message names the file the user asked for, never a temporary file.
    """


class AnalysisError(WhippleError, RuntimeError):
    """A numerical analysis failed (no convergence, no oscillation in a window, ...)."""
