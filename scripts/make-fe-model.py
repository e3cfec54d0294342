#!/usr/bin/env python3
"""Writes a large synthetic FE body for `rotorsweep reduce` (timing and memory of the sparse
reduction): Matrix Market mass and stiffness, nodes.csv, dofs.csv and a scene.toml whose [fe]
table names the interface nodes.

In: the model kind and size, an output folder (new). Out, SI units (kg, m, N, s, rad):
- `chain`: a steel tube (outer 320 mm, inner 280 mm) of N nodes on the z axis, 6 DOFs each
  (ux uy uz rx ry rz), 3-D Euler-Bernoulli beam elements of length 10 mm: axial and torsion
  bars and two bending planes, consistent mass (Przemieniecki, Theory of Matrix Structural
  Analysis (1968), ch. 5 and 11). DOFs = 6 N. Interface: both end nodes and the middle one.
- `lattice`: a cubic lattice of nx x ny x nz nodes (spacing 10 mm, 3 translations each) joined
  by steel bars (cross-section 10 mm^2) along the edges and the face and body diagonals (13
  neighbours a node), lumped mass 0.01 kg a node. DOFs = 3 nx ny nz. Interface: three corner
  nodes of the z = 0 face and three of the far face. A 3-D pattern: the factor fills in far
  more than the chain's.
- `shell`: a roll's shell as a truss: a tube (outer 320 mm, inner 300 mm) of nodes on two
  cylinders (r = 150 and 160 mm), nt around (>= 16) and nz along, square cells of side
  h = 2 pi r/nt at the mean radius, about 4.8 m long (15 diameters) at any size,
  3 translations each, joined by steel bars (cross-section 10 mm^2) to their neighbours along
  the edges and the face and body diagonals of the grid (periodic around; 13 neighbours a node,
  as the lattice), the tube's steel mass lumped equally on the nodes. DOFs = 6 nt nz.
  Interface: three nodes 120 degrees apart on the outer cylinder at each end. Its graph is a
  surface two nodes thick, so its factor fills in as a 2-D mesh's: the pattern of a shell
  model's, which is what a roll's FE model is.
With `--nastran` the same matrices also as Nastran files with their scenes: `body.bdf` (DMIG
cards MAAX and KAAX, free field, IFO 6 (the lower triangle), TIN 2, values in their shortest
round-trip form) with `dmig.toml`, and `body.op4` (ASCII OUTPUT4, BIGMAT sparse strings, both
triangles, `1P,3E23.16`: 17 significant digits) with `op4.toml`: the same numbers as the
Matrix Market files, so `rotorsweep reduce` gives the same reduction from each.
Method: numpy and scipy.sparse (duplicates summed), scipy.io.mmwrite's lower triangle with a
`% units: SI` line. Do not commit the output: 100 000 DOFs are some 100 MB of text.

Usage: make-fe-model.py chain --dofs 100000 -o DIR
       make-fe-model.py lattice --dofs 100000 [--nastran] -o DIR
       make-fe-model.py shell --dofs 500000 -o DIR
"""

import argparse
import sys
from pathlib import Path

import numpy as np
import scipy.io
import scipy.sparse as sp

E, NU, RHO = 210e9, 0.3, 7850.0


