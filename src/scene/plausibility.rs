//! Warnings, not errors: a scene that loads, but whose geometry is unlikely to be the machine
//! meant (a typo that passes every range check).
//!
//! In: a validated [`Scene`], its [`Source`] and the `--set` overrides it was loaded with. Out:
//! the warnings as [`InputError`]s (file, line and key of the value to look at, or `--set`),
//! for `rotorsweep check` to print. Method, per tube: a wall (nominal, or a thickness map's
//! thinnest point) under [`THIN_WALL_SHARE`] of the outer diameter (a wall of 0.022 mm on a
//! Ø500 roll was accepted); for a roll, a shell lighter than its ends (the two heads, shafts
//! and journals together: a tube roll's mass is mostly its shell).

use std::f64::consts::PI;

use super::check::Check;
use super::overrides::with_overrides;
use super::source::Source;
use super::types::Scene;
use crate::error::InputError;
use crate::rotor::fe::{SectionSpec, SegmentSpec};

/// A wall thinner than this share of its tube's outer diameter is warned about.
pub const THIN_WALL_SHARE: f64 = 0.01;

/// The warnings of `scene`, loaded from `source` with `overrides` (module doc).
pub fn warnings(
    source: &Source,
    overrides: &[String],
    scene: &Scene,
) -> Result<Vec<InputError>, InputError> {
    let (_, keys) = with_overrides(source, overrides)?;
    let c = Check {
        file: source.path(),
        source,
        overridden: &keys,
    };
    let roll = source.table.contains_key("roll");
    let segments = &scene.rotor.segments;
    let mut out = Vec::new();
    for (i, s) in segments.iter().enumerate() {
        let (outer, thinnest, key) = match &s.section {
            SectionSpec::Tube { inner, .. } if *inner <= 0.0 => continue,
            SectionSpec::Tube { outer, inner, .. } => {
                let key = if roll {
                    "roll.shell.wall_thickness_mm".to_string()
                } else {
                    format!("rotor.segments[{i}].inner_diameter_mm")
                };
                (*outer, 0.5 * (outer - inner), key)
            }
            SectionSpec::Mapped { outer, map, .. } => {
                let key = match source.table.get("roll").and_then(|r| r.get("shell")) {
                    Some(sh) if sh.get("synthetic_map").is_some() => "roll.shell.synthetic_map",
                    Some(sh) if sh.get("random_wall").is_some() => "roll.shell.random_wall",
                    _ => "roll.shell.thickness_map",
                };
                (*outer, map.stats().min_m, key.to_string())
            }
        };
        if thinnest < THIN_WALL_SHARE * outer {
            out.push(c.err_among(
                &[&key, "roll.shell.outer_diameter_mm"],
                format!(
                    "a wall of {:.4} mm on a Ø{:.1} mm tube is under {} % of the \
                     diameter (a typo in the wall or the diameter?)",
                    thinnest * 1e3,
                    outer * 1e3,
                    100.0 * THIN_WALL_SHARE
                ),
            ));
        }
    }
    if roll && segments.len() >= 3 {
        let mid = segments.len() / 2;
        let shell = mass(&segments[mid]);
        let ends: f64 = segments.iter().map(mass).sum::<f64>() - shell;
        if shell < ends {
            out.push(c.err_among(
                &["roll.shell.outer_diameter_mm", "roll.shell.length_mm"],
                format!(
                    "the shell ({shell:.1} kg) is lighter than the roll's heads, shafts \
                     and journals together ({ends:.1} kg): a tube roll's mass is mostly its shell \
                     (a typo in the shell's size or wall?)"
                ),
            ));
        }
    }
    Ok(out)
}

/// A segment's mass [kg]: its mean cross-section (a map's mean wall) × length × density.
fn mass(s: &SegmentSpec) -> f64 {
    let area = match &s.section {
        SectionSpec::Tube { outer, inner, .. } => 0.25 * PI * (outer * outer - inner * inner),
        SectionSpec::Mapped { outer, map, .. } => {
            let t = map.stats().mean_m;
            PI * (outer - t) * t
        }
    };
    area * s.length * s.material.density
}
