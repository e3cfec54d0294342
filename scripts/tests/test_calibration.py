"""A calibration read from Python (issue 24): :func:`rotorsweep.calibration` on a calibration
of the rigid Jeffcott rotor (studies/scenes/rigid-jeffcott.toml: a rigid cylinder on two
undamped supports of stiffness k, first critical speed f = sqrt(2k/m)/2pi, the closed form of
studies/sensitivity-jeffcott.toml) to a target critical speed of 8 Hz in both directions. The
fitted k must follow the closed form's scaling k = k0 (8 Hz / f(k0))^2 from the start value k0.

The binary is $ROTORSWEEP_BIN (scripts/python-test sets it), as in test_results.py.

The same file's figures (``python -m rotorsweep.figures CAL.h5``, module
rotorsweep/figures/calibration.py) are written and non-empty; the records and resonance
figures, which this calibration has no rows for, are drawn from rows as a calibration with
``[[records]]`` and ``[[resonances]]`` stores them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotorsweep as rs
from rotorsweep import figures
from rotorsweep.figures.calibration import correlation, record_rows, resonances, residuals
from test_plots import check_png
from test_results import ROOT, binary, run_ok

SCENE = ROOT / "studies" / "scenes" / "rigid-jeffcott.toml"
KEYS = [f"supports[{i}].spring.k{d}_n_per_m" for i in (0, 1) for d in ("x", "y")]


@pytest.fixture(scope="module")
def calibrated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder of the calibration (module doc): cal.h5 and its evaluations."""
    tmp_path = tmp_path_factory.mktemp("calibration")
    (tmp_path / "study.toml").write_text(
        f'name = "rigid"\nscene = "{SCENE.as_posix()}"\n[set]\n'
        '"simulation.t_end_s" = 0.3\n"simulation.settle_s" = 0.1\n'
        '[[axes]]\nkey = "speed.hz"\nvalues = [5.0]\n'
    )
    keys = ", ".join(f'"{k}"' for k in KEYS)
    (tmp_path / "cal.toml").write_text(
        'study = "study.toml"\n[fit]\nstep = 0.001\ntolerance = 1e-10\n'
        f'[[parameters]]\nname = "k"\nkeys = [{keys}]\ninitial = 1.0e5\nlower = 1.0e4\n'
        'upper = 1.0e6\nscale = "log"\n'
        "[[frequencies]]\ncritical = 1\nhz = 8.0\nstd_hz = 0.01\n"
        "[[frequencies]]\ncritical = 2\nhz = 8.0\nstd_hz = 0.01\n"
    )
    run_ok("calibrate", "cal.toml", "-o", "cal.h5", "--threads", "2", cwd=tmp_path)
    return tmp_path


def test_calibration_reads_back_and_follows_the_closed_form(calibrated: Path) -> None:
    tmp_path = calibrated
    c = rs.calibration(tmp_path / "cal.h5")
    p = c["parameters"].set_index("name")
    rows = c["rows"]
    f0 = rows["initial"].iloc[0]
    k_closed = 1.0e5 * (8.0 / f0) ** 2
    assert p.loc["k", "value"] == pytest.approx(k_closed, rel=1e-3)
    assert list(rows["output"]) == ["critical_speed_hz:1", "critical_speed_hz:2"]
    assert rows["model"].to_numpy() == pytest.approx([8.0, 8.0], abs=0.01)
    assert c["correlation"].loc["k", "k"] == pytest.approx(1.0)
    assert c["attrs"]["kind"] == "calibration"
    ev = c["evaluations"]
    assert len(ev) == c["attrs"]["evaluation_count"]
    assert ev["role"].iloc[0] == "start"
    assert ev["value:k"].iloc[0] == pytest.approx(1.0e5)
    with pytest.raises(rs.RotorsweepError):
        rs.calibration(tmp_path / "cal.h5.evaluations" / "batch-000.h5")


