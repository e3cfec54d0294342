//! Nastran bulk-data text: lines → cards of fields, and Nastran's real numbers.
//!
//! In: the text of a bulk-data file (a `.bdf`/`.dat` deck or a punch file `.pch`): cards in
//! small field (8-character fields: columns 1–8 the name, 9–72 eight data fields, 73–80 the
//! continuation field), large field (name ending in `*`: four 16-character data fields a line,
//! continuation lines starting with `*`) or free field (fields separated by commas; a name
//! ending in `*` takes four data fields a line); continuation lines start with `+`, `*`, `,`
//! or a blank first field; `$` starts a comment (`$ units: …` is read like Matrix Market's
//! `% units:`); tabs expand to the next multiple of 8 columns; everything before a
//! `BEGIN BULK` line (executive and case control), if the file has one, and after `ENDDATA` is
//! skipped. Out: the [`Card`]s, each field with its line and columns, and the units comment;
//! or an [`InputError`] naming the file and line: a fixed-field line longer than 80 columns, a
//! free-field line with more fields than a line holds, a continuation line with no card before
//! it, an `INCLUDE` (not followed), characters that are not ASCII.
//! Method: MSC/NX Nastran Quick Reference Guide, "Bulk Data Entry Format": a card's data fields
//! are numbered from 2; a large-field line's four fields and its continuation's four make the
//! eight of one small-field line, so a card is its data fields in order whatever the format.
//! The continuation field (columns 73–80, a punch file's sequence number) is not read.
//! [`real`] reads Nastran's real numbers: `1.5`, `1.5E+3`, `1.5D+3`, and the exponent without
//! its letter, `1.5+3`, `-.5-2`.

use std::path::Path;

use crate::error::InputError;

/// One data field of a card.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// Its text, trimmed (empty: a blank field).
    pub text: String,
    /// The 1-based line it is on.
    pub line: usize,
    /// Its first column (1-based) and width on a fixed-field line; (0, 0) in free field.
    pub columns: (usize, usize),
}

impl Field {
    /// Where the field is, for an error: `field N, columns a–b` or `field N (free field)`,
    /// `number` the card's field number (2 = the first data field).
    pub fn place(&self, number: usize) -> String {
        match self.columns {
            (0, _) => format!("field {number} (free field)"),
            (a, w) => format!("field {number}, columns {a}-{}", a + w - 1),
        }
    }
}

/// A card: its name (upper case, without a large field's `*`) and its data fields (field 2 on).
#[derive(Debug, Clone, PartialEq)]
pub struct Card {
    /// The card's name, `DMIG`.
    pub name: String,
    /// The 1-based line the card starts on.
    pub line: usize,
    /// Whether the card is in large field (`DMIG*`).
    pub large: bool,
    /// Data fields, `fields[0]` being the card's field 2.
    pub fields: Vec<Field>,
}

/// A units comment (`$ units: …`) and its line.
pub type UnitsComment = Option<(String, usize)>;

/// The largest bulk-data file read: 4 GiB, as the sparse Matrix Market reader's (a 20 000-DOF
/// matrix as DMIG cards is ~0.1 GB).
pub const MAX_BYTES: u64 = super::matrix_market::MAX_SPARSE_BYTES;

fn expand_tabs(l: &str) -> String {
    let mut s = String::with_capacity(l.len() + 16);
    for c in l.chars() {
        if c == '\t' {
            let pad = 8 - s.len() % 8;
            s.extend(std::iter::repeat_n(' ', pad));
        } else {
            s.push(c);
        }
    }
    s
}

/// The cards of bulk-data text and its `$ units:` comment with its line (module doc); `path`
/// names the file in errors.
pub fn cards(path: &Path, text: &str) -> Result<(Vec<Card>, UnitsComment), InputError> {
    let mut out = Vec::new();
    let units = for_each_card(path, text, |c| {
        out.push(c);
        Ok(())
    })?;
    Ok((out, units))
}

