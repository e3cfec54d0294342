"""The HDF5 results as a Python user sees them: the real binary on a tiny study, read back with
h5py, pandas and the package rotorsweep (python/).

The binary is $ROTORSWEEP_BIN, else target/release/rotorsweep in the repository (scripts/python-test
builds it). The tiny study is the reference roll for 0.2 s at two speeds × two hmax (4 jobs, two
reference runs); it runs in well under a second.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest

import rotorsweep as rp

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "studies" / "scenes" / "reference-roll.toml"
SPEEDS = [12.0, 16.0]
HMAX = [1e-4, 5e-4]
VARYING = ["speed.hz", "solver.hmax"]
# Units of each dataset family under a run's group, by first path component.
UNITS = {"time": "s", "runout": "um", "journal": "um", "stand": "um", "contact": "N"}

STUDY = f"""\
name = "py-tiny"
description = "scripts/tests: 2 speeds x 2 hmax, 0.2 s"
scene = "{SCENE.as_posix()}"

[set]
"simulation.t_end_s" = 0.2
"simulation.settle_s" = 0.1

[[axes]]
key = "speed.hz"
values = [{", ".join(map(str, SPEEDS))}]

[[axes]]
key = "solver.hmax"
values = [{", ".join(map(repr, HMAX))}]

