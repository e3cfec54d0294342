//! The neutral form of a report, which every table builder fills and every renderer reads.
//!
//! A [`Report`] holds the file read, the study's name, a one-line overview and its [`Table`]s;
//! a table is a short name (`--table NAME`), a title, a legend with the units, named columns
//! (units in the names) and rows of [`Cell`]s, and optionally the [`Grid`] of text that
//! markdown and HTML show instead (transposed, or a matrix). A cell as markdown shows it
//! ([`md_cell`]): 4 significant digits (`crate::text::significant`), `–` for no value.

use std::path::PathBuf;

use serde::Serialize;

use crate::text::significant;

/// One cell of a table.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// Text.
    Text(String),
    /// A measured value; NaN when there is none (empty in CSV, `–` in markdown, null in JSON).
    Number(f64),
    /// A count.
    Count(u64),
}

impl Serialize for Cell {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Cell::Text(t) => s.serialize_str(t),
            Cell::Number(x) if x.is_finite() => s.serialize_f64(*x),
            Cell::Number(_) => s.serialize_none(),
            Cell::Count(n) => s.serialize_u64(*n),
        }
    }
}

/// A grid of text: how markdown and HTML show a table whose long form reads badly there.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Column headings.
    pub columns: Vec<String>,
    /// Rows of cell text.
    pub rows: Vec<Vec<String>>,
    /// Per row, each cell's class ([`error_class`](super::error_class)) by which HTML colours
    /// it; empty: none.
    pub classes: Vec<Vec<String>>,
}

impl Grid {
    /// A grid of `columns` and `rows` that HTML does not colour.
    pub(crate) fn plain(columns: Vec<String>, rows: Vec<Vec<String>>) -> Self {
        Self {
            columns,
            rows,
            classes: Vec::new(),
        }
    }
}

/// A table: named columns (units in the names), rows of cells.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// Short name (`--table NAME`).
    pub name: String,
    /// A short heading.
    pub title: String,
    /// What the columns hold, with units.
    pub legend: String,
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, one cell per column.
    pub rows: Vec<Vec<Cell>>,
    /// The markdown form when it differs from the rows (transposed, or a matrix).
    #[serde(skip)]
    pub markdown: Option<Grid>,
}

/// The tables of one results file.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The file read.
    pub file: PathBuf,
    /// The study's name.
    pub study: String,
    /// One line: job count by status, and the varying keys.
    pub overview: String,
    /// The tables the file has data for.
    pub tables: Vec<Table>,
}

impl Report {
    /// The names of the tables this report has.
    pub fn table_names(&self) -> Vec<&str> {
        self.tables.iter().map(|t| t.name.as_str()).collect()
    }
}

/// A text cell of a stored variable-length string.
pub(crate) fn text_cell(s: &hdf5::types::VarLenUnicode) -> Cell {
    Cell::Text(s.as_str().to_string())
}

/// A cell as markdown shows it: 4 significant digits, `–` for no value.
pub(crate) fn md_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) => t.clone(),
        Cell::Number(x) => significant(*x, 4),
        Cell::Count(n) => n.to_string(),
    }
}

/// The index of `item` in `list`, appending it first when absent.
pub(crate) fn position_or_push<'a>(list: &mut Vec<&'a str>, item: &'a str) -> usize {
    list.iter().position(|x| *x == item).unwrap_or_else(|| {
        list.push(item);
        list.len() - 1
    })
}

/// The order sensors are shown in: `centre` first, then by name.
pub(crate) fn sensor_rank(name: &str) -> (bool, &str) {
    (name != "centre", name)
}

#[cfg(test)]
mod tests {
    use crate::text::{number_text, significant};

    #[test]
    fn numbers_are_written_one_way() {
        // Parameters: shortest form, scientific below 1e-3 and from 1e6; measured values to
        // their significant digits by the same rule.
        assert_eq!(number_text(1e-4), "1e-4");
        assert_eq!(number_text(16.4), "16.4");
        assert_eq!(number_text(10.0), "10");
        assert_eq!(number_text(2.5e7), "2.5e7");
        assert_eq!(significant(1.234e-4, 3), "1.23e-4");
        assert_eq!(significant(16.2345, 4), "16.23");
        assert_eq!(significant(f64::NAN, 4), "–");
    }
}
