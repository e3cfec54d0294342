//! Matrix Market coordinate files (`.mtx`): the reader and the writer.
//!
//! In: a file `%%MatrixMarket matrix coordinate real|integer general|symmetric|skew-symmetric`,
//! comment lines (`%`), a size line `rows cols entries` and one `i j value` line per entry,
//! 1-based, as ANSYS, Abaqus (via scripts), scipy.io.mmwrite and the NIST collection write them.
//! Out: a dense square matrix ([`read`]) or its entries ([`read_sparse`], for large models)
//! (units as in the file) and the `% units:` comment if the file has
//! one; or an [`InputError`] naming the file and line (a bad header, an entry outside the size,
//! a repeated entry, an entry above the diagonal of a symmetric file, fewer entries than the
//! size line announces — a truncated file — or a value that is not a finite number).
//! Method: read line by line; a symmetric file stores one triangle (either one is taken, never
//! both), a skew-symmetric one the strict lower triangle; the other triangle is mirrored.
//! Hand-written rather than a crate's: the errors must name the file and line of the entry, and
//! the crates that read the format (sprs, nalgebra-sparse) return no line and pull a parser.
//! The writer prints each value in Rust's shortest round-trip form, so a matrix written and
//! read again is bit-identical.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::DMatrix;

use crate::error::{read_text, read_text_up_to, InputError};

/// The symmetry a Matrix Market file declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// Every entry stored.
    General,
    /// a_ji = a_ij; one triangle stored.
    Symmetric,
    /// a_ji = −a_ij, zero diagonal; the strict lower triangle stored.
    SkewSymmetric,
}

impl Symmetry {
    fn word(self) -> &'static str {
        match self {
            Symmetry::General => "general",
            Symmetry::Symmetric => "symmetric",
            Symmetry::SkewSymmetric => "skew-symmetric",
        }
    }
}

/// A matrix read from a Matrix Market file.
#[derive(Debug, Clone)]
pub struct MarketMatrix {
    /// The dense matrix.
    pub matrix: DMatrix<f64>,
    /// The symmetry the header declares.
    pub symmetry: Symmetry,
    /// The `% units: …` comment, with the line it is on, if the file has one.
    pub units: Option<(String, usize)>,
}

/// The largest dimension read into a dense matrix (the dense eigen-solvers' range).
pub const MAX_DIM: usize = 20_000;

/// Reads a square Matrix Market coordinate file (module doc).
pub fn read(path: &Path) -> Result<MarketMatrix, InputError> {
    let text = read_text(path)
        .map_err(|e| InputError::new(path, format!("cannot read the matrix file: {e}")))?;
    parse(path, &text)
}

/// One entry as the file writes it: 0-based row and column, value, line.
#[derive(Debug, Clone, Copy)]
struct Entry {
    i: usize,
    j: usize,
    x: f64,
    line: usize,
}

/// A file's entries as written (one triangle of a symmetric file), before any is mirrored.
struct Entries {
    n: usize,
    symmetry: Symmetry,
    units: Option<(String, usize)>,
    entries: Vec<Entry>,
}

/// Parses Matrix Market text; `path` names it in errors.
pub fn parse(path: &Path, text: &str) -> Result<MarketMatrix, InputError> {
    let e = parse_entries(path, text, MAX_DIM)?;
    let n = e.n;
    let mut a = DMatrix::zeros(n, n);
    let mut seen = DMatrix::<u8>::zeros(n, n);
    for &Entry { i, j, x, line } in &e.entries {
        if seen[(i, j)] != 0 {
            return Err(twice(path, i, j, line));
        }
        seen[(i, j)] = 1;
        a[(i, j)] = x;
        match e.symmetry {
            Symmetry::General => {}
            Symmetry::Symmetric => a[(j, i)] = x,
            Symmetry::SkewSymmetric => a[(j, i)] = -x,
        }
    }
    Ok(MarketMatrix {
        matrix: a,
        symmetry: e.symmetry,
        units: e.units,
    })
}

fn twice(path: &Path, i: usize, j: usize, line: usize) -> InputError {
    InputError::new(path, format!("entry ({}, {}) is given twice", i + 1, j + 1)).at_line(line)
}

/// A matrix read from a Matrix Market file as its entries, for the sparse path.
#[derive(Debug, Clone)]
pub struct SparseMarket {
    /// Dimension.
    pub n: usize,
    /// Every entry (row, column, value), 0-based, a symmetric file's other triangle mirrored.
    pub entries: Vec<(usize, usize, f64)>,
    /// The symmetry the header declares.
    pub symmetry: Symmetry,
    /// The `% units: …` comment, with the line it is on, if the file has one.
    pub units: Option<(String, usize)>,
}