[reference]
"solver.hmax" = 5e-5
"solver.tolerance" = 1e-9
"""


def binary() -> Path:
    b = Path(os.environ.get("ROTORSWEEP_BIN", ROOT / "target" / "release" / "rotorsweep"))
    if not b.is_absolute():
        b = ROOT / b
    if not b.is_file():
        pytest.fail(f"no rotorsweep binary at {b}: build it (cargo build --release) or set ROTORSWEEP_BIN")
    return b


def rotorsweep(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(binary()), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600
    )


def run_ok(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    p = rotorsweep(*args, cwd=cwd)
    assert p.returncode == 0, f"rotorsweep {' '.join(map(str, args))} failed:\n{p.stderr}"
    return p


@pytest.fixture(scope="module")
def study_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("study")
    (d / "tiny.toml").write_text(STUDY)
    return d


@pytest.fixture(scope="module")
def results(study_dir: Path) -> Path:
    run_ok("run", "tiny.toml", "-o", "tiny.h5", "--threads", "2", cwd=study_dir)
    out = study_dir / "tiny.h5"
    assert out.is_file()
    assert not (study_dir / "tiny.h5.part").exists() and not (study_dir / "tiny.h5.tmp").exists()
    return out


def test_summary_reads_with_plain_h5py_and_pandas(results: Path) -> None:
    with h5py.File(results, "r") as f:
        df = pd.DataFrame(f["summary"][()])
    required = [
        "job_id", "status", "cpu_time_s", "wall_time_s", "steps", "rejected_steps",
        "iterations_per_step", "error_max_um", "error_rms_um", *VARYING,
    ]
    missing = [c for c in required if c not in df.columns]
    assert not missing, f"summary lacks {missing}; has {list(df.columns)}"
    assert len(df) == 4
    # Text columns are variable-length UTF-8, which h5py returns as bytes inside a compound
    # dataset; the README's one-line decode makes them str.
    assert set(df["status"]) == {b"ok"}
    df["status"] = df["status"].str.decode("utf-8")
    assert (df.status == "ok").all()
    # Counts are integers, and every column has its units.
    with h5py.File(results, "r") as f:
        ds = f["summary"]
        assert ds.dtype["steps"].kind == "u" and ds.dtype["job_index"].kind == "u"
        units = {c: ds.attrs[f"units:{c}"] for c in ds.dtype.names}
    assert units["cpu_time_s"] == "s" and units["speed.hz"] == "Hz" and units["error_max_um"] == "um"
    assert units["solver.hmax"] == "s" and units["steps"] == "1" and units["status"] == ""


def test_summary_through_loader(results: Path) -> None:
    df = rp.load_summary(results)
    assert len(df) == 4
    assert list(df["status"]) == ["ok"] * 4, df[["job_id", "status", "cause"]]
    assert all(isinstance(x, str) for x in df["job_id"])
    assert df["job_id"].is_unique
    assert list(df["job_index"]) == [0, 1, 2, 3]
    # The cartesian product of the axes, each combination once.
    combos = sorted(zip(df["speed.hz"], df["solver.hmax"]))
    assert combos == sorted((s, h) for s in SPEEDS for h in HMAX)
    for col in ["error_max_um", "error_rms_um", "cpu_time_s", "wall_time_s", "iterations_per_step"]:
        v = df[col].to_numpy(dtype=float)
        assert np.all(np.isfinite(v)) and np.all(v >= 0), f"{col}: {v}"
    assert np.all(df["error_rms_um"] <= df["error_max_um"])
    assert np.all(df["steps"] > 0) and np.all(df["rejected_steps"] >= 0)
    assert np.allclose(df["t_end_s"].to_numpy(dtype=float), 0.2)
    # The coarser step is the less accurate one at each speed.
    for s in SPEEDS:
        at = df[df["speed.hz"] == s].set_index("solver.hmax")
        assert at.loc[5e-4, "error_max_um"] > at.loc[1e-4, "error_max_um"]
    by_id = rp.load_summary(results, index=True)
    assert by_id.index.name == "job_id" and list(by_id.index) == list(df["job_id"])


def test_file_attributes(results: Path, study_dir: Path) -> None:
    a = rp.file_attrs(results)
    for key in [
        "tool", "tool_version", "created_utc", "host", "threads", "command", "study_name",
        "study_path", "study_text", "varying_keys", "shard",
    ]:
        assert key in a, f"file attribute {key} missing; has {sorted(a)}"
    assert a["tool"] == "rotorsweep"
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", a["tool_version"])
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ", a["created_utc"])
    assert a["threads"] == 2
    assert a["study_name"] == "py-tiny"
    assert a["study_text"] == (study_dir / "tiny.toml").read_text()
    assert "run" in a["command"] and "tiny.toml" in a["command"]
    assert a["shard"] == "0/1"
    assert rp.varying_keys(results) == VARYING


def test_every_dataset_has_units(results: Path) -> None:
    seen: dict[str, str] = {}
    with h5py.File(results, "r") as f:
        for group in ("jobs", "references"):

            def check(name: str, obj: h5py.HLObject, group: str = group) -> None:
                if not isinstance(obj, h5py.Dataset) or h5py.h5ds.is_scale(obj.id):
                    return  # the axes (time, spectrum/freq_hz) are checked below
                assert "units" in obj.attrs, f"/{group}/{name} has no units attribute"
                units = obj.attrs["units"]
                assert isinstance(units, str), f"/{group}/{name}: units is {type(units)}, not str"
                family = name.split("/")[1]
                if family in UNITS:
                    assert units == UNITS[family], f"/{group}/{name}: units {units!r}"
                seen[family] = units

            f[group].visititems(check)
            for run in f[group].values():
                assert run["time"].attrs["units"] == "s"
    assert seen.get("runout") == "um" and seen.get("spectrum") == "um"


def test_job_groups(results: Path) -> None:
    df = rp.load_summary(results, index=True)
    ids = rp.job_ids(results)
    assert ids == list(df.index)
    refs = set(rp.job_ids(results, "references"))
    assert len(refs) == len(SPEEDS)  # one reference per distinct physics
    mods = rp.models(results)
    assert len(mods) == 1
    for job_id in ids:
        j = rp.load_job(results, job_id)
        a = j["attrs"]
        assert j["group"] == "jobs"
        assert a["status"] == "ok" and a["kind"] == "job"
        assert a["reference_id"] in refs and a["model_id"] in mods
        assert a["speed.hz"] == df.loc[job_id, "speed.hz"]
        assert a["solver.hmax"] == df.loc[job_id, "solver.hmax"]
        assert a["steps"] == df.loc[job_id, "steps"]
        assert math.isclose(a["error_max_um"], df.loc[job_id, "error_max_um"])
        # The overall error is the largest per-channel error.
        per = [v for k, v in a.items() if k.startswith("error_max_um:")]
        assert per and math.isclose(max(per), a["error_max_um"])
        t = j["data"]["time"]
        assert j["units"]["time"] == "s"
        assert t.ndim == 1 and len(t) > 10 and np.all(np.diff(t) > 0)
        assert t[-1] == pytest.approx(0.2)
        runout = [k for k in j["data"] if k.startswith("runout/")]
        assert len(runout) == 6  # three sensors × two directions
        for k in runout:
            assert j["data"][k].shape == t.shape and j["units"][k] == "um"
            assert np.all(np.isfinite(j["data"][k]))
    ref = rp.load_job(results, sorted(refs)[0])
    assert ref["group"] == "references" and ref["attrs"]["kind"] == "reference"


def test_channel_and_models(results: Path) -> None:
    job = rp.job_ids(results)[0]
    assert "runout/centre/vertical" in rp.channels(results, job)
    assert "time" not in rp.channels(results, job)
    x = rp.channel(results, job, "runout/centre/vertical")
    assert x.attrs["units"] == "um" and x.dims == ("time",) and x.time.attrs["units"] == "s"
    with pytest.raises(KeyError, match="no channel"):
        rp.channel(results, job, "runout/nowhere/vertical")
    with pytest.raises(KeyError, match="no job or reference"):
        rp.load_job(results, "j0000000000000000")
    (m,) = rp.models(results).values()
    modes = m["modes"]
    assert m["attrs"]["mass_kg"] > 0
    assert len(modes) > 0 and {"index", "freq_hz", "label", "kind"} <= set(modes.columns)
    assert modes.attrs["units"]["freq_hz"] == "Hz"
    assert all(isinstance(s, str) for s in modes["kind"])
    assert np.all(modes["freq_hz"] >= 0)


def test_plot_a_channel(results: Path, tmp_path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    df = rp.load_summary(results)
    fig, ax = plt.subplots()
    for job in df["job_id"]:
        x = rp.channel(results, job, "runout/centre/vertical")
        ax.plot(x.time, x, label=job)
    ax.set_xlabel(f"t [{x.time.attrs['units']}]")
    ax.set_ylabel(f"runout [{x.attrs['units']}]")
    fig.savefig(tmp_path / "runout.png")
    plt.close(fig)
    assert (tmp_path / "runout.png").stat().st_size > 0


def test_shards_merge_to_the_same_results(results: Path, study_dir: Path) -> None:
    for i in range(2):
        run_ok("run", "tiny.toml", "-o", f"shard-{i}.h5", "--shard", f"{i}/2", "--threads", "1", cwd=study_dir)
        assert rp.file_attrs(study_dir / f"shard-{i}.h5")["shard"] == f"{i}/2"
        assert len(rp.load_summary(study_dir / f"shard-{i}.h5")) == 2
    run_ok("merge", "shard-0.h5", "shard-1.h5", "-o", "merged.h5", cwd=study_dir)
    merged = rp.load_summary(study_dir / "merged.h5")
    whole = rp.load_summary(results)
    assert list(merged["job_id"]) == list(whole["job_id"])
    for col in ["steps", "rejected_steps", "error_max_um", "error_rms_um", *VARYING]:
        assert np.allclose(merged[col].to_numpy(dtype=float), whole[col].to_numpy(dtype=float)), col
    assert rp.varying_keys(study_dir / "merged.h5") == VARYING
    assert set(rp.job_ids(study_dir / "merged.h5", "references")) == set(rp.job_ids(results, "references"))


def test_text_axis_columns(tmp_path: Path) -> None:
    """A text-valued axis (solver.integrator) is a str column under its dotted key."""
    study = STUDY.replace('key = "speed.hz"\nvalues = [12.0, 16.0]', 'key = "speed.hz"\nvalues = [12.0]')
    study = study.replace(
        'key = "solver.hmax"\nvalues = [0.0001, 0.0005]',
        'key = "solver.integrator"\nvalues = ["bdf", "gen-alpha"]',
    )
    assert "gen-alpha" in study and "values = [12.0]" in study
    (tmp_path / "integrators.toml").write_text(study)
    run_ok("run", "integrators.toml", "-o", "out.h5", "--threads", "2", cwd=tmp_path)
    keys = rp.varying_keys(tmp_path / "out.h5")
    assert keys == ["speed.hz", "solver.integrator"]
    df = rp.load_summary(tmp_path / "out.h5")
    assert list(df[keys]["solver.integrator"]) == ["bdf", "gen-alpha"]
    assert list(df["integrator"]) == ["bdf", "gen-alpha"]
    assert list(df["status"]) == ["ok", "ok"]


def test_simulate_file(tmp_path: Path) -> None:
    run_ok(
        "simulate", SCENE, "-o", "run.h5",
        "--set", "simulation.t_end_s=0.2", "--set", "simulation.settle_s=0.1",
        "--set", "outputs.journal_orbits=true", "--set", "outputs.contact_forces=true",
        "--set", "outputs.stand_motion=true",
        cwd=tmp_path,
    )
    path = tmp_path / "run.h5"
    assert rp.job_ids(path) == ["reference-roll"]
    j = rp.load_job(path, "reference-roll")
    assert j["attrs"]["status"] == "ok"
    assert j["attrs"]["simulation.t_end_s"] == 0.2
    t = j["data"]["time"]
    assert j["units"]["time"] == "s" and t[-1] == pytest.approx(0.2)
    families = {k.split("/")[0] for k in j["data"]}
    assert {"time", "runout", "journal", "stand", "contact"} <= families, families
    for k, units in j["units"].items():
        assert units == UNITS[k.split("/")[0]], (k, units)
        assert j["data"][k].shape == t.shape
    a = rp.file_attrs(path)
    assert a["tool"] == "rotorsweep" and "scene_text" in a
    df = rp.load_summary(path)  # no /summary: one row from the attributes
    assert list(df["job_id"]) == ["reference-roll"] and df.loc[0, "status"] == "ok"
    assert rp.models(path) == {}


def test_bad_study_fails_with_its_file_name(tmp_path: Path) -> None:
    (tmp_path / "broken-study.toml").write_text(
        STUDY.replace('"simulation.settle_s" = 0.1', '"simulation.no_such_key" = 0.1')
    )
    p = rotorsweep("run", "broken-study.toml", "-o", "broken.h5", "--threads", "2", cwd=tmp_path)
    assert p.returncode != 0
    assert "broken-study.toml" in p.stderr, p.stderr
    assert "no_such_key" in p.stderr, p.stderr
    assert not (tmp_path / "broken.h5").exists()


def test_existing_output_is_not_overwritten(results: Path, study_dir: Path) -> None:
    before = results.read_bytes()
    p = rotorsweep("run", "tiny.toml", "-o", results.name, "--threads", "2", cwd=study_dir)
    assert p.returncode != 0 and "exists" in p.stderr, p.stderr
    assert results.read_bytes() == before


BANDS_STUDY = f"""\
name = "py-bands"
description = "scripts/tests: a table-valued axis (damping bands) with non-ASCII labels"
scene = "{SCENE.as_posix()}"

