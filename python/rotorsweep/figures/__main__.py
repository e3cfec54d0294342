"""``python -m rotorsweep.figures``: the command line of :mod:`rotorsweep.figures` (its doc)."""

from __future__ import annotations

import sys

#: What to install when matplotlib is missing.
INSTALL = ('the figures need matplotlib: pip install "rotorsweep[figures]" (from a source tree: '
           'pip install "./python[figures]")')


def run(argv: list[str] | None = None, prog: str = "python -m rotorsweep.figures") -> int:
    """:func:`rotorsweep.figures.main`, or exit code 1 saying what to install when matplotlib is
    missing."""
    try:
        from rotorsweep.figures.run import main
    except ModuleNotFoundError as e:
        if (e.name or "").partition(".")[0] != "matplotlib":
            raise
        print(f"{prog}: error: {INSTALL}", file=sys.stderr)
        return 1
    return main(argv, prog)


if __name__ == "__main__":
    sys.exit(run())
