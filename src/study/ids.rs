//! The ids of a study's jobs, reduced models, linear systems and reference runs: stable hashes
//! (the same on every machine and run) of every input that defines each.
//!
//! In: the text of every file a job's scene reads ([`scene_inputs`]), the base scene table with
//! the job's overrides applied ([`JobTable`]), its pruning share and the pilot's overrides. Out:
//! ids `m…` (the unpruned reduced model: the model tables), `l…` (the linearised system: the
//! model on its supports and drive, and gravity), `j…` (the job: the whole scene, and for a
//! pruned job how its pilot ran) and `r…` (the reference: the job's physics with the reference's
//! solver keys), each a prefix and 16 hex digits of FNV-1a 64 ([`fnv1a`]) over canonically
//! serialised subtrees.

use std::path::Path;

use super::job_table::JobTable;
use super::values::value_text;
use crate::scene::source::Source;

/// Scene tables that make the reduced model (a pruning pilot runs on its jobs' model).
pub(super) const MODEL_TABLES: [&str; 5] = ["materials", "roll", "rotor", "reduction", "fe"];

/// The pilot overrides as one canonical text (for ids).
pub(crate) fn pilot_text(pilot: &[(String, toml::Value)]) -> String {
    pilot
        .iter()
        .map(|(k, v)| format!("{k}={}", value_text(v)))
        .collect::<Vec<_>>()
        .join(";")
}

/// FNV-1a 64-bit: a stable hash for ids (the same on every machine and run).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    fnv1a_from(FNV_OFFSET, bytes)
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a 64 continued from `state` (the hash of what came before) over `bytes`.
fn fnv1a_from(state: u64, bytes: &[u8]) -> u64 {
    let mut h = state;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The text of every file a scene reads (the scene, the scenes it extends, then its thickness
/// map), as the state of FNV-1a after it: every id starts with it, so a study hashes it once
/// per distinct map, not once per id (the reference roll's map alone is longer than the rest of
/// a job's id text).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Inputs {
    state: u64,
}

/// The inputs of a scene `source` whose thickness map (if any) has the text `map_text`.
pub(super) fn scene_inputs(source: &Source, map_text: Option<&str>) -> Inputs {
    let mut state = FNV_OFFSET;
    for l in &source.layers {
        state = fnv1a_from(state, l.text.as_bytes());
    }
    if let Some(t) = map_text {
        state = fnv1a_from(state, t.as_bytes());
    }
    Inputs { state }
}

/// The thickness map a job's scene reads (`roll.shell.thickness_map`), as written.
pub(super) fn map_of<'t>(merged: &'t JobTable) -> Option<&'t str> {
    merged
        .get("roll")
        .and_then(|r| r.get("shell"))
        .and_then(|s| s.get("thickness_map"))
        .and_then(|m| m.as_str())
}

/// The text of the thickness map `csv` (relative to the scene `source`); empty when it cannot
/// be read (the scene's own check reports that).
pub(super) fn map_text(source: &Source, csv: &str) -> String {
    let p = source.path().parent().unwrap_or(Path::new(".")).join(csv);
    crate::error::read_text(&p).unwrap_or_default()
}

/// `prefix` and 16 hex digits of FNV-1a over the inputs' text and the parts: first the
/// canonical parts of `merged`'s selection `keep`/`drop` (named `selection`:
/// [`JobTable::hash_parts`]), then `rest`, each part (the concatenation of its pieces) after a
/// U+001F.
fn hash_id(
    prefix: char,
    inputs: Inputs,
    merged: &JobTable,
    (selection, keep, drop): (&'static str, &[&str], &[&str]),
    rest: &[&[&str]],
) -> String {
    let start = fnv1a_from(inputs.state, "\u{1f}".as_bytes());
    let mut h = merged.hash_parts(selection, keep, drop, start, |h, piece| {
        fnv1a_from(h, piece.as_bytes())
    });
    for p in rest {
        h = fnv1a_from(h, "\u{1f}".as_bytes());
        for piece in *p {
            h = fnv1a_from(h, piece.as_bytes());
        }
    }
    format!("{prefix}{h:016x}")
}

/// The id of the unpruned reduced model of a job's scene.
pub(super) fn model_id(inputs: Inputs, merged: &JobTable) -> String {
    hash_id('m', inputs, merged, ("model", &MODEL_TABLES, &[]), &[])
}

/// The tables of a job's linearised system: its model with its modal damping, on its supports
/// and drive.
const LINEAR_TABLES: [&str; 8] = [
    "materials",
    "roll",
    "rotor",
    "reduction",
    "fe",
    "damping",
    "supports",
    "drive",
];

/// The id of a merged scene's linearised system: its model with its modal damping, on its
/// supports and drive, with gravity.
pub(super) fn linear_id(inputs: Inputs, merged: &JobTable) -> String {
    let gravity = merged
        .get("simulation")
        .and_then(|s| s.get("gravity_m_s2"))
        .map(value_text)
        .unwrap_or_default();
    hash_id(
        'l',
        inputs,
        merged,
        ("linear", &LINEAR_TABLES, &[]),
        &[&[&gravity]],
    )
}

/// The id of a job: its whole merged scene and, for a pruned job, how its pilot ran.
pub(super) fn job_id(
    inputs: Inputs,
    merged: &JobTable,
    prune: Option<f64>,
    pilot: &[(String, toml::Value)],
) -> String {
    // A pruned job also depends on how its pilot ran.
    let prune_text = prune
        .map(|p| format!("{p:e}|{}", pilot_text(pilot)))
        .unwrap_or_default();
    hash_id('j', inputs, merged, ("job", &[], &[]), &[&[&prune_text]])
}

/// The id of a job's reference run: the job's physics (its scene without the solver keys, and
/// without the mode set when the reference sets its own) and the reference's solver keys.
pub(super) fn reference_id(
    inputs: Inputs,
    merged: &JobTable,
    reference_merged: &JobTable,
    sets_modes: bool,
) -> String {
    let physics: (&'static str, &[&str], &[&str]) = if sets_modes {
        ("physics without modes", &[], &["solver", "reduction"])
    } else {
        ("physics", &[], &["solver"])
    };
    hash_id(
        'r',
        inputs,
        merged,
        physics,
        &[&reference_merged.canonical_parts(&["solver"], &[])],
    )
}
