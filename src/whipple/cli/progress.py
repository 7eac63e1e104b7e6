"""Progress bars of long commands: on standard error, only when it is a terminal.

A bar (tqdm) appears after :data:`DELAY` seconds, so quick runs show none; it is removed when
its block ends, also on an error, so that an error message starts on a line of its own. In a
pipe, a log file or a test nothing is drawn and tqdm is not even imported.
"""

from __future__ import annotations

import sys
from types import TracebackType
from typing import Any

#: Seconds before a bar appears.
DELAY = 1.0


def shown() -> bool:
    """Return True if progress is drawn: standard error is a terminal."""
    isatty = getattr(sys.stderr, "isatty", None)
    return bool(isatty and isatty())


class Progress:
    """A progress bar (a context manager); does nothing unless standard error is a terminal.

    Parameters
    ----------
    total : int or None
        Steps expected (None: unknown, a counter and a rate are shown).
    unit : str
        What a step is (``"set"``, ``"run"``).
    description : str
        Text before the bar.
    enabled : bool
        False: no bar (``--quiet``).
    """

    def __init__(self, total: int | None, unit: str, description: str = "", enabled: bool = True) -> None:
        self.bar: Any = None
        if enabled and shown():
            from tqdm import tqdm  # only on a terminal: 90 ms of start-up otherwise

            self.bar = tqdm(total=total, unit=unit, desc=description or None, leave=False, file=sys.stderr,
                            delay=DELAY, dynamic_ncols=True)

    def update(self, steps: int = 1) -> None:
        """Count `steps` more steps done."""
        if self.bar is not None:
            self.bar.update(steps)

    def finished(self, name: str) -> None:
        """Count one step done, naming it before the bar."""
        if self.bar is not None:
            self.bar.set_postfix_str(name, refresh=False)
            self.bar.update(1)

    def close(self) -> None:
        """Remove the bar (the line it was on is cleared)."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()


#: The words each stage of the library's progress callback shows.
STAGES = {"runs": ("runs measured", "run"), "candidates": ("candidate causes fitted", "cause"),
          "folds": ("held-out speeds diagnosed", "speed")}


class ProgressBars:
    """The library's progress callback, ``progress(stage, done, total)``, drawn as one bar per stage.

    A context manager: on leaving, the bar is removed (also when an error is raised). Draws
    nothing unless standard error is a terminal (:class:`Progress`).
    """

    def __init__(self, enabled: bool = True) -> None:
        self.enabled = enabled
        self._stage: str | None = None
        self._done = 0
        self._bar: Progress | None = None

    def __call__(self, stage: str, done: int, total: int | None) -> None:
        """Show that ``done`` of ``total`` (None: unknown) steps of ``stage`` are done."""
        if stage != self._stage or self._bar is None or done < self._done:
            self.close()
            words, unit = STAGES.get(stage, (stage, "step"))
            self._stage, self._done = stage, 0
            self._bar = Progress(total, unit, words, self.enabled)
        self._bar.update(done - self._done)
        self._done = done

    def close(self) -> None:
        """Remove the current bar, if any."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> ProgressBars:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()
