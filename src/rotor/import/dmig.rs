//! Nastran DMIG matrices (direct matrix input at grid points): bulk-data cards as Nastran
//! punches them (`.pch`) or a deck carries them (`K2GG = KAAX`, `M2GG = MAAX`).
//!
//! In: bulk-data files ([`super::bulk`]: small, large `DMIG*` or free field, continuations)
//! holding DMIG matrices: a header card `DMIG NAME 0 IFO TIN TOUT POLAR _ NCOL` (IFO 6 =
//! symmetric, 1 = square; TIN 1 or 2, real single or double precision) and column cards
//! `DMIG NAME GJ CJ _ G1 C1 A1 B1` with continuations `G2 C2 A2 B2 G3 C3 A3 B3 …`: the entries
//! (row G_i C_i, column GJ CJ) = A_i, each DOF a GRID id and a component 1–6 (u_x, u_y, u_z,
//! θ_x, θ_y, θ_z); the matrix to read by name (the file's only DMIG if no name is given); the
//! node table, whose ids every GRID must be. Out: the mass and stiffness matrices' [`Entries`] over
//! the DOFs that occur in either, ordered by node id then component, with those DOFs
//! ([`read_pair`]), or a third matrix on the same DOFs ([`read_on`], the stress stiffness), in
//! the file's units, and the `$ units:` comment; or an [`InputError`] naming the file and the
//! line (and the scene key of the matrix name where it is at fault): no header, a header
//! given twice, a form other than 1 or 6, a complex matrix, a GRID the node table lacks, a
//! component outside 1–6 (a scalar point's 0 too), a value that is no number, a B field filled
//! in a real matrix or a field that does not parse (a value wider than its field), an entry
//! given twice, an entry with no value (a truncated file), a symmetric matrix whose two
//! triangles both give an entry and disagree, a square matrix that is not symmetric.
//! Method: the cards are read one at a time ([`bulk::for_each_card`]) and each column card's
//! entries kept as numbers, so the cards' text fields are never all held at once (only column
//! cards that come before their header card wait). MSC Nastran Quick Reference Guide, DMIG: a
//! symmetric matrix (IFO 6) gives each
//! off-diagonal entry in either triangle, mirrored here; both given must agree (to 1e-10 of
//! the largest entry; Nastran refuses both, rotorsweep accepts agreeing ones); a square one
//! (IFO 1) gives both, which must agree likewise. Other cards of a deck are skipped.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use super::bulk::{self, Card, Field, UnitsComment};
use super::entries::Entries;
use super::tables::{Dof, Node, DOF_NAMES};
use crate::error::{read_text_up_to, InputError};

/// The hint of an error where a field holds what belongs elsewhere.
const WIDTH: &str =
    "a field of the wrong width? (small field: 8 characters; large field, `DMIG*`: 16)";

/// Relative disagreement two mirror entries may have (of the matrix's largest entry).
const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// A DOF as a card gives it: GRID id, component 0..6.
type GridDof = (i64, usize);

/// One entry: row, column, value, line.
#[derive(Debug, Clone, Copy)]
struct Entry {
    row: GridDof,
    col: GridDof,
    x: f64,
    line: usize,
}

/// A DMIG matrix as read (module doc).
#[derive(Debug, Clone)]
struct Dmig {
    form: i64,
    line: usize,
    entries: Vec<Entry>,
}

fn dof_text(d: GridDof) -> String {
    format!("GRID {} component {} ({})", d.0, d.1 + 1, DOF_NAMES[d.1])
}