def test_calibration_figures_are_written(calibrated: Path, tmp_path: Path) -> None:
    out = tmp_path / "pngs"
    written = figures.render(calibrated / "cal.h5", out)
    # Frequency rows only: no records figure.
    assert [p.name for p in written] == [
        "calibration_rows.png", "calibration_residuals.png", "calibration_cost.png",
        "calibration_parameters.png"]
    for p in written:
        check_png(p)
    # A study file's figures are not a calibration's.
    with pytest.raises(figures.PlotError, match="balancing needs a study results file"):
        figures.render(calibrated / "cal.h5", tmp_path / "x", balance=calibrated / "cal.toml")


def record_table() -> pd.DataFrame:
    """Rows as a ``[[records]]`` calibration stores them (src/calibration/record.rs): the real
    and imaginary part of two channels' 1x at 20 speeds, then one resonance table's speed and
    amplitude rows."""
    rows = []
    for channel in ("disk/vertical", "disk/horizontal"):
        for k, speed in enumerate(np.linspace(40.0, 48.0, 20)):
            a = 100.0 / complex(44.0**2 - speed**2, 4.0 * speed) * 1000.0
            for part, v in (("re", a.real), ("im", a.imag)):
                rows.append(dict(target=f"records[0].block[{k}].{channel}:1x.{part}", line=9,
                                 output=f"order_{part}_um:{channel}:1x@{float(speed)!r}Hz", job=0,
                                 measured=v, std=2.0, weight=1.0, initial=0.9 * v,
                                 model=v + 0.5, residual=0.25))
    rows.append(dict(target="resonances[0].speed_hz", line=3,
                     output="peak_speed_hz:disk/vertical:1x", job=0, measured=44.0, std=0.1,
                     weight=1.0, initial=43.5, model=44.05, residual=0.5))
    rows.append(dict(target="resonances[0].amplitude_um", line=5,
                     output="peak_amplitude_um:disk/vertical:1x", job=0, measured=1500.0,
                     std=30.0, weight=1.0, initial=1300.0, model=1490.0, residual=-1.0 / 3.0))
    return pd.DataFrame(rows)


def test_record_rows_are_drawn_over_speed(tmp_path: Path) -> None:
    rows = record_table()
    fig = record_rows(rows, "records")
    # Two channels: a column each, the real part above the imaginary.
    assert [ax.get_title() for ax in fig.axes if ax.get_visible()] == [
        "disk/vertical 1x: real part", "disk/horizontal 1x: real part",
        "disk/vertical 1x: imaginary part", "disk/horizontal 1x: imaginary part"]
    # The fit's line of the first panel is the stored model, over the parsed speeds.
    line = next(ln for ln in fig.axes[0].get_lines() if ln.get_label() == "model at fit")
    re_rows = rows[rows["output"].str.startswith("order_re_um:disk/vertical")]
    assert line.get_xdata() == pytest.approx(np.linspace(40.0, 48.0, 20))
    assert line.get_ydata() == pytest.approx(re_rows["model"].to_numpy())
    fig.savefig(tmp_path / "records.png", dpi=110)
    check_png(tmp_path / "records.png")
    # The residuals: the stored residual at the fit, grouped by channel and kind.
    fig = residuals(rows, "records")
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert labels == ["record disk/vertical 1x", "record disk/horizontal 1x", "peak_speed_hz",
                      "peak_amplitude_um"]
    # The resonance table's point: measured, start and fit at (speed, amplitude) as stored.
    fig = resonances(rows, "records")
    ax = fig.axes[0]
    points = [(ln.get_marker(), float(ln.get_xdata()[0]), float(ln.get_ydata()[0]))
              for ln in ax.get_lines() if len(ln.get_xdata())]
    assert ("o", 44.0, 1500.0) in points
    assert ("s", 43.5, 1300.0) in points
    assert ("D", 44.05, 1490.0) in points
    assert ax.get_legend_handles_labels()[1][0] == "disk/vertical:1x"


