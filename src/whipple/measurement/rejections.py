"""Why a push gave no window, in a user's words (the rejected stretches of the window finder).

:func:`whipple.measurement.windows.find_windows` follows the swings after each push; where
none of them is free, or only a single swing back, the stretch is rejected. Its reason says
what was seen after the push and how the stretch ended, e.g. ``a single swing back before the
bicycle comes to rest (held): a push and its return, not an oscillation``.
"""

from __future__ import annotations

#: How a window's end reads in a rejected stretch's reason: (the end's reason up to its time, if
#: any, and the words for it).
_ENDINGS = (
    ("abrupt swing at", "the bicycle is caught (or pushed) at"),
    ("forcing at", "the bicycle is pushed again at"),
    ("caught (growth stops)", "the bicycle is caught at its largest lean"),
    ("collapsed (a catch?)", "the bicycle is caught"),
    ("came to rest", "the bicycle comes to rest (held)"),
    ("stopped at", "the bicycle is stopped (caught) at"),
    ("decayed into the background", "the motion sinks into the background"),
    ("decayed into the noise", "the motion sinks into the noise"),
    ("oscillation stops (slow swing)", "the motion stops swinging back"),
    ("next push at", "the next push at"),
    ("quick swing at", "a hand holds the bicycle from"),
    ("signal saturates", "the signal saturates"),
    ("end of record", "the record ends"),
)


def no_oscillation(free: int, why: str, short: bool) -> str:
    """Why a push gave no window: the free swings seen (`free`) and how the stretch ended.

    `why` is the finder's end reason (``came to rest``, ``abrupt swing at 7.80 s``, ...);
    `short` says the stretch held fewer than 3 samples.
    """
    for start, words in _ENDINGS:
        if why.startswith(start):
            # The words say it was a catch; the end reason's doubt is not repeated.
            ending = (words + why[len(start):]).replace(" (a catch?)", "").replace(" (a hand?)", "")
            break
    else:
        ending = why
    if short:
        return f"fewer than 3 samples before {ending}"
    if free < 1:
        return f"no free swing before {ending}"
    return f"a single swing back before {ending}: a push and its return, not an oscillation"
