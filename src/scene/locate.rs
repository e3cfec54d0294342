//! Where a dotted key sits in a TOML text, and dotted-key overrides (`--set a.b=1`).
//!
//! In: the file's text and a path like `roll.shafts[1].diameter_mm`.
//! Out: the 1-based line of that key (or of its nearest existing parent).

use toml_edit::{ArrayOfTables, Document, Item, Table};

use crate::error::line_of_offset;

/// One step of a dotted path.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A table key.
    Key(String),
    /// An array index.
    Index(usize),
}

/// Splits `a.b[2].c` into steps.
pub fn parse_path(path: &str) -> Vec<Step> {
    let mut steps = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        if let Some(i) = rest.find('[') {
            if i > 0 {
                steps.push(Step::Key(rest[..i].to_string()));
            }
            rest = &rest[i..];
            while let Some(stripped) = rest.strip_prefix('[') {
                let end = stripped.find(']').unwrap_or(stripped.len());
                if let Ok(n) = stripped[..end].parse() {
                    steps.push(Step::Index(n));
                }
                rest = stripped.get(end + 1..).unwrap_or("");
            }
        } else if !rest.is_empty() {
            steps.push(Step::Key(rest.to_string()));
        }
    }
    steps
}

/// The 1-based line where `path` (or the deepest existing prefix of it) is written in `text`.
pub fn line_of(text: &str, path: &str) -> Option<usize> {
    let doc = Document::parse(text).ok()?;
    let mut table: &Table = doc.as_table();
    let mut aot: Option<&ArrayOfTables> = None;
    let mut best = None;
    for step in parse_path(path) {
        match (step, aot) {
            (Step::Index(i), Some(a)) => {
                let Some(t) = a.get(i) else { break };
                best = t.span().or(best);
                table = t;
                aot = None;
            }
            (Step::Key(k), None) => {
                let Some((key, item)) = table.get_key_value(&k) else {
                    break;
                };
                best = key.span().or(best);
                match item {
                    Item::Table(t) => table = t,
                    Item::ArrayOfTables(a) => aot = Some(a),
                    _ => break,
                }
            }
            _ => break,
        }
    }
    best.map(|r| line_of_offset(text, r.start))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_lines_of_nested_keys() {
        let text = "a = 1\n[roll.shell]\nlength_mm = 4500\n\n[[roll.shafts]]\nd = 1\n[[roll.shafts]]\nd = 2\n";
        assert_eq!(line_of(text, "a"), Some(1));
        assert_eq!(line_of(text, "roll.shell.length_mm"), Some(3));
        assert_eq!(line_of(text, "roll.shafts[1].d"), Some(8));
        assert_eq!(line_of(text, "roll.shafts[0].d"), Some(6));
        // A missing key points at its deepest existing parent.
        assert_eq!(line_of(text, "roll.shell.elements"), Some(2));
    }

    #[test]
    fn parses_paths() {
        assert_eq!(
            parse_path("x.y[3].z"),
            vec![
                Step::Key("x".into()),
                Step::Key("y".into()),
                Step::Index(3),
                Step::Key("z".into())
            ]
        );
    }
}
