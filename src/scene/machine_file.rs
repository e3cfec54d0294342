//! The raw schema of a machine file (several rolls in nips), exactly as written (units in key
//! names); `machine.rs` validates it.

use serde::Deserialize;

use super::file::HarmonicFile;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MachineFile {
    pub name: Option<String>,
    pub description: Option<String>,
    pub rolls: Vec<MachineRollFile>,
    #[serde(default)]
    pub nips: Vec<NipFile>,
    #[serde(default)]
    pub webs: Vec<WebFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MachineRollFile {
    pub name: String,
    pub scene: String,
    #[serde(default)]
    pub set: Vec<String>,
    pub position_mm: Vec<f64>,
    pub surface_speed_of: Option<String>,
    pub arm_force_n: Option<Vec<f64>>,
    pub arm_profile: Option<String>,
    pub arm_amplitude_n: Option<Vec<f64>>,
    pub arm_frequency_hz: Option<f64>,
    pub arm_phase_deg: Option<f64>,
    pub arm_times_s: Option<Vec<f64>>,
    pub arm_table_n: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    pub roundness: Vec<HarmonicFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct NipFile {
    pub name: String,
    pub roll_a: String,
    pub roll_b: String,
    pub from_mm: f64,
    pub to_mm: f64,
    pub segments: usize,
    pub law: String,
    pub stiffness_n_per_m2: Option<f64>,
    pub cover_on: Option<String>,
    pub cover_thickness_mm: Option<f64>,
    pub cover_modulus_mpa: Option<f64>,
    pub cover_poisson: Option<f64>,
    pub cover_unrelaxed_modulus_mpa: Option<f64>,
    pub cover_relaxation_time_s: Option<f64>,
    pub cover_loss_factor: Option<f64>,
    pub cover_loss_frequency_hz: Option<f64>,
    pub cover_points: Option<usize>,
    #[serde(default)]
    pub cover_roundness: Vec<HarmonicFile>,
    pub damping_ns_per_m2: Option<f64>,
    pub line_load_kn_per_m: Option<f64>,
    pub crown_um: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct WebFile {
    pub name: String,
    pub roll: String,
    pub from_mm: f64,
    pub to_mm: f64,
    pub tension_kn_per_m: Option<f64>,
    pub wrap_deg: f64,
    pub resultant_deg: f64,
    pub profile: Option<String>,
    pub amplitude_kn_per_m: Option<f64>,
    pub frequency_hz: Option<f64>,
    pub phase_deg: Option<f64>,
    pub times_s: Option<Vec<f64>>,
    pub table_kn_per_m: Option<Vec<f64>>,
}
