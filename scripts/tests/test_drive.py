"""Driving the binary from Python (issue 20, item 7): :class:`rotorsweep.Scene` (get, ``--set``
semantics, save keeping comments, errors that name the key), the runners ``modes``, ``linear``,
``simulate`` and ``run`` against the files and JSON the binary writes for the same command, their
errors (:class:`rotorsweep.RotorsweepError` with the binary's message and exit code, a timeout),
and the shipped example python/examples/campbell_variant.py.

The binary is $ROTORSWEEP_BIN (scripts/python-test sets it), as in test_results.py.
"""

from __future__ import annotations

import importlib.util
import json
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import rotorsweep as rs
from test_results import ROOT, SCENE, binary, rotorsweep, run_ok

TIMING = ROOT / "studies" / "scenes" / "timing-case.toml"
EXAMPLE = ROOT / "python" / "examples" / "campbell_variant.py"
#: A short simulation of the reference roll (0.2 s, as test_results.py's study).
SHORT = {"speed.hz": 14.0, "simulation.t_end_s": 0.2, "simulation.settle_s": 0.1}
SPEEDS = "0:40:5"


@pytest.fixture(autouse=True)
def _binary_env(monkeypatch: pytest.MonkeyPatch) -> None:
    """The runners find the binary the other tests use."""
    monkeypatch.setenv("ROTORSWEEP_BIN", str(binary()))


def sets(values: dict[str, object]) -> list[str]:
    out: list[str] = []
    for k, v in values.items():
        out += ["--set", f"{k}={json.dumps(v)}"]
    return out


# --- Scene -------------------------------------------------------------------------------------


def test_scene_get_reads_the_effective_scene() -> None:
    s = rs.Scene(SCENE)
    assert s["roll.shell.outer_diameter_mm"] == 320.0
    assert s["supports[1].rollers[0].name"] == "front"
    assert s["roll.sensors[1].z_mm"] == 2250.0
    assert s.get("speed.hz") is None and s.get("speed.hz", 9.0) == 9.0
    assert "roll.shell.length_mm" in s and "speed.hz" not in s
    assert s.name == "reference-roll"
    # timing-case extends the reference roll: its own keys and its base's.
    t = rs.Scene(TIMING)
    assert t["speed.hz"] == 16.4
    assert t["roll.shell.length_mm"] == 4500.0
    assert t["roll.shell.thickness_map"] == "../maps/reference-roll-thickness.csv"
    assert "supports[0].stand.mass_kg" in set(t.keys())


def test_scene_get_of_a_missing_key_names_it() -> None:
    s = rs.Scene(SCENE)
    with pytest.raises(KeyError, match="roll.shell.outer_diamter_mm") as e:
        s["roll.shell.outer_diamter_mm"]
    assert isinstance(e.value, rs.SceneKeyError) and e.value.key == "roll.shell.outer_diamter_mm"
    assert "outer_diameter_mm" in str(e.value)  # the keys that are there
    with pytest.raises(KeyError, match=r"index 5 out of range \(length 3\)"):
        s["roll.sensors[5].z_mm"]


