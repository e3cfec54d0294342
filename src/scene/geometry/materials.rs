//! The scene's `[materials]`: each named material → a [`Material`] in SI.
//!
//! In: a `[materials.NAME]` table (Young's modulus in GPa, Poisson's ratio, density in kg/m³).
//! Out: the [`Material`] (Pa, -, kg/m³) or an [`InputError`] at the key. Method: range checks
//! (Poisson's ratio in [-0.99, 0.499]).

use crate::error::InputError;
use crate::rotor::fe::Material;
use crate::scene::check::Check;
use crate::scene::file::MaterialFile;

pub(crate) fn material(c: &Check, key: &str, m: &MaterialFile) -> Result<Material, InputError> {
    let nu = c.range(&format!("{key}.poisson"), m.poisson, -0.99, 0.499)?;
    Ok(Material {
        youngs_modulus: 1e9
            * c.positive(&format!("{key}.youngs_modulus_gpa"), m.youngs_modulus_gpa)?,
        poisson: nu,
        density: c.positive(&format!("{key}.density_kg_m3"), m.density_kg_m3)?,
    })
}
