//! Markdown: the report's tables under headings.
//!
//! In: a [`Report`] and the tables to show. Out: `# Study <name>` with the file and overview
//! (left out when one table is asked for), then per table a `##` heading of its title and its
//! name (in backticks), its legend and a table whose columns are padded to their widest cell:
//! a table's [`Grid`](crate::report::Grid) when it has one, else its rows as [`md_cell`] writes
//! them (4 significant digits, `–` for no value) with the all-numeric columns right-aligned
//! (none in a table without rows). `|` in a cell is escaped, line breaks become spaces.

use std::fmt::Write as _;

use crate::report::table::{md_cell, Cell, Report, Table};

/// A markdown table, columns padded; `right` aligns the numeric columns right.
fn md_grid(out: &mut String, columns: &[String], rows: &[Vec<String>], right: &[bool]) {
    let clean = |s: &str| s.replace('|', "\\|").replace(['\n', '\r'], " ");
    let head: Vec<String> = columns.iter().map(|c| clean(c)).collect();
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| r.iter().map(|c| clean(c)).collect())
        .collect();
    let width: Vec<usize> = (0..head.len())
        .map(|c| {
            body.iter()
                .filter_map(|r| r.get(c))
                .chain(std::iter::once(&head[c]))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
                .max(3)
        })
        .collect();
    let line = |out: &mut String, cells: &[String]| {
        out.push('|');
        for (c, w) in width.iter().enumerate() {
            let s = cells.get(c).map_or("", String::as_str);
            if right.get(c) == Some(&true) {
                let _ = write!(out, " {s:>w$} |");
            } else {
                let _ = write!(out, " {s:<w$} |");
            }
        }
        out.push('\n');
    };
    line(out, &head);
    out.push('|');
    for (c, w) in width.iter().enumerate() {
        let dashes = "-".repeat(*w);
        if right.get(c) == Some(&true) {
            let _ = write!(out, " {}: |", &dashes[1..]);
        } else {
            let _ = write!(out, " {dashes} |");
        }
    }
    out.push('\n');
    for r in &body {
        line(out, r);
    }
}

/// One table: heading, legend and its grid (or its rows).
fn markdown(out: &mut String, t: &Table) {
    let _ = writeln!(out, "## {} (`{}`)\n\n{}\n", t.title, t.name, t.legend);
    match &t.markdown {
        Some(g) => md_grid(out, &g.columns, &g.rows, &[]),
        None => {
            let right: Vec<bool> = (0..t.columns.len())
                .map(|c| {
                    !t.rows.is_empty()
                        && t.rows
                            .iter()
                            .all(|r| !matches!(r.get(c), Some(Cell::Text(_))))
                })
                .collect();
            let rows: Vec<Vec<String>> = t
                .rows
                .iter()
                .map(|r| r.iter().map(md_cell).collect())
                .collect();
            md_grid(out, &t.columns, &rows, &right);
        }
    }
}

/// The markdown of `tables` of `r`; `only`: one table was asked for (no study heading).
pub(crate) fn document(r: &Report, tables: &[&Table], only: bool) -> String {
    let mut out = String::new();
    if !only {
        let _ = writeln!(
            out,
            "# Study {}\n\n`{}`: {}\n",
            r.study,
            r.file.display(),
            r.overview
        );
    }
    for (i, t) in tables.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        markdown(&mut out, t);
    }
    out
}
