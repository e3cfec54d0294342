//! CSV: each table's long form at full precision.
//!
//! In: the tables of a [`Report`](crate::report::Report). Out: per table a `# <title>` and a
//! `# <legend>` line (left out when one table is asked for, so that `pandas.read_csv` reads
//! it), the column names, then one line per row; tables apart by a blank line. A number is
//! written in Rust's shortest round-trip form, no value as an empty field. The records are
//! written by the `csv` crate (`\n` after each; a field with `,`, `"`, `\r` or `\n` quoted, `"`
//! doubled; it would also quote an empty field that is a record's only one, which no table
//! has: each has several columns).

use std::fmt::Write as _;

use crate::report::table::{Cell, Table};

/// A cell as a CSV field: full precision, empty for no value (quoted by the writer when needed).
fn field(c: &Cell) -> String {
    match c {
        Cell::Text(t) => t.clone(),
        Cell::Number(x) if x.is_finite() => format!("{x}"),
        Cell::Number(_) => String::new(),
        Cell::Count(n) => n.to_string(),
    }
}

/// One table: its column names, then its rows.
fn csv(t: &Table) -> Result<String, ::csv::Error> {
    let mut w = ::csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    w.write_record(&t.columns)?;
    for r in &t.rows {
        w.write_record(r.iter().map(field))?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    String::from_utf8(bytes)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e).into())
}

/// The CSV of `tables`; `only`: one table was asked for (no title and legend lines).
pub(crate) fn document(tables: &[&Table], only: bool) -> Result<String, ::csv::Error> {
    let mut out = String::new();
    for (i, t) in tables.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        if !only {
            let _ = writeln!(out, "# {}\n# {}", t.title, t.legend);
        }
        out.push_str(&csv(t)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_quoted_only_when_needed() {
        // As the hand-written writer did: quotes around `,`, `"` (doubled), `\r` and `\n` only;
        // no value as an empty field.
        let t = Table {
            name: "t".into(),
            title: "T".into(),
            legend: "L".into(),
            columns: vec!["a,b".into(), "c".into(), "d".into()],
            rows: vec![
                vec![
                    Cell::Text("say \"hi\"".into()),
                    Cell::Number(f64::NAN),
                    Cell::Text("x\ny".into()),
                ],
                vec![
                    Cell::Text("it's # / <ok>".into()),
                    Cell::Number(0.1),
                    Cell::Count(3),
                ],
            ],
            markdown: None,
        };
        assert_eq!(
            document(&[&t], true).unwrap(),
            "\"a,b\",c,d\n\"say \"\"hi\"\"\",,\"x\ny\"\nit's # / <ok>,0.1,3\n"
        );
    }
}
