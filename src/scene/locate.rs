//! Where a dotted key sits in a TOML text, and dotted-key overrides (`--set a.b=1`).
//!
//! In: the file's text and a path like `roll.shafts[1].diameter_mm` (or a byte offset).
//! Out: the 1-based line of that key (or of its nearest existing parent); the dotted path of the
//! key written at an offset ([`key_at`]). Paths run through tables, arrays of tables, inline
//! tables and arrays (`supports[0].journal_roundness[1].amplitude_um`).

use std::ops::Range;

use toml_edit::{Document, Item, Table, Value};

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
    let mut node = Node::Table(doc.as_table());
    let mut best = None;
    for step in parse_path(path) {
        let (span, next) = match (step, node) {
            (Step::Key(k), Node::Table(t)) => match t.get_key_value(&k) {
                Some((key, item)) => (key.span(), Node::of_item(item)),
                None => break,
            },
            (Step::Key(k), Node::Inline(t)) => match t.get_key_value(&k) {
                Some((key, item)) => (key.span(), Node::of_item(item)),
                None => break,
            },
            (Step::Index(i), Node::Tables(a)) => match a.get(i) {
                Some(t) => (t.span(), Node::Table(t)),
                None => break,
            },
            (Step::Index(i), Node::Array(a)) => match a.get(i) {
                Some(v) => (v.span(), Node::of_value(v)),
                None => break,
            },
            _ => break,
        };
        best = span.or(best);
        node = next;
    }
    best.map(|r| line_of_offset(text, r.start))
}

/// The dotted path (`roll.shell.length_mm`, `supports[0].journal_roundness[1].order`) of the
/// deepest key, table header or value in `text` whose written span contains byte `offset`.
pub fn key_at(text: &str, offset: usize) -> Option<String> {
    let doc = Document::parse(text).ok()?;
    let mut best = None;
    walk_table(doc.as_table(), "", offset, &mut best);
    best
}

/// Where a path step can lead.
#[derive(Clone, Copy)]
enum Node<'a> {
    Table(&'a Table),
    Tables(&'a toml_edit::ArrayOfTables),
    Inline(&'a toml_edit::InlineTable),
    Array(&'a toml_edit::Array),
    Leaf,
}

impl<'a> Node<'a> {
    fn of_item(item: &'a Item) -> Self {
        match item {
            Item::Table(t) => Node::Table(t),
            Item::ArrayOfTables(a) => Node::Tables(a),
            Item::Value(v) => Node::of_value(v),
            Item::None => Node::Leaf,
        }
    }

    fn of_value(v: &'a Value) -> Self {
        match v {
            Value::InlineTable(t) => Node::Inline(t),
            Value::Array(a) => Node::Array(a),
            _ => Node::Leaf,
        }
    }
}

fn contains(span: Option<Range<usize>>, offset: usize) -> bool {
    span.is_some_and(|r| r.start <= offset && offset < r.end.max(r.start + 1))
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

fn walk_table(t: &Table, path: &str, offset: usize, best: &mut Option<String>) {
    if !path.is_empty() && contains(t.span(), offset) {
        *best = Some(path.to_string());
    }
    for (k, _) in t.iter() {
        let Some((key, item)) = t.get_key_value(k) else {
            continue;
        };
        let p = join(path, k);
        if contains(key.span(), offset) {
            *best = Some(p.clone());
        }
        walk_item(item, &p, offset, best);
    }
}

fn walk_item(item: &Item, path: &str, offset: usize, best: &mut Option<String>) {
    match item {
        Item::Table(t) => walk_table(t, path, offset, best),
        Item::ArrayOfTables(a) => {
            for (i, t) in a.iter().enumerate() {
                walk_table(t, &format!("{path}[{i}]"), offset, best);
            }
        }
        Item::Value(v) => walk_value(v, path, offset, best),
        Item::None => {}
    }
}

fn walk_value(v: &Value, path: &str, offset: usize, best: &mut Option<String>) {
    if contains(v.span(), offset) {
        *best = Some(path.to_string());
    }
    match v {
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                walk_value(x, &format!("{path}[{i}]"), offset, best);
            }
        }
        Value::InlineTable(t) => {
            for (k, _) in t.iter() {
                let Some((key, item)) = t.get_key_value(k) else {
                    continue;
                };
                let p = join(path, k);
                if contains(key.span(), offset) {
                    *best = Some(p.clone());
                }
                walk_item(item, &p, offset, best);
            }
        }
        _ => {}
    }
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
    fn finds_lines_inside_inline_tables_and_arrays() {
        let text = "[[s]]\nh = [\n  { o = 1, a = 2 },\n  { o = 2, a = 3 },\n]\nk = { x = 1 }\n";
        assert_eq!(line_of(text, "s[0].h[1].a"), Some(4));
        assert_eq!(line_of(text, "s[0].h[0]"), Some(3));
        assert_eq!(line_of(text, "s[0].k.x"), Some(6));
        assert_eq!(line_of(text, "s[0].h[5].a"), Some(2));
    }

    #[test]
    fn names_the_key_at_an_offset() {
        let text =
            "a = 1\n[roll.shell]\nlength_mm = \"4500\"\n[[s]]\nh = [{ o = 1 }, { o = \"x\" }]\n";
        let at = |needle: &str| key_at(text, text.find(needle).unwrap());
        assert_eq!(at("a =").as_deref(), Some("a"));
        assert_eq!(at("[roll.shell]").as_deref(), Some("roll.shell"));
        assert_eq!(at("length_mm").as_deref(), Some("roll.shell.length_mm"));
        assert_eq!(at("\"4500\"").as_deref(), Some("roll.shell.length_mm"));
        assert_eq!(at("\"x\"").as_deref(), Some("s[0].h[1].o"));
        assert_eq!(at("{ o = 1").as_deref(), Some("s[0].h[0]"));
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