/// The file's DMIG matrices by name, read and checked (module doc), and its units comment.
fn read_file(
    path: &Path,
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<(BTreeMap<String, Dmig>, UnitsComment), InputError> {
    let text = read_text_up_to(path, bulk::MAX_BYTES)
        .map_err(|e| InputError::new(path, format!("cannot read the DMIG file: {e}")))?;
    let ids: std::collections::HashSet<i64> = nodes.iter().map(|n| n.id).collect();
    let mut out: BTreeMap<String, Dmig> = BTreeMap::new();
    // Column cards that come before their matrix's header card (read once the file is).
    let mut early: Vec<Card> = Vec::new();
    let units = bulk::for_each_card(path, &text, |c| {
        if c.name != "DMIG" {
            return Ok(());
        }
        let name = c.fields[0].text.to_ascii_uppercase();
        if name.is_empty() {
            return Err(InputError::new(path, "a DMIG card without a matrix name").at_line(c.line));
        }
        if integer(path, &c.fields[1], 3)? == Some(0) {
            let form = header(path, &c)?;
            if let Some(first) = out.get(&name) {
                return Err(InputError::new(
                    path,
                    format!(
                        "DMIG {name}: a second header card (the first on line {})",
                        first.line
                    ),
                )
                .at_line(c.line));
            }
            let m = Dmig {
                form,
                line: c.line,
                entries: Vec::new(),
            };
            out.insert(name, m);
        } else if let Some(m) = out.get_mut(&name) {
            column(path, &c, &ids, nodes_file, &mut m.entries)?;
        } else {
            early.push(c);
        }
        Ok(())
    })?;
    for c in early {
        let name = c.fields[0].text.to_ascii_uppercase();
        let m = out.get_mut(&name).ok_or_else(|| {
            InputError::new(
                path,
                format!(
                    "DMIG {name}: a column card but no header card (`DMIG {name} 0 IFO TIN …`)"
                ),
            )
            .at_line(c.line)
        })?;
        column(path, &c, &ids, nodes_file, &mut m.entries)?;
    }
    for (name, m) in &mut out {
        check(path, name, m)?;
    }
    Ok((out, units))
}

/// An integer field (blank: `None`); `number` is the card's field number for the error.
fn integer(path: &Path, f: &Field, number: usize) -> Result<Option<i64>, InputError> {
    if f.text.is_empty() {
        return Ok(None);
    }
    f.text.parse::<i64>().map(Some).map_err(|_| {
        InputError::new(
            path,
            format!(
                "{} holds `{}` where an integer belongs: {WIDTH}",
                f.place(number),
                f.text
            ),
        )
        .at_line(f.line)
    })
}

/// The form of a header card (module doc).
fn header(path: &Path, c: &Card) -> Result<i64, InputError> {
    let name = &c.fields[0].text;
    let at = |f: &Field, r: String| InputError::new(path, r).at_line(f.line);
    let form = integer(path, &c.fields[2], 4)?;
    let tin = integer(path, &c.fields[3], 5)?;
    match form {
        Some(1 | 6) => {}
        Some(f) => {
            return Err(at(
                &c.fields[2],
                format!(
                    "DMIG {name}: IFO = {f}; a mass or stiffness matrix is square: IFO 6 \
                     (symmetric) or 1 (square)"
                ),
            ))
        }
        None => {
            return Err(at(
                &c.fields[2],
                format!("DMIG {name}: the header has no IFO"),
            ))
        }
    }
    match tin {
        Some(1 | 2) => {}
        Some(t) => {
            return Err(at(
                &c.fields[3],
                format!("DMIG {name}: TIN = {t}; only real matrices (TIN 1 or 2) are read"),
            ))
        }
        None => {
            return Err(at(
                &c.fields[3],
                format!("DMIG {name}: the header has no TIN"),
            ))
        }
    }
    Ok(form.expect("checked"))
}

/// A GRID and component pair of fields as a DOF of the node table (module doc).
fn grid_dof(
    path: &Path,
    g: (&Field, usize),
    c: (&Field, usize),
    ids: &std::collections::HashSet<i64>,
    nodes_file: &Path,
) -> Result<GridDof, InputError> {
    let Some(id) = integer(path, g.0, g.1)? else {
        return Err(
            InputError::new(path, format!("no GRID id in {}: {WIDTH}", g.0.place(g.1)))
                .at_line(g.0.line),
        );
    };
    if !ids.contains(&id) {
        return Err(InputError::new(
            path,
            format!(
                "GRID {id} ({}) does not exist in the node table {}",
                g.0.place(g.1),
                nodes_file.display()
            ),
        )
        .at_line(g.0.line));
    }
    match integer(path, c.0, c.1)? {
        Some(k @ 1..=6) => Ok((id, k as usize - 1)),
        Some(k) => Err(InputError::new(
            path,
            format!(
                "GRID {id}: component {k} ({}) is not one of 1-6 (a scalar point's 0 is not \
                 read either)",
                c.0.place(c.1)
            ),
        )
        .at_line(c.0.line)),
        None => Err(InputError::new(
            path,
            format!("GRID {id}: no component ({})", c.0.place(c.1)),
        )
        .at_line(c.0.line)),
    }
}

/// The entries of a column card (module doc).
fn column(
    path: &Path,
    c: &Card,
    ids: &std::collections::HashSet<i64>,
    nodes_file: &Path,
    out: &mut Vec<Entry>,
) -> Result<(), InputError> {
    let f = &c.fields;
    let name = &f[0].text;
    let col = grid_dof(path, (&f[1], 3), (&f[2], 4), ids, nodes_file)?;
    if !f[3].text.is_empty() {
        return Err(InputError::new(
            path,
            format!(
                "DMIG {name}: {} holds `{}` but is blank on a column card: {WIDTH}",
                f[3].place(5),
                f[3].text
            ),
        )
        .at_line(f[3].line));
    }
    let mut count = 0;
    for q in (4..f.len()).step_by(4) {
        let quad: Vec<&Field> = (q..q + 4).filter_map(|k| f.get(k)).collect();
        if quad.iter().all(|x| x.text.is_empty()) {
            continue;
        }
        let number = |k: usize| q + k + 2;
        if quad[0].text.is_empty() {
            return Err(InputError::new(
                path,
                format!(
                    "DMIG {name}: {} is blank but the fields after it are not: {WIDTH}",
                    quad[0].place(number(0))
                ),
            )
            .at_line(quad[0].line));
        }
        let Some(a) = quad.get(2).filter(|a| !a.text.is_empty()) else {
            return Err(InputError::new(
                path,
                format!(
                    "DMIG {name}: the entry of GRID {} has no value: truncated file?",
                    quad[0].text
                ),
            )
            .at_line(quad.last().expect("one field").line));
        };
        let c_field = quad.get(1).copied().expect("a value field comes after it");
        let row = grid_dof(
            path,
            (quad[0], number(0)),
            (c_field, number(1)),
            ids,
            nodes_file,
        )?;
        let x = bulk::real(&a.text).ok_or_else(|| {
            InputError::new(
                path,
                format!(
                    "DMIG {name}: {} holds `{}`, not a finite number",
                    a.place(number(2)),
                    a.text
                ),
            )
            .at_line(a.line)
        })?;
        if let Some(b) = quad.get(3).filter(|b| !b.text.is_empty()) {
            return Err(InputError::new(
                path,
                format!(
                    "DMIG {name}: {} holds `{}`: a real matrix leaves its B fields blank; {WIDTH}",
                    b.place(number(3)),
                    b.text
                ),
            )
            .at_line(b.line));
        }
        out.push(Entry {
            row,
            col,
            x,
            line: a.line,
        });
        count += 1;
    }
    if count == 0 {
        return Err(InputError::new(
            path,
            format!(
                "DMIG {name}: the column card of {} has no entry: truncated file?",
                dof_text(col)
            ),
        )
        .at_line(c.line));
    }
    Ok(())
}

/// Entries given twice, mirror pairs that disagree, a square matrix not symmetric (module doc);
/// a symmetric matrix's pairs given twice keep one.
fn check(path: &Path, name: &str, m: &mut Dmig) -> Result<(), InputError> {
    if m.entries.is_empty() {
        return Err(InputError::new(
            path,
            format!("DMIG {name}: a header card but no column card: truncated file?"),
        )
        .at_line(m.line));
    }
    let scale = m.entries.iter().fold(0.0f64, |s, e| s.max(e.x.abs()));
    let mut at: HashMap<(GridDof, GridDof), usize> = HashMap::new();
    for (k, e) in m.entries.iter().enumerate() {
        if let Some(first) = at.insert((e.row, e.col), k) {
            return Err(InputError::new(
                path,
                format!(
                    "DMIG {name}: the entry {} × {} is given twice (first on line {})",
                    dof_text(e.row),
                    dof_text(e.col),
                    m.entries[first].line
                ),
            )
            .at_line(e.line));
        }
    }
    let mut drop = vec![false; m.entries.len()];
    for (k, e) in m.entries.iter().enumerate() {
        if e.row == e.col {
            continue;
        }
        let mirror = at.get(&(e.col, e.row)).map(|&j| m.entries[j]);
        if m.form == 6 && mirror.is_none() {
            // One triangle of a symmetric matrix: mirrored on assembly.
            continue;
        }
        let y = mirror.map_or(0.0, |o| o.x);
        if (e.x - y).abs() > SYMMETRY_TOLERANCE * scale {
            let reason = match (m.form, mirror) {
                (6, Some(o)) => format!(
                    "DMIG {name} (IFO 6, symmetric): the entry {} × {} = {:e} and its mirror on \
                     line {} = {:e} disagree: give each off-diagonal entry in one triangle",
                    dof_text(e.row),
                    dof_text(e.col),
                    e.x,
                    o.line,
                    o.x
                ),
                (_, Some(o)) => format!(
                    "DMIG {name} (IFO 1, square) is not symmetric: the entry {} × {} = {:e} but \
                     its mirror on line {} = {:e}",
                    dof_text(e.row),
                    dof_text(e.col),
                    e.x,
                    o.line,
                    o.x
                ),
                _ => format!(
                    "DMIG {name} (IFO 1, square) is not symmetric: the entry {} × {} = {:e} has \
                     no mirror entry (a mass or stiffness matrix is symmetric: give both \
                     triangles, or IFO 6 and one)",
                    dof_text(e.row),
                    dof_text(e.col),
                    e.x
                ),
            };
            let line = mirror.map_or(e.line, |o| o.line.max(e.line));
            return Err(InputError::new(path, reason).at_line(line));
        }
        if m.form == 6 && mirror.is_some() && e.row > e.col {
            drop[k] = true;
        }
    }
    if drop.contains(&true) {
        let mut k = 0;
        m.entries.retain(|_| {
            k += 1;
            !drop[k - 1]
        });
    }
    Ok(())
}

/// The matrix `name` of a file's DMIG matrices (`None`: the only one) in `all`;
/// `key` is the scene key that names it.
fn select<'a>(
    path: &Path,
    all: &'a BTreeMap<String, Dmig>,
    name: Option<&str>,
    key: &str,
) -> Result<&'a Dmig, InputError> {
    let names = all.keys().cloned().collect::<Vec<_>>().join(", ");
    let wanted = match name {
        Some(n) => n.to_ascii_uppercase(),
        None if all.len() == 1 => names.clone(),
        None if all.is_empty() => return Err(InputError::new(path, "the file has no DMIG matrix")),
        None => {
            return Err(InputError::new(
                path,
                format!("the file holds the DMIG matrices {names}: name one"),
            )
            .with_key(key))
        }
    };
    all.get(&wanted).ok_or_else(|| {
        InputError::new(
            path,
            format!(
                "no DMIG matrix `{}` in the file (it holds: {names})",
                name.unwrap_or_default()
            ),
        )
        .with_key(key)
    })
}

