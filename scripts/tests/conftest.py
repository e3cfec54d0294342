"""Puts scripts/ on sys.path so the tests import rotorsweep_py without installing it."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
