"""The figures (``python -m rotorsweep.figures``, the package python/rotorsweep/figures, and its
wrapper scripts/plots.py) on results files of two small studies run by the real binary (found as
in test_results.py), each 0.6 s of simulated time (0.3 s recorded) at three speeds:

* trial masses: the ideal roll without and with 100 g at the centre (axis roll.masses labelled
  "reference" / "100 g", [analysis] baseline "reference") → two speed sweeps with maps, the
  trial-mass table, 6 jobs;
* solvers: the reference roll with bdf and gen-alpha and a [reference] → two speed sweeps, errors
  against the reference, a varying solver.integrator, 6 jobs.

Both run in about a second once built; rendering takes a few seconds. And a
``rotorsweep linear -o --shapes`` file of studies/scenes/jeffcott.toml (101 speeds 0–100 Hz,
about 8 s): its Campbell diagram with log decrements, mode shapes, Bode and polar plots,
critical-speed map and Floquet chart (the Jeffcott's rotating damping makes it unstable above
about 71 Hz, so the chart has a range to shade). The error classes and number text come from the
binary's ``report --format json`` (found as ROTORSWEEP_BIN, as the tests find it) or a
``--tables`` file of it; the package imports no matplotlib until it draws.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import h5py
import matplotlib.image
from matplotlib.collections import QuadMesh
from matplotlib.colors import to_rgb
import numpy as np
import pandas as pd
import pytest

import rotorsweep as rp
from rotorsweep import figures
from rotorsweep.figures import jobs as job_figures, ramps
from rotorsweep.figures._common import significant
from rotorsweep.figures.linear import peak_label
from rotorsweep.figures.tables import NumberTexts, ReportTables
from test_results import ROOT, binary, rotorsweep, run_ok


def study(name: str, scene: str, rest: str) -> str:
    """A study file: ``scene`` (a file of studies/scenes), 0.6 s with 0.3 s recorded, at three
    speeds, then ``rest`` (more axes, [analysis], [reference])."""
    return f"""\
name = "{name}"
scene = "{(ROOT / "studies" / "scenes" / scene).as_posix()}"

[set]
"simulation.t_end_s" = 0.6
"simulation.settle_s" = 0.3

[[axes]]
key = "speed.hz"
values = [10.0, 14.0, 18.0]

{rest}"""


TRIAL_STUDY = study(
    "py-trial-mass",
    "ideal-roll.toml",
    """\
[[axes]]
key = "roll.masses"
values = [[], [{ z_mm = 2250.0, radius_mm = 160.0, angle_deg = 0.0, mass_g = 100.0 }]]
labels = ["reference", "100 g"]

[analysis]
baseline = "reference"
max_freq_hz = 100.0
""",
)
SOLVER_STUDY = study(
    "py-solvers",
    "reference-roll.toml",
    """\
[[axes]]
key = "solver.integrator"
values = ["bdf", "gen-alpha"]

[reference]
"solver.hmax" = 5e-5
"solver.tolerance" = 1e-9

