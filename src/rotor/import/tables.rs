//! The node and DOF tables of an imported FE body, and the unit systems its files are in.
//!
//! In: `nodes.csv` with the columns `id,x,y,z` (node id, coordinates in the unit system's
//! length) and `dofs.csv` with `index,node,dof` (1-based matrix row, node id, DOF name `ux uy uz
//! rx ry rz` or the FE codes' numbers 1–6). Out: the [`Node`]s in SI (m) and the [`Dof`] of each
//! matrix row, or an [`InputError`] naming the file, line and column (a missing or repeated
//! node, a row given twice or not at all, a DOF name that is none of the six, a node the DOF
//! table names that the node table lacks). Method: the `csv` crate, line by line.

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::InputError;

/// The unit system of an FE body's files (the scene says which; a file's `% units:` comment
/// must agree).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// kg, m, N, s, rad.
    Si,
    /// t, mm, N, s, rad (ANSYS and Abaqus models in millimetres).
    MmTonne,
}

impl Units {
    /// Parses the scene's name of a unit system: `SI` or `mm-t-s`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "SI" | "si" => Ok(Units::Si),
            "mm-t-s" => Ok(Units::MmTonne),
            _ => Err(format!(
                "`{s}`: expected `SI` (kg, m, N, s) or `mm-t-s` (t, mm, N, s)"
            )),
        }
    }

    /// The name a `% units:` comment uses.
    pub fn name(self) -> &'static str {
        match self {
            Units::Si => "SI",
            Units::MmTonne => "mm-t-s",
        }
    }

    /// Metres per length unit.
    pub fn length(self) -> f64 {
        match self {
            Units::Si => 1.0,
            Units::MmTonne => 1e-3,
        }
    }

    /// Kilograms per mass unit (the stiffness scales the same way: N/mm = 1e3 N/m = t/s²).
    pub fn mass(self) -> f64 {
        match self {
            Units::Si => 1.0,
            Units::MmTonne => 1e3,
        }
    }
}

/// A node of the body, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// The FE code's node id.
    pub id: i64,
    /// Position [m].
    pub x: [f64; 3],
}

/// What a matrix row is: a node's DOF, 0–2 translations x, y, z, 3–5 rotations about x, y, z.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dof {
    /// The node's id.
    pub node: i64,
    /// 0..6: ux, uy, uz, rx, ry, rz.
    pub dof: usize,
}

/// The DOF names in the order of their numbers.
pub const DOF_NAMES: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];

/// Parses a DOF name (`ux` … `rz`) or an FE code's number 1–6.
pub fn dof_number(s: &str) -> Option<usize> {
    let s = s.trim();
    DOF_NAMES
        .iter()
        .position(|n| n.eq_ignore_ascii_case(s))
        .or_else(|| {
            s.parse::<usize>()
                .ok()
                .filter(|d| (1..=6).contains(d))
                .map(|d| d - 1)
        })
}

fn reader(
    path: &Path,
    what: &str,
    columns: &[&str],
) -> Result<csv::Reader<std::fs::File>, InputError> {
    crate::error::regular_file(path, crate::error::MAX_INPUT_BYTES)
        .map_err(|e| InputError::new(path, format!("cannot read the {what}: {e}")))?;
    let mut r = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| InputError::new(path, format!("cannot read the {what}: {e}")))?;
    let head: Vec<String> = r
        .headers()
        .map_err(|e| InputError::new(path, format!("cannot read the {what}: {e}")))?
        .iter()
        .map(str::to_string)
        .collect();
    if head != columns {
        return Err(InputError::new(
            path,
            format!(
                "the {what} needs the columns {}, found {}",
                columns.join(","),
                head.join(",")
            ),
        )
        .at_line(1));
    }
    Ok(r)
}

fn records(
    path: &Path,
    r: csv::Reader<std::fs::File>,
) -> impl Iterator<Item = Result<(usize, csv::StringRecord), InputError>> + '_ {
    r.into_records().map(move |rec| {
        let rec = rec.map_err(|e| InputError::new(path, e.to_string()))?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        Ok((line, rec))
    })
}

/// Reads the node table (module doc); coordinates scaled to metres.
pub fn read_nodes(path: &Path, units: Units) -> Result<Vec<Node>, InputError> {
    let r = reader(path, "node table", &["id", "x", "y", "z"])?;
    let mut nodes = Vec::new();
    let mut ids = BTreeMap::new();
    for rec in records(path, r) {
        let (line, rec) = rec?;
        let err = |reason: String| InputError::new(path, reason).at_line(line);
        let id: i64 = rec[0]
            .parse()
            .map_err(|_| err(format!("node id `{}` is not an integer", &rec[0])))?;
        let mut x = [0.0; 3];
        for (k, v) in x.iter_mut().enumerate() {
            *v = rec[k + 1]
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    err(format!(
                        "node {id}: coordinate `{}` is not a finite number",
                        &rec[k + 1]
                    ))
                })?
                * units.length();
        }
        if let Some(first) = ids.insert(id, line) {
            return Err(err(format!(
                "node {id} is given twice (first on line {first})"
            )));
        }
        nodes.push(Node { id, x });
    }
    if nodes.is_empty() {
        return Err(InputError::new(path, "the node table has no nodes"));
    }
    Ok(nodes)
}

/// Reads the DOF table (module doc) of a matrix of size `n`; every node it names must be in
/// `nodes`.
pub fn read_dofs(
    path: &Path,
    n: usize,
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<Vec<Dof>, InputError> {
    let r = reader(path, "DOF table", &["index", "node", "dof"])?;
    let mut dofs: Vec<Option<(Dof, usize)>> = vec![None; n];
    let mut pairs = BTreeMap::new();
    let ids: std::collections::HashSet<i64> = nodes.iter().map(|p| p.id).collect();
    for rec in records(path, r) {
        let (line, rec) = rec?;
        let err = |reason: String| InputError::new(path, reason).at_line(line);
        let index = rec[0]
            .parse::<usize>()
            .ok()
            .filter(|i| (1..=n).contains(i))
            .ok_or_else(|| {
                err(format!(
                    "row `{}` does not exist: the matrices are {n} × {n} (rows are 1-based)",
                    &rec[0]
                ))
            })?;
        let node: i64 = rec[1]
            .parse()
            .map_err(|_| err(format!("node id `{}` is not an integer", &rec[1])))?;
        if !ids.contains(&node) {
            return Err(err(format!(
                "node {node} does not exist in the node table {}",
                nodes_file.display()
            )));
        }
        let dof = dof_number(&rec[2]).ok_or_else(|| {
            err(format!(
                "DOF `{}`: expected one of ux uy uz rx ry rz or 1-6",
                &rec[2]
            ))
        })?;
        if let Some((_, first)) = dofs[index - 1] {
            return Err(err(format!(
                "row {index} is given twice (first on line {first})"
            )));
        }
        if let Some(first) = pairs.insert((node, dof), line) {
            return Err(err(format!(
                "node {node} {} is given twice (first on line {first})",
                DOF_NAMES[dof]
            )));
        }
        dofs[index - 1] = Some((Dof { node, dof }, line));
    }
    dofs.iter()
        .enumerate()
        .map(|(i, d)| {
            d.map(|(d, _)| d).ok_or_else(|| {
                InputError::new(
                    path,
                    format!(
                        "row {} of the {n} × {n} matrices has no line: the DOF table must name every row",
                        i + 1
                    ),
                )
            })
        })
        .collect()
}
