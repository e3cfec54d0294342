"""A sampled study read from Python (issue 24): :func:`rotorsweep.statistics` and
:func:`rotorsweep.sensitivity` on studies/sensitivity-jeffcott.toml (n = 32 instead of 256),
against the closed forms its comments derive, and the static sag's mean under a normal density
against the exact value.

The binary is $ROTORSWEEP_BIN (scripts/python-test sets it), as in test_results.py.
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest

import rotorsweep as rs
from test_results import ROOT, binary

STUDY = ROOT / "studies" / "sensitivity-jeffcott.toml"
SCENE = ROOT / "studies" / "scenes" / "rigid-jeffcott.toml"

#: A Saltelli design (n = 16) of the density (normal) and the speed (uniform, moving no static
#: sag) on the rigid Jeffcott rotor at two gravity values: 2 × 16 × 4 jobs.
GRID_STUDY = "\n".join([
    'name = "g"', f'scene = "{SCENE.as_posix()}"', "[linear]", 'speeds = "0:1:2"', "static = true",
    "[[axes]]", 'key = "simulation.gravity_m_s2"', "values = [9.81, 4.905]",
    "[sample]", 'method = "saltelli"', "n = 16", "seed = 3",
    "[[sample.parameters]]", 'key = "materials.steel.density_kg_m3"', 'distribution = "normal"',
    "mean = 7850.0", "std = 392.5",
    "[[sample.parameters]]", 'key = "speed.hz"', 'distribution = "uniform"', "lower = 5.0",
    "upper = 10.0", "",
])


@pytest.fixture(autouse=True)
def _binary_env(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROTORSWEEP_BIN", str(binary()))


@pytest.fixture(scope="module")
def sens(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("sens")
    text = STUDY.read_text().replace("n = 256", "n = 32")
    text = text.replace('scene = "scenes/rigid-jeffcott.toml"', f'scene = "{SCENE.as_posix()}"')
    study = d / "sens.toml"
    study.write_text(text)
    out = d / "sens.h5"
    rs.run(study, output=out, threads=2)
    return out


def test_sensitivity_frame_holds_the_closed_form(sens: Path) -> None:
    si = rs.sensitivity(sens)
    assert list(si.columns) == [
        "output", "parameter", "n", "first_order", "first_order_low", "first_order_high",
        "total", "total_low", "total_high",
    ]
    # Critical speed f ∝ k^(1/2) ρ^(-1/2) with log-stds 0.2 and 0.1: the factors' log-stds are
    # a = 0.1, b = 0.05 and S_k = (e^{a²} − 1)/(e^{a²+b²} − 1) = 0.79900, S_Tρ = 1 − S_k
    # (studies/sensitivity-jeffcott.toml).
    a2, b2 = 0.1**2, 0.05**2
    s_k = math.expm1(a2) / math.expm1(a2 + b2)
    row = si[(si.output == "critical_speed_hz:1") & (si.parameter == "supports[0].spring.kx_n_per_m")].iloc[0]
    assert row.n == 32
    assert row.first_order_low <= s_k <= row.first_order_high
    rho = si[(si.output == "critical_speed_hz:1") & (si.parameter == "materials.steel.density_kg_m3")].iloc[0]
    assert rho.total_low <= 1 - s_k <= rho.total_high
    speed = si[(si.output == "critical_speed_hz:1") & (si.parameter == "speed.hz")].iloc[0]
    assert speed.first_order == 0.0 and speed.total == 0.0


def test_statistics_frame_holds_the_lognormal_mean(sens: Path) -> None:
    st = rs.statistics(sens)
    assert {"output", "n", "mean", "mean_low", "mean_high", "std", "q05", "q95", "min", "max"} <= set(st.columns)
    row = st[st.output == "critical_speed_hz:1"].iloc[0]
    # f = √(2k/m)/2π with m = ρ π (0.1 m)² 0.4 m; at the medians (k = 1e5 N/m, ρ = 7850 kg/m³)
    # 7.1663 Hz, and E[f] = median · e^{(a² + b²)/2} for the lognormal f (a = 0.1, b = 0.05).
    median = math.sqrt(2e5 / (7850 * math.pi * 0.01 * 0.4)) / (2 * math.pi)
    mean = median * math.exp((0.1**2 + 0.05**2) / 2)
    assert row.n == 64  # the rows of A and B
    assert row.mean_low <= mean <= row.mean_high
    assert isinstance(st, pd.DataFrame) and st.attrs["title"]


def test_a_grid_study_has_no_sensitivity_table(tmp_path: Path) -> None:
    study = tmp_path / "grid.toml"
    study.write_text(f'name = "g"\nscene = "{SCENE.as_posix()}"\n[[axes]]\nkey = "speed.hz"\nvalues = [5.0, 6.0]\n')
    out = tmp_path / "grid.h5"
    rs.run(study, output=out)
    with pytest.raises(rs.RotorsweepError):
        rs.sensitivity(out)


def test_samples_frame_holds_every_job_with_its_inputs(sens: Path) -> None:
    # n (d + 2) = 32 × 5 jobs, each with its three sampled values and its outputs; the critical
    # speed √(2k/m)/2π of each job from its own k and ρ (m = ρ π 0.1² 0.4, scenes/rigid-jeffcott).
    sa = rs.samples(sens)
    assert len(sa) == 160
    assert {"job_id", "label", "speed.hz", "critical_speed_hz:1"} <= set(sa.columns)
    m = sa["materials.steel.density_kg_m3"] * math.pi * 0.1**2 * 0.4
    f = (2 * sa["supports[0].spring.kx_n_per_m"] / m) ** 0.5 / (2 * math.pi)
    assert ((sa["critical_speed_hz:1"] / f - 1).abs() < 1e-4).all()
    # Each critical speed's log decrement is an output: the job's linear system's
    # /linear/<linear_id>/critical_log_dec, read with h5py.
    import h5py

    with h5py.File(sens, "r") as h5:
        for _, row in sa.iloc[:20].iterrows():
            lid = h5[f"jobs/{row.job_id}"].attrs["linear_id"]
            lid = lid.decode() if isinstance(lid, bytes) else lid
            stored = h5[f"linear/{lid}/critical_log_dec"][:]
            got = [row[f"critical_log_dec:{k + 1}"] for k in range(len(stored))]
            assert got == pytest.approx(list(stored), abs=0, rel=0, nan_ok=True)


def test_a_sampled_study_gets_its_histograms_scatter_and_sensitivity_figures(
        sens: Path, tmp_path: Path) -> None:
    from rotorsweep.figures import render

    names = [p.name for p in render(sens, tmp_path / "figs")]
    assert {"histograms.png", "scatter.png", "sensitivity.png"} <= set(names)


def test_a_sampled_study_on_a_grid_axis_reads_per_grid_point(tmp_path: Path) -> None:
    # The static sag s = ρ V g/(2k) of the rigid Jeffcott rotor (V = π 0.1² 0.4 m³, k = 1e5 N/m)
    # under ρ ~ N(7850, 392.5²), at g = 9.81 and 4.905 m/s²: a statistics row per output and
    # grid point led by the swept key, the exact mean within each point's interval, and the
    # figures drawn (a sensitivity bar pair per parameter and grid point).
    study = tmp_path / "grid.toml"
    study.write_text(GRID_STUDY)
    out = tmp_path / "grid.h5"
    rs.run(study, output=out, threads=2)
    st = rs.statistics(out)
    assert list(st.columns[:2]) == ["simulation.gravity_m_s2", "output"]
    sag = st[st.output == "sag_vertical_um:centre"]
    assert list(sag["simulation.gravity_m_s2"]) == [9.81, 4.905]
    for _, row in sag.iterrows():
        mean = -7850 * math.pi * 0.01 * 0.4 * row["simulation.gravity_m_s2"] / 2e5 * 1e6
        assert row.n == 32 and row.mean_low <= mean <= row.mean_high
    si = rs.sensitivity(out)
    assert len(si[si.output == "sag_vertical_um:centre"]) == 4
    # The samples frame: every job with its grid point's gravity beside its sampled density,
    # each job's sag the rigid body's closed form at its own ρ and g, to 2e-5 (the cylinder's
    # own bending adds under 2e-5 of the sag: studies/sensitivity-jeffcott.toml).
    sa = rs.samples(out)
    assert list(sa.columns[:4]) == ["job_id", "label", "simulation.gravity_m_s2",
                                    "materials.steel.density_kg_m3"]
    assert len(sa) == 2 * 16 * 4 and sorted(set(sa["simulation.gravity_m_s2"])) == [4.905, 9.81]
    exact = (-sa["materials.steel.density_kg_m3"] * math.pi * 0.01 * 0.4
             * sa["simulation.gravity_m_s2"] / 2e5 * 1e6)
    assert ((sa["sag_vertical_um:centre"] / exact - 1).abs() < 2e-5).all()
    from rotorsweep.figures import render

    names = [p.name for p in render(out, tmp_path / "figs")]
    assert {"histograms.png", "scatter.png", "sensitivity.png"} <= set(names)
