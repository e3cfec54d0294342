//! Nastran OUTPUT4 (`.op4`) ASCII matrix files: the dense column format and the sparse string
//! formats (the 65 536-row "string header" one and BIGMAT).
//!
//! In: an ASCII OP4 file of one or more matrices, each a header line (`NCOL NROW NF NTYPE` in
//! 4I8, the name in columns 33–40, then the Fortran format of the values, e.g. `1P,3E23.16`;
//! NROW < 0 marks BIGMAT), column records `ICOL IROW NW` (3I8) each followed by its values,
//! and the end record `NCOL+1 1 1` with one value. A dense column (IROW > 0) gives the values
//! of rows IROW, IROW+1, …; a sparse one (IROW = 0) gives strings, each a header and its
//! values: without BIGMAT one integer IS = IROW + 65536 (L + 1), with BIGMAT two, L + 1 and
//! IROW, L the string's words (two per double-precision value). Values are read by the
//! format's field width (they may run together: `1.0E+00-2.0E+00`), with `E` or `D`
//! exponents. Real single (NTYPE 1) or double (NTYPE 2) precision, forms 1 (square),
//! 2 (rectangular, read when square) and 6 (symmetric). The matrix to read by name (the file's
//! only one if no name is given). Out: the square matrix's [`Entries`] (units as written; OP4
//! carries none; every entry stored, as the file stores both triangles) in the file's row
//! order, which a DOF table names as for Matrix Market; or an [`InputError`] naming the file and the line (and the scene key of the matrix name where it
//! is at fault): a header that does not parse, a matrix not square, complex or of another
//! form, a row or column outside the matrix, a dense column whose value count is not its NW
//! (in words or values, below), a string whose value count is not its header's L, an entry given twice, a value that is no number, the file ending before a
//! matrix's end record (a truncated file), a matrix that is not symmetric (an entry and its
//! mirror differing by more than 1e-10 of the largest entry: both lines).
//! Method: MSC Nastran DMAP Programmer's Guide, OUTPUT4, and the formats as pyyeti's `op4`
//! module (tested against Nastran) reads and writes them. A line whose first word has a decimal
//! point is a value line; a record, string header or matrix header starts with an integer. The
//! values of a column or string are the value lines up to the next header; their count must be
//! what the header says in words (two per double-precision value, as Nastran and pyyeti write)
//! or in values (as pyNastran 1.4 writes NW and the BIGMAT L). pyNastran's non-BIGMAT string
//! header carries the column's length, not the string's, and is refused when a column has more
//! than one string.

use std::collections::HashMap;
use std::path::Path;

use super::bulk;
use super::entries::Entries;
use crate::error::{read_text_up_to, InputError};

/// Relative asymmetry a matrix may have (of its largest entry).
const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// The largest OP4 file read: 4 GiB (as the sparse Matrix Market reader's).
pub const MAX_BYTES: u64 = super::matrix_market::MAX_SPARSE_BYTES;

/// The largest dimension read (the sparse path's, [`super::matrix_market::MAX_SPARSE_DIM`]).
const MAX_DIM: usize = super::matrix_market::MAX_SPARSE_DIM;

/// A matrix of the file: name, header line, dimension, entries (row, column, value, line).
struct Op4 {
    name: String,
    line: usize,
    n: usize,
    entries: Vec<(usize, usize, f64, usize)>,
}

/// The lines of a file, numbered, with a cursor.
struct Lines<'a> {
    lines: Vec<(usize, &'a str)>,
    at: usize,
}

impl<'a> Lines<'a> {
    fn peek(&self) -> Option<(usize, &'a str)> {
        self.lines.get(self.at).copied()
    }
    fn next(&mut self) -> Option<(usize, &'a str)> {
        let l = self.peek();
        self.at += 1;
        l
    }
    fn last_line(&self) -> usize {
        self.lines.last().map_or(1, |l| l.0)
    }
}