/// The largest dimension the sparse reader takes (its memory is that of the entries).
pub const MAX_SPARSE_DIM: usize = 10_000_000;

/// The largest file the sparse reader takes: 4 GiB (a 100 000-DOF solid of quadratic
/// hexahedra writes about 0.5 GB; the text is held while it is parsed).
pub const MAX_SPARSE_BYTES: u64 = 4 << 30;

/// Reads a square Matrix Market coordinate file as its entries (module doc; the same checks,
/// a position given twice found by sorting).
pub fn read_sparse(path: &Path) -> Result<SparseMarket, InputError> {
    let text = read_text_up_to(path, MAX_SPARSE_BYTES)
        .map_err(|e| InputError::new(path, format!("cannot read the matrix file: {e}")))?;
    let e = parse_entries(path, &text, MAX_SPARSE_DIM)?;
    drop(text);
    let mut sorted = e.entries;
    sorted.sort_unstable_by_key(|x| (x.j, x.i, x.line));
    if let Some(w) = sorted
        .windows(2)
        .find(|w| (w[0].i, w[0].j) == (w[1].i, w[1].j))
    {
        return Err(twice(path, w[1].i, w[1].j, w[1].line));
    }
    let mut entries = Vec::with_capacity(2 * sorted.len());
    for &Entry { i, j, x, .. } in &sorted {
        entries.push((i, j, x));
        if i != j {
            match e.symmetry {
                Symmetry::General => {}
                Symmetry::Symmetric => entries.push((j, i, x)),
                Symmetry::SkewSymmetric => entries.push((j, i, -x)),
            }
        }
    }
    Ok(SparseMarket {
        n: e.n,
        entries,
        symmetry: e.symmetry,
        units: e.units,
    })
}

