"""A machine's nip forces as a Python user reads them: the shipped two-roll nip
(studies/scenes/two-roll-nip.toml) simulated by the real binary, read back with
``rotorsweep.nip_forces`` as xarray.

Checks: the layout ([segments x time] in N, the segment centres ``z_mm`` in mm and ``time`` in s
as coordinates); the total nip force carries the line load (10 kN/m over 4 m, the upper roll's
weight on top); each segment's band width is the thin Winkler layer's, 2a with a = sqrt(2 R d)
and the force per length (4 sqrt(2)/3) k sqrt(R) d^1.5 (the indentation of a cylinder of radius R
into a Winkler foundation of modulus k: Johnson, *Contact Mechanics*, 1985, §5.9); the profile
is symmetric (both rolls and the load are symmetric about the shell's centre; only the reference
roll's measured-like wall map breaks it, slightly).
"""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path

import pytest

import rotorsweep as rp

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "studies" / "scenes" / "two-roll-nip.toml"


def binary() -> Path:
    b = Path(os.environ.get("ROTORSWEEP_BIN", ROOT / "target" / "release" / "rotorsweep"))
    if not b.is_absolute():
        b = ROOT / b
    if not b.is_file():
        pytest.fail(f"no rotorsweep binary at {b}: build it (cargo build --release) or set ROTORSWEEP_BIN")
    return b


def run_study(tmp_path: Path, name: str, key: str, values: list[float]) -> Path:
    """The results of a study of the shipped nip over one axis ``key`` = ``values``."""
    study = tmp_path / "study.toml"
    study.write_text(
        f'name = "{name}"\nscene = "{SCENE.as_posix()}"\n'
        f'[[axes]]\nkey = "{key}"\nvalues = {values!r}\n'
    )
    out = tmp_path / "study.h5"
    p = subprocess.run(
        [str(binary()), "run", str(study), "-o", str(out)], capture_output=True, text=True, timeout=600
    )
    assert p.returncode == 0, p.stderr
    return out


@pytest.fixture(scope="module")
def nip_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("nips") / "nip.h5"
    p = subprocess.run(
        [str(binary()), "simulate", str(SCENE), "-o", str(out)], capture_output=True, text=True, timeout=600
    )
    assert p.returncode == 0, p.stderr
    return out


def test_layout_units_and_axes(nip_file: Path) -> None:
    job = rp.job_ids(nip_file)[0]
    f = rp.nip_forces(nip_file, job, nip="press")
    assert f.dims == ("z_mm", "time")
    assert f.shape[0] == 20
    assert f.attrs["units"] == "N"
    assert f.z_mm.attrs["units"] == "mm" and f.time.attrs["units"] == "s"
    # Segment centres: 250 ... 4250 mm in 200 mm segments.
    assert f.z_mm.values[0] == pytest.approx(350.0) and f.z_mm.values[-1] == pytest.approx(4150.0)
    with pytest.raises(KeyError, match="no nip 'other'"):
        rp.nip_forces(nip_file, job, nip="other")
    # The nip's rolls and their speeds: the reference roll (Ø320 mm shell) at its 5 Hz, the
    # covered roll (160 mm + 15 mm cover, two-roll-nip.toml) at equal surface speed, 5 x 160/175.
    assert (f.attrs["roll_a"], f.attrs["roll_b"]) == ("reference", "covered")
    assert f.attrs["speed_a_hz"] == 5.0
    assert f.attrs["speed_b_hz"] == pytest.approx(5.0 * 160.0 / 175.0, rel=1e-12)


def test_total_force_carries_the_line_load(nip_file: Path) -> None:
    job = rp.job_ids(nip_file)[0]
    total = rp.nip_forces(nip_file, job, nip="press").sum("z_mm")
    line_load = 10e3 * 4.0
    # The upper roll (about 740 kg) and its two 40 kg housings add about 8 kN.
    assert line_load < float(total.mean()) < line_load + 10e3