/// A value line: its first word has a decimal point (a record, string header or matrix
/// header starts with an integer).
fn is_values(l: &str) -> bool {
    l.split_whitespace().next().is_some_and(|w| w.contains('.'))
}

fn ints(l: &str) -> Option<Vec<i64>> {
    l.split_whitespace().map(|w| w.parse().ok()).collect()
}

/// The values of a value line, `width` characters each.
fn values(path: &Path, no: usize, l: &str, width: usize) -> Result<Vec<f64>, InputError> {
    let l = l.trim_end();
    let mut out = Vec::new();
    let mut a = 0;
    while a < l.len() {
        let b = (a + width).min(l.len());
        let s = l.get(a..b).unwrap_or("");
        let x = bulk::real(s).ok_or_else(|| {
            InputError::new(
                path,
                format!(
                    "columns {}-{} hold `{}`, not a number of the format's {width}-character \
                     fields",
                    a + 1,
                    b,
                    s.trim()
                ),
            )
            .at_line(no)
        })?;
        out.push(x);
        a = b;
    }
    Ok(out)
}

/// A matrix header: NCOL, NROW, NF, NTYPE, the name, and the values' field width.
struct Header {
    ncol: i64,
    nrow: i64,
    form: i64,
    ntype: i64,
    name: String,
    width: usize,
}

/// The header of a matrix (module doc).
fn header(path: &Path, no: usize, l: &str) -> Result<Header, InputError> {
    let err = |r: String| InputError::new(path, r).at_line(no);
    let field = |a: usize, b: usize| l.get(a..b.min(l.len())).unwrap_or("").trim();
    let int = |a: usize, what: &str| -> Result<i64, InputError> {
        field(a, a + 8).parse().map_err(|_| {
            err(format!(
                "expected an OP4 header `NCOL NROW NF NTYPE NAME FORMAT` (4I8, A8, the format): \
                 {what} in columns {}-{} is `{}`",
                a + 1,
                a + 8,
                field(a, a + 8)
            ))
        })
    };
    let (ncol, nrow, form, ntype) = (
        int(0, "NCOL")?,
        int(8, "NROW")?,
        int(16, "NF")?,
        int(24, "NTYPE")?,
    );
    let name = field(32, 40).to_string();
    let fmt = field(40, l.len()).to_ascii_uppercase();
    let fmt = fmt.strip_prefix("1P,").unwrap_or(&fmt);
    let width = match fmt.find(['E', 'D']) {
        Some(p) => {
            let per = fmt[..p].parse::<usize>();
            let width = fmt[p + 1..]
                .split('.')
                .next()
                .unwrap_or("")
                .parse::<usize>();
            match (per, width) {
                (Ok(per), Ok(width)) if per > 0 && width > 0 => width,
                _ => {
                    return Err(err(format!(
                        "the value format `{fmt}` does not parse (expected e.g. `1P,3E23.16`)"
                    )))
                }
            }
        }
        // Nastran's default, 1P,5E16.9.
        None => 16,
    };
    Ok(Header {
        ncol,
        nrow,
        form,
        ntype,
        name,
        width,
    })
}

/// Reads the value lines at the cursor, up to the next record or string header or the end.
fn read_values(
    path: &Path,
    lines: &mut Lines,
    width: usize,
) -> Result<Vec<(f64, usize)>, InputError> {
    let mut out = Vec::new();
    while let Some((no, l)) = lines.peek().filter(|(_, l)| is_values(l)) {
        lines.next();
        for x in values(path, no, l, width)? {
            out.push((x, no));
        }
    }
    Ok(out)
}

