//! A roll shell's wall as a seeded synthetic thickness map: `roll.shell.synthetic_map` → a
//! [`SyntheticSpec`] in m.
//!
//! In: the synthetic map's table (mean, min, max and standard deviation of the wall in mm,
//! harmonics with phases in degrees, the random share, the correlation length in mm, the grid).
//! Out: the [`SyntheticSpec`] (m, rad) that [`ThicknessMap::synthetic`](crate::rotor::wall::ThicknessMap::synthetic)
//! draws, or an [`InputError`] at the key. Method: range checks; min < mean < max.

use std::f64::consts::PI;

use crate::error::InputError;
use crate::rotor::wall::{AxialShape, HarmonicSpec, SyntheticSpec};
use crate::scene::check::Check;
use crate::scene::file::SyntheticMapFile;

pub(super) fn synthetic_spec(c: &Check, s: &SyntheticMapFile) -> Result<SyntheticSpec, InputError> {
    let k = "roll.shell.synthetic_map";
    let mean = c.positive(&format!("{k}.mean_mm"), s.mean_mm)?;
    let min = c.positive(&format!("{k}.min_mm"), s.min_mm)?;
    let max = c.positive(&format!("{k}.max_mm"), s.max_mm)?;
    let std = c.positive(&format!("{k}.std_mm"), s.std_mm)?;
    if !(min < mean && mean < max) {
        return Err(c.err(k, "needs min_mm < mean_mm < max_mm"));
    }
    let mut harmonics = Vec::new();
    for (i, h) in s.harmonics.iter().enumerate() {
        let hk = format!("{k}.harmonics[{i}]");
        harmonics.push(HarmonicSpec {
            order: c.count(&format!("{hk}.order"), h.order as usize, 1, 64)? as u32,
            weight: c.non_negative(&format!("{hk}.weight"), h.weight)?,
            phase_rad: c.finite(&format!("{hk}.phase_deg"), h.phase_deg)? * PI / 180.0,
            phase_twist_rad: c.finite(&format!("{hk}.twist_deg"), h.twist_deg)? * PI / 180.0,
            axial_shape: match h.axial_shape.as_str() {
                "constant" => AxialShape::Constant,
                "half-sine" => AxialShape::HalfSine,
                "linear" => AxialShape::Linear,
                other => {
                    return Err(c.err(
                        &format!("{hk}.axial_shape"),
                        format!("`{other}`: expected constant, half-sine or linear"),
                    ))
                }
            },
        });
    }
    Ok(SyntheticSpec {
        seed: s.seed,
        mean_m: mean * 1e-3,
        std_m: std * 1e-3,
        min_m: min * 1e-3,
        max_m: max * 1e-3,
        harmonics,
        random_share: c.range(&format!("{k}.random_share"), s.random_share, 0.0, 1.0)?,
        correlation_length_m: 1e-3
            * c.positive(
                &format!("{k}.correlation_length_mm"),
                s.correlation_length_mm,
            )?,
        n_angles: c.count(&format!("{k}.angles"), s.angles, 8, 4096)?,
        n_stations: c.count(&format!("{k}.stations"), s.stations, 2, 4096)?,
    })
}
