//! The scene's `[materials]`: each named material → a [`Material`] in SI, looked up by name.
//!
//! In: the `[materials.NAME]` tables (Young's modulus in GPa, Poisson's ratio, density in
//! kg/m³). Out: [`Materials`], each a [`Material`] (Pa, -, kg/m³), or an [`InputError`] at the
//! key; a name no table defines is an error where it is used, listing the defined ones. Method:
//! range checks (Poisson's ratio in [-0.99, 0.499], Young's modulus and density within what a
//! material can have), in name order.

use std::collections::BTreeMap;

use crate::error::InputError;
use crate::rotor::fe::Material;
use crate::scene::check::Check;
use crate::scene::file::MaterialFile;

/// The scene's materials by name.
pub(crate) struct Materials(BTreeMap<String, Material>);

impl Materials {
    /// Every `[materials.NAME]`, checked in name order.
    pub(crate) fn new(
        c: &Check,
        list: &BTreeMap<String, MaterialFile>,
    ) -> Result<Self, InputError> {
        let mut materials = BTreeMap::new();
        for (name, m) in list {
            materials.insert(name.clone(), material(c, &format!("materials.{name}"), m)?);
        }
        Ok(Self(materials))
    }

    /// The material `name`, as the key `key` names it.
    pub(crate) fn get(&self, c: &Check, key: &str, name: &str) -> Result<Material, InputError> {
        self.0.get(name).copied().ok_or_else(|| {
            c.err(
                key,
                format!(
                    "unknown material `{name}` (defined: {})",
                    self.0.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            )
        })
    }
}

/// Young's modulus [GPa] a material may have: from soft rubber (1e-4) to ten times diamond's
/// (1e4); E = 1e30 GPa left the eigen-solvers without an answer.
pub(crate) const YOUNGS_MODULUS_GPA: (f64, f64) = (1e-4, 1e4);

/// Density [kg/m³] a material may have: from foams (1) to five times osmium's (1e5); 1e300
/// overflowed the mass matrix.
pub(crate) const DENSITY_KG_M3: (f64, f64) = (1.0, 1e5);

fn material(c: &Check, key: &str, m: &MaterialFile) -> Result<Material, InputError> {
    let nu = c.range(&format!("{key}.poisson"), m.poisson, -0.99, 0.499)?;
    let (e0, e1) = YOUNGS_MODULUS_GPA;
    let (d0, d1) = DENSITY_KG_M3;
    Ok(Material {
        youngs_modulus: 1e9
            * c.range(
                &format!("{key}.youngs_modulus_gpa"),
                m.youngs_modulus_gpa,
                e0,
                e1,
            )?,
        poisson: nu,
        density: c.range(&format!("{key}.density_kg_m3"), m.density_kg_m3, d0, d1)?,
    })
}
