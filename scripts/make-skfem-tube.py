#!/usr/bin/env python3
"""Builds an independent FE model of a roll with scikit-fem: a solid steel tube closed by heads
on hollow journals, meshed with 27-node hexahedra (linear elasticity), and writes it in the
format rotorsweep's [fe] import reads, with scipy's own eigenvalues for comparison.

In (command line; lengths in mm): the geometry (tube outer/inner diameter and length, head
thickness, journal outer diameter, length and bore), the mesh (cells around, along the tube,
through each radial band) and an output folder (new). Material: steel, E 210 GPa, nu 0.3,
rho 7850 kg/m^3.
Out, SI units (kg, m, N, s):
- `mass.mtx`, `stiffness.mtx`: M and K, Matrix Market `coordinate real symmetric` (lower
  triangle, `% units: SI`), rows node-major (node 1 ux uy uz, node 2 ...);
- `nodes.csv` (`id,x,y,z`), `dofs.csv` (`index,node,dof`);
- `scene.toml`: an [fe] body with the rings `journal_tending`, `journal_drive` (the journals'
  outer surface at their mid-length) and `centre` (the tube's outer surface at mid-length),
  given by position (`z`, `radius`), for `rotorsweep reduce`;
- `journals.toml`: the same body with the two journal rings only (its fixed-interface modes
  are the body on its journals with every DOF of their rings fixed);
- `supported.toml`: a scene on the body (`extends = "scene.toml"`): linear supports of
  SUPPORT_N_PER_M in x and y on the two journal rings' reference points (the RBE3 mean of
  each ring), the drive's axial spring of the same stiffness on `journal_tending`, the sensor
  `centre` (the centre ring's mean lateral displacement), and every mode of the Craig–Bampton
  set (40 normal modes + all interface DOFs), for `rotorsweep check|modes|linear|simulate`;
- `beam.toml`: rotorsweep's own beam model ([rotor] segments) of the same geometry on stiff
  linear supports at the journals' mid-length;
- `eigen.json` (unless --no-eigen): scipy's eigenvalues: `free_hz` (free-free, the rigid-body
  modes near 0) and `supported_hz` (every DOF of the two journal rings fixed: the constraint
  `rotorsweep reduce` applies to its interface when the scene's interface is those rings), the
  ring node ids, DOF count and the mesh parameters.
Method: the cross-section is a union of annular bands on one radial grid (bore, journal,
tube inner, tube outer radii), so journal, head and tube cells share their nodes; a structured
grid in (r, theta, z) is built with MeshHex1.init_tensor, cells without material removed, mapped
to x = r cos theta, y = r sin theta, the seam's duplicate nodes merged; MeshHex2.from_mesh adds
the edge, face and centre nodes, whose radius is then put back on the cylinder (a chord midpoint
at a half angle step lies at r cos(pi/n), so it is divided by that), giving isoparametric
quadratic geometry. K from skfem.models.elasticity.linear_elasticity with the Lame parameters,
M = rho u.v, both by skfem's Gauss quadrature (3 points a direction for ElementHex2).
Eigenvalues: scipy.sparse.linalg.eigsh in shift-invert mode (sigma = -(2 pi 1 Hz)^2 for the free
body, 0 for the supported one), tol = 0 (machine precision).

Usage: make-skfem-tube.py -o DIR [--n-theta 12 --n-z 8 --n-radial 1 --eigen 20]
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, ElementHex2, ElementVector, MeshHex1, MeshHex2, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

E, NU, RHO = 210e9, 0.3, 7850.0


def geometry(a):
    """Radii and axial stations [m] of the tube (module doc)."""
    g = {
        "r_bore": a.bore_mm / 2e3,
        "r_journal": a.journal_od_mm / 2e3,
        "r_in": a.tube_id_mm / 2e3,
        "r_out": a.tube_od_mm / 2e3,
        "l_journal": a.journal_length_mm / 1e3,
        "l_head": a.head_mm / 1e3,
        "l_tube": a.tube_length_mm / 1e3,
    }
    if not g["r_bore"] < g["r_journal"] < g["r_in"] < g["r_out"]:
        sys.exit("make-skfem-tube: needs bore < journal diameter < tube inner < tube outer")
    return g


def mesh(g, n_theta, n_z, n_radial):
    """The quadratic hexahedral mesh (MeshHex2) of the module doc, and the z of every station."""
    bands = [g["r_bore"], g["r_journal"], g["r_in"], g["r_out"]]
    r = np.concatenate([np.linspace(bands[i], bands[i + 1], n_radial + 1)[:-1]
                        for i in range(3)] + [[bands[3]]])
    lj, lh, lt = g["l_journal"], g["l_head"], g["l_tube"]
    z = np.concatenate([[0.0, lj, lj + lh], lj + lh + lt * np.arange(1, n_z + 1) / n_z,
                        [lj + 2 * lh + lt, 2 * lj + 2 * lh + lt]])
    m = MeshHex1.init_tensor(r, np.arange(n_theta + 1, dtype=float), z)
    c = m.p[:, m.t].mean(axis=1)  # cell centres in (r, theta index, z)
    in_journal = (c[2] < lj) | (c[2] > lj + 2 * lh + lt)
    in_head = ((c[2] > lj) & (c[2] < lj + lh)) | ((c[2] > lj + lh + lt) & (c[2] < lj + 2 * lh + lt))
    keep = np.where(in_head | (in_journal & (c[0] < g["r_journal"]))
                    | (~in_journal & (c[0] > g["r_in"])))[0]
    # The seam: a node at theta index n_theta is the node at index 0 with the same r and z.
    index = {(r, z): i for i, (r, th, z) in enumerate(m.p.T) if th == 0.0}
    seam = np.arange(m.p.shape[1])
    for i in np.where(m.p[1] == n_theta)[0]:
        seam[i] = index[(m.p[0, i], m.p[2, i])]
    step = 2 * np.pi / n_theta
    p = np.vstack([m.p[0] * np.cos(m.p[1] * step), m.p[0] * np.sin(m.p[1] * step), m.p[2]])
    m1 = MeshHex1(p, seam[m.t[:, keep]]).remove_unused_nodes()
    m2 = MeshHex2.from_mesh(m1)
    d = m2.doflocs.copy()
    angle = np.arctan2(d[1], d[0]) / step
    half = np.abs(angle - np.round(angle)) > 0.25
    d[:2, half] /= np.cos(step / 2)
    return MeshHex2(d, m2.t), z


def assemble(m2):
    """K and M (scipy CSR), the node coordinates and the node of each DOF (node-major order)."""
    basis = Basis(m2, ElementVector(ElementHex2()))
    lam, mu = lame_parameters(E, NU)
    k = asm(linear_elasticity(lam, mu), basis)

    @BilinearForm
    def mass(u, v, _):
        return RHO * dot(u, v)

    m = asm(mass, basis)
    comp = basis.split_indices()
    xyz = basis.doflocs[:, comp[0]].T
    for c in comp[1:]:
        if np.abs(basis.doflocs[:, c].T - xyz).max() > 1e-12:
            sys.exit("make-skfem-tube: the components' DOF locations differ")
    # Nodes sorted by z, then angle, then radius; the matrices permuted to node-major order.
    order = np.lexsort((np.hypot(xyz[:, 0], xyz[:, 1]), np.arctan2(xyz[:, 1], xyz[:, 0]),
                        np.round(xyz[:, 2], 12)))
    perm = np.column_stack([c[order] for c in comp]).ravel()
    k = k[perm][:, perm].tocsr()
    m = m[perm][:, perm].tocsr()
    return k, m, xyz[order]


def ring(xyz, z, radius, tol):
    """Indices of the nodes on the circle (z, radius)."""
    r = np.hypot(xyz[:, 0], xyz[:, 1])
    return np.where((np.abs(xyz[:, 2] - z) <= tol) & (np.abs(r - radius) <= tol))[0]


def beam_scene(g):
    """rotorsweep's beam model of the same body: journal, head, tube, head, journal."""
    mm = lambda x: f"{x * 1e3:.6g}"  # noqa: E731
    segs = [(g["l_journal"], g["r_journal"], g["r_bore"], 4),
            (g["l_head"], g["r_out"], g["r_bore"], 2),
            (g["l_tube"], g["r_out"], g["r_in"], 32),
            (g["l_head"], g["r_out"], g["r_bore"], 2),
            (g["l_journal"], g["r_journal"], g["r_bore"], 4)]
    text = ['name = "skfem-tube-beam"',
            'description = "rotorsweep beam model of scripts/make-skfem-tube.py\'s tube"',
            "[materials.steel]", f"youngs_modulus_gpa = {E / 1e9}", f"poisson = {NU}",
            f"density_kg_m3 = {RHO}", "[rotor]", "z_start_mm = 0.0"]
    for length, ro, ri, n in segs:
        text += ["[[rotor.segments]]", f"length_mm = {mm(length)}",
                 f"outer_diameter_mm = {mm(2 * ro)}", f"inner_diameter_mm = {mm(2 * ri)}",
                 f"elements = {n}", 'material = "steel"']
    total = 2 * g["l_journal"] + 2 * g["l_head"] + g["l_tube"]
    text += ["[rotor.nodes]", f"journal_tending = {mm(g['l_journal'] / 2)}",
             f"journal_drive = {mm(total - g['l_journal'] / 2)}"]
    for name in ["journal_tending", "journal_drive"]:
        text += ["[[supports]]", f'node = "{name}"', 'type = "linear"',
                 "spring = { kx_n_per_m = 1.0e12, ky_n_per_m = 1.0e12 }"]
    text += ["[drive]", 'node = "journal_tending"', "axial_stiffness_n_per_m = 1.0e9",
             "[reduction]", 'boundary = ["journal_tending", "journal_drive"]',
             'modes = "30n+12st"']
    return "\n".join(text) + "\n"