/// The header, size line and entries of Matrix Market text, each entry checked but not yet
/// for repetition (module doc); dimensions up to `max_dim`.
fn parse_entries(path: &Path, text: &str, max_dim: usize) -> Result<Entries, InputError> {
    let err = |line: usize, reason: String| InputError::new(path, reason).at_line(line);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let (_, header) = lines
        .next()
        .ok_or_else(|| InputError::new(path, "empty file: expected a %%MatrixMarket header"))?;
    let words: Vec<String> = header
        .split_whitespace()
        .map(|w| w.to_ascii_lowercase())
        .collect();
    if words.len() != 5 || words[0] != "%%matrixmarket" || words[1] != "matrix" {
        return Err(err(
            1,
            format!("expected `%%MatrixMarket matrix coordinate real symmetric`, got `{header}`"),
        ));
    }
    if words[2] != "coordinate" {
        return Err(err(
            1,
            format!("format `{}`: only `coordinate` is read", words[2]),
        ));
    }
    if words[3] != "real" && words[3] != "integer" {
        return Err(err(
            1,
            format!("field `{}`: only `real` or `integer` is read", words[3]),
        ));
    }
    let symmetry = match words[4].as_str() {
        "general" => Symmetry::General,
        "symmetric" => Symmetry::Symmetric,
        "skew-symmetric" => Symmetry::SkewSymmetric,
        w => {
            return Err(err(
                1,
                format!("symmetry `{w}`: expected general, symmetric or skew-symmetric"),
            ))
        }
    };
    let mut units = None;
    let mut size = None;
    let mut last_line = 1;
    for (no, l) in lines.by_ref() {
        last_line = no;
        if let Some(c) = l.strip_prefix('%') {
            if let Some(u) = c.trim().strip_prefix("units:") {
                units = Some((u.trim().to_string(), no));
            }
            continue;
        }
        if l.is_empty() {
            continue;
        }
        let v: Vec<&str> = l.split_whitespace().collect();
        let nums: Option<Vec<usize>> = v.iter().map(|x| x.parse().ok()).collect();
        match nums.as_deref() {
            Some(&[r, c, nnz]) => {
                if r != c {
                    return Err(err(
                        no,
                        format!("a {r} × {c} matrix: only square ones are read"),
                    ));
                }
                if r == 0 || r > max_dim {
                    return Err(err(
                        no,
                        format!("dimension {r}: must lie in [1, {max_dim}]"),
                    ));
                }
                size = Some((r, nnz, no));
                break;
            }
            _ => {
                return Err(err(
                    no,
                    format!("expected the size line `rows cols entries`, got `{l}`"),
                ))
            }
        }
    }
    let (n, nnz, size_line) = size.ok_or_else(|| {
        err(
            last_line,
            "no size line `rows cols entries`: truncated file".into(),
        )
    })?;
    let mut entries = Vec::with_capacity(nnz.min(100_000_000));
    let mut count = 0usize;
    let mut triangle: Option<(bool, usize)> = None;
    for (no, l) in lines {
        last_line = no;
        if l.is_empty() || l.starts_with('%') {
            continue;
        }
        if count == nnz {
            return Err(err(
                no,
                format!("more entries than the {nnz} the size line (line {size_line}) announces"),
            ));
        }
        let v: Vec<&str> = l.split_whitespace().collect();
        if v.len() != 3 {
            return Err(err(
                no,
                format!("expected an entry `row col value`, got `{l}`"),
            ));
        }
        let index = |s: &str| s.parse::<usize>().ok().filter(|&i| (1..=n).contains(&i));
        let (Some(i), Some(j)) = (index(v[0]), index(v[1])) else {
            return Err(err(
                no,
                format!(
                    "entry ({}, {}) lies outside the {n} × {n} matrix (indices are 1-based)",
                    v[0], v[1]
                ),
            ));
        };
        let x: f64 = v[2]
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| {
                err(
                    no,
                    format!(
                        "value `{}` of entry ({i}, {j}) is not a finite number",
                        v[2]
                    ),
                )
            })?;
        let (i, j) = (i - 1, j - 1);
        match symmetry {
            Symmetry::General => {}
            Symmetry::Symmetric => {
                let lower = i >= j;
                if i != j {
                    match triangle {
                        None => triangle = Some((lower, no)),
                        Some((t, first)) if t != lower => {
                            return Err(err(
                                no,
                                format!(
                                    "entry ({}, {}) lies in the other triangle than line {first}'s: a symmetric file stores one triangle",
                                    i + 1,
                                    j + 1
                                ),
                            ))
                        }
                        Some(_) => {}
                    }
                }
            }
            Symmetry::SkewSymmetric => {
                if i <= j {
                    return Err(err(
                        no,
                        format!("entry ({}, {}): a skew-symmetric file stores the strict lower triangle", i + 1, j + 1),
                    ));
                }
            }
        }
        entries.push(Entry { i, j, x, line: no });
        count += 1;
    }
    if count < nnz {
        return Err(err(
            last_line,
            format!(
                "the size line (line {size_line}) announces {nnz} entries, the file ends after {count}: truncated file"
            ),
        ));
    }
    Ok(Entries {
        n,
        symmetry,
        units,
        entries,
    })
}

/// The Matrix Market text of `a` with the given `symmetry` (a symmetric matrix as its lower
/// triangle, a skew one as its strict lower triangle, zeros left out), `units` as a
/// `% units:` comment and `comment` as further comment lines.
pub fn format(a: &DMatrix<f64>, symmetry: Symmetry, units: &str, comment: &str) -> String {
    let n = a.nrows();
    let mut entries = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let keep = match symmetry {
                Symmetry::General => true,
                Symmetry::Symmetric => i >= j,
                Symmetry::SkewSymmetric => i > j,
            };
            if keep && a[(i, j)] != 0.0 {
                entries.push((i, j, a[(i, j)]));
            }
        }
    }
    let mut s = format!(
        "%%MatrixMarket matrix coordinate real {}\n% units: {units}\n",
        symmetry.word()
    );
    for c in comment.lines() {
        let _ = writeln!(s, "% {c}");
    }
    let _ = writeln!(s, "{n} {n} {}", entries.len());
    for (i, j, x) in entries {
        let _ = writeln!(s, "{} {} {x:e}", i + 1, j + 1);
    }
    s
}

/// A dense rows × cols matrix (`at(i, j)`) as Matrix Market `array real general` text: the
/// header, a `% units:` line, the comment lines, the size line and the entries column by column
/// (the format's order), each in its shortest round-trip form.
pub fn format_array(
    rows: usize,
    cols: usize,
    at: impl Fn(usize, usize) -> f64,
    units: &str,
    comment: &str,
) -> String {
    let mut s = format!("%%MatrixMarket matrix array real general\n% units: {units}\n");
    for c in comment.lines() {
        let _ = writeln!(s, "% {c}");
    }
    let _ = writeln!(s, "{rows} {cols}");
    for j in 0..cols {
        for i in 0..rows {
            let _ = writeln!(s, "{:e}", at(i, j));
        }
    }
    s
}