/// One matrix from its header line at the cursor (module doc).
fn matrix(path: &Path, lines: &mut Lines) -> Result<Op4, InputError> {
    let (hl, h) = lines.next().expect("the caller peeked");
    let err = |line: usize, r: String| InputError::new(path, r).at_line(line);
    let hd = header(path, hl, h)?;
    let (ncol, nrow, form, ntype, width) = (hd.ncol, hd.nrow, hd.form, hd.ntype, hd.width);
    let name = hd.name;
    let bigmat = !(0..=65535).contains(&nrow);
    let nrow = nrow.unsigned_abs() as usize;
    if ncol <= 0 || nrow as i64 != ncol {
        return Err(err(
            hl,
            format!("matrix {name} is {nrow} × {ncol}: a mass or stiffness matrix is square"),
        ));
    }
    let n = nrow;
    if n > MAX_DIM {
        return Err(err(
            hl,
            format!("matrix {name}: dimension {n} is above the {MAX_DIM} read"),
        ));
    }
    if !matches!(form, 1 | 2 | 6) {
        return Err(err(
            hl,
            format!("matrix {name}: form NF = {form}; read are 1 (square), 2 (rectangular) and 6 (symmetric)"),
        ));
    }
    let words = match ntype {
        1 => 1,
        2 => 2,
        t => {
            return Err(err(
                hl,
                format!("matrix {name}: NTYPE = {t}; only real matrices (1 single, 2 double precision) are read"),
            ))
        }
    };
    let mut entries = Vec::new();
    let record = |line: usize, l: &str| -> Result<(usize, i64, i64), InputError> {
        match ints(l).as_deref() {
            Some(&[c, r, nw]) if c >= 1 && r >= 0 && nw >= 0 => Ok((c as usize, r, nw)),
            _ => Err(err(
                line,
                format!(
                    "matrix {name}: expected a column record `ICOL IROW NW`, got `{}`",
                    l.trim()
                ),
            )),
        }
    };
    loop {
        let Some((no, l)) = lines.next() else {
            return Err(err(
                lines.last_line(),
                format!("the file ends inside matrix {name} before its end record (column {}): truncated file", n + 1),
            ));
        };
        let (col, irow, nw) = record(no, l)?;
        if col > n {
            read_values(path, lines, width)?;
            break;
        }
        let what = format!("column {col} of matrix {name}");
        let mut put = |row: usize, x: f64, line: usize| -> Result<(), InputError> {
            if row == 0 || row > n {
                return Err(err(
                    line,
                    format!("{what}: row {row} lies outside the {n} × {n} matrix"),
                ));
            }
            if x != 0.0 {
                entries.push((row - 1, col - 1, x, line));
            }
            Ok(())
        };
        if irow > 0 {
            let v = read_values(path, lines, width)?;
            let got = v.len() as i64;
            if got != nw && got * words != nw {
                return Err(err(
                    no,
                    format!(
                        "{what}: NW = {nw} but {got} values follow: truncated or damaged column"
                    ),
                ));
            }
            for (k, (x, line)) in v.into_iter().enumerate() {
                put(irow as usize + k, x, line)?;
            }
            continue;
        }
        // Sparse: strings until the next column record.
        while let Some((sl, s)) = lines.peek() {
            let h = ints(s);
            let (l_words, row) = match (h.as_deref(), bigmat) {
                (Some(&[is]), false) => (is / 65536 - 1, is - 65536 * (is / 65536)),
                (Some(&[l1, r]), true) => (l1 - 1, r),
                (Some(&[_, _, _]), _) => break,
                _ => {
                    return Err(err(
                        sl,
                        format!(
                            "{what}: expected a string header ({}), got `{}`",
                            if bigmat {
                                "L+1 IROW, BIGMAT"
                            } else {
                                "IS = IROW + 65536 (L+1)"
                            },
                            s.trim()
                        ),
                    ))
                }
            };
            lines.next();
            if l_words < 1 || row < 1 {
                return Err(err(
                    sl,
                    format!("{what}: the string header `{}` gives no values", s.trim()),
                ));
            }
            let v = read_values(path, lines, width)?;
            let got = v.len() as i64;
            if got * words != l_words && got != l_words {
                return Err(err(
                    sl,
                    format!(
                        "{what}: the string header says L = {l_words} words ({} values) but \
                         {got} values follow: truncated or damaged string",
                        l_words / words
                    ),
                ));
            }
            for (k, (x, line)) in v.into_iter().enumerate() {
                put(row as usize + k, x, line)?;
            }
        }
    }
    Ok(Op4 {
        name,
        line: hl,
        n,
        entries,
    })
}

