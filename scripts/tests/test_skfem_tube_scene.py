"""A solid FE body in a scene on supports (issue 23): the scikit-fem tube of
scripts/make-skfem-tube.py (coarse: 8 cells around, 2 along, 3 024 DOFs) standing on two linear
supports attached through rings at its journals (supported.toml: springs of 1e9 N/m in x and y
on each journal ring's reference point, the drive's axial spring of 1e9 N/m on the tending one,
the centre ring as sensor), run through `rotorsweep check`, `modes`, `linear` and `simulate`.

In: the script (run here) and the binary ($ROTORSWEEP_BIN, as scripts/python-test sets it). Out:
pass or fail; the numbers measured are printed (pytest -s). The references are computed here
from scikit-fem's K and M with scipy, independently of rotorsweep: each ring's reference point
is the mean of its nodes' translations (RBE3 with equal weights: the reference translation is
the weighted mean, src/rotor/import/rings.rs), so a spring k on it adds k r rᵀ to K, r the
ring's mean row.
- Same model: the Craig–Bampton reduction rotorsweep makes (interface every DOF of the three
  rings' nodes, 40 fixed-interface modes: a subspace defined by K and M alone, as long as the
  40th and 41st fixed-interface eigenvalues differ, which is checked) built here with scipy
  (constraint modes by a sparse LU, the fixed-interface modes by eigsh): its free-free
  frequencies against `modes`' orthogonalised set, its frequencies with the springs against
  `modes`' supported frequencies (every lateral one below 3 kHz, each way), within 1e-6
  relative.
- Whole model: eigsh of the full K and M (free, and with the springs) against `rotorsweep
  reduce supported.toml --free 14 --supported 12` (the whole imported model's own modes, free
  and on the scene's supports, by its sparse shift-invert Lanczos solver): within 1e-6
  relative (the issue's tolerance). The Craig–Bampton model `modes` uses is not that close
  on this body: its first modes are within its truncation error of the whole model's,
  printed and bounded (2e-4 below 1 kHz; measured up to 9.7e-5 on the supported 830 Hz
  pair; 600 normal modes still leave 1.1e-5).
- `simulate` from the static equilibrium under gravity (−y, 9.81 m/s²): the centre sensor's
  vertical displacement equals the static solution of the same reduced model here,
  K̂_s u = −9.81 M̂ r_y, sensor = the centre ring's mean u_y (1e-6 relative; constant in time);
  from rest, the record rings at the first vertical supported frequency (the spectral peak
  within 2 %: the record's 0.6 s give a 1.7 Hz bin).
- `linear --no-floquet` at 0 and 100 Hz runs and reports the same first vertical supported
  frequency.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import scipy.io
import scipy.linalg as sl
import scipy.sparse as sp
import scipy.sparse.linalg as spla

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "make-skfem-tube.py"
K_SUPPORT = 1.0e9  # N/m, make-skfem-tube.py's SUPPORT_N_PER_M
N_NORMAL = 40  # supported.toml's "40n+…st"
# The whole model's modes compared with scipy: every mode below 1.3 kHz (12 with the springs,
# the spin mode first; 14 free, six rigid first).
N_WHOLE_SUPPORTED, N_WHOLE_FREE = 12, 14
GRAVITY = 9.81  # m/s², the scene default (simulation.gravity_m_s2)


def binary():
    return os.environ.get("ROTORSWEEP_BIN", str(ROOT / "target" / "release" / "rotorsweep"))


def run(*args):
    return subprocess.run([binary(), *map(str, args)], check=True, capture_output=True,
                          text=True).stdout


def hz(lam):
    return np.sqrt(np.abs(lam)) / (2 * np.pi)


@pytest.fixture(scope="module")
def tube(tmp_path_factory):
    base = tmp_path_factory.mktemp("skfem-scene")
    body = base / "tube"
    subprocess.run([sys.executable, str(SCRIPT), "-o", str(body), "--n-theta", "8", "--n-z",
                    "2", "--no-eigen"], check=True)
    k = scipy.io.mmread(body / "stiffness.mtx").tocsr()
    m = scipy.io.mmread(body / "mass.mtx").tocsr()
    nodes = pd.read_csv(body / "nodes.csv")
    n = k.shape[0]
    r = np.hypot(nodes.x, nodes.y)
    ring_at = {"journal_tending": (0.05, 0.06), "journal_drive": (1.83, 0.06),
               "centre": (0.94, 0.16)}  # make-skfem-tube.py's defaults: z, radius [m]
    rings = {name: np.where((np.abs(nodes.z - z) < 1e-9) & (np.abs(r - rad) < 1e-9))[0]
             for name, (z, rad) in ring_at.items()}
    assert all(len(v) == 16 for v in rings.values())

    def mean_row(ring, c):
        row = np.zeros(n)
        row[3 * rings[ring] + c] = 1.0 / len(rings[ring])
        return row

    springs = [mean_row(s, c) for s in ["journal_tending", "journal_drive"] for c in (0, 1)]
    springs.append(mean_row("journal_tending", 2))
    rigid_y = np.zeros(n)
    rigid_y[1::3] = 1.0
    return {"base": base, "body": body, "k": k, "m": m, "n": n, "rings": rings,
            "springs": springs, "centre_y": mean_row("centre", 1), "rigid_y": rigid_y,
            "modes": json.loads(run("modes", body / "supported.toml", "--json"))}


@pytest.fixture(scope="module")
def reduced(tube):
    """The Craig–Bampton model built here (module doc): T, K̂, M̂, K̂ with the springs."""
    k, m, n = tube["k"], tube["m"], tube["n"]
    iface = np.sort(np.concatenate([3 * v[:, None] + np.arange(3)
                                    for v in tube["rings"].values()]).ravel())
    inner = np.setdiff1d(np.arange(n), iface)
    kii, mii = k[inner][:, inner].tocsc(), m[inner][:, inner].tocsc()
    lam, vec = spla.eigsh(kii, k=N_NORMAL + 1, M=mii, sigma=0.0, which="LM", tol=0)
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    gap = (lam[N_NORMAL] - lam[N_NORMAL - 1]) / lam[N_NORMAL]
    assert gap > 1e-3, f"the 40th and 41st fixed-interface modes are too close ({gap:e})"
    psi = -spla.splu(kii).solve(k[inner][:, iface].toarray())
    nb = len(iface)
    t = np.zeros((n, nb + N_NORMAL))
    t[iface, np.arange(nb)] = 1.0
    t[np.ix_(inner, np.arange(nb))] = psi
    t[np.ix_(inner, nb + np.arange(N_NORMAL))] = vec[:, :N_NORMAL]
    kh, mh = t.T @ (k @ t), t.T @ (m @ t)
    kh, mh = 0.5 * (kh + kh.T), 0.5 * (mh + mh.T)
    ks = kh.copy()
    for row in tube["springs"]:
        rt = t.T @ row
        ks += K_SUPPORT * np.outer(rt, rt)
    return {"t": t, "kh": kh, "mh": mh, "ks": ks}


def test_free_modes_equal_the_same_reduction_in_scipy(tube, reduced):
    ours = np.array([md["freq_hz"] for md in tube["modes"]["modes"]])
    theirs = hz(sl.eigh(reduced["kh"], reduced["mh"], eigvals_only=True))
    # rotorsweep keeps five rigid modes (the spin is prescribed): scipy's six come first.
    assert np.all(ours[:5] == 0.0) and np.all(theirs[:6] < 1e-2)
    rel = np.abs(ours[5:] / theirs[6:] - 1)
    print(f"free modes, {len(rel)} elastic ({theirs[6]:.3f}–{theirs[-1]:.0f} Hz): largest "
          f"relative difference to scipy's reduction {rel.max():.2e}")
    assert rel.max() < 1e-6


def test_supported_modes_equal_the_same_reduction_in_scipy(tube, reduced):
    lam, vec = sl.eigh(reduced["ks"], reduced["mh"])
    theirs = hz(lam)
    # Kinetic-energy share of u_z: axial modes are not in `supported_hz` (lateral planes).
    t = reduced["t"]
    uz = np.zeros(tube["n"])
    uz[2::3] = 1.0
    tz = t * uz[:, None]
    share = np.einsum("ij,ij->j", vec, (tz.T @ (tube["m"] @ tz)) @ vec)
    sup = tube["modes"]["supported_hz"]
    ours = np.sort(np.array(sup["vertical"] + sup["horizontal"]))
    ours = ours[ours < 3000.0]
    lateral = theirs[(theirs > 1.0) & (theirs < 3000.0) & (share < 0.5)]
    worst = 0.0
    for f in ours:
        worst = max(worst, np.min(np.abs(theirs / f - 1)))
    for f in lateral:
        worst = max(worst, np.min(np.abs(ours / f - 1)))
    print(f"supported modes below 3 kHz: {len(ours)} reported, {len(lateral)} lateral in scipy; "
          f"largest relative difference {worst:.2e}; first {ours[:4]}")
    assert len(ours) == len(lateral)
    assert worst < 1e-6


@pytest.fixture(scope="module")
def whole(tube):
    """scipy's eigenvalues of the whole model (eigsh, shift-invert at -(2 pi 1 Hz)^2, tol 0):
    with the springs (12 lowest) and free (14 lowest); and `rotorsweep reduce supported.toml
    --free 14 --supported 12`: the same whole model's modes by rotorsweep's sparse Lanczos."""
    k, m = tube["k"].tocsc(), tube["m"].tocsc()
    entries = []
    for row in tube["springs"]:
        nz = np.nonzero(row)[0]
        i, j = np.meshgrid(nz, nz, indexing="ij")
        entries.append((i.ravel(), j.ravel(), K_SUPPORT * np.outer(row[nz], row[nz]).ravel()))
    i, j, x = (np.concatenate(c) for c in zip(*entries))
    ks = (k + sp.coo_matrix((x, (i, j)), shape=k.shape)).tocsc()
    supported = hz(np.sort(spla.eigsh(ks, k=N_WHOLE_SUPPORTED, M=m, sigma=-(2 * np.pi) ** 2,
                                      which="LM", tol=0, return_eigenvectors=False)))
    free = hz(np.sort(spla.eigsh(k, k=N_WHOLE_FREE, M=m, sigma=-(2 * np.pi) ** 2, which="LM",
                                 tol=0, return_eigenvectors=False)))
    out = tube["base"] / "whole"
    run("reduce", tube["body"] / "supported.toml", "--normal", N_NORMAL, "--free", N_WHOLE_FREE,
        "--supported", N_WHOLE_SUPPORTED, "-o", out)
    f = pd.read_csv(out / "frequencies.csv")
    return {"supported": supported, "free": free,
            "ours_supported": f[f["set"] == "supported-body"].hz.values,
            "ours_free": f[f["set"] == "free-body"].hz.values}


def test_whole_model_on_its_supports_equals_scipys(whole):
    """The issue's check: the imported model's free-free and supported frequencies equal
    scipy's eigenvalues of the same K and M (and the same springs) within 1e-6 relative. The
    whole model's, by `reduce --free/--supported` (a Craig–Bampton model converges too slowly
    on this body for that: the next test)."""
    for name, rigid in [("supported", 1), ("free", 6)]:
        ours, theirs = whole[f"ours_{name}"], whole[name]
        assert len(ours) == len(theirs)
        # Rigid-body modes (the spin the supports leave free; six for the free body): near 0 in
        # both, 1e-2 Hz being 2e-5 of the first elastic mode.
        assert np.all(ours[:rigid] < 1e-2) and np.all(theirs[:rigid] < 1e-2)
        rel = np.abs(ours[rigid:] / theirs[rigid:] - 1)
        print(f"whole model, {name}: {len(rel)} elastic modes {theirs[rigid]:.3f}–"
              f"{theirs[-1]:.3f} Hz, largest relative difference to scipy {rel.max():.2e}")
        assert rel.max() < 1e-6


def test_reduced_model_is_close_to_the_whole_model(tube, reduced, whole):
    full, free = whole["supported"], whole["free"]
    red_s = hz(sl.eigh(reduced["ks"], reduced["mh"], eigvals_only=True))[:N_WHOLE_SUPPORTED]
    red_f = hz(sl.eigh(reduced["kh"], reduced["mh"], eigvals_only=True))[6:N_WHOLE_FREE]
    low_s, low_f = full[1:] < 1000.0, free[6:] < 1000.0
    es = red_s[1:][low_s] / full[1:][low_s] - 1
    ef = red_f[low_f] / free[6:][low_f] - 1
    print(f"whole model, supported (spin mode aside) {full[1:][low_s]} Hz: reduction error "
          f"{es}; free {free[6:][low_f]} Hz: {ef}")
    # Craig–Bampton only adds constraint, so it can only raise a frequency.
    assert np.all(es > -1e-9) and np.all(ef > -1e-9)
    assert es.max() < 2e-4 and ef.max() < 2e-4


def test_simulate_holds_the_static_sag_and_rings_at_the_first_mode(tube, reduced):
    t, kh_s, mh = reduced["t"], reduced["ks"], reduced["mh"]
    load = -GRAVITY * (mh @ np.linalg.lstsq(t, tube["rigid_y"], rcond=None)[0])
    sag = tube["centre_y"] @ (t @ np.linalg.solve(kh_s, load))
    out = tube["base"] / "static.h5"
    run("simulate", tube["body"] / "supported.toml", "--set", "simulation.t_end_s=0.1", "-o", out)
    with h5py.File(out) as f:
        g = f["jobs/skfem-tube-supported/runout/centre"]
        assert g["vertical"].attrs["units"] == "um"
        v = g["vertical"][:] * 1e-6
    rel = np.abs(v / sag - 1).max()
    print(f"static sag at the centre ring: simulate {v[0] * 1e6:.6f} um, scipy {sag * 1e6:.6f} "
          f"um, largest relative difference over the record {rel:.2e}")
    assert rel < 1e-6
    out = tube["base"] / "rest.h5"
    run("simulate", tube["body"] / "supported.toml", "--set", "simulation.t_end_s=0.6", "--set",
        "simulation.static_start=false", "--set", "simulation.sample_rate_hz=4000", "-o", out)
    with h5py.File(out) as f:
        v = f["jobs/skfem-tube-supported/runout/centre/vertical"][:]
    spec = np.abs(np.fft.rfft((v - v.mean()) * np.hanning(len(v)), 16 * len(v)))
    peak = np.fft.rfftfreq(16 * len(v), 1 / 4000.0)[np.argmax(spec)]
    first = tube["modes"]["supported_hz"]["vertical"][0]
    print(f"from rest: spectral peak {peak:.2f} Hz, first vertical supported {first:.2f} Hz")
    assert abs(peak / first - 1) < 0.02


def test_linear_runs_on_the_solid_body(tube):
    lin = json.loads(run("linear", tube["body"] / "supported.toml", "--no-floquet", "--speeds",
                         "0:100:2", "--json"))
    ours, theirs = lin["supported_hz"]["vertical"][:4], tube["modes"]["supported_hz"]["vertical"][:4]
    print(f"linear: speeds {lin['speeds_hz']} Hz, first vertical supported {ours} Hz")
    assert lin["speeds_hz"] == [0.0, 100.0]
    assert np.allclose(ours, theirs, rtol=1e-12, atol=0)
