"""The values the figures take from the Rust report: each job's error class and the text of every
number a label writes, as ``rotorsweep report FILE --format json`` prints them (the Rust report
computes them, with its ``number_text`` and ``error_class``; Python never computes them again).

In: the report's JSON document, ``{"study": str, "tables": [{"name", "title", "legend",
"columns", "rows"}, …], "labels": {…}}``, from the file of ``--tables TABLES.json`` (what
``rotorsweep report FILE --format json --labels`` prints, saved; the binary's ``report
--format html`` passes its own) or, without it, from running the binary (:func:`find_binary`)
as ``rotorsweep report FILE --format json --labels`` (``… --compare SIMULATED.h5`` for a
comparison). The binary runs once, the first time a figure needs one of these values: a
``rotorsweep linear -o`` file, or a study whose figures write no number of the report, needs
none.

What is read (everything else in the document is left alone):

* ``tables[name == "stability"]``, columns ``job_id`` and ``error_class``: the class of each
  job (``< 1 µm`` … ``≥ 100 µm`` by the decade of its max error, ``no reference``, or its status
  when it did not end ok), by which ``stability.png`` colours its cells;
* ``labels.numbers``, ``[[value, text], …]``: the text of a number exactly as stored in the
  results file (JSON numbers are the shortest round trip of the stored f64, so the lookup is by
  equality): every finite value of a numeric varying key of every job (``key=value`` in the
  job settings of every figure), every job's ``speed.hz`` (the panels of ``balancing.png``), the
  orders of every speed sweep (``/analysis/sweeps/<n>/orders``, the legend of
  ``harmonics.png``) and every tracked order (``/analysis/orders`` ``order``; with
  ``--compare`` of both files: the labels of the waterfalls, order maps and
  ``compare_orders.png``);
* ``labels.roller_ratios``, ``[[value, text], …]``: each finite ``roller_ratio:<node>/<roller>``
  job attribute as stored, its text rounded to 4 decimals (the title of ``spectral_map.png``);
* ``labels.error_classes``, ``[[class, colour], …]``: every error class with its fill colour
  (``#rrggbb``, the HTML report's), from the best to the worst (a cell of several jobs shows the
  worst).

A number or class the figures need and the document lacks is a :class:`PlotError` naming the
document and the field; a non-finite number is written "–" (as the report's markdown writes a
missing value).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path

import pandas as pd

from rotorsweep import PathLike

from ._common import PlotError

#: The binary's environment variable (as for the tests).
BIN_ENV = "ROTORSWEEP_BIN"


def find_binary() -> str:
    """The rotorsweep binary: ``$ROTORSWEEP_BIN``, else ``rotorsweep`` on ``PATH``, else the
    checkout's ``target/release/rotorsweep``, else its ``target/debug/rotorsweep`` (when this
    package runs from a source tree: as the binary's ``report --format html`` runs it, from the
    tree it was built in); :class:`PlotError` saying what to install when there is none."""
    given = os.environ.get(BIN_ENV)
    if given:
        if not Path(given).is_file():
            raise PlotError(f"{BIN_ENV}={given}: no such file")
        return given
    on_path = shutil.which("rotorsweep")
    if on_path:
        return on_path
    tree = Path(__file__).resolve().parents[3]
    built = [tree / "target" / profile / "rotorsweep" for profile in ("release", "debug")]
    for path in built:
        if path.is_file():
            return str(path)
    raise PlotError(
        "the figures need `rotorsweep report FILE --format json` (error classes and number "
        "text) and found no rotorsweep binary: $ROTORSWEEP_BIN is unset, none is on PATH and "
        f"there is no {built[0]} (nor debug). Install the binary (`cargo install --path .` in "
        "rotorsweep's source tree, or `cargo build --release` there), set ROTORSWEEP_BIN to it, "
        "or pass "
        "--tables TABLES.json saved from `rotorsweep report FILE --format json`"
    )


def run_report(results: PathLike, compare: PathLike | None = None) -> tuple[dict, str]:
    """The binary's ``report RESULTS --format json --labels [--compare COMPARE]`` document and a
    name for it in messages."""
    cmd = [find_binary(), "report", str(results), "--format", "json", "--labels"]
    if compare is not None:
        cmd += ["--compare", str(compare)]
    where = "`" + " ".join(cmd) + "`"
    try:
        p = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as e:
        raise PlotError(f"cannot run {where}: {e}") from None
    if p.returncode != 0:
        raise PlotError(f"{where} failed (exit code {p.returncode}): {p.stderr.strip()}")
    return parse(p.stdout, where), where


def parse(text: str, where: str) -> dict:
    """The report document of ``text``; :class:`PlotError` naming ``where`` when it is not
    one."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise PlotError(f"{where}: not the JSON of `rotorsweep report --format json`: "
                        f"{e}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("tables"), list):
        raise PlotError(f"{where}: not the JSON of `rotorsweep report --format json` (no "
                        "'tables' list)")
    labels = doc.get("labels")
    if labels is not None and not isinstance(labels, dict):
        raise PlotError(f"{where}: 'labels' is not an object")
    return doc


