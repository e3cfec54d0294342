"""Transitional: the Python copies of the Rust report's ``number_text`` and ``CLASS_COLOURS`` that
the figures used before the report gave them (:mod:`.tables`). Used only when the report's JSON
has no ``labels`` object, i.e. with a binary from before the Rust side of issue 19 item 4.
Delete this module and the two imports of it in :mod:`.tables` once the binary prints
``labels``: scripts/tests/test_plots.py's ``test_the_report_prints_labels``, an expected failure
until then, then fails while this module is still here, to say so.
"""

from __future__ import annotations

import numpy as np


def number_text(x: float) -> str:
    """The Rust ``number_text``: shortest round-trip digits, scientific below 1e-3 and from
    1e6 (``1e-4``, not ``0.0001``), no trailing ``.0``."""
    if x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e6):
        return np.format_float_scientific(x, unique=True, trim="-", exp_digits=1).replace("+", "")
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


class _Formatted(dict):
    """Formats each number it is asked for with ``how``."""

    def __init__(self, how) -> None:
        super().__init__()
        self._how = how

    def __missing__(self, x: float) -> str:
        return self._how(x)


#: What ``labels.numbers`` and ``labels.roller_ratios`` would give.
TEXTS = {
    "numbers": _Formatted(number_text),
    "roller_ratios": _Formatted(lambda r: number_text(round(r, 4))),
}

#: The Rust report's CLASS_COLOURS: what ``labels.error_classes`` would give.
CLASS_COLOURS = (
    ("< 1 µm", "#a5d6a7"),
    ("1–10 µm", "#fff59d"),
    ("10–100 µm", "#ffcc80"),
    ("≥ 100 µm", "#ef9a9a"),
    ("no reference", "#b3e5fc"),
    ("untrusted", "#80cbc4"),
    ("diverged", "#ce93d8"),
    ("budget", "#bdbdbd"),
)
