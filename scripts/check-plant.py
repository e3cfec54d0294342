#!/usr/bin/env python3
"""Checks an exported linear plant against `rotorsweep linear` in another code: python-control
and scipy.signal.

In: a scene and a spin speed F [Hz] (and the binary: $ROTORSWEEP_BIN, else
target/release/rotorsweep). Runs `rotorsweep export SCENE --state-space --speed-hz F` to an
HDF5, an .npz and a MATLAB .mat file (read by scipy.io.loadmat) in a temporary folder and `rotorsweep linear SCENE --speed-hz F --json
--no-floquet`. Out: for each file, the plant's frequency response at s = i 2 pi F, evaluated by
python-control (`StateSpace(...)(s)`) and by scipy.signal (`StateSpace.to_tf` is lossy; the
response is C (sI - A)^-1 B + D from `scipy.linalg.solve` on scipy.signal's matrices), turned
into the unbalance response X = Omega^2 (H[out, unbalance/cos] - i H[out, unbalance/sin]) at
every sensor's displacement_x|y, and compared with linear's `unbalance_response` (amplitude_um,
phase_deg) of the same sensor and direction; and the .npz and .mat plants' A, B, C, D and
names against the .h5 plant's, bit for bit. Prints the largest relative difference; exits 1
when it is above --tolerance (default 1e-6) or a file's plant differs, 0 otherwise.

docs/export.md describes the plant's layout.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import control
import h5py
import numpy as np
import scipy.io
import scipy.linalg
import scipy.signal

ROOT = Path(__file__).resolve().parents[1]


def binary() -> str:
    return os.environ.get("ROTORSWEEP_BIN", str(ROOT / "target" / "release" / "rotorsweep"))


def run(*args: str) -> str:
    p = subprocess.run([binary(), *args], capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit(f"rotorsweep {' '.join(args)} failed ({p.returncode}):\n{p.stderr}")
    return p.stdout


def read_plant(path: Path) -> dict:
    """A, B, C, D and the names, from .h5, .npz or .mat."""
    if path.suffix == ".mat":
        m = scipy.io.loadmat(path)
        p = {k: m[k] for k in "ABCD"}
        for k in ("inputs", "outputs"):
            p[k] = [str(c[0]) if c.size else "" for c in m[k][:, 0]]
        return p
    if path.suffix == ".h5":
        with h5py.File(path, "r") as f:
            p = {k: f[k][()] for k in "ABCD"}
            for k in ("inputs", "outputs"):
                p[k] = [s.decode() if isinstance(s, bytes) else str(s) for s in f[k][()]]
        return p
    z = np.load(path)
    p = {k: z[k] for k in "ABCD"}
    for k in ("inputs", "outputs"):
        p[k] = [str(s) for s in z[k]]
    return p


def responses(p: dict, w: float) -> dict:
    """H(i w) by python-control and by scipy.signal's matrices."""
    s = 1j * w
    h_control = np.asarray(control.ss(p["A"], p["B"], p["C"], p["D"])(s))
    sys_sp = scipy.signal.StateSpace(p["A"], p["B"], p["C"], p["D"])
    n = sys_sp.A.shape[0]
    x = scipy.linalg.solve(s * np.eye(n) - sys_sp.A, sys_sp.B)
    h_scipy = sys_sp.C @ x + sys_sp.D
    return {"python-control": h_control, "scipy.signal": h_scipy}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", type=Path)
    ap.add_argument("--speed-hz", type=float, required=True)
    ap.add_argument("--tolerance", type=float, default=1e-6)
    a = ap.parse_args()
    w = 2 * np.pi * a.speed_hz
    lin = json.loads(
        run("linear", str(a.scene), "--speed-hz", str(a.speed_hz), "--json", "--no-floquet")
    )["unbalance_response"]
    worst = 0.0
    same = True
    with tempfile.TemporaryDirectory(prefix="check-plant-") as tmp:
        first = None
        for ext in ("h5", "npz", "mat"):
            path = Path(tmp) / f"plant.{ext}"
            run("export", str(a.scene), "--state-space", "--speed-hz", str(a.speed_hz), "-o", str(path))
            p = read_plant(path)
            if first is None:
                first = p
            else:
                equal = all(np.array_equal(p[k], first[k]) for k in "ABCD") and all(
                    p[k] == first[k] for k in ("inputs", "outputs"))
                same = same and equal
                print(f"{ext}: A, B, C, D and the names {'equal' if equal else 'DIFFER FROM'} "
                      "the .h5 plant's bit for bit")
            cos, sin = p["inputs"].index("unbalance/cos"), p["inputs"].index("unbalance/sin")
            for tool, h in responses(p, w).items():
                for sensor, r in lin.items():
                    for d, key in (("x", "horizontal"), ("y", "vertical")):
                        row = p["outputs"].index(f"{sensor}/displacement_{d}")
                        x = w * w * (h[row, cos] - 1j * h[row, sin])
                        want = r[key]["amplitude_um"][0] * 1e-6 * np.exp(1j * np.radians(r[key]["phase_deg"][0]))
                        err = abs(x - want) / abs(want)
                        worst = max(worst, err)
                        print(f"{ext:3} {tool:14} {sensor}/{d}: |X| = {abs(x) * 1e6:.6f} um, "
                              f"linear {abs(want) * 1e6:.6f} um, relative difference {err:.2e}")
    print(f"largest relative difference {worst:.2e} (tolerance {a.tolerance:.0e})")
    return 0 if worst <= a.tolerance and same else 1


if __name__ == "__main__":
    sys.exit(main())
