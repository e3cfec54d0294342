//! Abaqus matrix files: `*MATRIX GENERATE` written with `*MATRIX OUTPUT, MASS=YES,
//! STIFFNESS=YES, FORMAT=COORDINATE` (one file per matrix, `*.mtx`).
//!
//! In: two files, the mass and the stiffness, each line `row node, row dof, column node, column
//! dof, value` (DOFs 1–6: u_x, u_y, u_z, θ_x, θ_y, θ_z; comment lines start with `*`), one
//! triangle or both; the node table, whose ids every line must name. Out: the two matrices'
//! [`Entries`] over the DOFs that occur in either file, ordered by node id then DOF, and those
//! DOFs; or an [`InputError`] naming the file and line (a line without five fields, a DOF
//! outside 1–6, a node the table lacks, an entry given twice, a value that is not a finite
//! number, an empty file). Method: two passes, the DOFs first, then the entries; an entry whose mirror is not in
//! the file is mirrored (symmetric storage), both given are kept (the symmetry checks of
//! [`super::body`] and [`super::sparse_body`] then compare them). A third file on the same DOFs (the stress stiffness)
//! is read by [`read_on`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::entries::Entries;
use super::tables::{Dof, Node};
use crate::error::{read_text, InputError};

type Entry = ((i64, usize), (i64, usize), f64);

/// The mass and stiffness matrices and their DOFs.
pub type Pair = (Entries, Entries, Vec<Dof>);

fn entries(
    path: &Path,
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<Vec<(usize, Entry)>, InputError> {
    let text = read_text(path)
        .map_err(|e| InputError::new(path, format!("cannot read the matrix file: {e}")))?;
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let no = i + 1;
        let l = l.trim();
        if l.is_empty() || l.starts_with('*') {
            continue;
        }
        let err = |r: String| InputError::new(path, r).at_line(no);
        let v: Vec<&str> = l.split(',').map(str::trim).collect();
        if v.len() != 5 {
            return Err(err(format!(
                "expected `row node, row dof, column node, column dof, value`, got `{l}`"
            )));
        }
        let node = |s: &str| -> Result<i64, InputError> {
            let id: i64 = s
                .parse()
                .map_err(|_| err(format!("node id `{s}` is not an integer")))?;
            if nodes.iter().any(|p| p.id == id) {
                Ok(id)
            } else {
                Err(err(format!(
                    "node {id} does not exist in the node table {}",
                    nodes_file.display()
                )))
            }
        };
        let dof = |s: &str| -> Result<usize, InputError> {
            s.parse::<usize>()
                .ok()
                .filter(|d| (1..=6).contains(d))
                .map(|d| d - 1)
                .ok_or_else(|| err(format!("DOF `{s}` is not one of 1-6")))
        };
        let x: f64 = v[4]
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| err(format!("value `{}` is not a finite number", v[4])))?;
        out.push((
            no,
            ((node(v[0])?, dof(v[1])?), (node(v[2])?, dof(v[3])?), x),
        ));
    }
    if out.is_empty() {
        return Err(InputError::new(path, "the file has no matrix entries"));
    }
    Ok(out)
}

fn assemble(
    path: &Path,
    e: &[(usize, Entry)],
    index: &BTreeMap<(i64, usize), usize>,
) -> Result<Entries, InputError> {
    let n = index.len();
    let mut given: BTreeMap<(usize, usize), (usize, f64)> = BTreeMap::new();
    for &(no, (r, c, x)) in e {
        let (i, j) = (index[&r], index[&c]);
        if let Some((first, _)) = given.insert((i, j), (no, x)) {
            return Err(InputError::new(
                path,
                format!(
                    "entry node {} dof {} × node {} dof {} is given twice (first on line {first})",
                    r.0,
                    r.1 + 1,
                    c.0,
                    c.1 + 1
                ),
            )
            .at_line(no));
        }
    }
    let mut entries = Vec::with_capacity(2 * given.len());
    for (&(i, j), &(_, x)) in &given {
        entries.push((i, j, x));
        if !given.contains_key(&(j, i)) {
            entries.push((j, i, x));
        }
    }
    Ok(Entries { n, entries })
}

/// Reads the mass and stiffness files (module doc).
pub fn read_pair(
    mass: &Path,
    stiffness: &Path,
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<Pair, InputError> {
    let em = entries(mass, nodes, nodes_file)?;
    let ek = entries(stiffness, nodes, nodes_file)?;
    let set: BTreeSet<(i64, usize)> = em
        .iter()
        .chain(&ek)
        .flat_map(|(_, (r, c, _))| [*r, *c])
        .collect();
    let index: BTreeMap<(i64, usize), usize> =
        set.iter().enumerate().map(|(i, &d)| (d, i)).collect();
    let dofs = set.iter().map(|&(node, dof)| Dof { node, dof }).collect();
    Ok((
        assemble(mass, &em, &index)?,
        assemble(stiffness, &ek, &index)?,
        dofs,
    ))
}

/// Reads one more matrix file (a stress stiffness) on the DOFs `dofs` of the pair already read
/// ([`read_pair`]); an entry on a DOF the pair does not have is an error naming its line.
pub fn read_on(
    path: &Path,
    dofs: &[Dof],
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<Entries, InputError> {
    let e = entries(path, nodes, nodes_file)?;
    let index: BTreeMap<(i64, usize), usize> = dofs
        .iter()
        .enumerate()
        .map(|(i, d)| ((d.node, d.dof), i))
        .collect();
    for &(no, (r, c, _)) in &e {
        if let Some(d) = [r, c].into_iter().find(|d| !index.contains_key(d)) {
            return Err(InputError::new(
                path,
                format!(
                    "node {} dof {} is not a DOF of the mass and stiffness matrices",
                    d.0,
                    d.1 + 1
                ),
            )
            .at_line(no));
        }
    }
    assemble(path, &e, &index)
}
