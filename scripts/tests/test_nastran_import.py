"""Nastran files imported (issue 23): the reference roll's beam model exported by
`rotorsweep export --model full`, written as DMIG cards and as ASCII OP4 (dense and BIGMAT) by
pyNastran (scripts/make-nastran-files.py), imported through [fe] format = "dmig" | "op4".

In: the script, the binary ($ROTORSWEEP_BIN, as scripts/python-test sets it) and pyNastran
(scripts/requirements-nastran.txt). Out: pass or fail; the numbers are printed (pytest -s).
Checks, `rotorsweep modes --json` of each scene against the Matrix Market import of the same
values (free-rotor frequencies, supported frequencies in both planes, whirl and critical
speeds; zero frequencies (rigid modes) equal zero in both):
- both OP4 files (17 significant digits, the export's values exactly) against the export's own
  scene.toml: within 1e-10 relative (measured: bit-identical);
- the DMIG file against dmig-readback.toml, the matrices pyNastran itself reads from that DMIG
  file written as Matrix Market: within 1e-10 (measured: bit-identical). Against the export's
  scene the DMIG body differs by the rounding of pyNastran's large-field DMIG values to 11
  significant digits (16-character fields): measured 1.3e-6 relative at most, checked below
  1e-5 so that the DMIG body is the same roll.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "make-nastran-files.py"


def binary():
    return os.environ.get("ROTORSWEEP_BIN", str(ROOT / "target" / "release" / "rotorsweep"))


def frequencies(scene):
    d = json.loads(subprocess.run([binary(), "modes", str(scene), "--json"], check=True,
                                  capture_output=True, text=True).stdout)
    return {"free": [m["freq_hz"] for m in d["modes"]],
            "vertical": d["supported_hz"]["vertical"],
            "horizontal": d["supported_hz"]["horizontal"],
            "whirl": d["whirl_hz"], "critical": d["critical_speeds_hz"]}


def worst(got, ref):
    """The largest relative difference over every frequency; zeros must match exactly."""
    w = 0.0
    for key, values in ref.items():
        assert len(got[key]) == len(values), key
        for a, b in zip(got[key], values):
            if b == 0.0:
                assert a == 0.0, (key, a)
            else:
                w = max(w, abs(a - b) / abs(b))
    return w


@pytest.fixture(scope="module")
def body(tmp_path_factory):
    pytest.importorskip("pyNastran", reason="pyNastran (scripts/requirements-nastran.txt)")
    d = tmp_path_factory.mktemp("nastran") / "body"
    subprocess.run([binary(), "export", str(ROOT / "studies/scenes/reference-roll.toml"),
                    "--model", "full", "-o", str(d)], check=True)
    subprocess.run([sys.executable, str(SCRIPT), str(d)], check=True)
    return d


def test_op4_import_equals_the_matrix_market_import(body):
    ref = frequencies(body / "scene.toml")
    for scene in ["dense-op4.toml", "bigmat-op4.toml"]:
        w = worst(frequencies(body / scene), ref)
        print(f"{scene}: largest relative difference {w:.3g}")
        assert w <= 1e-10


def test_dmig_import_equals_the_matrix_market_import(body):
    got = frequencies(body / "dmig.toml")
    w = worst(got, frequencies(body / "dmig-readback.toml"))
    print(f"dmig.toml against pyNastran's reading of it: {w:.3g}")
    assert w <= 1e-10
    w = worst(got, frequencies(body / "scene.toml"))
    print(f"dmig.toml against the export (11-digit DMIG values): {w:.3g}")
    assert w <= 1e-5
