"""A calibration read from Python (issue 24): :func:`rotorsweep.calibration` on a calibration
of the rigid Jeffcott rotor (studies/scenes/rigid-jeffcott.toml: a rigid cylinder on two
undamped supports of stiffness k, first critical speed f = sqrt(2k/m)/2pi, the closed form of
studies/sensitivity-jeffcott.toml) to a target critical speed of 8 Hz in both directions. The
fitted k must follow the closed form's scaling k = k0 (8 Hz / f(k0))^2 from the start value k0.

The binary is $ROTORSWEEP_BIN (scripts/python-test sets it), as in test_results.py.
"""

from __future__ import annotations

import pytest

import rotorsweep as rs
from test_results import ROOT, binary, run_ok

SCENE = ROOT / "studies" / "scenes" / "rigid-jeffcott.toml"
KEYS = [f"supports[{i}].spring.k{d}_n_per_m" for i in (0, 1) for d in ("x", "y")]


def test_calibration_reads_back_and_follows_the_closed_form(tmp_path) -> None:
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
