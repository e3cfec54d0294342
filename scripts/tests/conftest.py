"""Puts scripts/ on sys.path so the tests import its scripts (work_precision_ratio.py); the
package `rotorsweep` (the results reader and its figures) is the installed one (scripts/python-test
installs python/ into the .venv)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
