//! Where a dotted key sits in a TOML text, and dotted-key overrides (`--set a.b=1`).
//!
//! In: the file's text and a path like `roll.shafts[1].diameter_mm` (or a byte offset).
//! Out: the 1-based line of that key (or of its nearest existing parent); the dotted path of the
//! key written at an offset ([`key_at`]). Paths run through tables, arrays of tables, inline
//! tables and arrays (`supports[0].journal_roundness[1].amplitude_um`). A TOML parse or schema
//! error as an [`InputError`] with its line and key ([`toml_error`]).

use std::ops::Range;
use std::path::Path;

use toml_edit::{Document, Item, Table, Value};

use crate::error::{line_of_offset, InputError};

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
/// A table key may itself contain dots when written quoted (`"simulation.t_end_s" = 1` in a
/// study's `[set]`): the longest run of path keys that names one written key wins.
pub fn line_of(text: &str, path: &str) -> Option<usize> {
    let doc = Document::parse(text).ok()?;
    let steps = parse_path(path);
    let mut node = Node::Table(doc.as_table());
    let mut best = None;
    let mut i = 0;
    while i < steps.len() {
        let Some((taken, span, next)) = step_into(node, &steps[i..]) else {
            break;
        };
        best = span.or(best);
        node = next;
        i += taken;
    }
    best.map(|r| line_of_offset(text, r.start))
}

/// One move down from `node` along `steps`: how many steps it took, the span of what it found
/// and where it leads.
fn step_into<'a>(
    node: Node<'a>,
    steps: &[Step],
) -> Option<(usize, Option<Range<usize>>, Node<'a>)> {
    match (&steps[0], node) {
        (Step::Key(_), Node::Table(_) | Node::Inline(_)) => {
            let keys = steps
                .iter()
                .take_while(|s| matches!(s, Step::Key(_)))
                .count();
            (1..=keys).rev().find_map(|n| {
                let name = steps[..n]
                    .iter()
                    .filter_map(|s| match s {
                        Step::Key(k) => Some(k.as_str()),
                        Step::Index(_) => None,
                    })
                    .collect::<Vec<_>>()
                    .join(".");
                let (key, item) = match node {
                    Node::Table(t) => t.get_key_value(&name)?,
                    Node::Inline(t) => t.get_key_value(&name)?,
                    _ => return None,
                };
                Some((n, key.span(), Node::of_item(item)))
            })
        }
        (Step::Index(i), Node::Tables(a)) => a.get(*i).map(|t| (1, t.span(), Node::Table(t))),
        (Step::Index(i), Node::Array(a)) => a.get(*i).map(|v| (1, v.span(), Node::of_value(v))),
        _ => None,
    }
}

/// A TOML error of `text` (the file `file`) as an input error: the line of its span and the
/// dotted key there. A text that does not parse (a syntax error, a key given twice) has no
/// document to look keys up in: the key is then the one written at the span, under the nearest
/// table header above it (`set.speed.hz`).
pub fn toml_error(file: &Path, text: &str, e: &toml::de::Error) -> InputError {
    let mut err = InputError::new(file, plain_type_error(e.message()));
    if let Some(span) = e.span() {
        let start = span.start.min(text.len());
        err = err.at_line(line_of_offset(text, start));
        let key = key_at(text, start).or_else(|| written_key(text, span));
        if let Some(key) = key {
            if e.message().contains("duplicate key") && !err.reason.contains('`') {
                err.reason = format!("duplicate key `{key}`: given twice in one table");
            }
            err = err.with_key(key);
        }
    }
    err
}

/// serde's "invalid type: string \"one\", expected u32" with what the key takes in words
/// ("a whole number ≥ 0, written without quotes"); any other message as it is.
pub(crate) fn plain_type_error(message: &str) -> String {
    let Some((found, expected)) = message
        .strip_prefix("invalid type: ")
        .and_then(|m| m.split_once(", expected "))
    else {
        return message.to_string();
    };
    let (what, quoted) = match expected.trim() {
        "f32" | "f64" => ("a number", true),
        "u8" | "u16" | "u32" | "u64" | "usize" => ("a whole number ≥ 0", true),
        "i8" | "i16" | "i32" | "i64" | "isize" => ("a whole number", true),
        "a boolean" => ("true or false", true),
        _ => return message.to_string(),
    };
    let hint = if quoted && found.starts_with("string ") {
        ", written without quotes"
    } else {
        ""
    };
    format!("{message}: the key takes {what}{hint}")
}

/// The key written at `span` of a text that may not parse, prefixed with the table header above
/// it; `None` when the span does not hold a bare or quoted key.
fn written_key(text: &str, span: Range<usize>) -> Option<String> {
    let raw = text.get(span.clone())?.trim();
    let name = raw
        .strip_prefix('"')
        .and_then(|r| r.strip_suffix('"'))
        .or_else(|| raw.strip_prefix('\'').and_then(|r| r.strip_suffix('\'')))
        .unwrap_or(raw);
    let bare = |c: char| c.is_ascii_alphanumeric() || "_-.".contains(c);
    if name.is_empty() || (name == raw && !name.chars().all(bare)) {
        return None;
    }
    let header = text[..span.start.min(text.len())]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .and_then(|l| l.split(']').next())
        .map(|h| h.trim_start_matches('[').trim().to_string());
    Some(match header {
        Some(h) if !h.is_empty() => format!("{h}.{name}"),
        _ => name.to_string(),
    })
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
    fn type_errors_say_what_the_key_takes() {
        assert_eq!(
            plain_type_error("invalid type: string \"one\", expected u32"),
            "invalid type: string \"one\", expected u32: the key takes a whole number ≥ 0, \
             written without quotes"
        );
        assert_eq!(
            plain_type_error("invalid type: boolean `true`, expected f64"),
            "invalid type: boolean `true`, expected f64: the key takes a number"
        );
        assert_eq!(
            plain_type_error("invalid type: integer `3`, expected a string"),
            "invalid type: integer `3`, expected a string"
        );
        assert_eq!(plain_type_error("missing field `x`"), "missing field `x`");
    }

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
    fn finds_quoted_dotted_keys() {
        let text = "[set]\n\"simulation.t_end_s\" = 1.0\n[set.speed]\nhz = 3\n";
        assert_eq!(line_of(text, "set.simulation.t_end_s"), Some(2));
        assert_eq!(line_of(text, "set.speed.hz"), Some(4));
        // A quoted key that is only a prefix of the path: its line.
        assert_eq!(line_of(text, "set.simulation.t_end_s.x"), Some(2));
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
    fn names_duplicate_keys_and_keeps_lines_of_syntax_errors() {
        let p = Path::new("f.toml");
        let text = "[set]\n\"speed.hz\" = 1\n\"speed.hz\" = 2\n";
        let e = toml::from_str::<toml::Table>(text).unwrap_err();
        let e = toml_error(p, text, &e);
        assert_eq!(e.line, Some(3), "{e}");
        assert_eq!(e.key.as_deref(), Some("set.speed.hz"), "{e}");
        assert!(e.reason.contains("duplicate key `set.speed.hz`"), "{e}");
        let text = "a = 1\nb = = 2\n";
        let e = toml::from_str::<toml::Table>(text).unwrap_err();
        assert_eq!(toml_error(p, text, &e).line, Some(2));
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
