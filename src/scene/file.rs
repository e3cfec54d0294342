//! The scene file's raw schema, exactly as written (units in key names); `mod.rs` validates it.

use std::collections::BTreeMap;

use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub name: Option<String>,
    pub description: Option<String>,
    pub materials: BTreeMap<String, MaterialFile>,
    pub roll: Option<RollFile>,
    pub rotor: Option<RotorFile>,
    #[serde(default)]
    pub supports: Vec<SupportFile>,
    pub drive: Option<DriveFile>,
    #[serde(default)]
    pub reduction: ReductionFile,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialFile {
    pub youngs_modulus_gpa: f64,
    pub poisson: f64,
    pub density_kg_m3: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RollFile {
    pub material: String,
    pub shell: ShellFile,
    pub heads: HeadFile,
    pub shafts: Vec<ShaftFile>,
    pub journal: ShaftFile,
    #[serde(default)]
    pub sensors: Vec<SensorFile>,
    #[serde(default)]
    pub masses: Vec<MassFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShellFile {
    pub outer_diameter_mm: f64,
    pub length_mm: f64,
    pub wall_thickness_mm: f64,
    pub elements: usize,
    pub thickness_map: Option<String>,
    pub synthetic_map: Option<SyntheticMapFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SyntheticMapFile {
    pub seed: u64,
    pub mean_mm: f64,
    pub std_mm: f64,
    pub min_mm: f64,
    pub max_mm: f64,
    pub random_share: f64,
    pub correlation_length_mm: f64,
    pub angles: usize,
    pub stations: usize,
    #[serde(default)]
    pub harmonics: Vec<SyntheticHarmonicFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SyntheticHarmonicFile {
    pub order: u32,
    pub weight: f64,
    #[serde(default)]
    pub phase_deg: f64,
    #[serde(default)]
    pub twist_deg: f64,
    pub axial_shape: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct HeadFile {
    pub thickness_mm: f64,
    pub material: Option<String>,
    #[serde(default = "one")]
    pub elements: usize,
}

fn one() -> usize {
    1
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShaftFile {
    pub diameter_mm: f64,
    pub length_mm: f64,
    pub elements: usize,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SensorFile {
    pub name: String,
    pub z_mm: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MassFile {
    pub z_mm: f64,
    pub radius_mm: f64,
    pub angle_deg: f64,
    pub mass_g: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RotorFile {
    #[serde(default)]
    pub z_start_mm: f64,
    pub segments: Vec<SegmentFile>,
    #[serde(default)]
    pub disks: Vec<DiskFile>,
    #[serde(default)]
    pub masses: Vec<MassFile>,
    #[serde(default)]
    pub nodes: BTreeMap<String, f64>,
    #[serde(default)]
    pub sensors: Vec<SensorFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SegmentFile {
    pub length_mm: f64,
    pub outer_diameter_mm: f64,
    #[serde(default)]
    pub inner_diameter_mm: f64,
    pub elements: usize,
    pub material: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DiskFile {
    pub z_mm: f64,
    pub mass_kg: f64,
    pub polar_kg_m2: f64,
    pub diametral_kg_m2: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpringFile {
    pub kx_n_per_m: f64,
    pub ky_n_per_m: f64,
    #[serde(default)]
    pub cx_ns_per_m: f64,
    #[serde(default)]
    pub cy_ns_per_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StandFile {
    pub mass_kg: f64,
    pub kx_n_per_m: f64,
    pub ky_n_per_m: f64,
    pub cx_ns_per_m: f64,
    pub cy_ns_per_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ContactFile {
    pub k_n_per_mm_e: f64,
    pub exponent: f64,
    pub c_max_ns_per_mm: f64,
    pub d_um: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct HarmonicFile {
    pub order: u32,
    pub amplitude_um: f64,
    #[serde(default)]
    pub phase_rad: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RollerFile {
    pub name: String,
    pub angle_deg: f64,
    pub diameter_mm: f64,
    #[serde(default)]
    pub roundness: Vec<HarmonicFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SupportFile {
    pub node: String,
    #[serde(rename = "type")]
    pub kind: String,
    pub spring: Option<SpringFile>,
    pub mass_kg: Option<f64>,
    pub ground: Option<SpringFile>,
    pub journal_diameter_mm: Option<f64>,
    pub stand: Option<StandFile>,
    pub contact: Option<ContactFile>,
    #[serde(default)]
    pub rollers: Vec<RollerFile>,
    #[serde(default)]
    pub journal_roundness: Vec<HarmonicFile>,
    pub roller_phase: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DriveFile {
    pub node: String,
    pub axial_stiffness_n_per_m: f64,
    #[serde(default)]
    pub axial_damping_ns_per_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ReductionFile {
    #[serde(default = "default_modes")]
    pub modes: String,
    pub boundary: Option<Vec<String>>,
}

impl Default for ReductionFile {
    fn default() -> Self {
        Self {
            modes: default_modes(),
            boundary: None,
        }
    }
}

fn default_modes() -> String {
    "30n+12st".to_string()
}
