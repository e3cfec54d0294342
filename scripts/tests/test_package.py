"""The Python package `rotorsweep` (python/) and the raw netCDF view, on results files the real
binary makes (issue 12):

* the README's five-line session, taken from the README's "Python" section and run as written on
  the shipped smoke study (12 jobs at 4 speeds, about 3 s);
* ``xarray.open_dataset(..., group="jobs/<id>/runout/<sensor>", engine="h5netcdf")`` without the
  package: runout over a ``time`` coordinate in seconds, also after ``merge`` (whose copies of
  the job groups must keep their axes);
* job lookup by id, label and a dict of summary values; ``str`` text columns; integer counts;
  units everywhere;
* a ``simulate -o`` file and a ``linear -o`` file (Campbell data against the JSON the same
  command prints).
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import xarray as xr

import rotorsweep as rs
from test_results import ROOT, SCENE, STUDY, rotorsweep, run_ok

README = ROOT / "README.md"

# xarray notes that it names the dimensions of datasets without a scale ("phony_dims"): /summary
# on the way to a job group (README, "Results file layout"). The arrays opened here all have
# their scales, which the tests check.
pytestmark = pytest.mark.filterwarnings("ignore:The 'phony_dims' kwarg:UserWarning")


def readme_session() -> str:
    """The first ```python block of the README's "## Python" section."""
    text = README.read_text(encoding="utf-8")
    section = text[text.index("\n## Python\n") :]
    section = section[: section.index("\n## ", 1)]
    m = re.search(r"```python\n(.*?)```", section, re.S)
    assert m, "README's Python section has no python block"
    return m.group(1)


@pytest.fixture(scope="module")
def smoke(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("smoke")
    run_ok("run", ROOT / "studies" / "smoke.toml", "-o", "smoke.h5", "--threads", "2", cwd=d)
    return d / "smoke.h5"


def test_readme_session_runs_as_written(smoke: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    code = readme_session()
    lines = [line for line in code.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    assert len(lines) == 5, f"the README session is {len(lines)} lines, not five:\n{code}"
    monkeypatch.chdir(smoke.parent)
    ns: dict[str, object] = {}
    exec(compile(code, "README.md (Python session)", "exec"), ns)
    df, r, s, m = ns["df"], ns["r"], ns["s"], ns["m"]
    # The summary: str text, integer counts, units.
    assert isinstance(df, pd.DataFrame) and len(df) == 12
    assert (df.status == "ok").all() and all(isinstance(x, str) for x in df.job_id)
    assert pd.api.types.is_integer_dtype(df["steps"]) and pd.api.types.is_integer_dtype(df["job_index"])
    assert df.attrs["units"]["cpu_time_s"] == "s" and df.attrs["units"]["speed.hz"] == "Hz"
    assert df.attrs["units"]["status"] == "" and df.attrs["units"]["steps"] == "1"
    # A runout series over time [s]: the smoke study records 0.5 s…1.0 s (settle_s, t_end_s).
    assert isinstance(r, xr.Dataset) and set(r.data_vars) == {"vertical", "horizontal"}
    assert r.vertical.dims == ("sensor", "time") and set(r.sensor.values) == {"centre", "drive", "tending"}
    assert r.time.attrs["units"] == "s" and r.vertical.attrs["units"] == "um"
    assert r.time[0] == pytest.approx(0.5) and r.time[-1] == pytest.approx(1.0)
    # A spectrum over freq_hz [Hz], from 0 Hz in steps of 1/record length (the sample count of
    # the record over its span: n / (n - 1) / 0.5 s).
    n = r.sizes["time"]
    assert s.vertical.dims == ("sensor", "freq_hz") and s.freq_hz.attrs["units"] == "Hz"
    df_hz = np.diff(s.freq_hz.to_numpy())
    assert s.freq_hz[0] == 0.0 and np.allclose(df_hz, (n - 1) / 0.5 / n)
    # The spectral map of the first sweep: 4 speeds (smoke.toml) × frequencies.
    assert m.vertical.dims == ("sensor", "speed_hz", "freq_hz")
    assert list(m.speed_hz.values) == [12.0, 14.0, 16.0, 16.4]
    assert m.speed_hz.attrs["units"] == "Hz" and m.freq_hz.attrs["units"] == "Hz"
    assert set(m.job_id.values) <= set(df.job_id)
    # The map's row at a speed is that job's spectrum (same bins as far as both go).
    job = str(m.job_id.values[1])
    own = rs.spectrum(smoke, job).vertical.sel(sensor="centre")
    k = min(own.sizes["freq_hz"], m.sizes["freq_hz"])
    assert np.allclose(m.vertical.sel(sensor="centre").isel(speed_hz=1)[:k], own[:k])


def test_readme_raw_h5py_decode(smoke: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The README's decode of the summary for users without the package (Results file layout)."""
    text = README.read_text(encoding="utf-8")
    layout = text[text.index("### Results file layout") : text.index("\n## Python\n")]
    (code,) = [b for b in re.findall(r"```python\n(.*?)```", layout, re.S) if '["summary"]' in b]
    monkeypatch.chdir(smoke.parent)
    ns: dict[str, object] = {}
    exec(compile(code, "README.md (raw decode)", "exec"), ns)
    df = ns["df"]
    assert isinstance(df, pd.DataFrame) and len(df) == 12
    assert (df.status == "ok").all() and all(isinstance(x, str) for x in df.job_id)
    assert df["steps"].dtype.kind == "u"  # counts stay integers
    assert list(df.job_id) == list(rs.summary(smoke).job_id)
    # As the README says: attributes are str, a string dataset's items bytes until asstr().
    with h5py.File(smoke, "r") as f:
        ids = f["analysis/sweeps/0/job_ids"]
        assert isinstance(f.attrs["tool"], str) and isinstance(ids[0], bytes)
        assert all(isinstance(i, str) for i in ids.asstr()[()])


def test_open_dataset_without_the_package_gives_time_in_seconds(smoke: Path) -> None:
    job = rs.summary(smoke).job_id[0]
    with h5py.File(smoke, "r") as f:
        t = f[f"jobs/{job}/time"][()]
        v = f[f"jobs/{job}/runout/centre/vertical"][()]
    ds = xr.open_dataset(smoke, group=f"jobs/{job}/runout/centre", engine="h5netcdf")
    assert set(ds.data_vars) == {"vertical", "horizontal"}
    assert ds.vertical.dims == ("time",) and ds.time.attrs["units"] == "s"
    assert np.array_equal(ds.time.values, t) and np.array_equal(ds.vertical.values, v)
    assert ds.vertical.attrs["units"] == "um"
    # The spectrum's group over freq_hz, the sweep's map over speed × frequency.
    sp = xr.open_dataset(smoke, group=f"jobs/{job}/spectrum/centre", engine="h5netcdf")
    assert sp.vertical.dims == ("freq_hz",) and sp.freq_hz.attrs["units"] == "Hz"
    mp = xr.open_dataset(smoke, group="analysis/sweeps/0/map/centre", engine="h5netcdf")
    assert mp.vertical.dims == ("speed_hz", "freq_hz")
    ln = xr.open_dataset(smoke, group="analysis/sweeps/0/lines/centre", engine="h5netcdf")
    assert ln.vertical.dims == ("speed_hz", "orders")


def test_axes_survive_shards_and_merge(smoke: Path) -> None:
    d = smoke.parent
    for i in range(2):
        run_ok("run", ROOT / "studies" / "smoke.toml", "-o", f"s{i}.h5", "--shard", f"{i}/2", cwd=d)
    run_ok("merge", "s0.h5", "s1.h5", "-o", "merged.h5", cwd=d)
    merged = d / "merged.h5"
    for job in rs.summary(merged).job_id:
        ds = xr.open_dataset(merged, group=f"jobs/{job}/runout/drive", engine="h5netcdf")
        assert ds.horizontal.dims == ("time",) and ds.time.attrs["units"] == "s"
        whole = rs.runout(smoke, job)
        assert np.array_equal(ds.time.values, whole.time.values)
    ref = rs.job_ids(merged, "references")[0]
    ds = xr.open_dataset(merged, group=f"references/{ref}/runout/centre", engine="h5netcdf")
    assert ds.vertical.dims == ("time",)
    assert rs.spectral_map(merged, 0).vertical.dims == ("sensor", "speed_hz", "freq_hz")


def without_units(path: Path) -> list[str]:
    """The datasets of ``path`` without a str ``units`` attribute, and the table columns without
    ``units:<column>``."""
    missing: list[str] = []

    def check(name: str, obj: h5py.HLObject) -> None:
        if not isinstance(obj, h5py.Dataset):
            return
        if obj.dtype.names:
            missing.extend(f"{name}:{c}" for c in obj.dtype.names if f"units:{c}" not in obj.attrs)
        elif not isinstance(obj.attrs.get("units"), str):
            missing.append(name)

    with h5py.File(path, "r") as f:
        f.visititems(check)
    return missing


def test_every_dataset_and_table_column_has_units(smoke: Path) -> None:
    assert not without_units(smoke)


def labels_study(speeds: str) -> str:
    """test_results' tiny study (its scene, 0.2 s) at ``speeds`` × a labelled axis of masses."""
    head = STUDY[: STUDY.index("[[axes]]")].replace("py-tiny", "py-labels")
    head = head.replace(STUDY.splitlines()[1], 'description = "scripts/tests: labelled masses"')
    return head + f"""[[axes]]
key = "speed.hz"
values = [{speeds}]

[[axes]]
key = "roll.masses"
values = [[], [{{ z_mm = 2250.0, radius_mm = 160.0, angle_deg = 0.0, mass_g = 100.0 }}]]
labels = ["reference", "100 g"]
"""


def test_job_lookup_by_label_and_by_values(tmp_path: Path) -> None:
    (tmp_path / "one.toml").write_text(labels_study("14.0"))
    run_ok("run", "one.toml", "-o", "one.h5", cwd=tmp_path)
    path = tmp_path / "one.h5"
    df = rs.summary(path, index=True)
    by_label = df.reset_index().set_index("label")["job_id"]
    for label in ["reference", "100 g"]:
        assert rs.job_id(path, label) == by_label[label]
        r = rs.runout(path, label)
        assert r.attrs["job_id"] == by_label[label] and r.attrs["label"] == label
    assert not np.allclose(rs.runout(path, "reference").vertical, rs.runout(path, "100 g").vertical)
    with pytest.raises(KeyError, match="no job or reference with id or label 'heavy'"):
        rs.runout(path, "heavy")
    with pytest.raises(TypeError, match="job must be"):
        rs.runout(path, 3)  # type: ignore[arg-type]

    # At two speeds a label names two jobs: an error naming them; a dict picks one.
    (tmp_path / "two.toml").write_text(labels_study("12.0, 14.0"))
    run_ok("run", "two.toml", "-o", "two.h5", cwd=tmp_path)
    path = tmp_path / "two.h5"
    df = rs.summary(path)
    with pytest.raises(KeyError, match="2 jobs with id or label '100 g'"):
        rs.runout(path, "100 g")
    with pytest.raises(KeyError, match="no job or reference with speed.hz=16.0"):
        rs.runout(path, {"speed.hz": 16.0})
    with pytest.raises(ValueError, match="empty dict"):
        rs.runout(path, {})
    want = df[(df.label == "100 g") & (df["speed.hz"] == 14.0)].job_id
    assert rs.job_id(path, {"label": "100 g", "speed.hz": 14.0}) == want.item()
    with pytest.raises(KeyError, match="no column 'speed'"):
        rs.job_id(path, {"speed": 14.0})


def test_simulate_file(tmp_path: Path) -> None:
    run_ok(
        "simulate", SCENE, "-o", "run.h5",
        "--set", "simulation.t_end_s=0.2", "--set", "simulation.settle_s=0.1",
        "--set", "outputs.journal_orbits=true", "--set", "outputs.contact_forces=true",
        cwd=tmp_path,
    )
    path = tmp_path / "run.h5"
    assert not without_units(path)
    df = rs.summary(path)
    assert list(df.job_id) == ["reference-roll"] and df.status[0] == "ok"
    assert df.attrs["units"]["cpu_time_s"] == "s" and df.attrs["units"]["status"] == ""
    r = rs.runout(path, "reference-roll")
    assert r.time.attrs["units"] == "s" and r.time[-1] == pytest.approx(0.2)
    o = rs.orbits(path, "reference-roll")
    assert set(o.data_vars) == {"x", "y"} and o.x.dims == ("node", "time")
    assert np.array_equal(o.time.values, r.time.values)
    c = rs.contact_forces(path, "reference-roll")
    assert all(v.attrs["units"] == "N" for v in c.data_vars.values())
    node = str(o.node.values[0])
    raw = xr.open_dataset(path, group=f"jobs/reference-roll/journal/{node}", engine="h5netcdf")
    assert raw.x.dims == ("time",) and np.array_equal(raw.x.values, o.x.sel(node=node).values)
    with pytest.raises(ValueError, match="'journal' or 'stand'"):
        rs.orbits(path, "reference-roll", "roll")


def test_linear_file_campbell(tmp_path: Path) -> None:
    jeffcott = ROOT / "studies" / "scenes" / "jeffcott.toml"
    run_ok("linear", jeffcott, "--speeds", "0:100:21", "-o", "lin.h5", cwd=tmp_path)
    printed = json.loads(run_ok("linear", jeffcott, "--speeds", "0:100:21", "--json", cwd=tmp_path).stdout)
    path = tmp_path / "lin.h5"
    assert not without_units(path)
    (system,) = rs.linear_systems(path)
    c = rs.campbell(path)
    assert c.attrs["system"] == system
    assert c.whirl_hz.dims == ("speed_hz", "mode") and c.speed_hz.attrs["units"] == "Hz"
    assert np.allclose(c.speed_hz, printed["speeds_hz"])
    assert np.allclose(c.critical_speed_hz, printed["critical_speeds_hz"])
    assert set(c.critical_whirl.values) <= {"forward", "backward", "mixed"}
    # The JSON's modes per speed include every kind; the file's are the lateral ones, ascending.
    for i in (0, 10, 20):
        lateral = sorted(m["freq_hz"] for m in printed["modes"][i] if m["kind"] == "lateral")
        assert np.allclose(c.whirl_hz[i].values, lateral[: c.sizes["mode"]])
    raw = xr.open_dataset(path, group=f"linear/{system}/campbell", engine="h5netcdf")
    assert raw.whirl_hz.dims == ("speed_hz", "mode") and raw.speed_hz.attrs["units"] == "Hz"
    assert np.array_equal(raw.whirl_hz.values, c.whirl_hz.values)
    assert list(raw["mode"].values) == list(range(c.sizes["mode"]))
    fl = xr.open_dataset(path, group=f"linear/{system}/floquet", engine="h5netcdf")
    assert fl.growth_per_rev.dims == ("speed_hz",)
    assert c.unbalance_amplitude.dims == ("sensor", "direction", "speed_hz")
    assert c.unbalance_amplitude.attrs["units"] == "um"


def test_old_file_without_scales_never_gets_a_wrong_axis(tmp_path: Path) -> None:
    """A file written before the axes were dimension scales: the readers find the axes by layout
    and refuse a spectrum whose frequencies do not match it (the 501-against-66 bug)."""
    path = tmp_path / "old.h5"
    with h5py.File(path, "w") as f:
        f.attrs["tool"] = "rotorsweep"
        g = f.create_group("jobs/j0")
        g.attrs["status"] = "ok"
        g["time"] = np.linspace(0.5, 1.0, 501)
        g["spectrum/freq_hz"] = np.arange(60) * 2.0
        for d in ("vertical", "horizontal"):
            g[f"runout/centre/{d}"] = np.zeros(501)
            g[f"spectrum/centre/{d}"] = np.zeros(66)
    r = rs.runout(path, "j0")
    assert r.sizes["time"] == 501
    with pytest.raises(ValueError, match="has 66 values along dimension 0 but its axis /jobs/j0/spectrum/freq_hz has 60"):
        rs.spectrum(path, "j0")
    with pytest.raises(ValueError, match="66 values"):
        rs.channel(path, "j0", "spectrum/centre/vertical")


def test_bad_paths_and_arguments(smoke: Path, tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        rs.summary(tmp_path / "none.h5")
    (tmp_path / "text.h5").write_text("not HDF5")
    with pytest.raises(OSError):
        rs.summary(tmp_path / "text.h5")
    with pytest.raises(KeyError, match="no sweep 9"):
        rs.spectral_map(smoke, 9)
    with pytest.raises(KeyError, match="no linear system 'x'"):
        rs.campbell(smoke, "x")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning from the package itself
        rs.runout(smoke, rs.summary(smoke).job_id[0])
    p = rotorsweep("run", ROOT / "studies" / "smoke.toml", "-o", smoke, cwd=tmp_path)
    assert p.returncode != 0  # the results file is never replaced without --overwrite
