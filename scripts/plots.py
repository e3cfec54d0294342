#!/usr/bin/env python3
"""The figures of a results file: ``python -m rotorsweep.figures`` (python/rotorsweep/figures,
its doc says what they are) from this checkout, without installing it.

    python3 scripts/plots.py OUT.h5 [-o DIR] [--channel SENSOR/DIR] [--balance JSON]
                             [--compare SIMULATED.h5] [--tables TABLES.json]
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

from rotorsweep.figures.__main__ import run  # noqa: E402 (after the checkout's path)

if __name__ == "__main__":
    sys.exit(run(prog="plots.py"))
