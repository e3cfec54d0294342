"""Puts scripts/ on sys.path so the tests import plots.py; the results reader `rotorsweep` is the
installed package (scripts/python-test installs python/ into the .venv)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