def read_tables(path: PathLike) -> tuple[dict, str]:
    """The report document saved in the file ``path`` (``--tables``)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise PlotError(f"{path}: cannot read the report's tables: {e}") from None
    return parse(text, str(path)), str(path)


class NumberTexts(Mapping):
    """The text of each number a figure writes: ``texts[value]``; "–" for a non-finite value, a
    :class:`PlotError` naming ``field`` for a value the report gave no text. ``texts`` is a
    mapping value → text, or a function returning one (called at the first lookup)."""

    def __init__(self, texts: Mapping[float, str] | Callable[[], Mapping[float, str]],
                 field: str = "labels.numbers", where: str = "the report") -> None:
        self._texts = texts
        self.field = field
        self.where = where

    def _loaded(self) -> Mapping[float, str]:
        if callable(self._texts):
            self._texts = self._texts()
        return self._texts

    def __getitem__(self, value: float) -> str:
        x = float(value)
        if not math.isfinite(x):
            return "–"
        try:
            return self._loaded()[x]
        except KeyError:
            raise PlotError(f"{self.where}: no text for the number {x!r} in {self.field}") from None

    def __iter__(self) -> Iterator[float]:
        return iter(self._loaded())

    def __len__(self) -> int:
        return len(self._loaded())


def _labels_of(doc: dict, where: str) -> dict:
    """The document's ``labels`` object; :class:`PlotError` when it has none (the JSON of
    ``report --format json`` without ``--labels``)."""
    labels = doc.get("labels")
    if labels is None:
        raise PlotError(f"{where}: no 'labels' object (save the tables with `rotorsweep report "
                        "RESULTS --format json --labels`)")
    return labels


def _pairs(labels: dict, field: str, where: str) -> dict[float, str]:
    """``labels[field]`` (``[[value, text], …]``) as a dict."""
    rows = labels.get(field)
    if not isinstance(rows, list) or not all(
            isinstance(r, list) and len(r) == 2 and isinstance(r[0], (int, float))
            and isinstance(r[1], str) for r in rows):
        raise PlotError(f"{where}: labels.{field} is not a list of [number, text] pairs")
    return {float(v): t for v, t in rows}


class ReportTables:
    """The report's document for the results file ``results`` (and, with ``compare``, the
    simulated file it is compared with): read from ``tables`` (a path) at once, else from the
    binary at the first use. :attr:`numbers`, :attr:`roller_ratios`, :meth:`error_classes` and
    :meth:`class_colours` give what the figures read (module doc)."""

    def __init__(self, results: PathLike, compare: PathLike | None = None,
                 tables: PathLike | None = None) -> None:
        self._results, self._compare = results, compare
        self._doc: tuple[dict, str] | None = None if tables is None else read_tables(tables)
        self.numbers = NumberTexts(lambda: self._labels("numbers"), "labels.numbers",
                                   self._where())
        self.roller_ratios = NumberTexts(lambda: self._labels("roller_ratios"),
                                         "labels.roller_ratios", self._where())

    def _where(self) -> str:
        return self._doc[1] if self._doc is not None else f"the report of {self._results}"

    def document(self) -> tuple[dict, str]:
        """The document and its name in messages (running the binary the first time)."""
        if self._doc is None:
            self._doc = run_report(self._results, self._compare)
            self.numbers.where = self.roller_ratios.where = self._doc[1]
        return self._doc

    def _labels(self, field: str) -> Mapping[float, str]:
        doc, where = self.document()
        return _pairs(_labels_of(doc, where), field, where)

    def error_classes(self, jobs: list[str] | None = None) -> pd.Series:
        """The error class of each job (index job_id) from the report's ``stability`` table;
        :class:`PlotError` when it lacks one of ``jobs`` (the tables of another file)."""
        doc, where = self.document()
        table = next((t for t in doc["tables"]
                      if isinstance(t, dict) and t.get("name") == "stability"), None)
        columns = table.get("columns", []) if table else []
        if "job_id" not in columns or "error_class" not in columns:
            raise PlotError(f"{where}: no 'stability' table with the columns job_id and "
                            "error_class (the JSON of `rotorsweep report FILE --format json`)")
        i, c = columns.index("job_id"), columns.index("error_class")
        classes = pd.Series({row[i]: row[c] for row in table["rows"]}, name="error_class")
        missing = [j for j in jobs or [] if j not in classes.index]
        if missing:
            raise PlotError(f"{where}: the stability table has no job {missing[0]} (the tables "
                            f"of another results file than {self._results}?)")
        return classes

    def class_colours(self) -> dict[str, str]:
        """Each error class's fill colour, from the best class to the worst."""
        doc, where = self.document()
        rows = _labels_of(doc, where).get("error_classes")
        if not isinstance(rows, list) or not all(
                isinstance(r, list) and len(r) == 2 and all(isinstance(x, str) for x in r)
                for r in rows):
            raise PlotError(f"{where}: labels.error_classes is not a list of [class, colour] "
                            "pairs")
        return dict(rows)