/// Hands each card of bulk-data text to `each` as soon as it is complete (its continuation
/// lines read), in file order, so a reader need not hold every card's fields at once; the
/// `$ units:` comment with its line (module doc). The first error, the text's or `each`'s,
/// stops the reading.
pub fn for_each_card(
    path: &Path,
    text: &str,
    mut each: impl FnMut(Card) -> Result<(), InputError>,
) -> Result<UnitsComment, InputError> {
    let err = |line: usize, r: String| InputError::new(path, r).at_line(line);
    let upper_start = |l: &str| l.trim_start().to_ascii_uppercase();
    let has_begin_bulk = text.lines().any(|l| {
        let u = upper_start(l);
        u.starts_with("BEGIN") && u.split_whitespace().any(|w| w == "BULK")
    });
    let mut in_bulk = !has_begin_bulk;
    let mut open: Option<Card> = None;
    let mut units = None;
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        if !in_bulk {
            let u = upper_start(raw);
            in_bulk = u.starts_with("BEGIN") && u.split_whitespace().any(|w| w == "BULK");
            continue;
        }
        if !raw.is_ascii() {
            return Err(err(
                no,
                "characters that are not ASCII: a bulk-data file is ASCII text".into(),
            ));
        }
        let line = expand_tabs(raw.trim_end_matches(['\r', '\n']));
        let line = line.trim_end();
        if line.trim().is_empty() {
            continue;
        }
        if let Some(c) = line.trim_start().strip_prefix('$') {
            if let Some(u) = c.trim().strip_prefix("units:") {
                units = Some((u.trim().to_string(), no));
            }
            continue;
        }
        let head = upper_start(line);
        if head.starts_with("ENDDATA") {
            break;
        }
        if head.starts_with("INCLUDE") {
            return Err(err(
                no,
                "INCLUDE is not followed: give the matrices in one file".into(),
            ));
        }
        let first = line.as_bytes()[0];
        let continuation = matches!(first, b'+' | b'*' | b',' | b' ');
        if continuation && open.is_none() {
            return Err(err(
                no,
                format!("a continuation line with no card before it: `{line}`"),
            ));
        }
        let free = line.contains(',');
        let (name, large, fields) = if free {
            let parts: Vec<&str> = line.split(',').collect();
            let head = parts[0].trim();
            let large = if continuation {
                head.starts_with('*')
            } else {
                head.ends_with('*')
            };
            let per = if large { 4 } else { 8 };
            let data = &parts[1..];
            if data.len() > per + 1 {
                return Err(err(
                    no,
                    format!(
                        "{} fields after the first on a free-field line: a {} line holds {per} \
                         data fields and a continuation field",
                        data.len(),
                        if large { "large-field" } else { "small-field" }
                    ),
                ));
            }
            let fields = (0..per)
                .map(|k| Field {
                    text: data.get(k).map_or("", |s| s.trim()).to_string(),
                    line: no,
                    columns: (0, 0),
                })
                .collect::<Vec<_>>();
            (head.to_ascii_uppercase(), large, fields)
        } else {
            let name_field = &line[..line.len().min(8)];
            let large = if continuation {
                first == b'*'
            } else {
                name_field.trim_end().ends_with('*')
            };
            let (width, per) = if large { (16, 4) } else { (8, 8) };
            if line.len() > 80 {
                return Err(err(
                    no,
                    format!(
                        "the line is {} columns long: a {} line has at most 80 (the name in 1-8, \
                         {per} fields of {width}, the continuation in 73-80): a field of the \
                         wrong width?",
                        line.len(),
                        if large { "large-field" } else { "small-field" }
                    ),
                ));
            }
            let fields = (0..per)
                .map(|k| {
                    let a = 8 + k * width;
                    let b = (a + width).min(line.len());
                    Field {
                        text: line.get(a..b).unwrap_or("").trim().to_string(),
                        line: no,
                        columns: (a + 1, width),
                    }
                })
                .collect();
            (name_field.trim().to_ascii_uppercase(), large, fields)
        };
        if continuation {
            open.as_mut().expect("checked").fields.extend(fields);
        } else {
            let card = Card {
                name: name.trim_end_matches('*').to_string(),
                line: no,
                large,
                fields,
            };
            if let Some(done) = open.replace(card) {
                each(done)?;
            }
        }
    }
    if let Some(done) = open {
        each(done)?;
    }
    Ok(units)
}

/// A Nastran real number (module doc), finite; `None` if the text is none.
pub fn real(s: &str) -> Option<f64> {
    let s = s.trim();
    if s.is_empty() {
        return None;
    }
    let t = s.replace(['D', 'd'], "E");
    let t = if t.contains(['E', 'e']) {
        t
    } else {
        // An exponent sign after the mantissa: 1.5+3, -.5-2.
        match t[1..].find(['+', '-']) {
            Some(p) => format!("{}E{}", &t[..p + 1], &t[p + 1..]),
            None => t,
        }
    };
    t.parse::<f64>().ok().filter(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nastran_reals() {
        for (s, x) in [
            ("1.5", 1.5),
            ("1.5E+3", 1500.0),
            ("1.5D+03", 1500.0),
            ("1.5+3", 1500.0),
            ("-.5-2", -0.005),
            ("7.", 7.0),
            ("-4.500000000D-07", -4.5e-7),
            ("2", 2.0),
        ] {
            assert_eq!(real(s), Some(x), "{s}");
        }
        for s in ["", "abc", "1.5E", "1.2.3"] {
            assert_eq!(real(s), None, "{s}");
        }
    }

    #[test]
    fn the_three_field_formats_give_the_same_fields() {
        let small = "DMIG    K       1       2               3       4             5.\n";
        let large = "DMIG*   K               1               2\n*       3               4               5.\n";
        let free = "DMIG,K,1,2,,3,4,5.\n";
        let texts = |t: &str| -> Vec<String> {
            let (c, _) = cards(Path::new("x"), t).unwrap();
            assert_eq!(c.len(), 1);
            c[0].fields.iter().map(|f| f.text.clone()).collect()
        };
        let want = ["K", "1", "2", "", "3", "4", "5.", ""];
        assert_eq!(texts(small), want);
        assert_eq!(texts(large), want);
        assert_eq!(texts(free), want);
    }
}
