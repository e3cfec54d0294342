//! CSV: each table's long form at full precision.
//!
//! In: the tables of a [`Report`](crate::report::Report). Out: per table a `# <title>` and a
//! `# <legend>` line (left out when one table is asked for, so that `pandas.read_csv` reads
//! it), the column names, then one line per row; tables apart by a blank line. A number is written in Rust's shortest
//! round-trip form, no value as an empty field; a field with `,`, `"` or a line break is quoted
//! (`"` doubled).

use std::fmt::Write as _;

use crate::report::table::{Cell, Table};

/// A cell as CSV holds it: full precision, empty for no value, quoted when needed.
fn csv_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) if t.contains([',', '"', '\n', '\r']) => {
            format!("\"{}\"", t.replace('"', "\"\""))
        }
        Cell::Text(t) => t.clone(),
        Cell::Number(x) if x.is_finite() => format!("{x}"),
        Cell::Number(_) => String::new(),
        Cell::Count(n) => n.to_string(),
    }
}

/// One table: its column names, then its rows.
fn csv(out: &mut String, t: &Table) {
    let header: Vec<String> = t
        .columns
        .iter()
        .map(|c| csv_cell(&Cell::Text(c.clone())))
        .collect();
    let _ = writeln!(out, "{}", header.join(","));
    for r in &t.rows {
        let cells: Vec<String> = r.iter().map(csv_cell).collect();
        let _ = writeln!(out, "{}", cells.join(","));
    }
}

/// The CSV of `tables`; `only`: one table was asked for (no title and legend lines).
pub(crate) fn document(tables: &[&Table], only: bool) -> String {
    let mut out = String::new();
    for (i, t) in tables.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        if !only {
            let _ = writeln!(out, "# {}\n# {}", t.title, t.legend);
        }
        csv(&mut out, t);
    }
    out
}
