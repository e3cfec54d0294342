"""scripts/h5compare.py: what counts as equal and what as a difference, on small hand-made HDF5
files (no binary needed)."""

from __future__ import annotations

import json

import h5py
import numpy as np
import pytest

import h5compare


def write(path, runout, status="ok", cpu=0.1, order=("a", "b"), timings=None):
    """A results-like file: a job group with attributes, a runout with a time scale attached to
    two datasets in `order`, a compound summary and a JSON attribute."""
    with h5py.File(path, "w") as f:
        f.attrs["created_utc"] = "now"
        job = f.create_group("jobs/j1")
        job.attrs.update(status=status, cpu_time_s=cpu, speed_hz=16.4)
        time = job.create_dataset("time", data=np.arange(3.0))
        time.make_scale("time")
        for name in order:
            job.create_dataset(name, data=np.asarray(runout)).dims[0].attach_scale(time)
        row = np.dtype([("job_id", h5py.string_dtype()), ("cpu_time_s", "f8"), ("steps", "u8")])
        f.create_dataset("summary", data=np.array([("j1", cpu, 10)], dtype=row))
        f["jobs/j1"].attrs["json"] = json.dumps({"speeds_hz": [1.0], "times_s": timings or {}})


def diffs(tmp_path, a, b, **kw):
    write(tmp_path / "a.h5", **a)
    write(tmp_path / "b.h5", **b)
    with h5py.File(tmp_path / "a.h5") as x, h5py.File(tmp_path / "b.h5") as y:
        return h5compare.compare(x, y, "/", skip={"cpu_time_s", "times_s"},
                                 skip_columns={"cpu_time_s"}, skip_top_attrs={"created_utc"},
                                 sides=("before", "after"), **kw)


def test_equal_files_count_what_was_compared(tmp_path) -> None:
    nan = [1.0, np.nan, -0.0]
    d, tally = diffs(tmp_path, dict(runout=nan, cpu=0.1, order=("a", "b"), timings={"x": 1}),
                     dict(runout=nan, cpu=0.2, order=("b", "a"), timings={"x": 2}))
    # NaN equals NaN; timings and the root's created_utc left out; the scale's REFERENCE_LIST
    # holds the same attachments in another order.
    assert d == []
    assert (tally.groups, tally.datasets) == (3, 4)
    # status, speed_hz, json on the job; CLASS, NAME, REFERENCE_LIST on the scale;
    # DIMENSION_LIST on a and b.
    assert tally.attributes == 8


@pytest.mark.parametrize("b, expected", [
    (dict(runout=[1.0, 2.0, 0.0]), "/jobs/j1/a: 1 of 3 values differ, first at [2]: -0.0 vs 0.0"),
    (dict(runout=[1.0, 2.0, np.nextafter(-0.0, 1)]), "/jobs/j1/a: 1 of 3 values differ"),
    (dict(runout=[1.0, 2.0]), "/jobs/j1/a: shape (3,) vs (2,)"),
    (dict(runout=[1.0, 2.0, -0.0], status="diverged"), "/jobs/j1 attribute status: 1 of 1"),
])
def test_a_difference_is_named(tmp_path, b, expected) -> None:
    d, _ = diffs(tmp_path, dict(runout=[1.0, 2.0, -0.0]), b)
    assert any(line.startswith(expected) for line in d), d


def test_names_on_one_side_only(tmp_path) -> None:
    write(tmp_path / "a.h5", runout=[1.0])
    write(tmp_path / "b.h5", runout=[1.0])
    with h5py.File(tmp_path / "b.h5", "r+") as f:
        f["jobs/j1/extra"] = [0]
        f["jobs/j1"].attrs["note"] = "x"
    with h5py.File(tmp_path / "a.h5") as x, h5py.File(tmp_path / "b.h5") as y:
        d, _ = h5compare.compare(x, y, "/", sides=("before", "after"))
    assert "/jobs/j1 attribute note: only in after" in d
    assert "/jobs/j1/extra: only in after" in d
    # Nothing left out: the timings and the root's attribute are compared like the rest.
    assert "/ attribute created_utc" not in " ".join(d)


def test_text_as_text_and_json_with_timings_masked() -> None:
    assert h5compare.value_difference(np.array([b"ok"], dtype=object), np.array(["ok"]),
                                      None, None) is None
    a = '{"speeds_hz": [1.0], "times_s": {"floquet": 0.2}}'
    assert h5compare._masked_json(a, {"times_s"}) == \
        h5compare._masked_json(a.replace("0.2", "0.3"), {"times_s"})
    # Numbers stay as written: 1.0 and 1 are different text.
    assert h5compare._masked_json(a, {"times_s"}) != \
        h5compare._masked_json(a.replace("1.0", "1"), {"times_s"})
    assert h5compare._masked_json("[]", {"times_s"}) == "[]"


def test_the_command_exits_0_when_equal_1_when_not_2_when_unreadable(tmp_path) -> None:
    # Run as a script it compares whole files (timings left out) and says so in its exit code:
    # before it had a command line, running it compared nothing and exited 0.
    import subprocess
    import sys
    from pathlib import Path

    script = Path(h5compare.__file__)
    write(tmp_path / "a.h5", runout=[1.0, 2.0, 3.0], cpu=0.1)
    write(tmp_path / "b.h5", runout=[1.0, 2.0, 3.0], cpu=0.7)
    write(tmp_path / "c.h5", runout=[1.0, 2.0, 3.5], cpu=0.1)

    def run(*args):
        return subprocess.run([sys.executable, str(script), *map(str, args)],
                              capture_output=True, text=True)

    same = run(tmp_path / "a.h5", tmp_path / "b.h5")
    assert same.returncode == 0, same.stdout + same.stderr
    assert "identical" in same.stdout
    differ = run(tmp_path / "a.h5", tmp_path / "c.h5")
    assert differ.returncode == 1, differ.stdout + differ.stderr
    # Both runout datasets (a and b) differ at their last sample.
    assert "2 differences" in differ.stdout and "/jobs/j1/a: 1 of 3 values differ" in differ.stdout
    assert run(tmp_path / "a.h5", tmp_path / "missing.h5").returncode == 2
    assert run(tmp_path / "a.h5").returncode == 2