/// A matrix file and the name of its matrix (`None`: the file's only one), with the scene key
/// that names it.
#[derive(Debug, Clone, Copy)]
pub struct Named<'a> {
    /// The file.
    pub path: &'a Path,
    /// The matrix's name.
    pub name: Option<&'a str>,
    /// The scene key of the name, for errors.
    pub key: &'a str,
}

/// A matrix with its units comment.
pub type WithUnits = (Entries, Option<(String, usize)>);

/// The entries of `m` on the DOFs `index`, a symmetric (IFO 6) matrix's other triangle mirrored
/// (the checks of [`read_file`] leave each position once).
fn assemble(m: &Dmig, index: &BTreeMap<GridDof, usize>) -> Entries {
    let mut entries = Vec::with_capacity(2 * m.entries.len());
    for e in &m.entries {
        let (i, j) = (index[&e.row], index[&e.col]);
        entries.push((i, j, e.x));
        if m.form == 6 && i != j {
            entries.push((j, i, e.x));
        }
    }
    Entries {
        n: index.len(),
        entries,
    }
}

/// Reads the mass and stiffness matrices (module doc): each with its units comment, and the
/// DOFs. A file that holds both is read once.
pub fn read_pair(
    mass: Named,
    stiffness: Named,
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<(WithUnits, WithUnits, Vec<Dof>), InputError> {
    let (all_m, um) = read_file(mass.path, nodes, nodes_file)?;
    let m = select(mass.path, &all_m, mass.name, mass.key)?;
    let other = if stiffness.path == mass.path {
        None
    } else {
        Some(read_file(stiffness.path, nodes, nodes_file)?)
    };
    let (all_k, uk) = match &other {
        Some((all, units)) => (all, units.clone()),
        None => (&all_m, um.clone()),
    };
    let k = select(stiffness.path, all_k, stiffness.name, stiffness.key)?;
    let set: BTreeSet<GridDof> = m
        .entries
        .iter()
        .chain(&k.entries)
        .flat_map(|e| [e.row, e.col])
        .collect();
    let index: BTreeMap<GridDof, usize> = set.iter().enumerate().map(|(i, &d)| (d, i)).collect();
    let dofs = set.iter().map(|&(node, dof)| Dof { node, dof }).collect();
    Ok(((assemble(m, &index), um), (assemble(k, &index), uk), dofs))
}

/// Reads one more matrix (a stress stiffness) on the DOFs `dofs` of the pair already read
/// ([`read_pair`]); an entry on a DOF the pair does not have is an error naming its line.
pub fn read_on(
    f: Named,
    dofs: &[Dof],
    nodes: &[Node],
    nodes_file: &Path,
) -> Result<WithUnits, InputError> {
    let (all, units) = read_file(f.path, nodes, nodes_file)?;
    let m = select(f.path, &all, f.name, f.key)?;
    let index: BTreeMap<GridDof, usize> = dofs
        .iter()
        .enumerate()
        .map(|(i, d)| ((d.node, d.dof), i))
        .collect();
    for e in &m.entries {
        if let Some(d) = [e.row, e.col].into_iter().find(|d| !index.contains_key(d)) {
            return Err(InputError::new(
                f.path,
                format!(
                    "{} is not a DOF of the mass and stiffness matrices",
                    dof_text(d)
                ),
            )
            .at_line(e.line));
        }
    }
    Ok((assemble(m, &index), units))
}