def test_band_width_is_the_winkler_layers(nip_file: Path) -> None:
    job = rp.job_ids(nip_file)[0]
    f = rp.nip_forces(nip_file, job, nip="press").isel(time=-1)
    w = rp.nip_forces(nip_file, job, nip="press", quantity="width").isel(time=-1)
    assert w.attrs["units"] == "mm"
    e, nu, h = 30e6, 0.45, 0.015
    k = e / ((1 - nu * nu) * h)
    r = 0.160 * 0.175 / (0.160 + 0.175)
    closed = 0
    for force, width in zip(f.values, w.values):
        q = force / 0.2
        if q <= 0.0:
            assert width == 0.0
            continue
        d = (q / (4 * math.sqrt(2) / 3 * k * math.sqrt(r))) ** (2 / 3)
        # The force also holds the cover damping's part (small at steady running).
        assert width == pytest.approx(2e3 * math.sqrt(2 * r * d), rel=1e-4)
        closed += 1
    assert closed >= 4
    # Symmetric about the centre within 1 % of the largest segment force.
    v = f.values
    assert max(abs(v - v[::-1])) < 0.01 * max(v)


def test_a_study_sweeps_the_line_load(tmp_path: Path) -> None:
    out = run_study(tmp_path, "nip-load", "nips[0].line_load_kn_per_m", [5.0, 10.0])
    df = rp.summary(out)
    totals = {
        float(row["nips[0].line_load_kn_per_m"]): float(rp.nip_forces(out, row["job_id"], nip="press").sum("z_mm").mean())
        for _, row in df.iterrows()
    }
    # 5 kN/m more over 4 m: 20 kN more through the nip (the housings' 1e5 N/m vertical springs
    # take a little of it).
    assert totals[10.0] - totals[5.0] == pytest.approx(20e3, rel=0.02)


def test_nip_profile_figure_of_a_simulate_file(nip_file: Path, tmp_path: Path) -> None:
    """One job: the profile is drawn, the map over speed is not (one speed); the machine's
    channels (roll.sensor) need no --channel."""
    from rotorsweep.figures.run import render

    written = [p.name for p in render(nip_file, tmp_path / "plots")]
    assert "nip_profile.png" in written
    assert "nip_orders.png" not in written


def test_nip_orders_draws_the_tables_amplitudes() -> None:
    """The spectral map draws the report's amplitudes of the summed force as they are: a panel per
    setting, a curve per order over speed (invented numbers, two loads x two speeds)."""
    import pandas as pd

    from rotorsweep.figures.nips import nip_orders, nip_profile

    cols = ["job_id", "nip", "segment", "z_mm", "length_mm", "static_n", "line_load_kn_per_m",
            "width_mm", "amplitude_1x_n", "amplitude_2x_n"]
    rows = []
    amps = {"a": (1.0, 20.0), "b": (2.0, 30.0), "c": (3.0, 40.0), "d": (4.0, 50.0)}
    for job, (a1, a2) in amps.items():
        rows.append([job, "press", "total", None, 400.0, 100.0, 0.25, 10.0, a1, a2])
        for s in range(2):
            rows.append([job, "press", s + 1, 100.0 + 200.0 * s, 200.0, 50.0, 0.25, 10.0,
                         a1 / 2, a2 / 2])
    doc = {"tables": [{"name": "nips", "columns": cols, "rows": rows}]}
    speeds = pd.Series({"a": 5.0, "b": 10.0, "c": 5.0, "d": 10.0})
    settings = pd.Series({"a": "5 kN/m", "b": "5 kN/m", "c": "10 kN/m", "d": "10 kN/m"})
    fig = nip_orders(doc, speeds, settings, "test")
    axes = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in axes] == ["nip press, 5 kN/m", "nip press, 10 kN/m"]
    for ax, (lo, hi) in zip(axes, [("a", "b"), ("c", "d")]):
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        assert list(lines["1×"].get_xdata()) == [5.0, 10.0]
        assert list(lines["1×"].get_ydata()) == [amps[lo][0], amps[hi][0]]
        assert list(lines["2×"].get_ydata()) == [amps[lo][1], amps[hi][1]]
    # The profile: amplitudes per length, a1/2 N over 0.2 m of job b (the largest line of the
    # 5 kN/m panel) is 2.5 a1 N/m.
    prof = nip_profile(doc, speeds, settings, "test")
    bottom = prof.axes[2]
    one = next(ln for ln in bottom.get_lines() if ln.get_label() == "1×")
    assert list(one.get_ydata()) == pytest.approx([2.5 * amps["b"][0] / 1e3] * 2)
    assert nip_orders({"tables": []}, speeds, settings, "test") is None