/// Entries given twice, and a matrix that is not symmetric (module doc).
fn check(path: &Path, m: Op4) -> Result<Entries, InputError> {
    let mut at: HashMap<(usize, usize), (f64, usize)> = HashMap::new();
    for &(i, j, x, line) in &m.entries {
        if let Some((_, first)) = at.insert((i, j), (x, line)) {
            return Err(InputError::new(
                path,
                format!(
                    "matrix {}: entry ({}, {}) is given twice (first on line {first})",
                    m.name,
                    i + 1,
                    j + 1
                ),
            )
            .at_line(line));
        }
    }
    let scale = m.entries.iter().fold(0.0f64, |s, e| s.max(e.2.abs()));
    for &(i, j, x, line) in &m.entries {
        let (y, mirror) = at.get(&(j, i)).copied().unwrap_or((0.0, 0));
        if (x - y).abs() > SYMMETRY_TOLERANCE * scale {
            let other = if mirror > 0 {
                format!("({}, {}) on line {mirror} = {y:e}", j + 1, i + 1)
            } else {
                format!(
                    "({}, {}) is not given (OP4 stores every entry)",
                    j + 1,
                    i + 1
                )
            };
            return Err(InputError::new(
                path,
                format!(
                    "matrix {} is not symmetric: entry ({}, {}) = {x:e} but {other}",
                    m.name,
                    i + 1,
                    j + 1
                ),
            )
            .at_line(line.max(mirror)));
        }
    }
    Ok(Entries {
        n: m.n,
        entries: m
            .entries
            .into_iter()
            .map(|(i, j, x, _)| (i, j, x))
            .collect(),
    })
}

/// Reads the matrix `name` (`None`: the file's only one) of an ASCII OP4 file, square and
/// symmetric (module doc); `key` is the scene key that names it.
pub fn read(path: &Path, name: Option<&str>, key: &str) -> Result<Entries, InputError> {
    let text = read_text_up_to(path, MAX_BYTES)
        .map_err(|e| InputError::new(path, format!("cannot read the OP4 file: {e}")))?;
    if text.as_bytes().iter().take(64).any(|&b| b == 0) {
        return Err(InputError::new(
            path,
            "a binary OP4 file: only ASCII OP4 is read (OUTPUT4 with FORMATTED)",
        ));
    }
    let mut lines = Lines {
        lines: text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l))
            .filter(|(_, l)| !l.trim().is_empty())
            .collect(),
        at: 0,
    };
    let mut found: Vec<(String, usize)> = Vec::new();
    let mut chosen = None;
    while lines.peek().is_some() {
        let m = matrix(path, &mut lines)?;
        let wanted = match name {
            Some(n) => m.name.eq_ignore_ascii_case(n),
            None => true,
        };
        found.push((m.name.clone(), m.line));
        if wanted && chosen.is_none() {
            chosen = Some(m);
        }
    }
    let names = found
        .iter()
        .map(|(n, l)| format!("{n} (line {l})"))
        .collect::<Vec<_>>()
        .join(", ");
    match (chosen, name) {
        (None, Some(n)) => Err(InputError::new(
            path,
            format!("no matrix `{n}` in the file (it holds: {names})"),
        )
        .with_key(key)),
        (None, None) => Err(InputError::new(path, "the file holds no matrix")),
        (Some(_), None) if found.len() > 1 => Err(InputError::new(
            path,
            format!("the file holds the matrices {names}: name one"),
        )
        .with_key(key)),
        (Some(m), _) => check(path, m),
    }
}
