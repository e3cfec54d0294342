//! CSV: each table's long form at full precision.
//!
//! In: the tables of a [`Report`](crate::report::Report). Out: per table a `# <title>` and a
//! `# <legend>` line (left out when one table is asked for, so that `pandas.read_csv` reads
//! it), the column names, then one line per row; tables apart by a blank line. A number is
//! written in its shortest round-trip form as [`number_text`] writes it (scientific below 1e-3
//! and from 1e6, as everywhere in the report: `1.427e-5`, not `0.00001427`), no value as an
//! empty field. The records are
//! written by the `csv` crate (`\n` after each; a field with `,`, `"`, `\r` or `\n` quoted, `"`
//! doubled; it would also quote an empty field that is a record's only one, which no table
//! has: each has several columns).

use std::fmt::Write as _;

use crate::report::table::{Cell, Table};
use crate::text::number_text;

/// A cell as a CSV field: full precision, empty for no value (quoted by the writer when needed).
fn field(c: &Cell) -> String {
    match c {
        Cell::Text(t) => t.clone(),
        Cell::Number(x) if x.is_finite() => number_text(*x),
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
                vec![
                    Cell::Number(1.427e-5),
                    Cell::Number(2.5e7),
                    Cell::Number(-0.0005),
                ],
            ],
            markdown: None,
        };
        // Numbers as everywhere in the report: scientific below 1e-3 and from 1e6, full
        // precision (they read back to the same f64).
        assert_eq!(
            document(&[&t], true).unwrap(),
            "\"a,b\",c,d\n\"say \"\"hi\"\"\",,\"x\ny\"\nit's # / <ok>,0.1,3\n1.427e-5,2.5e7,-5e-4\n"
        );
        for x in [1.427e-5, 2.5e7, -5e-4, 0.1 + 0.2] {
            assert_eq!(number_text(x).parse::<f64>().unwrap(), x);
        }
    }
}
