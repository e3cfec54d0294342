//! Axial positions in a scene file: a number of millimetres, or a place relative to the shell.
//!
//! In: the value of a `z_mm` key (`roll.sensors[i].z_mm`, `roll.balancing.planes_mm[i]`,
//! `roll.masses[i].z_mm`, and the `[rotor]` keys `sensors`, `masses`, `disks`, `nodes`).
//! A number is millimetres along the axis as before (from the shell's tending end for a
//! `[roll]`, on the rotor's own z for a `[rotor]`). A string is `ANCHOR` or `ANCHOR±MM`:
//! - `"centre"` (or `"center"`): the middle of the shell (of a `[rotor]`: of the rotor);
//! - `"0.25L"`: a fraction of the shell's length from its tending end (`"1L"` is the drive end);
//! - `"tending"` and `"drive"`: the shell's ends (a `[rotor]`: `"start"` and `"end"`);
//! - with `+MM` or `-MM` millimetres added: `"tending+150"`, `"drive-700"`, `"centre+100"`.
//!
//! So a roll of another length keeps its sensor planes at the same places relative to its
//! shell. Out: the position in millimetres on the scene's axis ([`Position::mm`]); the range
//! checks stay where the value is used.

use std::fmt;

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;

/// An axial position as written (module doc).
#[derive(Debug, Clone, PartialEq)]
pub enum Position {
    /// Millimetres on the scene's axis.
    Mm(f64),
    /// A place relative to the shell (or rotor) and an offset [mm].
    Relative {
        /// Where it is measured from.
        anchor: Anchor,
        /// Millimetres added (toward the drive end when positive).
        offset_mm: f64,
        /// As written, for messages.
        text: String,
    },
}

/// What a relative position is measured from.
#[derive(Debug, Clone, PartialEq)]
pub enum Anchor {
    /// The middle.
    Centre,
    /// A fraction of the length from the first end.
    Fraction(f64),
    /// A named end (`tending`, `drive`, `start`, `end`).
    End(String),
}

/// The axis that relative positions refer to: the shell of a `[roll]`, the whole `[rotor]`.
pub struct Frame {
    /// z of its first end [mm].
    pub start_mm: f64,
    /// Its length [mm].
    pub length_mm: f64,
    /// The names of its first and second end.
    pub ends: (&'static str, &'static str),
    /// What it is, for messages ("the shell", "the rotor").
    pub what: &'static str,
}

/// The syntax, for messages.
pub const SYNTAX: &str = "a number of mm, or \"centre\", a fraction of the length (\"0.25L\"), \
     or an end (\"tending\", \"drive\"; for a [rotor] \"start\", \"end\"), each optionally with \
     an offset in mm (\"tending+150\", \"drive-700\", \"centre+100\")";

impl Position {
    /// Parses the string form (module doc).
    pub fn parse(s: &str) -> Result<Position, String> {
        let t = s.trim();
        let bad = || format!("`{s}` is not an axial position: expected {SYNTAX}");
        let split = t
            .char_indices()
            .skip(1)
            .find(|&(_, c)| c == '+' || c == '-')
            .map_or(t.len(), |(i, _)| i);
        let (head, tail) = t.split_at(split);
        let head = head.trim();
        let anchor = if head == "centre" || head == "center" {
            Anchor::Centre
        } else if let Some(f) = head.strip_suffix('L') {
            let f: f64 = f.trim().parse().map_err(|_| bad())?;
            if !f.is_finite() {
                return Err(bad());
            }
            Anchor::Fraction(f)
        } else if !head.is_empty() && head.chars().all(|c| c.is_ascii_lowercase()) {
            Anchor::End(head.to_string())
        } else {
            return Err(bad());
        };
        let offset_mm = if tail.is_empty() {
            0.0
        } else {
            let sign = if tail.starts_with('-') { -1.0 } else { 1.0 };
            let v: f64 = tail[1..].trim().parse().map_err(|_| bad())?;
            if !v.is_finite() || tail[1..].trim().starts_with(['+', '-']) {
                return Err(bad());
            }
            sign * v
        };
        Ok(Position::Relative {
            anchor,
            offset_mm,
            text: t.to_string(),
        })
    }

    /// The position in mm on the scene's axis.
    pub fn mm(&self, frame: &Frame) -> Result<f64, String> {
        let (anchor, offset_mm, text) = match self {
            Position::Mm(v) => return Ok(*v),
            Position::Relative {
                anchor,
                offset_mm,
                text,
            } => (anchor, offset_mm, text),
        };
        let from = match anchor {
            Anchor::Centre => frame.start_mm + 0.5 * frame.length_mm,
            Anchor::Fraction(f) => frame.start_mm + f * frame.length_mm,
            Anchor::End(e) if e == frame.ends.0 => frame.start_mm,
            Anchor::End(e) if e == frame.ends.1 => frame.start_mm + frame.length_mm,
            Anchor::End(e) => {
                return Err(format!(
                    "`{text}`: unknown end `{e}`; the ends of {} are `{}` and `{}` (or use \
                     \"centre\" or a fraction such as \"0.25L\")",
                    frame.what, frame.ends.0, frame.ends.1
                ))
            }
        };
        Ok(from + offset_mm)
    }
}

impl<'de> Deserialize<'de> for Position {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Position;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(SYNTAX)
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Position, E> {
                Ok(Position::Mm(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Position, E> {
                Ok(Position::Mm(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Position, E> {
                Ok(Position::Mm(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Position, E> {
                Position::parse(v).map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHELL: Frame = Frame {
        start_mm: 0.0,
        length_mm: 4500.0,
        ends: ("tending", "drive"),
        what: "the shell",
    };

    fn at(s: &str) -> Result<f64, String> {
        Position::parse(s)?.mm(&SHELL)
    }

    #[test]
    fn relative_positions_on_a_4500_mm_shell() {
        // The reference roll's sensor and balancing planes (studies/scenes/reference-roll.toml):
        // 700 mm from each end and the centre; 150 mm from each end.
        assert_eq!(at("tending+700"), Ok(700.0));
        assert_eq!(at("drive-700"), Ok(3800.0));
        assert_eq!(at("centre"), Ok(2250.0));
        assert_eq!(at("center"), Ok(2250.0));
        assert_eq!(at("0.25L"), Ok(1125.0));
        assert_eq!(at(" 0.5L + 10 "), Ok(2260.0));
        assert_eq!(at("drive"), Ok(4500.0));
        assert_eq!(at("centre-2.5"), Ok(2247.5));
    }

    #[test]
    fn malformed_positions_are_refused_with_the_syntax() {
        for bad in [
            "",
            "middle+",
            "0.25",
            "L",
            "xL",
            "centre+-5",
            "drive+nan",
            "Centre",
            "1e999L",
        ] {
            let r = at(bad);
            assert!(r.is_err(), "{bad:?} gave {r:?}");
        }
        let e = at("start+10").unwrap_err();
        assert!(e.contains("`tending` and `drive`"), "{e}");
        assert!(at("centre+5x")
            .unwrap_err()
            .contains("not an axial position"));
    }
}