def test_nip_orders_draws_each_rolls_own_orders() -> None:
    """Dashed, the orders of a roll of the nip at its own speed (invented numbers, one load x two
    speeds); roll_a being the first roll (its columns the first roll's), only roll_b's are
    drawn."""
    import pandas as pd

    from rotorsweep.figures.nips import nip_orders

    cols = ["job_id", "nip", "segment", "z_mm", "length_mm", "static_n", "line_load_kn_per_m",
            "width_mm", "amplitude_1x_n", "amplitude_2x_n", "roll_a", "speed_a_hz",
            "amplitude_a_1x_n", "amplitude_a_2x_n", "roll_b", "speed_b_hz", "amplitude_b_1x_n",
            "amplitude_b_2x_n"]
    amps = {"a": (1.0, 20.0, 0.5, 7.0), "b": (2.0, 30.0, 0.25, 9.0)}
    rows = [[job, "press", "total", None, 400.0, 100.0, 0.25, 10.0, a1, a2, "top", 5.0, a1, a2,
             "covered", 4.5, b1, b2] for job, (a1, a2, b1, b2) in amps.items()]
    doc = {"tables": [{"name": "nips", "columns": cols, "rows": rows}]}
    fig = nip_orders(doc, pd.Series({"a": 5.0, "b": 10.0}), pd.Series({"a": "", "b": ""}), "test")
    lines = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    assert set(lines) == {"1×", "2×", "1× of covered", "2× of covered"}
    assert list(lines["2× of covered"].get_ydata()) == [7.0, 9.0]
    assert lines["2× of covered"].get_linestyle() == "--"
    assert list(lines["2×"].get_ydata()) == [20.0, 30.0]


def test_barring_map_figures_of_a_barring_file(tmp_path: Path) -> None:
    """`rotorsweep barring -o` on the shipped barring nip at two speeds: the figures read it as
    a barring file and draw its map and frequencies; the growth they draw is the file's."""
    import h5py

    from rotorsweep.figures._common import file_kind
    from rotorsweep.figures.run import render

    scene = ROOT / "studies" / "scenes" / "two-roll-nip-barring.toml"
    out = tmp_path / "map.h5"
    p = subprocess.run(
        [str(binary()), "barring", str(scene), "--speeds", "9:13:2", "--loads-kn-per-m", "10", "-o", str(out)],
        capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 0, p.stderr
    assert file_kind(out) == "barring"
    with h5py.File(out, "r") as f:
        g = f["barring/press"]
        assert g["growth_per_s"].shape == (1, 2)
        assert list(g["speeds_hz"][()]) == [9.0, 13.0]
        # 9 Hz stable, 13 Hz bars (docs/machines.md): the onset is 13 Hz on this grid.
        assert list(g["stable"][0]) == [1.0, 0.0]
        assert g["onset_speed_hz"][0] == 13.0
    written = [q.name for q in render(out, tmp_path / "plots")]
    assert written == ["barring_map.png", "barring_frequency.png"]


def test_nip_spectrum_of_a_speed_sweep(tmp_path: Path) -> None:
    """A two-speed study of the shipped nip gets the spectrum map over speed; each job's column
    spans 0 to the Nyquist frequency in steps of 1/(record length), and a sine injected into
    the force reads back its amplitude (the Hann window's scaling)."""
    import numpy as np

    from rotorsweep.figures.nips import _nip_spectra
    from rotorsweep.figures.run import render

    out = run_study(tmp_path, "nip-speeds", "speed.hz", [5.0, 6.0])
    jobs = list(rp.summary(out)["job_id"])
    spectra = _nip_spectra(out, jobs)["press"]
    for job in jobs:
        freq, amp = spectra[job]
        t = rp.nip_forces(out, job, nip="press")["time"].to_numpy()
        n, dt = len(t), float(np.median(np.diff(t)))
        assert len(freq) == n // 2 + 1
        assert freq[1] == pytest.approx(1.0 / (n * dt), rel=1e-9)
    # A 7 N sine on a bin of a job's force (the file copied and edited): +7 N at that bin.
    import shutil

    import h5py

    edited = tmp_path / "edited.h5"
    shutil.copy(out, edited)
    job = jobs[0]
    freq, before = spectra[job]
    k = int(np.argmin(np.abs(freq - 300.0)))
    with h5py.File(edited, "r+") as f:
        ds = f[f"jobs/{job}/nips/press/force"]
        t = f[f"jobs/{job}/nips/press/time"][()]
        force = ds[()]
        force[0] += 7.0 * np.sin(2 * np.pi * freq[k] * (t - t[0]))
        ds[...] = force
    _, after = _nip_spectra(edited, [job])["press"][job]
    assert after[k] - before[k] == pytest.approx(7.0, rel=2e-2)
    written = [q.name for q in render(out, tmp_path / "plots")]
    assert "nip_spectrum.png" in written