def test_set_save_round_trip_keeps_comments(tmp_path: Path) -> None:
    s = rs.Scene(SCENE)
    s.update({"roll.shell.outer_diameter_mm": 300.0, "roll.balancing.radius_mm": 145.0})
    s.set("speed.hz", 14.5)  # a table the file has not
    s.set("roll.sensors[1].z_mm", "0.25L")  # a position as a string
    s.set("supports[0].stand.mass_kg", 55.0)  # inside an inline table of an array
    assert s.overrides == [
        "roll.shell.outer_diameter_mm=300.0",
        "roll.balancing.radius_mm=145.0",
        "speed.hz=14.5",
        'roll.sensors[1].z_mm="0.25L"',
        "supports[0].stand.mass_kg=55.0",
    ]
    assert s["roll.shell.outer_diameter_mm"] == 300.0 and s["speed.hz"] == 14.5
    original = SCENE.read_text(encoding="utf-8")
    # Saved: every comment is kept, each set value on its line or in a new table.
    copy_dir = tmp_path / "scenes"
    copy_dir.mkdir()
    copy = s.save(copy_dir / "variant.toml")
    assert SCENE.read_text(encoding="utf-8") == original  # set and save never write the scene
    text = copy.read_text(encoding="utf-8")
    comments = [line for line in original.splitlines() if line.lstrip().startswith("#")]
    kept = text.splitlines()
    assert all(c in kept for c in comments)
    assert text.count("\n") >= original.count("\n")
    assert "thickness_map = " in text
    assert "outer_diameter_mm = 300.0" in text and "mass_kg = 55.0" in text
    # Elsewhere: the relative thickness map is rewritten to name the same file.
    out = s.save(tmp_path / "variant.toml")
    assert len(out.read_text(encoding="utf-8").splitlines()) == len(text.splitlines())
    with pytest.raises(FileExistsError):
        s.save(out)
    table = tomllib.loads(out.read_text(encoding="utf-8"))
    assert (out.parent / table["roll"]["shell"]["thickness_map"]).resolve() == (
        ROOT / "studies" / "maps" / "reference-roll-thickness.csv"
    ).resolve()
    back = rs.Scene(out)
    for key in ("roll.shell.outer_diameter_mm", "speed.hz", "roll.sensors[1].z_mm", "supports[0].stand.mass_kg"):
        assert back[key] == s[key], key
    # The binary reads the saved file as it reads the original with the same --set arguments.
    args = [a for o in s.overrides for a in ("--set", o)]
    a = json.loads(run_ok("modes", out, "--speed-hz", "0", "--json", cwd=tmp_path).stdout)
    b = json.loads(run_ok("modes", SCENE, *args, "--speed-hz", "0", "--json", cwd=tmp_path).stdout)
    assert a["mass_kg"] == b["mass_kg"]
    assert a["supported_hz"] == b["supported_hz"]


def test_save_of_an_extending_scene(tmp_path: Path) -> None:
    t = rs.Scene(TIMING)
    t.update({"supports[1].stand.mass_kg": 60.0, "simulation.t_end_s": 0.5})
    assert t["supports[1].stand.mass_kg"] == 60.0 and t["supports[0].stand.mass_kg"] == 50.0
    out = t.save(tmp_path / "timing-variant.toml")
    table = tomllib.loads(out.read_text(encoding="utf-8"))
    assert (out.parent / table["extends"]).resolve() == SCENE.resolve()
    # The base's supports are copied in whole (an array replaces the base's), the change in it.
    assert [sup["stand"]["mass_kg"] for sup in table["supports"]] == [50.0, 60.0]
    assert table["simulation"]["t_end_s"] == 0.5
    assert "# The source study's timing case" in out.read_text(encoding="utf-8")
    assert rs.Scene(out).effective()["supports"] == t.effective()["supports"]


def test_set_of_an_unknown_key_raises_with_the_key() -> None:
    s = rs.Scene(SCENE)
    with pytest.raises(KeyError, match="roll.shell.outer_diamter_mm") as e:
        s.set("roll.shell.outer_diamter_mm", 300.0)
    assert isinstance(e.value, rs.RotorsweepError) and e.value.returncode == 1
    assert e.value.key == "roll.shell.outer_diamter_mm"
    assert s.overrides == [] and "roll.shell.outer_diamter_mm" not in s  # not kept
    # Paths that do not fit the scene's structure, refused before the binary.
    with pytest.raises(rs.SceneKeyError, match="index it as"):
        s.set("roll.sensors.z_mm", 1.0)
    with pytest.raises(rs.SceneKeyError, match=r"index 9 out of range"):
        s.set("roll.sensors[9].z_mm", 1.0)
    # A key that replaces an earlier override is refused, as on the command line.
    s.set("speed.hz", 12.0)
    with pytest.raises(rs.SceneKeyError, match="would replace"):
        s.set("speed", {"hz": 13.0})


def test_set_of_a_wrong_type_raises_with_the_key() -> None:
    s = rs.Scene(SCENE)
    with pytest.raises((TypeError, ValueError), match="roll.shell.outer_diameter_mm") as e:
        s.set("roll.shell.outer_diameter_mm", "wide")
    assert isinstance(e.value, rs.SceneValueError) and isinstance(e.value, rs.RotorsweepError)
    assert e.value.key == "roll.shell.outer_diameter_mm" and e.value.returncode == 1
    assert s["roll.shell.outer_diameter_mm"] == 320.0 and s.overrides == []
    # Out of range, and values only valid together (update checks once, keeps none on failure).
    with pytest.raises(rs.SceneValueError, match="outer_diameter_mm"):
        s.set("roll.shell.outer_diameter_mm", -1.0)
    with pytest.raises(rs.SceneValueError):
        s.set("roll.shell.outer_diameter_mm", 300.0)  # the balancing radius 160 mm is outside
    s.update({"roll.shell.outer_diameter_mm": 300.0, "roll.balancing.radius_mm": 145.0})
    assert s["roll.shell.outer_diameter_mm"] == 300.0
    with pytest.raises(TypeError):
        s.set("speed.hz", object())


