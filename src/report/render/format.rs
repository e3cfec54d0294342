//! The output formats of `rotorsweep report` and [`Report::render`], which writes the report
//! (or one of its tables) in one of them: markdown ([`super::markdown`]), CSV ([`super::csv`]),
//! JSON (one object `{"study", "tables": [{"name", "title", "legend", "columns", "rows"}]}`
//! through serde, a cell as its text, number or null) or HTML without figures
//! ([`super::html`]).

use std::str::FromStr;

use serde::Serialize;

use super::{csv, markdown};
use crate::error::InputError;
use crate::report::table::{Report, Table};
use crate::report::tables::calibration_hint;
use crate::report::Labels;

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Markdown tables under headings.
    Markdown,
    /// CSV, each table after a `# title` and a `# legend` line, tables apart by a blank line.
    Csv,
    /// One JSON object `{"study", "tables": [{"name", "title", "legend", "columns", "rows"}]}`.
    Json,
    /// One self-contained HTML page: the tables and the figures ([`Report::render_html`]).
    Html,
}

impl FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "md" | "markdown" => Ok(Format::Markdown),
            "csv" => Ok(Format::Csv),
            "json" => Ok(Format::Json),
            "html" => Ok(Format::Html),
            _ => Err(format!("unknown format `{s}` (md, csv, json or html)")),
        }
    }
}

impl Report {
    /// The report as text: every table, or only the table `only` (an error naming the file and
    /// the tables it has when there is no such table).
    pub fn render(&self, format: Format, only: Option<&str>) -> Result<String, InputError> {
        let tables = self.pick(only)?;
        let out = match format {
            Format::Markdown => markdown::document(self, &tables, only.is_some()),
            Format::Csv => csv::document(&tables, only.is_some())
                .map_err(|e| InputError::new(&self.file, e.to_string()))?,
            Format::Html => self.html(&tables, &[], None),
            Format::Json => self.json(&tables, None)?,
        };
        Ok(out)
    }

    /// The JSON document of every table, or of the table `only`, with the figures' `labels`
    /// (module `labels`) when given: what `report --format json --labels` prints.
    pub fn render_json(&self, only: Option<&str>, labels: &Labels) -> Result<String, InputError> {
        let tables = self.pick(only)?;
        self.json(&tables, Some(labels))
    }

    /// The tables to render: every table, or only the table `only` (an error naming the file
    /// and the tables it has when there is no such table).
    fn pick(&self, only: Option<&str>) -> Result<Vec<&Table>, InputError> {
        Ok(match only {
            None => self.tables.iter().collect(),
            Some(name) => vec![self.tables.iter().find(|t| t.name == name).ok_or_else(|| {
                let why = calibration_hint(name, &self.tables);
                InputError::new(
                    &self.file,
                    format!(
                        "no table `{name}` in this file{why} (it has: {})",
                        self.table_names().join(", ")
                    ),
                )
            })?],
        })
    }

    /// The JSON document `{"study", "tables", ["labels"]}`, one line.
    fn json(&self, tables: &[&Table], labels: Option<&Labels>) -> Result<String, InputError> {
        #[derive(Serialize)]
        struct Doc<'a> {
            study: &'a str,
            tables: &'a [&'a Table],
            #[serde(skip_serializing_if = "Option::is_none")]
            labels: Option<&'a Labels>,
        }
        let doc = Doc {
            study: &self.study,
            tables,
            labels,
        };
        let mut out =
            serde_json::to_string(&doc).map_err(|e| InputError::new(&self.file, e.to_string()))?;
        out.push('\n');
        Ok(out)
    }
}
