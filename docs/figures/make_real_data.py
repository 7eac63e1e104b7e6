"""Regenerate docs/real-data/: the diagnosis of the bundled treadmill runs that the docs show.

Run from anywhere:  python docs/figures/make_real_data.py

The snapshot in docs/real-data/ is written by this script only. The command the README gives
to users writes the same report into out/real-data/ (ignored by git), so that running it never
changes tracked files: the last digits of the fitted numbers depend on the machine's
floating-point libraries (BLAS, SciPy's optimisers), so a run elsewhere differs from the
snapshot in its last digits while agreeing in everything the report concludes. This script
runs the command from the repository root with the docs paths, so that the report records it.
It adds every candidate's held-out gain (``--gain-by-cause pairs``: each cause and each pair of
physical causes refitted per fold, and the gain of choosing among them by prediction), on a
local Dask cluster of 2 processes (about 10 minutes on 2 cores; the results are the serial ones).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
COMMAND = ["diagnose", "--bundled", "--bicycle", "sbw2024", "--json", "docs/real-data/diagnosis.json",
           "--report", "docs/real-data", "--save-model", "docs/real-data/sbw2024-extended.toml",
           "--gain-by-cause", "pairs", "--workers", "2"]

if __name__ == "__main__":
    sys.exit(subprocess.run([sys.executable, "-m", "whipple", *COMMAND], cwd=ROOT).returncode)
