//! The rotor's geometry from a scene: `[materials]`, then either the roll builder (`[roll]`: a
//! tube roll, journal to journal), a general rotor (`[rotor]`: tube segments with disks) or an
//! FE body from files (`[fe]`, `fe`).
//!
//! In: the raw tables (lengths and diameters in mm, masses in g or kg, inertias in kg m²,
//! moduli in GPa) and the validation context. Out: a [`Geometry`]: the
//! [`RotorSpec`](crate::rotor::fe::RotorSpec) in SI with its named nodes, the shell's thickness
//! map, the sensors and the default Craig–Bampton boundary; or an
//! [`InputError`](crate::error::InputError) at the key. Method: `roll` and `rotor` lay out the
//! segments and named points, `shell` gives the roll shell's wall (nominal, a CSV map or a
//! synthetic one), `body` keeps masses in the material, `materials` reads the materials.

mod body;
mod built;
mod fe;
mod materials;
mod roll;
mod rotor;
mod shell;

pub(super) use built::Geometry;
pub(crate) use fe::{build_fe, FeFile};
pub use fe::{fe_body_files, fe_body_rings};
pub(super) use materials::Materials;
pub(super) use roll::build_roll;
pub(super) use rotor::build_rotor;