SUPPORT_N_PER_M = 1.0e9


def supported_scene(interface):
    """The tube on linear supports at its journal rings (module doc); `interface`: the number of
    interface DOFs (every DOF of the three rings' nodes), all kept as static modes."""
    text = ['name = "skfem-tube-supported"', 'extends = "scene.toml"',
            'description = "the scikit-fem tube on linear supports at its journal rings"',
            "[materials.steel]", f"youngs_modulus_gpa = {E / 1e9}", f"poisson = {NU}",
            f"density_kg_m3 = {RHO}", "[fe]", 'sensors = ["centre"]']
    for name in ["journal_tending", "journal_drive"]:
        text += ["[[supports]]", f'node = "{name}"', 'type = "linear"',
                 f"spring = {{ kx_n_per_m = {SUPPORT_N_PER_M}, ky_n_per_m = {SUPPORT_N_PER_M} }}"]
    text += ["[drive]", 'node = "journal_tending"', f"axial_stiffness_n_per_m = {SUPPORT_N_PER_M}",
             "[reduction]", f'modes = "40n+{interface}st"']
    return "\n".join(text) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("-o", "--output", type=Path, required=True, help="new folder")
    p.add_argument("--tube-od-mm", type=float, default=320.0)
    p.add_argument("--tube-id-mm", type=float, default=280.0)
    p.add_argument("--tube-length-mm", type=float, default=1600.0)
    p.add_argument("--head-mm", type=float, default=40.0, help="head thickness")
    p.add_argument("--journal-od-mm", type=float, default=120.0)
    p.add_argument("--journal-length-mm", type=float, default=100.0)
    p.add_argument("--bore-mm", type=float, default=50.0, help="bore of journals and heads")
    p.add_argument("--n-theta", type=int, default=12, help="cells around (>= 8)")
    p.add_argument("--n-z", type=int, default=8, help="cells along the tube (>= 2, even)")
    p.add_argument("--n-radial", type=int, default=1, help="cells through each radial band")
    p.add_argument("--eigen", type=int, default=20, help="eigenvalues scipy computes")
    p.add_argument("--no-eigen", action="store_true", help="write no eigen.json (large models)")
    a = p.parse_args()
    if a.output.exists():
        sys.exit(f"{a.output}: exists")
    if a.n_theta < 8 or a.n_z < 2 or a.n_z % 2 or a.n_radial < 1 or a.eigen < 1:
        sys.exit("make-skfem-tube: needs --n-theta >= 8, --n-z >= 2 and even, --n-radial >= 1, "
                 "--eigen >= 1")
    g = geometry(a)
    m2, z = mesh(g, a.n_theta, a.n_z, a.n_radial)
    k, m, xyz = assemble(m2)
    n = k.shape[0]
    tol = 1e-9 * g["r_out"]
    total = z[-1]
    rings = {"journal_tending": (g["l_journal"] / 2, g["r_journal"]),
             "journal_drive": (total - g["l_journal"] / 2, g["r_journal"]),
             "centre": (total / 2, g["r_out"])}
    ring_nodes = {name: ring(xyz, zz, rr, tol) for name, (zz, rr) in rings.items()}
    for name, nodes in ring_nodes.items():
        if len(nodes) != 2 * a.n_theta:
            sys.exit(f"make-skfem-tube: ring {name} has {len(nodes)} nodes, expected "
                     f"{2 * a.n_theta}")
    a.output.mkdir(parents=True)
    for name, mat in [("stiffness.mtx", k), ("mass.mtx", m)]:
        low = sp.tril(mat).tocoo()
        scipy.io.mmwrite(a.output / name, low, comment=" units: SI", field="real",
                         symmetry="symmetric", precision=17)
    with open(a.output / "nodes.csv", "w") as f:
        f.write("id,x,y,z\n")
        np.savetxt(f, np.column_stack([np.arange(1, len(xyz) + 1), xyz]),
                   fmt=["%d", "%.17g", "%.17g", "%.17g"], delimiter=",")
    with open(a.output / "dofs.csv", "w") as f:
        f.write("index,node,dof\n")
        for i in range(n):
            f.write(f"{i + 1},{i // 3 + 1},u{'xyz'[i % 3]}\n")
    scene = ['name = "skfem-tube"',
             'description = "scikit-fem solid tube with heads and journals '
             '(scripts/make-skfem-tube.py)"',
             "[fe]", 'format = "matrix-market"', 'mass = "mass.mtx"',
             'stiffness = "stiffness.mtx"', 'nodes = "nodes.csv"', 'dofs = "dofs.csv"',
             'units = "SI"', "named = {}"]
    journals = list(scene)
    for name, (zz, rr) in rings.items():
        ring_text = [f"[fe.rings.{name}]", f"z = {float(zz)!r}", f"radius = {float(rr)!r}"]
        scene += ring_text
        if name != "centre":
            journals += ring_text
    (a.output / "scene.toml").write_text("\n".join(scene) + "\n")
    (a.output / "journals.toml").write_text("\n".join(journals) + "\n")
    interface = 3 * sum(len(nodes) for nodes in ring_nodes.values())
    (a.output / "supported.toml").write_text(supported_scene(interface))
    (a.output / "beam.toml").write_text(beam_scene(g))
    info = {"dofs": n, "nodes": len(xyz), "elements": int(m2.t.shape[1]),
            "n_theta": a.n_theta, "n_z": a.n_z, "n_radial": a.n_radial,
            "rings": {name: [int(i) + 1 for i in nodes] for name, nodes in ring_nodes.items()}}
    if not a.no_eigen:
        sigma = -(2 * np.pi) ** 2
        lam = spla.eigsh(k.tocsc(), k=a.eigen, M=m.tocsc(), sigma=sigma, which="LM", tol=0,
                         return_eigenvectors=False)
        fixed = np.concatenate([3 * ring_nodes[s][:, None] + np.arange(3)
                                for s in ["journal_tending", "journal_drive"]]).ravel()
        free = np.setdiff1d(np.arange(n), fixed)
        ks, ms = k[free][:, free].tocsc(), m[free][:, free].tocsc()
        lam_s = spla.eigsh(ks, k=a.eigen, M=ms, sigma=0.0, which="LM", tol=0,
                           return_eigenvectors=False)
        to_hz = lambda v: [float(np.sqrt(max(x, 0.0)) / (2 * np.pi)) for x in np.sort(v)]  # noqa
        info["free_hz"] = to_hz(lam)
        info["supported_hz"] = to_hz(lam_s)
    (a.output / "eigen.json").write_text(json.dumps(info, indent=1) + "\n")
    print(f"{a.output}: {n} DOFs, {len(xyz)} nodes, {m2.t.shape[1]} elements, "
          f"{sp.tril(k).nnz} + {sp.tril(m).nnz} stored entries (K, M lower triangles)")


if __name__ == "__main__":
    main()