[analysis]
orders = [1.0, 2.0, 3.0, 4.0, 0.92]
max_freq_hz = 100.0
""",
)
SWEEP_PLOTS = [
    "spectral_map-0.png", "harmonics-0.png", "mean-0.png",
    "spectral_map-1.png", "harmonics-1.png", "mean-1.png",
]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def run_study(d: Path, text: str) -> Path:
    (d / "study.toml").write_text(text)
    run_ok("run", "study.toml", "-o", "out.h5", "--threads", "2", cwd=d)
    return d / "out.h5"


@pytest.fixture(scope="module")
def trial_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_study(tmp_path_factory.mktemp("trial"), TRIAL_STUDY)


@pytest.fixture(scope="module")
def solver_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_study(tmp_path_factory.mktemp("solvers"), SOLVER_STUDY)


@pytest.fixture(scope="module")
def linear_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("linear")
    scene = ROOT / "studies" / "scenes" / "jeffcott.toml"
    run_ok("linear", scene, "--shapes", "-o", "lin.h5", cwd=d)
    return d / "lin.h5"


LINEAR_PLOTS = [
    "campbell.png", "mode_shapes.png", "bode.png", "polar.png", "critical_map.png", "floquet.png"
]


def check_png(path: Path) -> np.ndarray:
    """The image of a written PNG [rows × columns × RGBA, 0…1] after checking that it is one."""
    assert path.read_bytes()[:8] == PNG_MAGIC, f"{path} is not a PNG"
    assert 10_000 < path.stat().st_size < 3_000_000, f"{path}: {path.stat().st_size} bytes"
    img = matplotlib.image.imread(path)
    assert img.ndim == 3 and img.shape[2] in (3, 4), f"{path}: shape {img.shape}"
    assert 300 <= img.shape[0] <= 2500 and 400 <= img.shape[1] <= 2500, f"{path}: {img.shape}"
    return img


def check_map(path: Path) -> None:
    """The inside of the first panel of a spectral map is an image, not a blank axes."""
    img = check_png(path)
    h, w = img.shape[:2]
    inside = img[int(0.3 * h) : int(0.8 * h), int(0.12 * w) : int(0.4 * w), :3]
    assert inside.var() > 0, f"{path}: the map is blank"
    colours = np.unique(inside.reshape(-1, 3), axis=0)
    assert len(colours) > 10, f"{path}: only {len(colours)} colours in the map"


def test_trial_mass_study(trial_results: Path, tmp_path: Path) -> None:
    written = figures.render(trial_results, tmp_path / "plots")
    assert [p.name for p in written] == [
        *SWEEP_PLOTS, "trial_mass.png", "timing.png", "campbell.png"
    ]
    assert all(p.parent == tmp_path / "plots" for p in written)
    for p in written:
        check_png(p)
    check_map(written[0])
    check_map(written[3])
    # The trial-mass table the plot draws: both directions of three sensors at three speeds.
    table = rp.analysis_table(trial_results, "trial_mass")
    assert set(table["label"]) == {"100 g"} and len(table) == 3 * 6
    assert np.all(table["vector_change_um"] > 0)


def test_solver_study_from_the_command_line(solver_results: Path, tmp_path: Path) -> None:
    out = tmp_path / "pngs"
    p = subprocess.run(
        [sys.executable, "-m", "rotorsweep.figures", solver_results, "-o", out,
         "--channel", "drive/horizontal"],
        capture_output=True, text=True, timeout=300,
    )
    assert p.returncode == 0, p.stderr
    names = [*SWEEP_PLOTS, "work_precision.png", "timing.png", "stability.png", "campbell.png"]
    assert p.stdout.split() == [str(out / n) for n in names]
    for n in names:
        check_png(out / n)
    check_map(out / "spectral_map-0.png")
    check_map(out / "spectral_map-1.png")
    # The sweeps the maps come from: one per integrator, the speeds ascending.
    sweeps = rp.sweeps(solver_results)
    assert [s["fixed"] for s in sweeps] == ["solver.integrator=bdf", "solver.integrator=gen-alpha"]
    for s in sweeps:
        assert list(s["speed_hz"]) == [10.0, 14.0, 18.0]
        assert s["maps"]["drive/horizontal"].shape == (3, len(s["freq_hz"]))
        assert s["lines"]["drive/horizontal"].shape == (3, len(s["orders"]))


def test_default_folder_is_beside_the_file(trial_results: Path, tmp_path: Path) -> None:
    copy = tmp_path / "trial.h5"
    copy.write_bytes(trial_results.read_bytes())
    assert figures.main([str(copy)]) == 0
    assert (tmp_path / "trial-plots" / "trial_mass.png").is_file()


def test_not_a_results_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = tmp_path / "notes.h5"
    text.write_text("not HDF5\n")
    bare = tmp_path / "bare.h5"
    with h5py.File(bare, "w") as f:
        f["x"] = np.zeros(3)
    for path in (text, bare, tmp_path / "missing.h5"):
        assert figures.main([str(path), "-o", str(tmp_path / "out")]) == 1
        err = capsys.readouterr().err
        assert str(path) in err and "error" in err, err
    assert not (tmp_path / "out").exists()


def test_unknown_channel(solver_results: Path, tmp_path: Path) -> None:
    with pytest.raises(figures.PlotError, match="no channel 'nowhere/vertical'.*centre/vertical"):
        figures.render(solver_results, tmp_path, channel="nowhere/vertical")
    with pytest.raises(figures.PlotError, match="SENSOR/DIR"):
        figures.render(solver_results, tmp_path, channel="centre")


def test_settings_name_labels_and_the_other_keys() -> None:
    """Labels stand for their axis (zipped keys included); other keys are written as key=value."""
    summary = pd.DataFrame(
        {
            "job_id": ["a", "b", "c", "d"],
            "contact.scale": [1.0, 1.0, 1000.0, 1000.0],
            "solver.hmax": [1e-4, 1e-4, 5e-5, 5e-5],
            "speed.hz": [10.0, 12.5, 10.0, 12.5],
            "solver.integrator": ["bdf", "bdf", "bdf", "rk45"],
        }
    )
    labels = pd.DataFrame(
        {"contact.scale": ["nominal", "nominal", "x1000", "x1000"]},
        index=pd.Index(["a", "b", "c", "d"], name="job_id"),
    )
    keys = ["contact.scale", "solver.hmax", "speed.hz", "solver.integrator"]
    # The numbers' text as the report's labels.numbers gives it (1e-4, not 0.0001: issue 12).
    numbers = NumberTexts({1.0: "1", 1000.0: "1000", 1e-4: "1e-4", 5e-5: "5e-5", 10.0: "10",
                           12.5: "12.5"})
    names = figures.settings(summary, labels, keys, numbers)
    assert list(names.index) == ["a", "b", "c", "d"]
    assert names["a"] == "nominal, speed.hz=10, solver.integrator=bdf"
    assert names["d"] == "x1000, speed.hz=12.5, solver.integrator=rk45"
    hmax = figures.settings(summary, labels, ["solver.hmax"], numbers)
    assert list(hmax) == ["solver.hmax=1e-4"] * 2 + ["solver.hmax=5e-5"] * 2
    assert list(figures.settings(summary, labels.iloc[:, :0], [], numbers)) == [""] * 4
    # A number the report gave no text for is an error naming the field, not a text of ours.
    with pytest.raises(figures.PlotError, match=r"no text for the number 0\.3 in labels\.numbers"):
        figures.settings(summary.assign(**{"solver.hmax": 0.3}), labels, ["solver.hmax"], numbers)


def colours(img: np.ndarray) -> int:
    """The number of distinct RGB colours of an image."""
    return len(np.unique(img[..., :3].reshape(-1, 3), axis=0))


def test_linear_file(linear_results: Path, tmp_path: Path) -> None:
    """Every linear figure from a `rotorsweep linear -o` file, and what each one draws."""
    assert figures.main([str(linear_results), "-o", str(tmp_path)]) == 0
    for name in LINEAR_PLOTS:
        # Lines and markers in several colours, not a blank or one-colour canvas.
        assert colours(check_png(tmp_path / name)) > 50, name
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(LINEAR_PLOTS)
    systems = figures.linear_groups(linear_results)
    assert list(systems) == ["jeffcott"]
    jeff = systems["jeffcott"]
    # Campbell: a colour bar of the log decrements beside the panel; the markers of the
    # forward, backward and mixed modes, the 1×…4× lines and the critical speeds.
    fig = figures.campbell([("", jeff)], "jeffcott")
    ax, bar = fig.axes
    assert "log decrement" in bar.get_ylabel()
    labels = ax.get_legend_handles_labels()[1]
    assert labels == ["forward whirl", "backward whirl", "mixed whirl", "critical speeds"]
    lo, hi = bar.get_ylim()
    assert lo < 0 < hi, "the Jeffcott's first forward mode goes unstable: δ < 0 in the scale"
    # Mode shapes: 2 speeds × 4 modes; the first mode at standstill peaks at the disk (350 mm).
    shapes = figures.mode_shapes(jeff, "jeffcott")
    assert len(shapes.axes) == 8
    x, y = shapes.axes[0].lines[0].get_data()
    assert abs(x[np.argmax(np.abs(y))] - 350.0) < 1e-6
    # Bode: amplitude and phase of the disk sensor, both directions; the peak at the first
    # critical speed (within the 1 Hz speed step).
    fig = figures.bode(jeff, "jeffcott")
    amp = fig.axes[0]
    assert amp.get_title() == "disk"
    speed, vertical = amp.lines[0].get_data()
    crit = jeff["critical_speeds_hz"]
    assert abs(speed[np.argmax(vertical)] - crit[0]) <= 1.0, (speed[np.argmax(vertical)], crit)
    # Polar: one polar axes per sensor.
    assert [a.name for a in figures.polar(jeff, "jeffcott").axes] == ["polar"]
    # Critical-speed map: the lowest six criticals, log–log, the actual stiffness marked.
    fig = figures.critical_map(jeff, "jeffcott")
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and len(ax.get_legend_handles_labels()[1]) == 6
    marks = [ln.get_xdata()[0] for ln in ax.lines if ln.get_linestyle() == "--"]
    assert marks == [2e7]
    # Floquet: the unstable range shaded where the file says, and the threshold marked.
    fig = figures.floquet(jeff, "jeffcott")
    ranges = jeff["floquet/unstable_ranges_hz"]
    assert ranges.shape == (1, 2) and 60 < ranges[0, 0] < 80
    spans = fig.axes[0].patches
    assert len(spans) == 1
    x0, x1 = spans[0].get_x(), spans[0].get_x() + spans[0].get_width()
    assert (x0, x1) == pytest.approx(tuple(ranges[0]))
    assert "unstable" in fig.axes[0].get_title()


def test_study_campbell_with_damping(trial_results: Path) -> None:
    """A study stores each linear system's damped modes as `rotorsweep linear -o` does: the
    Campbell diagram has its log-decrement colour bar; the figures that need a `linear -o`
    file's unbalance response, critical map or Floquet data are not drawn. The trial mass
    changes the model: two linear systems, two panels (and one colour bar)."""
    summary = rp.load_summary(trial_results)
    names = pd.Series("", index=summary["job_id"])
    systems = figures.study_systems(trial_results, names)
    assert len(systems) == 2
    fig = figures.campbell(systems, "t")
    assert sum("log decrement" in a.get_ylabel() for a in fig.axes) == 1
    assert figures.linear_figures(figures.linear_groups(trial_results)) == []


def test_linear_file_of_one_speed(tmp_path: Path) -> None:
    """`rotorsweep linear --speed-hz`: nothing to draw over speed, only the mode shapes (one
    row) and the critical-speed map."""
    scene = ROOT / "studies" / "scenes" / "jeffcott.toml"
    run_ok("linear", scene, "--speed-hz", "20", "--shapes", "-o", "one.h5", cwd=tmp_path)
    written = figures.render(tmp_path / "one.h5", tmp_path / "plots")
    assert [p.name for p in written] == ["mode_shapes.png", "critical_map.png"]
    for p in written:
        check_png(p)
    jeff = figures.linear_groups(tmp_path / "one.h5")["jeffcott"]
    assert len(figures.mode_shapes(jeff, "jeffcott").axes) == 4


def test_bode_marks_the_peaks_the_sweep_misses(tmp_path: Path) -> None:
    """Issue 20: on the new roll the default 1 Hz sweep passes between the samples of the first
    critical pair; the Bode figure marks the refined peaks (the file's ``unbalance_peaks``) at
    their speed and amplitude and says that the sweep misses them, the sampled curve drawn with
    a dot per sample."""
    scene = ROOT / "tests" / "fixtures" / "new-roll.toml"
    run_ok("linear", scene, "--no-floquet", "-o", "new.h5", cwd=tmp_path)
    written = figures.render(tmp_path / "new.h5", tmp_path / "plots")
    assert "bode.png" in [p.name for p in written]
    check_png(tmp_path / "plots" / "bode.png")
    roll = figures.linear_groups(tmp_path / "new.h5")["new-roll"]
    peaks = roll["unbalance_peaks"]
    centre = max((p for p in peaks if p["sensor"] == "centre"), key=lambda p: p["major_um"])
    assert centre["coarse"] and 27.2 < centre["speed_hz"] < 27.3, centre
    fig = figures.bode(roll, "new-roll")
    ax = next(a for a in fig.axes if a.get_title() == "centre")
    texts = [t.get_text() for t in ax.texts]
    assert peak_label(centre) in texts, texts
    assert f"peak {centre['major_um']:.4g} µm at {centre['speed_hz']:.2f} Hz (sweep misses it)" \
        in texts
    # The marker sits on the refined peak, above every sample of the sweep.
    marks = [ln for ln in ax.lines if ln.get_marker() == "X" and len(ln.get_xdata())]
    xy = {(float(ln.get_xdata()[0]), float(ln.get_ydata()[0])) for ln in marks}
    assert (centre["speed_hz"], centre["major_um"]) in xy
    sampled = max(float(np.max(ln.get_ydata())) for ln in ax.lines
                  if ln.get_marker() == "." and len(ln.get_ydata()))
    assert sampled < 0.99 * centre["major_um"]
    assert "misses" in fig.get_suptitle()
    # A peak the sweep resolves is marked without the note.
    resolved = dict(centre, coarse=False)
    assert "misses" not in peak_label(resolved)


def report_json(results: Path, *args: str) -> dict:
    """The document of ``rotorsweep report RESULTS --format json [ARGS]``."""
    return json.loads(run_ok("report", results, "--format", "json", *args,
                             cwd=results.parent).stdout)


def test_error_classes_are_the_reports(solver_results: Path, tmp_path: Path) -> None:
    """The stability matrix is coloured by the error_class column of the report's own stability
    table (the Rust error_class, computed once): the figure has no classes of its own. A
    tables file whose classes say otherwise is what the figure shows."""
    doc = report_json(solver_results, "--labels")
    (table,) = [t for t in doc["tables"] if t["name"] == "stability"]
    col = {c: i for i, c in enumerate(table["columns"])}
    expected = {row[col["job_id"]]: row[col["error_class"]] for row in table["rows"]}
    report = ReportTables(solver_results)
    assert report.error_classes().to_dict() == expected
    colours = report.class_colours()
    assert list(colours)[:4] == ["< 1 µm", "1–10 µm", "10–100 µm", "≥ 100 µm"]
    summary = rp.load_summary(solver_results)
    names = pd.Series("", index=summary["job_id"])
    fig = figures.stability(summary, names, "t", report.error_classes(), colours)
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == [c for c in colours if c in set(expected.values())]
    # The classes as a --tables file gives them: every job "≥ 100 µm", every cell that colour.
    for row in table["rows"]:
        row[col["error_class"]] = "≥ 100 µm"
    doctored = tmp_path / "tables.json"
    doctored.write_text(json.dumps(doc))
    report = ReportTables(solver_results, tables=doctored)
    fig = figures.stability(summary, names, "t", report.error_classes(), colours)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()] == ["≥ 100 µm"]
    cells = fig.axes[0].get_images()[0].get_array()
    assert np.allclose(cells, to_rgb(colours["≥ 100 µm"])), cells
    # A tables file without the stability table: an error naming it and what is missing.
    (tmp_path / "none.json").write_text(json.dumps({"study": "x", "tables": []}))
    with pytest.raises(figures.PlotError, match=r"none\.json: no 'stability' table"):
        ReportTables(solver_results, tables=tmp_path / "none.json").error_classes()
    # The tables of another file: a job without a class is an error, not a grey cell.
    del table["rows"][0]
    doctored.write_text(json.dumps(doc))
    with pytest.raises(figures.PlotError, match=r"tables\.json: the stability table has no job"):
        figures.render(solver_results, tmp_path / "other", tables=doctored)
    assert not (tmp_path / "other").exists()
    (tmp_path / "bad.json").write_text("[1, 2]")
    with pytest.raises(figures.PlotError, match=r"bad\.json: not the JSON of `rotorsweep report"):
        ReportTables(solver_results, tables=tmp_path / "bad.json")


@pytest.fixture(scope="module")
def roller_sim(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A simulate -o file of the timing case with its tending rollers driven by their own angle:
    roller ratios 115/125 on the tending side and 1 on the drive side."""
    d = tmp_path_factory.mktemp("rollers")
    scene = ROOT / "studies" / "scenes" / "timing-case.toml"
    run_ok("simulate", scene, "--set", "simulation.t_end_s=0.4", "--set",
           "simulation.settle_s=0.2", "--set", "supports[0].roller_phase=roller-angle",
           "-o", "sim.h5", cwd=d)
    return d / "sim.h5"


def test_the_report_prints_labels(solver_results: Path, roller_sim: Path) -> None:
    """`report --format json --labels` carries the text of the numbers the figures write
    (labels.numbers, labels.roller_ratios) and the error classes' colours
    (labels.error_classes), as rotorsweep.figures.tables describes them: the Rust number_text
    and error_class are the one implementation."""
    doc = report_json(solver_results, "--labels")
    numbers = {v: t for v, t in doc["labels"]["numbers"]}
    # Every job's speed.hz (a varying key here) and the sweeps' orders, as number_text writes
    # them.
    assert {v: numbers.get(v) for v in (10.0, 14.0, 18.0, 1.0, 2.0, 3.0, 4.0, 0.92)} == {
        10.0: "10", 14.0: "14", 18.0: "18", 1.0: "1", 2.0: "2", 3.0: "3", 4.0: "4", 0.92: "0.92"}
    classes = doc["labels"]["error_classes"]
    assert [c for c, _ in classes] == ["< 1 µm", "1–10 µm", "10–100 µm", "≥ 100 µm",
                                       "no reference", "untrusted", "diverged", "budget"]
    assert all(re.fullmatch("#[0-9a-f]{6}", colour) for _, colour in classes), classes
    ratios = {v: t for v, t in report_json(roller_sim, "--labels")["labels"]["roller_ratios"]}
    stored = rp.job_attrs(roller_sim).filter(regex="^roller_ratio:").iloc[0]
    assert {ratios[v] for v in stored} == {"0.92", "1"}, ratios


def test_import_rotorsweep_imports_no_matplotlib() -> None:
    """The readers stay light: neither ``import rotorsweep`` nor ``import rotorsweep.figures``
    (nor its tables module) imports matplotlib; drawing does."""
    code = ("import sys, rotorsweep, rotorsweep.figures, rotorsweep.figures.tables\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib'))\n"
            "rotorsweep.figures.render\n"
            "print('matplotlib' in sys.modules)\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split("\n")[:2] == ["[]", "True"], p.stdout


def test_without_matplotlib_the_command_says_what_to_install(tmp_path: Path) -> None:
    """Where matplotlib is not installed, ``python -m rotorsweep.figures`` exits 1 naming the
    extra that brings it."""
    code = ("import importlib.abc, runpy, sys\n"
            "class NoMatplotlib(importlib.abc.MetaPathFinder):\n"
            "    def find_spec(self, name, path=None, target=None):\n"
            "        if name.split('.')[0] == 'matplotlib':\n"
            "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
            "sys.meta_path.insert(0, NoMatplotlib())\n"
            "sys.argv = ['x', 'whatever.h5']\n"
            "runpy.run_module('rotorsweep.figures', run_name='__main__')\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                       cwd=tmp_path)
    assert p.returncode == 1, (p.stdout, p.stderr)
    assert p.stdout == ""
    assert 'pip install "rotorsweep[figures]"' in p.stderr and "matplotlib" in p.stderr, p.stderr


def test_without_a_binary_tables_file_or_error(solver_results: Path, linear_results: Path,
                                               tmp_path: Path) -> None:
    """With no rotorsweep binary to ask (ROTORSWEEP_BIN unset, none on PATH): a linear -o file
    needs none; a study's figures need the report's tables, from --tables (the same PNGs as
    with the binary) or else an error saying what to install, and nothing written."""
    tree = Path(figures.__file__).parents[3]
    if any((tree / "target" / p / "rotorsweep").exists() for p in ("release", "debug")):
        pytest.skip("the package runs from a source tree with a built binary: always found")
    env = {k: v for k, v in os.environ.items() if k not in ("ROTORSWEEP_BIN", "PYTHONPATH")}
    env["PATH"] = str(tmp_path / "empty")

    def figures_cli(*args: object) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "rotorsweep.figures", *map(str, args)],
                              capture_output=True, text=True, env=env, cwd=tmp_path,
                              timeout=300)

    p = figures_cli(linear_results, "-o", tmp_path / "lin")
    assert p.returncode == 0, p.stderr
    assert [Path(x).name for x in p.stdout.split()] == LINEAR_PLOTS
    p = figures_cli(solver_results, "-o", tmp_path / "none")
    assert p.returncode == 1 and p.stdout == ""
    assert "found no rotorsweep binary" in p.stderr and "cargo install" in p.stderr, p.stderr
    assert "--tables" in p.stderr and "ROTORSWEEP_BIN" in p.stderr, p.stderr
    assert not (tmp_path / "none").exists()
    # The tables as the binary prints them, saved: the same figures as the binary's run.
    (tmp_path / "tables.json").write_text(json.dumps(report_json(solver_results, "--labels")))
    p = figures_cli(solver_results, "-o", tmp_path / "t", "--tables", tmp_path / "tables.json")
    assert p.returncode == 0, p.stderr
    names = [*SWEEP_PLOTS, "work_precision.png", "timing.png", "stability.png", "campbell.png"]
    assert p.stdout.split() == [str(tmp_path / "t" / n) for n in names]
    assert [str(x) for x in figures.render(solver_results, tmp_path / "b")] == [
        str(tmp_path / "b" / n) for n in names]
    for n in names:
        assert (tmp_path / "t" / n).read_bytes() == (tmp_path / "b" / n).read_bytes(), n
    # ROTORSWEEP_BIN naming no file: said so.
    env["ROTORSWEEP_BIN"] = str(tmp_path / "no-such-binary")
    p = figures_cli(solver_results, "-o", tmp_path / "none")
    assert p.returncode == 1 and "no-such-binary: no such file" in p.stderr, p.stderr


def test_the_wrapper_runs_the_checkouts_package(solver_results: Path, tmp_path: Path) -> None:
    """scripts/plots.py (the README's command) is python -m rotorsweep.figures from the
    checkout's python/, even where another rotorsweep comes first on the path (here a broken
    one): the same lines printed, its errors under its own name."""
    decoy = tmp_path / "decoy" / "rotorsweep"
    decoy.mkdir(parents=True)
    (decoy / "__init__.py").write_text("raise ImportError('not the checkout rotorsweep')\n")
    env = dict(os.environ, PYTHONPATH=str(decoy.parent))
    out = tmp_path / "pngs"
    p = subprocess.run([sys.executable, ROOT / "scripts" / "plots.py", solver_results, "-o", out],
                       capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert p.returncode == 0, p.stderr
    names = [*SWEEP_PLOTS, "work_precision.png", "timing.png", "stability.png", "campbell.png"]
    assert p.stdout.split() == [str(out / n) for n in names]
    p = subprocess.run([sys.executable, ROOT / "scripts" / "plots.py", tmp_path / "missing.h5"],
                       capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 1 and p.stdout == ""
    assert p.stderr.startswith("plots.py: error: ") and "missing.h5: no such file" in p.stderr


def test_timing_is_drawn_for_every_study_size() -> None:
    """Above 12 jobs one horizontal bar a job (the figure was skipped there, issue 12)."""
    n = 130
    summary = pd.DataFrame({
        "job_id": [f"j{i}" for i in range(n)],
        "status": ["ok"] * (n - 1) + ["diverged"],
        "cpu_time_s": np.linspace(0.2, 0.6, n),
        "iterations_per_step": np.ones(n),
    })
    names = pd.Series([f"speed.hz={7.2 + 0.2 * i:.1f}" for i in range(n)], index=summary["job_id"])
    fig = figures.timing(summary, names, "t")
    ax = fig.axes[0]
    assert len(ax.patches) == n
    assert [t.get_text() for t in ax.get_yticklabels()][-1] == "speed.hz=33.0"
    assert all(p.get_width() > 0 for p in ax.patches), "horizontal bars, widths the CPU times"


def test_spectral_map_draws_the_scenes_roller_lines(roller_sim: Path, tmp_path: Path) -> None:
    """The rollers' dashed lines come from the jobs' roller_ratio attributes (the scene's
    journal/roller diameters), not a fixed 0.92: a simulate -o file of the timing case with its
    tending rollers driven by their own angle has 115/125 there and 1 on the drive side."""
    sim = roller_sim
    attrs = rp.job_attrs(sim)
    assert figures.roller_ratios(attrs, list(attrs.index)) == [0.92, 1.0]
    # A sweep with orders 1–3 and one roller ratio 0.92: 3 solid order lines, 3 dashed ones
    # per panel; a ratio of 1 adds none.
    freq = np.linspace(0.0, 60.0, 121)
    speed = np.array([10.0, 12.0, 14.0])
    amp = np.abs(np.sin(freq[None, :] / 3.0 + speed[:, None])) + 0.01
    sweep = {"n": 0, "fixed": "", "speed_hz": speed, "job_ids": [], "orders": np.array([1.0, 2.0, 3.0]),
             "lines": {}, "freq_hz": freq, "maps": {"centre/vertical": amp}}
    texts = ReportTables(sim).roller_ratios
    for ratios, dashed in (([0.92, 1.0], 3), ([1.0], 0)):
        fig = figures.spectral_map(sweep, "centre", "t", ratios, texts)
        styles = [ln.get_linestyle() for ln in fig.axes[0].lines]
        assert styles.count("-") == 3 and styles.count("--") == dashed, styles
        # The title names the ratios other than 1 by the report's text.
        title = fig.get_suptitle()
        assert ("rollers' lines 0.92·k·speed" in title) == bool(dashed), title
    # The simulate -o file plots as a study of one job: its timing bar.
    written = figures.render(sim, tmp_path / "plots")
    assert [p.name for p in written] == ["timing.png"]


def test_work_precision_points_are_labelled_per_physics(solver_results: Path) -> None:
    """One panel per physics (here the speed: one reference run each), every point labelled
    with its solver setting (issue 12: the points zig-zagged across physics, unnamed)."""
    summary = rp.load_summary(solver_results)
    labels = rp.job_labels(solver_results)
    reference = rp.job_attrs(solver_results)["reference_id"]
    numbers = ReportTables(solver_results).numbers
    solver = figures.settings(summary, labels, ["solver.integrator"], numbers)
    physics = figures.settings(summary, labels, ["speed.hz"], numbers)
    fig = figures.work_precision(summary, reference, "t", solver, physics)
    panels = [a for a in fig.axes if a.get_visible()]
    assert [a.get_title() for a in panels] == ["speed.hz=10", "speed.hz=14", "speed.hz=18"]
    for a in panels:
        texts = sorted(t.get_text() for t in a.texts)
        assert texts == ["solver.integrator=bdf", "solver.integrator=gen-alpha"], texts


def test_work_precision_stays_one_panel_per_physics_for_any_number(tmp_path: Path) -> None:
    """Above nine physics the figure used to collapse into one panel where no point could be
    told to its physics. Now: one panel per physics, 12 a figure (3 × 4, compact: one legend of
    the integrators below), further figures for more, the same colour per integrator on each;
    every figure within the PNG size the report embeds."""
    n_phys, ints = 20, ["bdf", "gen-alpha", "rk45"]
    rows = []
    for p in range(n_phys):
        for i, integ in enumerate(ints):
            for t, tol in enumerate((1e-6, 1e-8)):
                rows.append({"job_id": f"j{p}-{integ}-{t}", "integrator": integ,
                             "status": "diverged" if (p, i, t) == (3, 2, 1) else "ok",
                             "cpu_time_s": 0.01 * (1 + i) * (1 + t),
                             "error_max_um": 10.0 ** (-t - i) * (1 + p)})
    summary = pd.DataFrame(rows)
    ids = summary["job_id"].to_numpy()
    physics = pd.Series([f"speed.hz={10 + 2 * int(j[1:].split('-')[0])}" for j in ids], index=ids)
    solver = pd.Series([f"tol {j[-1]}" for j in ids], index=ids)
    reference = pd.Series(physics.to_numpy(), index=ids)
    pages = job_figures.work_precision_pages(summary, reference, "t", solver, physics)
    assert len(pages) == 2
    titles = []
    for n, fig in enumerate(pages, 1):
        panels = [a for a in fig.axes if a.get_visible()]
        assert len(panels) == (12 if n == 1 else 8)
        titles += [a.get_title() for a in panels]
        assert f"figure {n} of 2" in fig.get_suptitle()
        # One figure legend naming every integrator in its own colour, the same on each page.
        (legend,) = fig.legends
        colours = {t.get_text().split(" ")[0]: h.get_color()
                   for t, h in zip(legend.get_texts(), legend.legend_handles)}
        assert colours == {"bdf": "C0", "gen-alpha": "C1", "rk45": "C2"}
        path = tmp_path / f"wp-{n}.png"
        fig.savefig(path, dpi=110)
        check_png(path)
    assert titles == [f"speed.hz={10 + 2 * p}" for p in range(n_phys)]
    # The failed job is noted in its panel, in red.
    notes = [t.get_text() for t in pages[0].axes[3].texts if t.get_color() == "tab:red"]
    assert notes == ["rk45: 1 of 2 jobs, 1 failed"], notes


def test_measured_numbers_are_written_as_the_report_writes_them() -> None:
    """Scientific below 1e-3 and from 1e6, as Rust's text::significant (its own test's values):
    the stability matrix's errors, the mode shapes' log decrements."""
    assert significant(1.234e-4, 3) == "1.23e-4"
    assert significant(5e-4, 3) == "5.00e-4"
    assert significant(16.2345, 4) == "16.23"
    assert significant(0.001234, 3) == "0.00123"
    assert significant(2.5e7, 3) == "2.50e7"
    assert significant(float("nan"), 4) == "–"
    assert significant(0.0, 3) == "0"


def test_campbell_is_labelled_and_nothing_is_clipped(solver_results: Path) -> None:
    """The reference roll's first bending pair: labelled with its plane at standstill and its
    whirl at the top speed; every text inside the figure (the 1× label was cut off)."""
    summary = rp.load_summary(solver_results)
    names = pd.Series("", index=summary["job_id"])
    fig = figures.campbell(figures.study_systems(solver_results, names), "t")
    fig.canvas.draw()
    texts = [t for ax in fig.axes for t in ax.texts]
    words = " ".join(t.get_text() for t in texts)
    assert "vertical, forward" in words and "horizontal, backward" in words, words
    box = fig.bbox
    for t in texts:
        e = t.get_window_extent()
        assert box.x0 <= e.x0 and e.x1 <= box.x1 and box.y0 <= e.y0 and e.y1 <= box.y1, t


def test_html_report_with_figures_in_chromium(solver_results: Path, tmp_path: Path) -> None:
    """`rotorsweep report --format html -o` with this Python drawing the figures: every figure
    embedded as a PNG; rendered by headless Chromium (Debian's, when installed: the Rust test
    tests/it/report_html.rs installs it where it can) into a PNG with figures on it."""
    import base64
    import os
    import shutil

    page = tmp_path / "report.html"
    env = dict(os.environ, ROTORSWEEP_PYTHON=sys.executable)
    bin_ = Path(os.environ.get("ROTORSWEEP_BIN", ROOT / "target" / "release" / "rotorsweep"))
    p = subprocess.run([bin_, "report", solver_results, "--format", "html", "-o", page],
                       capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    html = page.read_text()
    chunks = html.split('src="data:image/png;base64,')[1:]
    names = [*SWEEP_PLOTS, "work_precision.png", "timing.png", "stability.png", "campbell.png"]
    assert len(chunks) == len(names)
    for name, chunk in zip(names, chunks):
        assert base64.b64decode(chunk[: chunk.index('"')])[:8] == PNG_MAGIC
        assert f'alt="{name}"' in html
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        pytest.skip("no chromium on PATH (apt-get install -y chromium): the page is not rendered")
    shot = tmp_path / "report.png"
    subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    "--window-size=1400,4000", f"--screenshot={shot}", page.as_uri()],
                   capture_output=True, timeout=300)
    img = matplotlib.image.imread(shot)
    inked = (img[..., :3] < 0.92).any(axis=-1).mean()
    assert inked > 0.05, inked
    assert colours(img) > 200, "figures (colour maps) on the page, not text alone"


# A run-up 30 → 60 Hz and a coast-down 60 → 30 Hz of the Jeffcott scene at 15 Hz/s (0.5 s held
# at the start speed, 2 s ramp, 0.5 s held; 2.5 s recorded at 1 kHz), tracked in blocks of 8
# revolutions, with the linear unbalance response at 31 speeds 30–60 Hz for the overlay: about
# half a second for the binary, a few seconds to draw.
RAMP_STUDY = f"""\
name = "py-ramp"
scene = "{(ROOT / "studies" / "scenes" / "jeffcott.toml").as_posix()}"

[set]
"speed.profile" = "ramp"
"speed.ramp_start_s" = 0.5
"simulation.settle_s" = 0.5
"simulation.sample_rate_hz" = 1000.0
"speed.rate_hz_per_s" = 15.0
"simulation.t_end_s" = 3.0

[[axes]]
keys = ["speed.from_hz", "speed.to_hz"]
values = [[30.0, 60.0], [60.0, 30.0]]
labels = ["run-up", "coast-down"]

[analysis]
orders = [1.0, 2.0]
order_revolutions = 8.0

[linear]
speeds = "30:60:31"
unbalance_response = true
"""


def test_ramp_study_waterfall_order_map_and_bode(tmp_path: Path) -> None:
    results = run_study(tmp_path, RAMP_STUDY)
    jobs = figures.ramp_jobs(results)
    assert len(jobs) == 2
    written = figures.render(results, tmp_path / "plots")
    names = [p.name for p in written]
    # Each ramp's files are named by its axis label (its job id is a hash nobody can place).
    labels = rp.job_labels(results)
    label = {j: labels.loc[j].dropna().iloc[0] for j in jobs}
    assert sorted(label.values()) == ["coast-down", "run-up"]
    for job in jobs:
        for what in ("waterfall", "order_map", "order_bode"):
            assert f"{what}-{label[job]}.png" in names, names
    for p in written:
        check_png(p)
    # The waterfall is an image, not a blank axes (the Jeffcott's only sensor, "disk", chosen
    # without --channel since the scene has no "centre").
    check_map(tmp_path / "plots" / f"waterfall-{label[jobs[0]]}.png")

    orders = rp.analysis_table(results, "orders")
    attrs = rp.job_attrs(results)
    linear = figures.linear_groups(results)[attrs.at[jobs[0], "linear_id"]]
    fig = figures.order_bode(orders, jobs[0], linear, "py-ramp", "run-up")
    assert fig is not None
    amp_ax, phase_ax = fig.axes[0], fig.axes[1]
    lines = {ln.get_label(): ln for ln in amp_ax.get_lines()}
    # Tracked and steady-state curves in both directions, each legend saying what the curve
    # holds (the run's 1× has every 1× source, journal roundness too; the linear steady state
    # the unbalance alone), and the critical speeds.
    tracked, steady = "tracked 1×, all sources", "steady state, unbalance only"
    assert tracked in ramps.TRACKED and "journal roundness" in ramps.TRACKED
    assert steady in ramps.STEADY_STATE
    lines = {k.replace(ramps.TRACKED, "tracked").replace(ramps.STEADY_STATE, "steady"): v
             for k, v in lines.items()}
    assert {"vertical, tracked", "horizontal, tracked", "vertical, steady",
            "horizontal, steady", "critical speeds"} <= set(lines)
    # The tracked curve is the table's 1× rows of that job and channel, in block order.
    rows = orders[(orders["job_id"] == jobs[0]) & (orders["order"] == 1.0)
                  & (orders["sensor"] == "disk") & (orders["direction"] == "vertical")]
    rows = rows.sort_values("block")
    np.testing.assert_array_equal(lines["vertical, tracked"].get_xdata(), rows["speed_hz"])
    np.testing.assert_array_equal(lines["vertical, tracked"].get_ydata(), rows["amplitude_um"])
    # The steady state is the linear response at its speeds.
    np.testing.assert_array_equal(lines["vertical, steady"].get_ydata(),
                                  linear["unbalance_response/disk/vertical/amplitude_um"])
    # Each tracked phase (the solid line of its colour; NaN points only break the line at
    # wraps) is the table's moved by whole turns, to within half a turn of the steady state's.
    colour = lines["vertical, tracked"].get_color()
    (lin_phase,) = [ln for ln in phase_ax.get_lines()
                    if ln.get_color() == colour and ln.get_linestyle() == "--"]
    (tracked_phase,) = [ln for ln in phase_ax.get_lines()
                        if ln.get_color() == colour and ln.get_linestyle() == "-"]
    x, y = np.asarray(tracked_phase.get_xdata()), np.asarray(tracked_phase.get_ydata())
    ok = np.isfinite(y)
    turns = (y[ok] - rows["phase_deg"].to_numpy()) / 360.0
    np.testing.assert_allclose(turns, np.round(turns), atol=1e-9)
    ref = np.interp(x[ok], lin_phase.get_xdata(), lin_phase.get_ydata())
    assert np.all(np.abs(y[ok] - ref) <= 180.0 + 1e-9)

    # Without a linear system no overlay is drawn.
    bare = figures.order_bode(orders, jobs[0], None, "py-ramp", "run-up")
    assert bare is not None
    assert not [ln for ln in bare.axes[0].get_lines() if "steady" in str(ln.get_label())]
    # Its tracked phase: the table's moved by whole turns, every block within the window from
    # 90° above to 270° below the phase at the lowest speed (not unwrapped along the blocks,
    # where the free vibration's beat past the critical adds a turn per beat).
    (bare_phase,) = [ln for ln in bare.axes[1].get_lines() if ln.get_color() == colour]
    y = np.asarray(bare_phase.get_ydata())
    y = y[np.isfinite(y)]
    turns = (y - rows["phase_deg"].to_numpy()) / 360.0
    np.testing.assert_allclose(turns, np.round(turns), atol=1e-9)
    first = y[np.argmin(rows["speed_hz"].to_numpy())]
    assert -180.0 < first <= 180.0
    assert np.all((y <= first + 90.0 + 1e-9) & (y > first - 270.0 - 1e-9))
    # A channel asked for by name must exist: the ramps' channels are listed.
    with pytest.raises(figures.PlotError, match="disk/vertical"):
        figures.render(results, tmp_path / "other", "centre/vertical")


def test_balancing_before_and_after(tmp_path: Path) -> None:
    """studies/balancing.toml (8 jobs, about 5 s CPU) and `rotorsweep balance --check --json`:
    balancing.png with one panel per speed (6 and 10 Hz), and bars that are the JSON's
    numbers."""
    study_file = ROOT / "studies" / "balancing.toml"
    run_ok("run", study_file, "-o", "bal.h5", "--threads", "2", cwd=tmp_path)
    out = run_ok("balance", "bal.h5", "--check", "--json", "--study", study_file, cwd=tmp_path)
    (tmp_path / "bal.json").write_text(out.stdout)
    written = figures.render(tmp_path / "bal.h5", tmp_path / "plots", balance=tmp_path / "bal.json")
    assert written[-1].name == "balancing.png"
    check_png(written[-1])

    data = json.loads(out.stdout)
    fig = figures.balancing(data, "balancing", ReportTables(tmp_path / "bal.h5").numbers)
    assert [ax.get_title() for ax in fig.axes] == ["6 Hz", "10 Hz"]
    heights = sorted(p.get_height() for p in fig.axes[0].patches)
    at6 = [r for key in ("predicted", "check") for r in data[key] if r["speed_hz"] == 6.0]
    drawn = sorted([r["before_um"] for r in data["predicted"] if r["speed_hz"] == 6.0]
                   + [r["after_um"] for r in at6])
    np.testing.assert_allclose(heights, drawn)

    # The report's balancing tables: the influence rows are the balance command's corrections;
    # the ideal rows the model's own balancing in the trial planes at their radius, as
    # `rotorsweep modes` prints it for roll.balancing in those planes (angles there in
    # (-180, 180]); their predicted residual is below 5 % of the reference's 1× everywhere (the
    # static, moment and first-mode shares of the model's unbalance cancelled, 6 and 10 Hz far
    # below the first bending mode at 32 Hz).
    rep = json.loads(run_ok("report", "bal.h5", "--table", "balancing", "--format", "json",
                            cwd=tmp_path).stdout)["tables"][0]
    rows = pd.DataFrame(rep["rows"], columns=rep["columns"])
    infl = rows[rows["method"] == "influence"]
    np.testing.assert_allclose(infl["mass_g"], [c["mass_g"] for c in data["corrections"]])
    np.testing.assert_allclose(infl["angle_deg"], [c["angle_deg"] for c in data["corrections"]])
    planes = infl["z_mm"].tolist()
    modes = json.loads(run_ok("modes", ROOT / "studies" / "scenes" / "reference-roll.toml",
                              "--set", f"roll.balancing.planes_mm={planes}",
                              "--set", "roll.balancing.radius_mm=160.0", "--json",
                              cwd=tmp_path).stdout)["balancing_masses"]
    ideal = rows[rows["method"] == "ideal"]
    np.testing.assert_allclose(ideal["mass_g"], [m["mass_g"] for m in modes], rtol=1e-9)
    np.testing.assert_allclose(ideal["angle_deg"], [m["angle_deg"] % 360.0 for m in modes],
                               atol=1e-9)
    res = json.loads(run_ok("report", "bal.h5", "--table", "balancing_residual", "--format",
                            "json", cwd=tmp_path).stdout)["tables"][0]
    res = pd.DataFrame(res["rows"], columns=res["columns"])
    assert len(res) == 12 and (res["ideal_um"] < 0.05 * res["before_um"]).all(), res

    # Not balance output: an error naming the file, nothing drawn.
    (tmp_path / "bad.json").write_text('{"corrections": []}')
    with pytest.raises(figures.PlotError, match="bad.json"):
        figures.render(tmp_path / "bal.h5", tmp_path / "none", balance=tmp_path / "bad.json")
    assert not (tmp_path / "none").exists()


def test_compare_measured_with_simulated(tmp_path: Path) -> None:
    """The shipped synthetic crossing of the Jeffcott critical (studies/measured/
    jeffcott-critical-synthetic.csv, scripts/make-synthetic.py 40 50) against the model's run-up
    it was made from: compare_waterfall.png (measured | simulated on one colour scale) and
    compare_orders.png (the orders tables' amplitudes in block order); about a second of
    binary."""
    csv = ROOT / "studies" / "measured" / "jeffcott-critical-synthetic.csv"
    run_ok("import", csv, "-o", "meas.h5", "--orders", "1,2,3", cwd=tmp_path)
    run_ok("simulate", ROOT / "studies" / "scenes" / "jeffcott.toml",
           "--set", 'speed.profile="ramp"', "--set", "speed.from_hz=40.0",
           "--set", "speed.to_hz=50.0", "--set", "speed.ramp_start_s=10.0",
           "--set", "speed.rate_hz_per_s=2.0", "--set", "simulation.settle_s=10.0",
           "--set", "simulation.t_end_s=15.0", "-o", "sim.h5", cwd=tmp_path)
    meas, sim = tmp_path / "meas.h5", tmp_path / "sim.h5"
    assert figures.main([str(meas), "--compare", str(sim), "-o", str(tmp_path / "p")]) == 0
    written = sorted(p.name for p in (tmp_path / "p").iterdir())
    assert written == ["compare_orders.png", "compare_waterfall.png"]
    for p in (tmp_path / "p").iterdir():
        check_png(p)
    check_map(tmp_path / "p" / "compare_waterfall.png")

    numbers = ReportTables(meas, sim).numbers
    figs = dict(figures.compare_figures(meas, sim, None, numbers))
    wf = figs["compare_waterfall.png"]
    # The four panels (measured and simulated, vertical and horizontal) before the colour bar.
    meshes = [c for a in wf.axes[:4] for c in a.collections if isinstance(c, QuadMesh)]
    assert len(meshes) == 4, meshes
    assert len({(m.norm.vmin, m.norm.vmax) for m in meshes}) == 1, "one colour scale"
    # The measured 1× curve is the measured orders table's 1× rows of disk/vertical in block
    # order; the measured 2× is make-synthetic.py's 3 µm out-of-roundness (median within the
    # import test's 0.35 µm), the simulated one, the model's own, stays below 1 µm.
    orders = rp.analysis_table(meas, "orders")
    rows = orders[(orders["order"] == 1.0) & (orders["sensor"] == "disk")
                  & (orders["direction"] == "vertical")].sort_values("block")
    ax = figs["compare_orders.png"].axes[0]
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and len(ln.get_xdata())]
    dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--" and len(ln.get_xdata())]
    assert len(solid) == len(dashed) == 3
    np.testing.assert_array_equal(solid[0].get_xdata(), rows["speed_hz"])
    np.testing.assert_array_equal(solid[0].get_ydata(), rows["amplitude_um"])
    assert abs(np.nanmedian(solid[1].get_ydata()) - 3.0) < 0.35
    assert np.nanmax(dashed[1].get_ydata()) < 1.0
    # Not one run-up each: an error naming the file.
    (tmp_path / "two").mkdir()
    two = run_study(tmp_path / "two", RAMP_STUDY)
    with pytest.raises(figures.PlotError, match="2 jobs whose speed changes"):
        figures.compare_figures(meas, two, None, numbers)
    with pytest.raises(figures.PlotError, match="no sensor 'centre'"):
        figures.compare_figures(meas, sim, "centre", numbers)
    # The HTML page of the comparison: both tables and both figures.
    env = dict(os.environ, ROTORSWEEP_PYTHON=sys.executable)
    subprocess.run([str(binary()), "report", str(meas), "--compare", str(sim), "--format", "html",
                    "-o", str(tmp_path / "cmp.html")], check=True, env=env, timeout=300)
    page = (tmp_path / "cmp.html").read_text()
    for name in ("compare", "compare_resonances"):
        assert f'<section id="{name}">' in page
    for name in ("compare_waterfall.png", "compare_orders.png"):
        assert f"<code>{name}</code>" in page
    assert page.count("<img") == 2
