//! Scene files: one rotor on its supports, in TOML, parsed strictly into SI values.
//!
//! In: a `.toml` scene (the commented `studies/scenes/reference-roll.toml` is the documentation's
//! spine; every key is in `docs/scene-keys.md`, from [`keys`]), the scenes it `extends`
//! ([`source`]), and optional dotted-key overrides (`--set roll.shell.elements=60`). Axial
//! positions may be written relative to the shell ([`position`]).
//! Out: a validated [`Scene`] in SI units (m, kg, N, s, rad), or an
//! [`InputError`](crate::error::InputError) naming the file, the line, the key and the reason.
//! Units live in key names (`length_mm`, `mass_kg`) and are converted here, once.
//!
//! Unknown keys, missing keys, wrong types, out-of-range values and inconsistent geometry are all
//! errors; nothing panics on bad input. So is anything that would change the physics silently or
//! exhaust the machine: a nominal wall next to a thickness map, a map that does not cover the
//! shell, masses outside the material (in the bore, beyond the outer surface), no supports,
//! an override that replaces an earlier one (`speed.hz` after `speed.hz.x`), a mesh above
//! [`MAX_FE_NODES`], a record above [`MAX_SAMPLES_PER_CHANNEL`] or [`MAX_RECORD_VALUES`].
//!
//! The stage, in the order a scene flows through it: [`source`] reads the file and its bases,
//! `overrides` applies `--set`, `load` reads the raw schema (`file`), `build` validates it
//! through `check`: `geometry` (materials, the roll builder or a general rotor, masses in the
//! material), `supports` (a contact's law as written or fitted to its geometry,
//! [`ContactGeometry`]), `speed` and `settings`, and `limits` (mesh and record size); the
//! result is the data of `types`; [`plausibility`] warns of geometry that loads but is unlikely.
//! [`keys`] documents every key, [`locate`] finds a key's line,
//! [`position`] resolves axial positions.

mod build;
mod check;
mod contact_fit;
mod file;
mod geometry;
pub mod keys;
mod keys_docs;
mod keys_docs_machine;
mod limits;
mod load;
pub mod locate;
mod machine;
mod machine_file;
mod machine_loads;
mod overrides;
pub mod plausibility;
pub mod position;
mod settings;
pub mod source;
mod speed;
mod supports;
mod types;

pub use contact_fit::{ContactFit, ContactGeometry};
pub use geometry::{fe_body_files, fe_body_rings};
pub use limits::{MAX_FE_NODES, MAX_RECORD_VALUES, MAX_SAMPLES_PER_CHANNEL};
pub use machine_loads::{LoadHistory, Variation, Web};
pub use overrides::{
    parse_override, replaces, set_path, with_override_values, with_overrides, COMMAND_LINE,
};
pub use settings::{DampingBands, Outputs, SimulationSettings};
pub use speed::{SpeedProfile, MAX_SPEED_HZ};
pub use types::{
    ContactLaw, CoverSpec, Drive, Harmonic, LinearSupport, Machine, MachineRoll, Nip, NipLaw,
    Roller, RollerPhase, RollerSupport, Scene, SpringDamper, Stand, Support, SupportModel,
};
