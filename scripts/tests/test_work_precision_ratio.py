"""scripts/work_precision_ratio.py: the work-precision front and the CPU time at equal error,
on hand-made points whose answers follow from the module doc's rule."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

import work_precision_ratio as wpr


def test_front_keeps_the_points_more_accurate_than_every_cheaper_one() -> None:
    cpu = np.array([0.3, 0.1, 0.2, 0.4])
    err = np.array([0.5, 10.0, 20.0, 0.05])
    c, e = wpr.front(cpu, err)
    # 0.2 s at 20 µm is worse than 0.1 s at 10 µm: not on the front.
    assert c.tolist() == [0.1, 0.3, 0.4]
    assert e.tolist() == [10.0, 0.5, 0.05]


def test_cpu_at_interpolates_in_log_log() -> None:
    # Between (0.1 s, 10 µm) and (1 s, 0.1 µm) the front is CPU = 0.1 s · (10 µm / E)^(1/2):
    # 1 µm, a decade below 10 µm, costs 0.1 · 10^(1/2) s.
    cpu, err = [0.1, 1.0], [10.0, 0.1]
    value, kind = wpr.cpu_at(cpu, err, 1.0)
    assert kind == "=" and value == pytest.approx(0.1 * math.sqrt(10.0), rel=1e-12)
    # A target at a point gives that point.
    assert wpr.cpu_at(cpu, err, 0.1) == (pytest.approx(1.0), "=")
    # Coarser than every point: the cheapest bounds it; finer than every point: not reached.
    assert wpr.cpu_at(cpu, err, 100.0) == (0.1, "≤")
    value, kind = wpr.cpu_at(cpu, err, 0.01)
    assert kind == "none" and math.isnan(value)
    assert wpr.cpu_at([], [], 1.0)[1] == "none"


def test_table_divides_by_the_reference_integrator_per_physics() -> None:
    rows = [
        # speed, integrator, cpu, error, status
        (16.0, "cvode", 0.1, 10.0, "ok"),
        (16.0, "cvode", 1.0, 0.1, "ok"),
        (16.0, "bdf", 0.05, 10.0, "ok"),
        (16.0, "bdf", 0.5, 0.1, "ok"),
        (16.0, "bdf", 0.01, 0.001, "diverged"),
        (31.0, "cvode", 0.2, 2.0, "ok"),
        (31.0, "bdf", 0.1, 0.5, "ok"),
    ]
    df = pd.DataFrame(rows, columns=["speed.hz", "integrator", "cpu_time_s", "error_max_um",
                                     "status"])
    text = wpr.table(df, ["speed.hz"], [1.0], "cvode")
    lines = {tuple(c.strip() for c in line.strip("|").split("|")[:2]): line
             for line in text.splitlines()[2:]}
    # 16 Hz: bdf's front is cvode's at half the CPU time (the diverged job is left out).
    assert lines[("speed.hz=16", "bdf")].rstrip(" |").endswith("0.5")
    assert "0.1581" in lines[("speed.hz=16", "bdf")]
    # 31 Hz: bdf's only point (0.5 µm) is finer than 1 µm: its CPU time bounds it; cvode's
    # only point is coarser: not reached, so no ratio.
    assert "≤ 0.1" in lines[("speed.hz=31", "bdf")]
    assert "not reached" in lines[("speed.hz=31", "cvode")]
    assert lines[("speed.hz=31", "bdf")].rstrip(" |").endswith("–")
    best = [k for k in lines if k[0] == "speed.hz=16" and k[1].startswith("best")]
    assert best and lines[best[0]].rstrip(" |").endswith("0.5")


def test_bad_arguments_are_usage_errors(tmp_path) -> None:
    assert wpr.main([str(tmp_path / "x.h5"), "--errors", "1,a"]) == 64
    assert wpr.main([str(tmp_path / "x.h5"), "--errors", "-1"]) == 64
    # A file that is not a results file: an input error.
    bad = tmp_path / "not.h5"
    bad.write_text("no")
    assert wpr.main([str(bad)]) == 1