@pytest.fixture(scope="module")
def two_parameters(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A calibration of two parameters, the horizontal and the vertical support stiffness of
    the rigid Jeffcott rotor (k_x, k_y), to its first three critical speeds (8, 9 and 11.7 Hz):
    three rows for two parameters, so standard errors and a correlation exist."""
    tmp_path = tmp_path_factory.mktemp("calibration-two")
    (tmp_path / "study.toml").write_text(
        f'name = "rigid"\nscene = "{SCENE.as_posix()}"\n[set]\n'
        '"simulation.t_end_s" = 0.3\n"simulation.settle_s" = 0.1\n'
        '[[axes]]\nkey = "speed.hz"\nvalues = [5.0]\n'
    )
    text = 'study = "study.toml"\n[fit]\nstep = 0.001\n'
    for name, d, start in (("k_x", "x", 1.0e5), ("k_y", "y", 1.3e5)):
        keys = ", ".join(f'"supports[{i}].spring.k{d}_n_per_m"' for i in (0, 1))
        text += (f'[[parameters]]\nname = "{name}"\nkeys = [{keys}]\ninitial = {start}\n'
                 'lower = 1.0e4\nupper = 1.0e6\nscale = "log"\n')
    for k, hz, std in ((1, 8.0, 0.01), (2, 9.0, 0.01), (3, 11.7, 0.05)):
        text += f"[[frequencies]]\ncritical = {k}\nhz = {hz}\nstd_hz = {std}\n"
    (tmp_path / "cal.toml").write_text(text)
    run_ok("calibrate", "cal.toml", "-o", "cal.h5", "--threads", "2", cwd=tmp_path)
    return tmp_path / "cal.h5"


def test_the_correlation_figure_shows_the_files_matrix(two_parameters: Path,
                                                       tmp_path: Path) -> None:
    written = figures.render(two_parameters, tmp_path / "pngs")
    assert written[-1].name == "calibration_correlation.png"
    check_png(written[-1])
    c = rs.calibration(two_parameters)
    corr = c["correlation"]
    m = corr.to_numpy(float)
    # A correlation matrix: unit diagonal, symmetric, entries in [−1, 1] (fitted, not held).
    assert np.diag(m) == pytest.approx([1.0, 1.0])
    assert m == pytest.approx(m.T)
    assert np.all(np.abs(m) <= 1.0 + 1e-12)
    fig = correlation(corr, "two")
    ax = fig.axes[0]
    assert np.asarray(ax.get_images()[0].get_array()) == pytest.approx(m)
    assert [t.get_text() for t in ax.texts] == [
        f"{v:.2f}".replace("-", "−") for v in m.ravel()]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["k_x", "k_y"]


def test_the_correlation_figure_marks_cells_without_a_value() -> None:
    names = ["E", "modal", "stand", "held"]
    m = np.array([[1.0, -0.25, 0.1, np.nan], [-0.25, 1.0, -0.96, np.nan],
                  [0.1, -0.96, 1.0, np.nan], [np.nan] * 4])
    fig = correlation(pd.DataFrame(m, index=names, columns=names), "four")
    ax = fig.axes[0]
    texts = [t.get_text() for t in ax.texts]
    assert texts[:4] == ["1.00", "−0.25", "0.10", "–"]
    assert texts[5:7] == ["1.00", "−0.96"]
    assert texts[12:] == ["–"] * 4
    image = ax.get_images()[0].get_array()
    assert np.ma.getmaskarray(image)[3].all() and not np.ma.getmaskarray(image)[:3, :3].any()
    # No figure for one parameter, nor when no cell has a value.
    assert correlation(pd.DataFrame([[1.0]], index=["k"], columns=["k"]), "one") is None
    empty = pd.DataFrame(np.full((2, 2), np.nan), index=["a", "b"], columns=["a", "b"])
    assert correlation(empty, "none") is None