# --- runners against the CLI -------------------------------------------------------------------


def test_modes_equals_the_cli_json(tmp_path: Path) -> None:
    s = rs.Scene(SCENE).set("roll.shell.elements", 30)
    df = rs.modes(s, max_speed_hz=60)
    cli = json.loads(
        run_ok("modes", SCENE, "--set", "roll.shell.elements=30", "--max-speed-hz", "60", "--json", cwd=tmp_path).stdout
    )
    assert list(df.columns[:4]) == ["index", "freq_hz", "label", "kind"]
    assert df.attrs["units"]["freq_hz"] == "Hz"
    assert np.array_equal(df["freq_hz"].to_numpy(), [m["freq_hz"] for m in cli["modes"]])
    assert list(df["label"]) == [m["label"] for m in cli["modes"]]
    assert df.attrs["supported_hz"] == cli["supported_hz"]
    assert df.attrs["critical_speeds_hz"] == cli["critical_speeds_hz"]
    assert df.attrs["mass_kg"] == cli["mass_kg"]
    # A path and set= give the same.
    other = rs.modes(SCENE, set={"roll.shell.elements": 30}, max_speed_hz=60)
    assert np.array_equal(other["freq_hz"], df["freq_hz"])


def test_linear_equals_reading_the_cli_file(tmp_path: Path) -> None:
    s = rs.Scene(SCENE).set("roll.shell.outer_diameter_mm", 330.0)
    kept = tmp_path / "kept.h5"
    ds = rs.linear(s, speeds=SPEEDS, output=kept)
    xr.testing.assert_identical(ds, rs.campbell(kept))
    run_ok("linear", SCENE, "--set", "roll.shell.outer_diameter_mm=330.0", "--speeds", SPEEDS, "-o", "cli.h5", cwd=tmp_path)
    cli = rs.campbell(tmp_path / "cli.h5")
    xr.testing.assert_equal(ds, cli)
    # A temporary output is removed; the tuple form of speeds is the same flag.
    tmp = rs.linear(s, speeds=(0, 40, 5))
    xr.testing.assert_equal(tmp, cli)
    # An existing output is refused without overwrite (usage error, 64), replaced with it.
    with pytest.raises(rs.RotorsweepError) as e:
        rs.linear(s, speeds=SPEEDS, output=kept)
    assert e.value.returncode == 64 and "overwrite" in e.value.message
    rs.linear(s, speeds=SPEEDS, output=kept, overwrite=True)


def test_simulate_equals_reading_the_cli_file(tmp_path: Path) -> None:
    kept = tmp_path / "sim.h5"
    r = rs.simulate(SCENE, set=SHORT, output=kept)
    xr.testing.assert_identical(r, rs.runout(kept, rs.job_ids(kept)[0]))
    assert r.attrs["status"] == "ok"
    run_ok("simulate", SCENE, *sets(SHORT), "-o", "cli.h5", cwd=tmp_path)
    cli = rs.runout(tmp_path / "cli.h5", rs.job_ids(tmp_path / "cli.h5")[0])
    xr.testing.assert_equal(r, cli)  # the same samples; attrs hold timings
    assert r.attrs["steps"] == cli.attrs["steps"]


