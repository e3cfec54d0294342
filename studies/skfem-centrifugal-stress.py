#!/usr/bin/env python3
"""The scikit-fem tube with its centrifugal stress stiffness, through `rotorsweep reduce`.

In: the tube of scripts/make-skfem-tube.py (its mesh options), a reference speed and the
normal-mode counts to try. Out (printed): the journal-held tube's lowest frequencies at
Omega = 0, Omega_ref and 3 Omega_ref of the whole model K + (Omega/Omega_ref)^2 dK (scipy
eigsh, shift-invert, tol 0), and those of the Craig-Bampton reduction `rotorsweep reduce`
writes (the normal-mode block of K^ + Omega^2 K^_sigma, interface held: the journal rings),
with their largest relative difference: how well the standstill basis spans the stiffened
shapes. Units SI.
Method: scikit-fem 12.0.2 (independent of rotorsweep): the centrifugal body force
rho Omega_ref^2 (x, y, 0) on the tube held at its journal rings (their DOFs fixed), the static
displacement u, the stress sigma = lambda tr(eps) I + 2 mu eps, eps = sym grad u, and the
geometric stiffness dK(u, v) = int sigma_ij d_i u_k d_j v_k (the second-order strain's work on
the prestress; Bathe, Finite Element Procedures, 6.3, the updated Lagrangian K_NL). No spin
softening in dK (the engine adds it). Cost: one sparse LU, one eigsh per speed, one `reduce`
per count (seconds on the default 8 x 2 mesh).
"""
import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.io
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, ElementHex2, ElementVector, LinearForm, asm
from skfem.helpers import grad, sym_grad, trace
from skfem.models.elasticity import lame_parameters

HERE = Path(__file__).resolve().parent
spec = importlib.util.spec_from_file_location("tube", HERE.parent / "scripts/make-skfem-tube.py")
tube = importlib.util.module_from_spec(spec)
spec.loader.exec_module(tube)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n-theta", type=int, default=8)
    p.add_argument("--n-z", type=int, default=2)
    p.add_argument("--ref-hz", type=float, default=100.0, help="Omega_ref / 2 pi")
    p.add_argument("--normal", type=int, nargs="+", default=[40, 200])
    p.add_argument("--modes", type=int, default=12, help="frequencies compared")
    a = p.parse_args()
    binary = os.environ.get("ROTORSWEEP_BIN", "rotorsweep")
    work = Path(tempfile.mkdtemp(prefix="skfem-stress-"))
    subprocess.run([sys.executable, str(HERE.parent / "scripts/make-skfem-tube.py"),
                    "--n-theta", str(a.n_theta), "--n-z", str(a.n_z), "--no-eigen",
                    "-o", str(work / "tube")], check=True)
    body = work / "tube"
    g = tube.geometry(tube.argparse.Namespace(
        tube_od_mm=320.0, tube_id_mm=280.0, tube_length_mm=1600.0, head_mm=40.0,
        journal_od_mm=120.0, journal_length_mm=100.0, bore_mm=50.0))
    m2, _ = tube.mesh(g, a.n_theta, a.n_z, 1)
    basis = Basis(m2, ElementVector(ElementHex2()))
    lam, mu = lame_parameters(tube.E, tube.NU)
    k = scipy.io.mmread(body / "stiffness.mtx").tocsr()
    m = scipy.io.mmread(body / "mass.mtx").tocsr()
    # The same node-major permutation as make-skfem-tube's assemble().
    comp = basis.split_indices()
    xyz = basis.doflocs[:, comp[0]].T
    order = np.lexsort((np.hypot(xyz[:, 0], xyz[:, 1]), np.arctan2(xyz[:, 1], xyz[:, 0]),
                        np.round(xyz[:, 2], 12)))
    perm = np.column_stack([c[order] for c in comp]).ravel()
    w_ref = 2 * np.pi * a.ref_hz

    @LinearForm
    def centrifugal(v, w):
        return tube.RHO * w_ref ** 2 * (w.x[0] * v[0] + w.x[1] * v[1])

    f = asm(centrifugal, basis)[perm]
    nodes = np.loadtxt(body / "nodes.csv", delimiter=",", skiprows=1)[:, 1:]
    tol = 1e-9 * g["r_out"]
    total = nodes[:, 2].max()
    held = np.concatenate([tube.ring(nodes, zz, g["r_journal"], tol)
                           for zz in (g["l_journal"] / 2, total - g["l_journal"] / 2)])
    fixed = (3 * held[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(k.shape[0]), fixed)
    u = np.zeros(k.shape[0])
    u[free] = spla.spsolve(k[free][:, free].tocsc(), f[free])
    u_skfem = np.zeros_like(u)
    u_skfem[perm] = u
    pre = basis.interpolate(u_skfem)

    @BilinearForm
    def geometric(uu, vv, w):
        e = sym_grad(w["pre"])
        s = 2 * mu * e + lam * trace(e) * np.eye(3)[:, :, None, None]
        return np.einsum("ij...,ki...,kj...->...", s, grad(uu), grad(vv))

    dk = asm(geometric, basis, pre=pre)[perm][:, perm].tocsr()
    dk = 0.5 * (dk + dk.T)
    scipy.io.mmwrite(body / "stress.mtx", sp.tril(dk).tocoo(), comment=" units: SI",
                     field="real", symmetry="symmetric", precision=17)
    scene = (body / "journals.toml").read_text().replace(
        'units = "SI"', f'units = "SI"\nstress_stiffness = "stress.mtx"\n'
        f'stress_stiffness_kind = "increment"\nstress_reference_hz = {a.ref_hz!r}', 1)
    (body / "stressed.toml").write_text(scene)
    nb = len(fixed)
    kf, mf, dkf = (x[free][:, free].tocsc() for x in (k, m, dk))
    print(f"tube: {k.shape[0]} DOFs, {nb} journal DOFs held; centrifugal prestress at "
          f"{a.ref_hz} Hz: largest |u| {np.abs(u).max():.3e} m")
    reduced = {}
    for n in a.normal:
        out = work / f"out{n}"
        subprocess.run([binary, "reduce", str(body / "stressed.toml"), "--normal", str(n),
                        "-o", str(out)], check=True, stdout=subprocess.DEVNULL)
        reduced[n] = [scipy.io.mmread(out / x).toarray()[nb:, nb:] for x in
                      ("stiffness.mtx", "mass.mtx", "stress_stiffness.mtx")]
    for ratio in (0.0, 1.0, 3.0):
        whole = spla.eigsh(kf + ratio ** 2 * dkf, k=a.modes, M=mf, sigma=0.0, which="LM",
                           tol=0, return_eigenvectors=False)
        whole = np.sqrt(np.sort(whole)) / (2 * np.pi)
        line = [f"Omega/Omega_ref = {ratio}: whole model {whole[0]:.3f}-{whole[-1]:.3f} Hz"]
        for n, (kh, mh, kh_s) in reduced.items():
            lam_r = scipy.linalg.eigh(kh + (ratio * w_ref) ** 2 * kh_s, mh,
                                      eigvals_only=True)[:a.modes]
            red = np.sqrt(lam_r) / (2 * np.pi)
            line.append(f"on {n} modes {red[0]:.3f}-{red[-1]:.3f} Hz, largest relative "
                        f"difference {np.abs(red / whole - 1).max():.2e}")
        print("; ".join(line))


if __name__ == "__main__":
    main()