def beam_element(length):
    """The 12 x 12 stiffness and mass of a tube beam along z, DOFs (ux uy uz rx ry rz) x 2."""
    ro, ri = 0.16, 0.14
    area = np.pi * (ro**2 - ri**2)
    inertia = np.pi * (ro**4 - ri**4) / 4.0
    polar = 2.0 * inertia
    g = E / (2.0 * (1.0 + NU))
    L = length
    kb = E * inertia / L**3 * np.array(
        [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
         [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])
    mb = RHO * area * L / 420.0 * np.array(
        [[156, 22 * L, 54, -13 * L], [22 * L, 4 * L**2, 13 * L, -3 * L**2],
         [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    bar_m = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0
    k = np.zeros((12, 12))
    m = np.zeros((12, 12))
    # Bending in x-z: (ux, ry), theta = dux/dz; in y-z: (uy, rx), theta = -duy/dz.
    for (u, r, s) in [(0, 4, 1.0), (1, 3, -1.0)]:
        idx = [u, r, u + 6, r + 6]
        sign = np.array([1.0, s, 1.0, s])
        k[np.ix_(idx, idx)] += kb * np.outer(sign, sign)
        m[np.ix_(idx, idx)] += mb * np.outer(sign, sign)
    for d, kk, mm in [(2, E * area / L, RHO * area * L), (5, g * polar / L, RHO * polar * L)]:
        idx = [d, d + 6]
        k[np.ix_(idx, idx)] += kk * bar
        m[np.ix_(idx, idx)] += mm * bar_m
    return k, m


def chain(dofs):
    n = max(dofs // 6, 3)
    L = 0.01
    ke, me = beam_element(L)
    ne = n - 1
    base = 6 * np.arange(ne)[:, None] + np.arange(12)[None, :]
    rows = np.repeat(base, 12, axis=1).ravel()
    cols = np.tile(base, (1, 12)).ravel()
    k = sp.coo_matrix((np.tile(ke.ravel(), ne), (rows, cols)), shape=(6 * n, 6 * n)).tocsr()
    m = sp.coo_matrix((np.tile(me.ravel(), ne), (rows, cols)), shape=(6 * n, 6 * n)).tocsr()
    xyz = np.zeros((n, 3))
    xyz[:, 2] = L * np.arange(n)
    node_dofs = np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)
    named = {"end_a": 0, "middle": n // 2, "end_b": n - 1}
    return k, m, xyz, node_dofs, named


def lattice(dofs):
    nodes = max(dofs // 3, 8)
    nx = ny = max(int(round((nodes / 4) ** (1 / 3))), 2)
    nz = max(nodes // (nx * ny), 2)
    h, area, mass = 0.01, 1e-5, 0.01
    ids = np.arange(nx * ny * nz).reshape(nx, ny, nz)
    xyz = np.stack(np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"),
                   axis=-1).reshape(-1, 3) * h
    offsets = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1),
               (0, 1, 1), (0, 1, -1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (1, -1, -1)]
    rows, cols, vals = [], [], []
    for o in offsets:
        sl_a = tuple(slice(max(0, -d), n - max(0, d)) for d, n in zip(o, (nx, ny, nz)))
        sl_b = tuple(slice(max(0, d), n - max(0, -d)) for d, n in zip(o, (nx, ny, nz)))
        a, b = ids[sl_a].ravel(), ids[sl_b].ravel()
        e = np.array(o, float) / np.linalg.norm(o)
        kbar = E * area / (h * np.linalg.norm(o))
        block = kbar * np.outer(e, e)
        for (p, q, s) in [(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)]:
            for i in range(3):
                for j in range(3):
                    if block[i, j] != 0.0:
                        rows.append(3 * p + i)
                        cols.append(3 * q + j)
                        vals.append(np.full(p.size, s * block[i, j]))
    n = 3 * ids.size
    k = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n)).tocsr()
    m = sp.identity(n, format="csr") * mass
    node_dofs = np.repeat(np.arange(ids.size), 3), np.tile(np.arange(3), ids.size)
    named = {"a0": ids[0, 0, 0], "a1": ids[-1, 0, 0], "a2": ids[0, -1, 0],
             "b0": ids[0, 0, -1], "b1": ids[-1, 0, -1], "b2": ids[0, -1, -1]}
    return k, m, xyz, node_dofs, named


def bars(xyz, pairs, area):
    """K of steel bars of cross-section `area` joining the node pairs (a, b) (index arrays) at
    coordinates `xyz`: E A / l e e^T on each end's translations (e the unit vector a -> b)."""
    a, b = pairs
    d = xyz[b] - xyz[a]
    length = np.linalg.norm(d, axis=1)
    e = d / length[:, None]
    kbar = E * area / length
    rows, cols, vals = [], [], []
    for (p, q, s) in [(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)]:
        for i in range(3):
            for j in range(3):
                rows.append(3 * p + i)
                cols.append(3 * q + j)
                vals.append(s * kbar * e[:, i] * e[:, j])
    n = 3 * len(xyz)
    k = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n)).tocsr()
    k.eliminate_zeros()  # e_i e_j of a bar along an axis
    return k


def shell(dofs):
    """The `shell` kind (module doc)."""
    nodes = max(dofs // 3, 64)
    radii = np.array([0.150, 0.160])
    # square cells at the mean radius, a 4.8 m tube (15 diameters): nz h = 4.8, nt h = 2 pi r
    aspect = 4.8 / (2 * np.pi * radii.mean())
    nt = max(16, int(round(np.sqrt(nodes / (2 * aspect)))))
    nz = max(2, nodes // (2 * nt))
    h = 2 * np.pi * radii.mean() / nt
    t, z, r = np.meshgrid(np.arange(nt), np.arange(nz), np.arange(2), indexing="ij")
    ids = (t * nz + z) * 2 + r
    ang = 2 * np.pi * t / nt
    xyz = np.zeros((ids.size, 3))
    xyz[ids.ravel(), 0] = (radii[r] * np.cos(ang)).ravel()
    xyz[ids.ravel(), 1] = (radii[r] * np.sin(ang)).ravel()
    xyz[ids.ravel(), 2] = (h * z).ravel()
    offsets = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1), (1, 0, -1),
               (0, 1, 1), (0, 1, -1), (1, 1, 1), (1, 1, -1), (1, -1, 1), (1, -1, -1)]
    pa, pb = [], []
    for o in offsets:
        # around: periodic (every t has a neighbour t + o[0] mod nt); along and through: bounded
        sl_a = (slice(None),) + tuple(slice(max(0, -d), n - max(0, d))
                                      for d, n in zip(o[1:], (nz, 2)))
        sl_b = (slice(None),) + tuple(slice(max(0, d), n - max(0, -d))
                                      for d, n in zip(o[1:], (nz, 2)))
        pa.append(ids[sl_a].ravel())
        pb.append(np.roll(ids, -o[0], axis=0)[sl_b].ravel())
    k = bars(xyz, (np.concatenate(pa), np.concatenate(pb)), 1e-5)
    length = h * (nz - 1)
    mass = RHO * np.pi * (0.160**2 - 0.150**2) * length / ids.size
    n = 3 * ids.size
    m = sp.identity(n, format="csr") * mass
    node_dofs = np.repeat(np.arange(ids.size), 3), np.tile(np.arange(3), ids.size)
    third = nt // 3
    named = {"a0": ids[0, 0, 1], "a1": ids[third, 0, 1], "a2": ids[2 * third, 0, 1],
             "b0": ids[0, -1, 1], "b1": ids[third, -1, 1], "b2": ids[2 * third, -1, 1]}
    return k, m, xyz, node_dofs, named


def write_dmig(path, mats, node, dof):
    """DMIG cards (module doc): one column card per column, two entries a continuation."""
    with open(path, "w") as f:
        f.write("$ units: SI\n")
        for name, mat in mats:
            low = sp.tril(mat).tocsc()
            low.eliminate_zeros()
            f.write(f"DMIG,{name},0,6,2,0\n")
            for j in range(low.shape[0]):
                rows = low.indices[low.indptr[j]:low.indptr[j + 1]]
                vals = low.data[low.indptr[j]:low.indptr[j + 1]]
                if len(rows) == 0:
                    continue
                cells = [f"{node[i] + 1},{dof[i] + 1},{float(v)!r},"
                         for i, v in zip(rows, vals)]
                lines = [",".join(cells[:1])] + [",".join(cells[n:n + 2])
                                                  for n in range(1, len(cells), 2)]
                f.write(f"DMIG,{name},{node[j] + 1},{dof[j] + 1},," + "\n,".join(lines) + "\n")


def write_op4(path, mats):
    """ASCII OP4, BIGMAT sparse strings (module doc): each run of consecutive non-zero rows of a
    column is a string, its header L + 1 and IROW (L in words, two per value)."""
    with open(path, "w") as f:
        for name, mat in mats:
            # Both triangles from the lower one (the one the other files hold): an assembled
            # matrix's triangles may differ in the last bits.
            low = sp.tril(mat).tocsr()
            low.eliminate_zeros()
            full = (low + sp.tril(low, -1).T).tocsc()
            full.sort_indices()
            n = full.shape[0]
            f.write(f"{n:>8}{-n:>8}{6:>8}{2:>8}{name:<8}1P,3E23.16\n")
            for j in range(n):
                rows = full.indices[full.indptr[j]:full.indptr[j + 1]]
                vals = full.data[full.indptr[j]:full.indptr[j + 1]]
                breaks = np.flatnonzero(np.diff(rows) != 1) + 1
                runs = list(zip(np.split(rows, breaks), np.split(vals, breaks)))
                nw = sum(2 + 2 * len(r) for r, _ in runs)
                f.write(f"{j + 1:>8}{0:>8}{nw:>8}\n")
                for r, v in runs:
                    f.write(f"{2 * len(r) + 1:>8}{r[0] + 1:>8}\n")
                    for c in range(0, len(v), 3):
                        f.write("".join(f"{x:23.16E}" for x in v[c:c + 3]) + "\n")
            f.write(f"{n + 1:>8}{1:>8}{1:>8}\n{1.0:23.16E}\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("kind", choices=["chain", "lattice", "shell"])
    p.add_argument("--dofs", type=int, required=True, help="about this many DOFs")
    p.add_argument("-o", "--output", type=Path, required=True, help="new folder")
    p.add_argument("--nastran", action="store_true", help="also DMIG and OP4 files and scenes")
    a = p.parse_args()
    if a.output.exists():
        sys.exit(f"{a.output}: exists")
    kinds = {"chain": chain, "lattice": lattice, "shell": shell}
    k, m, xyz, (node, dof), named = kinds[a.kind](a.dofs)
    a.output.mkdir(parents=True)
    for name, mat in [("stiffness.mtx", k), ("mass.mtx", m)]:
        low = sp.tril(mat).tocsr()
        low.eliminate_zeros()
        scipy.io.mmwrite(a.output / name, low.tocoo(), comment=" units: SI",
                         field="real", symmetry="symmetric")
    with open(a.output / "nodes.csv", "w") as f:
        f.write("id,x,y,z\n")
        np.savetxt(f, np.column_stack([np.arange(1, len(xyz) + 1), xyz]),
                   fmt=["%d", "%.17g", "%.17g", "%.17g"], delimiter=",")
    names = np.array(["ux", "uy", "uz", "rx", "ry", "rz"])
    with open(a.output / "dofs.csv", "w") as f:
        f.write("index,node,dof\n")
        for i, (nd, d) in enumerate(zip(node + 1, names[dof]), start=1):
            f.write(f"{i},{nd},{d}\n")
    named_text = ", ".join(f"{k} = {v + 1}" for k, v in named.items())
    (a.output / "scene.toml").write_text(
        f'name = "{a.kind}-{k.shape[0]}"\n[fe]\nmass = "mass.mtx"\nstiffness = "stiffness.mtx"\n'
        f'nodes = "nodes.csv"\ndofs = "dofs.csv"\nunits = "SI"\nnamed = {{ {named_text} }}\n')
    if a.nastran:
        write_dmig(a.output / "body.bdf", [("MAAX", m), ("KAAX", k)], node, dof)
        write_op4(a.output / "body.op4", [("MAAX", m), ("KAAX", k)])
        names = 'mass_matrix = "MAAX"\nstiffness_matrix = "KAAX"\n'
        for fmt, file, dofs in [("dmig", "body.bdf", ""), ("op4", "body.op4",
                                                           'dofs = "dofs.csv"\n')]:
            (a.output / f"{fmt}.toml").write_text(
                f'name = "{a.kind}-{k.shape[0]}-{fmt}"\n[fe]\nformat = "{fmt}"\n'
                f'mass = "{file}"\nstiffness = "{file}"\n{names}nodes = "nodes.csv"\n{dofs}'
                f'units = "SI"\nnamed = {{ {named_text} }}\n')
    print(f"{a.output}: {a.kind}, {k.shape[0]} DOFs, {sp.tril(k).nnz} + {sp.tril(m).nnz} "
          f"stored entries (K, M lower triangles)")


if __name__ == "__main__":
    main()
