#!/usr/bin/env python3
"""Writes an FE body exported by rotorsweep as Nastran files with pyNastran, an independent
writer, for the DMIG and OP4 import of rotorsweep's [fe] (format = "dmig" | "op4").

In: DIR, the folder `rotorsweep export SCENE --model full -o DIR` wrote (mass.mtx,
stiffness.mtx: Matrix Market, SI; dofs.csv: index,node,dof; scene.toml: the scene on them).
Out, in DIR (SI units, as the export):
- `dmig.bdf`: the mass as DMIG `MAAX` and the stiffness as `KAAX`, symmetric (IFO 6), real
  double precision (TIN 2), one triangle (row DOF index <= column DOF index), each DOF its
  node id (GRID) and component 1-6 from dofs.csv; written by pyNastran's BDF writer
  (`BDF.add_dmig`, `write_bdf`), which writes TIN 2 matrices in large field (`DMIG*`, values
  in 16 characters with a D exponent: 11 significant digits);
- `dense.op4`: MAAX and KAAX in ASCII OUTPUT4, dense columns (`pyNastran.op4` `write_op4`,
  is_binary=False; 1P,3E23.16: 17 significant digits);
- `bigmat.op4`: the same as BIGMAT sparse strings (pyNastran's sparse ASCII writer
  `_write_sparse_matrix_ascii` with is_big_mat=True; its public `write_op4` always writes the
  non-BIGMAT string format, whose string headers it gives the column's length instead of the
  string's, which rotorsweep refuses for a column of several strings);
- `dmig-mass.mtx`, `dmig-stiffness.mtx`: MAAX and KAAX as pyNastran reads dmig.bdf back
  (`BDF.read_bdf`, `DMIG.get_matrix` with its symmetry applied), in dofs.csv's row order,
  Matrix Market (scipy.io.mmwrite, 17 significant digits): the matrices the DMIG file holds,
  rounded to its 11 digits, for a comparison that the rounding does not blur;
- `dmig.toml`, `dmig-readback.toml`, `dense-op4.toml`, `bigmat-op4.toml`: scene.toml with its
  [fe] on those files (`mass_matrix = "MAAX"`, `stiffness_matrix = "KAAX"`; the OP4 and
  read-back scenes keep dofs.csv, the DMIG one drops it), everything else unchanged (the
  [fe.rotating] terms stay the export's Matrix Market files).
Method: scipy.io.mmread of the two matrices, tomlkit for the scenes. pyNastran 1.4.1 (PyPI)
declares numpy<2, and its BDF module uses np.in1d, which numpy 2.4 removed: the script aliases
np.in1d to np.isin (the same function under its current name) before importing it.

Usage: make-nastran-files.py DIR
"""

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.io
import scipy.sparse as sp
import tomlkit

if not hasattr(np, "in1d"):
    np.in1d = np.isin
from pyNastran.bdf.bdf import BDF  # noqa: E402
from pyNastran.op4.op4 import OP4, _write_sparse_matrix_ascii  # noqa: E402

DOF_NUMBER = {"ux": 1, "uy": 2, "uz": 3, "rx": 4, "ry": 5, "rz": 6}


def read_body(d):
    """M, K (dense, SI) and each row's (node id, component 1-6)."""
    m = scipy.io.mmread(d / "mass.mtx").toarray()
    k = scipy.io.mmread(d / "stiffness.mtx").toarray()
    dofs = pd.read_csv(d / "dofs.csv").sort_values("index")
    assert list(dofs["index"]) == list(range(1, len(dofs) + 1)), "dofs.csv names every row"
    grid = [(int(n), DOF_NUMBER[str(c)]) for n, c in zip(dofs["node"], dofs["dof"])]
    return m, k, grid


def write_dmig(path, matrices, grid):
    """DMIG cards of the symmetric matrices (module doc)."""
    model = BDF(debug=None)
    for name, a in matrices.items():
        gcj, gci, real = [], [], []
        for j in range(a.shape[1]):
            for i in range(j + 1):
                if a[i, j] != 0.0:
                    gcj.append(grid[j])
                    gci.append(grid[i])
                    real.append(float(a[i, j]))
        model.add_dmig(name, 6, 2, 0, 0, None, GCj=gcj, GCi=gci, Real=real)
    model.write_bdf(str(path), size=16, is_double=True)


def write_readback(d, grid):
    """dmig-mass.mtx and dmig-stiffness.mtx: dmig.bdf as pyNastran reads it (module doc)."""
    model = BDF(debug=None)
    model.read_bdf(str(d / "dmig.bdf"), punch=True)
    at = {g: i for i, g in enumerate(grid)}
    for name, out in [("MAAX", "dmig-mass.mtx"), ("KAAX", "dmig-stiffness.mtx")]:
        a, rows, cols = model.dmig[name].get_matrix(is_sparse=False, apply_symmetry=True)
        b = np.zeros((len(grid), len(grid)))
        for i, gi in rows.items():
            for j, gj in cols.items():
                b[at[(int(gi[0]), int(gi[1]))], at[(int(gj[0]), int(gj[1]))]] = a[i, j]
        scipy.io.mmwrite(str(d / out), sp.coo_matrix(b), comment="units: SI", precision=17,
                         symmetry="symmetric")


def write_op4(d, matrices):
    """dense.op4 and bigmat.op4 (module doc)."""
    OP4().write_op4(str(d / "dense.op4"), {n: (6, a) for n, a in matrices.items()},
                    name_order=list(matrices), is_binary=False)
    with open(d / "bigmat.op4", "w") as f:
        for n, a in matrices.items():
            _write_sparse_matrix_ascii(f, n, sp.coo_matrix(a), form=6, is_big_mat=True)


def write_scene(d, out, fe_changes, drop):
    scene = tomlkit.parse((d / "scene.toml").read_text())
    fe = scene["fe"]
    for key in drop:
        if key in fe:
            del fe[key]
    for key, value in fe_changes.items():
        fe[key] = value
    (d / out).write_text(tomlkit.dumps(scene))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("dir", type=Path, help="a folder of `rotorsweep export --model full`")
    a = p.parse_args()
    m, k, grid = read_body(a.dir)
    matrices = {"MAAX": m, "KAAX": k}
    write_dmig(a.dir / "dmig.bdf", matrices, grid)
    write_readback(a.dir, grid)
    write_op4(a.dir, matrices)
    names = {"mass_matrix": "MAAX", "stiffness_matrix": "KAAX"}
    write_scene(a.dir, "dmig.toml",
                {"format": "dmig", "mass": "dmig.bdf", "stiffness": "dmig.bdf", **names},
                ["dofs"])
    write_scene(a.dir, "dmig-readback.toml",
                {"mass": "dmig-mass.mtx", "stiffness": "dmig-stiffness.mtx"}, [])
    for kind in ["dense", "bigmat"]:
        write_scene(a.dir, f"{kind}-op4.toml",
                    {"format": "op4", "mass": f"{kind}.op4", "stiffness": f"{kind}.op4", **names},
                    [])
    print(f"{a.dir}: dmig.bdf (and as read back), dense.op4, bigmat.op4 and their scenes ({len(grid)} DOFs)",
          file=sys.stderr)


if __name__ == "__main__":
    main()