[set]
"simulation.t_end_s" = 0.1
"simulation.settle_s" = 0.05

[[axes]]
key = "damping.bands"
labels = ["α", "β", "γ – 100 g ≥ 2 %"]
values = [
  [{{ below_hz = 250.0, ratio = 0.005 }}, {{ below_hz = 1070.0, ratio = 0.01 }}],
  [{{ below_hz = 250.0, ratio = 0.02 }}, {{ below_hz = 1070.0, ratio = 0.01 }}],
  [{{ below_hz = 250.0, ratio = 0.02 }}, {{ below_hz = 1070.0, ratio = 0.05 }}],
]
"""


def test_table_valued_axis_and_unicode_labels_read_back_distinct(tmp_path: Path) -> None:
    """Issue 9: a damping-bands axis (values differing after 32 characters) and non-ASCII labels
    give one distinct value per job, through rotorsweep and through raw h5py."""
    (tmp_path / "bands.toml").write_text(BANDS_STUDY, encoding="utf-8")
    run_ok("run", "bands.toml", "-o", "bands.h5", "--threads", "2", cwd=tmp_path)
    labels = ["α", "β", "γ – 100 g ≥ 2 %"]
    df = rp.load_summary(tmp_path / "bands.h5")
    assert list(df["label"]) == labels
    assert df["damping.bands"].nunique() == 3, list(df["damping.bands"])
    assert all(isinstance(v, str) for v in df["damping.bands"])
    assert "ratio = 0.02" in df.loc[1, "damping.bands"] and "ratio = 0.05" in df.loc[2, "damping.bands"]
    with h5py.File(tmp_path / "bands.h5", "r") as f:
        raw = pd.DataFrame(f["summary"][()])
    for c in ["label", "damping.bands", "status"]:
        raw[c] = raw[c].str.decode("utf-8")  # the documented one-line decode
    assert list(raw["label"]) == labels
    assert raw["damping.bands"].nunique() == 3
    assert list(raw["damping.bands"]) == list(df["damping.bands"])


def test_channel_pairs_a_spectrum_with_its_frequencies(results: Path) -> None:
    """Issue 12: a spectrum came back with the time axis (501 against 66 values, no error)."""
    job = rp.summary(results)["job_id"][0]
    a = rp.channel(results, job, "spectrum/centre/vertical")
    x = rp.channel(results, job, "runout/centre/vertical")
    assert a.dims == ("freq_hz",) and x.dims == ("time",) and a.size != x.size
    assert a.attrs["units"] == "um" and a.freq_hz.attrs["units"] == "Hz"
    f = a.freq_hz.to_numpy()
    assert f[0] == 0.0 and np.all(np.diff(f) > 0)
    with h5py.File(results, "r") as h:
        assert np.array_equal(f, h[f"jobs/{job}/spectrum/freq_hz"][()])
        assert np.array_equal(x.time.to_numpy(), h[f"jobs/{job}/time"][()])
