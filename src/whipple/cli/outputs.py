"""Output files shared by the subcommands: checked before any work, written atomically.

Every output is checked up front (not over an input, not named twice, a folder where a folder
is wanted, an image format that exists), so that a long analysis is not lost to a typo; writing
itself goes through :mod:`whipple.atomic`, whose failures name the user's path.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from whipple.atomic import atomic_path, check_writable, refuse_input_overwrite, refuse_shared_outputs
from whipple.errors import InputError

#: Image formats a figure may be written in (by file suffix); a name without suffix gets PNG.
FIGURE_FORMATS = ("png", "pdf", "svg", "eps", "ps", "jpg", "jpeg", "tif", "tiff", "webp")


def figure_format(path: str | Path) -> str:
    """Return the image format of a figure file from its suffix (``png`` when it has none)."""
    suffix = Path(path).suffix.lower().removeprefix(".")
    if not suffix:
        return "png"
    if suffix not in FIGURE_FORMATS:
        raise InputError(f"cannot write a figure as .{suffix} (formats: {', '.join(FIGURE_FORMATS)})", path)
    return suffix


def check_outputs(files: Mapping[str, str | Path | None], inputs: Iterable[str | Path],
                  folders: Mapping[str, str | Path | None] | None = None) -> None:
    """Refuse, before any work, outputs that cannot be right.

    Parameters
    ----------
    files : mapping
        Option name to the output file it names (None when not given).
    inputs : iterable of path
        Input files, never to be overwritten.
    folders : mapping, optional
        Option name to an output folder (None when not given); it must not be a file.
    """
    inputs = list(inputs)
    refuse_shared_outputs({**files, **(folders or {})})
    for option, folder in (folders or {}).items():
        if folder is None:
            continue
        if Path(folder).exists() and not Path(folder).is_dir():
            raise InputError(f"{option} needs a folder; this is a file", folder)
        check_writable(folder, is_folder=True)
    for option, path in files.items():
        if path is None:
            continue
        refuse_input_overwrite(path, inputs)
        if Path(path).is_dir():
            raise InputError(f"{option} names a folder, not a file", path)
        check_writable(path)


def save_figure(figure: Any, path: str | Path, dpi: int) -> None:
    """Write a matplotlib figure atomically, in the format of :func:`figure_format`."""
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format=figure_format(path), dpi=dpi)
