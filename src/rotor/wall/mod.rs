//! Wall-thickness map t(φ, z) of a tube roll's shell.
//!
//! **In:** a measured map as CSV ([`ThicknessMap::from_csv`]), a synthetic recipe
//! ([`SyntheticSpec`] → [`ThicknessMap::synthetic`]), a random field ([`RandomFieldSpec`] →
//! [`ThicknessMap::random_field`]) or one thickness ([`ThicknessMap::uniform`]),
//! plus the shell length.
//! **Out:** the wall thickness t(φ, z) in metres anywhere on the shell
//! ([`ThicknessMap::thickness`]), the thinnest wall at a z ([`ThicknessMap::min_thickness_at`]),
//! its statistics ([`ThicknessMap::stats`]) and the map written
//! back as CSV ([`ThicknessMap::write_csv`]). The section integrator turns t into
//! R_i(φ, z) = R_o − t(φ, z).
//!
//! | file | what |
//! |---|---|
//! | `map.rs` | the map: stations, interpolation, statistics |
//! | `csv.rs` | the `angle_deg,z_mm,thickness_mm` CSV: reading (file:line errors) and writing |
//! | `synthetic.rs` | synthetic maps: harmonics, seeded random field, fit of the tails |
//! | `random_field.rs` | random walls: a stationary Gaussian field per seed, realised statistics |
//!
//! # Conventions
//! - SI inside: φ in radians, z and t in metres.
//! - φ is the **body-frame** angle, positive about +z (x toward y): with y up and z from the
//!   tending end to the drive end, that is **clockwise seen from the tending end** (looking along
//!   +z) and counter-clockwise seen from the drive end; φ = 0 along +x of the body frame. z runs
//!   along the shell from its tending end (z = 0) to its drive end (z = L).
//! - CSV files use the source's convention, the same direction of angle in degrees (`csv.rs`).

mod csv;
mod map;
mod random_field;
mod synthetic;

#[cfg(test)]
mod test_support;

pub(crate) use self::csv::data_rows;
pub use self::csv::COVERAGE_SHARE;
pub use map::{MapStats, ThicknessMap};
pub use random_field::{Angular, FieldStats, RandomFieldSpec};
pub use synthetic::{AxialShape, HarmonicSpec, SyntheticSpec};
