"""A time column of dates and times, as phone apps and data loggers write it.

Many loggers stamp each sample with its date and time (``2026-12-07 10:00:00.010``, ISO 8601),
or its time of day alone (``10:00:00.010``), instead of seconds. Such a column is read as seconds
since the file's first stamp, so that the run's time starts at 0 as a column of seconds would.
"""

from __future__ import annotations

from datetime import date, datetime, time

import numpy as np
from numpy.typing import NDArray


def seconds_since(cells: list[str], origin: datetime | None
                  ) -> tuple[NDArray[np.float64], NDArray[np.bool_], datetime] | None:
    """Return date-and-time cells as seconds since `origin`, where they are not, and the origin.

    Parameters
    ----------
    cells : list of str
        One column's cells, in row order. Empty cells are gaps (NaN).
    origin : datetime or None
        The stamp that is time 0 (the file's first, from an earlier block of rows); None: this
        block's first stamp.

    Returns
    -------
    (ndarray, ndarray of bool, datetime) or None
        The times [s] (NaN where a cell is empty or not a stamp), where a non-empty cell is not
        an ISO 8601 date and time or time of day (or has a time zone where the origin has none,
        or the other way round), and the origin; None when no cell is a stamp. Times of day
        alone fall on one nominal day: a run across midnight goes back in time there.
    """
    values = np.full(len(cells), np.nan)
    unread = np.zeros(len(cells), dtype=bool)
    for i, cell in enumerate(cells):
        cell = cell.strip()
        if not cell:
            continue
        try:
            stamp = _stamp(cell)
            values[i] = (stamp - (origin or stamp)).total_seconds()
            origin = origin or stamp
        except (ValueError, TypeError):
            unread[i] = True
    if origin is None:
        return None
    return values, unread, origin


def _stamp(cell: str) -> datetime:
    """Return an ISO 8601 date and time, or a time of day alone (on one nominal day), as a datetime."""
    try:
        return datetime.fromisoformat(cell)
    except ValueError:
        return datetime.combine(date(2000, 1, 1), time.fromisoformat(cell))