def test_run_equals_reading_the_cli_file(tmp_path: Path) -> None:
    study = tmp_path / "tiny.toml"
    study.write_text(
        f'name = "py-drive"\nscene = "{SCENE.as_posix()}"\n[set]\n'
        '"simulation.t_end_s" = 0.2\n"simulation.settle_s" = 0.1\n'
        '[[axes]]\nkey = "speed.hz"\nvalues = [12.0, 16.0]\n'
    )
    kept = tmp_path / "kept.h5"
    df = rs.run(study, output=kept, threads=2)
    pd.testing.assert_frame_equal(df, rs.summary(kept))
    assert list(df["status"]) == ["ok", "ok"] and list(df["speed.hz"]) == [12.0, 16.0]
    run_ok("run", study, "-o", "cli.h5", "--threads", "2", cwd=tmp_path)
    cli = rs.summary(tmp_path / "cli.h5")
    timing = [c for c in df if c.endswith("time_s") or c in ("model_build_s",)]
    pd.testing.assert_frame_equal(df.drop(columns=timing), cli.drop(columns=timing))
    # A temporary output.
    again = rs.run(study)
    assert list(again["job_id"]) == list(df["job_id"])


# --- errors ------------------------------------------------------------------------------------


def test_a_nonexistent_scene_is_a_rotorsweep_error(tmp_path: Path) -> None:
    missing = tmp_path / "no-such-scene.toml"
    for call in (rs.modes, rs.linear, rs.simulate):
        with pytest.raises(rs.RotorsweepError) as e:
            call(missing)
        assert isinstance(e.value, RuntimeError)
        assert e.value.returncode == 1
        assert "no-such-scene.toml" in str(e.value) and "no-such-scene.toml" in e.value.stderr
    p = rotorsweep("modes", missing, cwd=tmp_path)
    assert p.stderr.strip() in str(e.value)
    with pytest.raises(rs.RotorsweepError, match="no-such-study.toml"):
        rs.run(tmp_path / "no-such-study.toml")
    with pytest.raises(rs.SceneError, match="no-such-scene.toml"):
        rs.Scene(missing)


def test_a_bad_override_at_run_time_names_the_key() -> None:
    with pytest.raises(rs.RotorsweepError, match="roll.shell.nope") as e:
        rs.modes(SCENE, set={"roll.shell.nope": 1.0})
    assert e.value.returncode == 1


def test_timeout_kills_the_binary() -> None:
    with pytest.raises(rs.RotorsweepTimeout, match="did not finish within") as e:
        rs.linear(SCENE, speeds="0:100:2001", timeout=0.05)
    assert isinstance(e.value, rs.RotorsweepError) and isinstance(e.value, TimeoutError)
    assert e.value.returncode is None


def test_no_binary_is_an_error(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    with pytest.raises(rs.RotorsweepError, match="no rotorsweep binary"):
        rs.modes(SCENE, binary=tmp_path / "nothing")


def test_exit_code_2_returns_results_with_a_warning(tmp_path: Path) -> None:
    bad = {**SHORT, "solver.max_steps": 3}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = rs.simulate(SCENE, set=bad)
    assert r.attrs["status"] != "ok"
    assert any(issubclass(w.category, rs.RotorsweepWarning) for w in caught)


# --- the example -------------------------------------------------------------------------------


def test_campbell_variant_example(tmp_path: Path) -> None:
    spec = importlib.util.spec_from_file_location("campbell_variant", EXAMPLE)
    assert spec and spec.loader
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    r = example.main(tmp_path / "out", speeds="0:60:13")
    png = r["png"]
    assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    # The frequencies are the binary's own for the same command.
    args = [a for o in r["scene"].overrides for a in ("--set", o)]
    assert args and "roll.shell.outer_diameter_mm=300.0" in args
    cli_modes = json.loads(run_ok("modes", SCENE, *args, "--json", cwd=tmp_path).stdout)
    assert np.array_equal(r["modes"]["freq_hz"], [m["freq_hz"] for m in cli_modes["modes"]])
    assert r["modes"].attrs["supported_hz"] == cli_modes["supported_hz"]
    run_ok("linear", SCENE, *args, "--speeds", "0:60:13", "-o", "cli.h5", cwd=tmp_path)
    xr.testing.assert_equal(r["campbell"], rs.campbell(tmp_path / "cli.h5"))
    # A thinner shell is a softer roll: its first supported frequency is lower.
    ref = json.loads(run_ok("modes", SCENE, "--json", cwd=tmp_path).stdout)
    assert cli_modes["supported_hz"]["vertical"][0] < ref["supported_hz"]["vertical"][0]
    # The saved variant runs as a scene of its own, giving the same modes.
    saved = json.loads(run_ok("modes", r["saved"], "--json", cwd=tmp_path).stdout)
    assert saved["supported_hz"] == cli_modes["supported_hz"]
