"""Progress bars on standard error for long commands, drawn only on a terminal.

The library reports progress through a callback, ``progress(stage, done, total)``
(:data:`whipple.measurement.measure.Progress`); :class:`ProgressBars` draws one bar per stage
with tqdm and removes it when the stage changes or the command ends, so that nothing is left on
the line an error message or the results are printed on.
"""

from __future__ import annotations

import sys
from types import TracebackType
from typing import Any

from tqdm import tqdm

#: The words each stage's bar shows.
STAGES = {"runs": "runs measured", "candidates": "candidate causes fitted", "folds": "held-out speeds"}


class ProgressBars:
    """A progress callback drawing tqdm bars on standard error, when it is a terminal.

    Use it as a context manager: on leaving, every bar is removed (also when an error is raised).
    """

    def __init__(self, enabled: bool | None = None) -> None:
        self.enabled = sys.stderr.isatty() if enabled is None else enabled
        self._stage: str | None = None
        self._bar: Any = None

    def __call__(self, stage: str, done: int, total: int | None) -> None:
        """Show that ``done`` of ``total`` (None: unknown) steps of ``stage`` are done."""
        if not self.enabled:
            return
        if stage != self._stage or self._bar is None or done < self._bar.n:
            self.close()
            self._stage = stage
            self._bar = tqdm(total=total, desc=STAGES.get(stage, stage), file=sys.stderr, leave=False,
                             dynamic_ncols=True)
        if total is not None and self._bar.total != total:
            self._bar.total = total
        self._bar.update(done - self._bar.n)

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
