//! The scene file's raw schema, exactly as written (units in key names); `build.rs` validates it.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::position::Position;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub name: Option<String>,
    pub description: Option<String>,
    pub materials: BTreeMap<String, MaterialFile>,
    pub roll: Option<RollFile>,
    pub rotor: Option<RotorFile>,
    pub fe: Option<super::geometry::FeFile>,
    #[serde(default)]
    pub supports: Vec<SupportFile>,
    pub drive: Option<DriveFile>,
    #[serde(default)]
    pub reduction: ReductionFile,
    #[serde(default)]
    pub speed: SpeedFile,
    #[serde(default)]
    pub damping: DampingFile,
    #[serde(default)]
    pub simulation: SimulationFile,
    #[serde(default)]
    pub solver: SolverFile,
    #[serde(default)]
    pub outputs: OutputsFile,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpeedFile {
    #[serde(default = "constant")]
    pub profile: String,
    pub hz: Option<f64>,
    pub rpm: Option<f64>,
    pub from_hz: Option<f64>,
    pub to_hz: Option<f64>,
    pub ramp_start_s: Option<f64>,
    pub ramp_end_s: Option<f64>,
    pub times_s: Option<Vec<f64>>,
    pub steps_hz: Option<Vec<f64>>,
    pub rate_hz_per_s: Option<f64>,
    pub table_hz: Option<Vec<f64>>,
}

impl Default for SpeedFile {
    fn default() -> Self {
        Self {
            profile: constant(),
            hz: Some(0.0),
            rpm: None,
            from_hz: None,
            to_hz: None,
            ramp_start_s: None,
            ramp_end_s: None,
            times_s: None,
            steps_hz: None,
            rate_hz_per_s: None,
            table_hz: None,
        }
    }
}

fn constant() -> String {
    "constant".to_string()
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DampingBandFile {
    pub below_hz: f64,
    pub ratio: f64,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct DampingFile {
    pub schedule: Option<String>,
    pub bands: Option<Vec<DampingBandFile>>,
    pub above_ratio: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SimulationFile {
    #[serde(default = "default_t_end")]
    pub t_end_s: f64,
    #[serde(default)]
    pub settle_s: f64,
    #[serde(default = "default_rate")]
    pub sample_rate_hz: f64,
    #[serde(default = "yes")]
    pub static_start: bool,
    #[serde(default = "default_bound")]
    pub runout_bound_mm: f64,
    #[serde(default = "default_gravity")]
    pub gravity_m_s2: f64,
}

impl Default for SimulationFile {
    fn default() -> Self {
        Self {
            t_end_s: default_t_end(),
            settle_s: 0.0,
            sample_rate_hz: default_rate(),
            static_start: true,
            runout_bound_mm: default_bound(),
            gravity_m_s2: default_gravity(),
        }
    }
}

fn default_t_end() -> f64 {
    1.0
}
fn default_rate() -> f64 {
    1000.0
}
fn default_gravity() -> f64 {
    9.81
}
fn default_bound() -> f64 {
    50.0
}
fn yes() -> bool {
    true
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SolverFile {
    #[serde(default = "default_integrator")]
    pub integrator: String,
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    #[serde(default = "default_hmax")]
    pub hmax: f64,
    #[serde(default = "default_hmin")]
    pub hmin: f64,
    #[serde(default = "default_h0")]
    pub h0: f64,
    #[serde(default = "default_order")]
    pub max_order: usize,
    #[serde(default = "default_rho")]
    pub rho_inf: f64,
    #[serde(default)]
    pub fixed_step: bool,
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
    pub cpu_budget_s: Option<f64>,
    #[serde(default = "default_contact_events")]
    pub contact_events: bool,
}

impl Default for SolverFile {
    fn default() -> Self {
        Self {
            integrator: default_integrator(),
            tolerance: default_tolerance(),
            hmax: default_hmax(),
            hmin: default_hmin(),
            h0: default_h0(),
            max_order: default_order(),
            rho_inf: default_rho(),
            fixed_step: false,
            max_steps: default_max_steps(),
            cpu_budget_s: None,
            contact_events: default_contact_events(),
        }
    }
}

fn default_integrator() -> String {
    "bdf".to_string()
}
fn default_tolerance() -> f64 {
    1e-7
}
fn default_hmax() -> f64 {
    1e-4
}
fn default_hmin() -> f64 {
    1e-12
}
fn default_h0() -> f64 {
    1e-6
}
fn default_order() -> usize {
    5
}
fn default_rho() -> f64 {
    0.8
}
fn default_contact_events() -> bool {
    false
}
fn default_max_steps() -> u64 {
    50_000_000
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OutputsFile {
    #[serde(default = "yes")]
    pub runout: bool,
    #[serde(default)]
    pub journal_orbits: bool,
    #[serde(default)]
    pub contact_forces: bool,
    #[serde(default)]
    pub stand_motion: bool,
    #[serde(default)]
    pub modal: bool,
    pub speed: Option<bool>,
}

impl Default for OutputsFile {
    fn default() -> Self {
        Self {
            runout: true,
            journal_orbits: false,
            contact_forces: false,
            stand_motion: false,
            modal: false,
            speed: None,
        }
    }
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
    pub balancing: Option<BalancingFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BalancingFile {
    pub planes_mm: Vec<Position>,
    pub radius_mm: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShellFile {
    pub outer_diameter_mm: f64,
    pub length_mm: f64,
    pub wall_thickness_mm: Option<f64>,
    pub elements: usize,
    pub thickness_map: Option<String>,
    pub synthetic_map: Option<SyntheticMapFile>,
    pub random_wall: Option<RandomWallFile>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RandomWallFile {
    pub seed: u64,
    pub mean_mm: f64,
    pub std_mm: Option<f64>,
    pub correlation_around_mm: Option<f64>,
    pub correlation_along_mm: Option<f64>,
    pub spectrum: Option<Vec<RandomWallHarmonicFile>>,
    #[serde(default = "random_wall_angles")]
    pub angles: usize,
    #[serde(default = "random_wall_stations")]
    pub stations: usize,
}

/// One line of a random wall's spectrum; the order read as a number so that a fraction is
/// refused with its key and line.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RandomWallHarmonicFile {
    pub order: f64,
    pub std_mm: f64,
}

/// The default grid of a random wall: 36 angles (10°) …
fn random_wall_angles() -> usize {
    36
}

/// … and 31 stations, the grid of the shipped reference map.
fn random_wall_stations() -> usize {
    31
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
    pub z_mm: Position,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MassFile {
    pub z_mm: Position,
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
    pub nodes: BTreeMap<String, Position>,
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
    #[serde(default)]
    pub bending_asymmetry: f64,
    pub elements: usize,
    pub material: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DiskFile {
    pub z_mm: Position,
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
    pub kxy_n_per_m: f64,
    #[serde(default)]
    pub kyx_n_per_m: f64,
    #[serde(default)]
    pub cx_ns_per_m: f64,
    #[serde(default)]
    pub cy_ns_per_m: f64,
    #[serde(default)]
    pub cxy_ns_per_m: f64,
    #[serde(default)]
    pub cyx_ns_per_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpringBySpeedFile {
    pub hz: f64,
    pub spring: SpringFile,
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
    pub k_n_per_mm_e: Option<f64>,
    pub exponent: Option<f64>,
    pub geometry: Option<ContactGeometryFile>,
    pub c_max_ns_per_mm: f64,
    pub d_um: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ContactGeometryFile {
    pub contact_length_mm: f64,
    pub roller_diameter_mm: Option<f64>,
    pub journal_material: Option<String>,
    pub roller_material: Option<String>,
    #[serde(default = "default_fit_loads")]
    pub fit_loads_n: Vec<f64>,
    #[serde(default = "default_fit_points")]
    pub fit_points: usize,
}

fn default_fit_loads() -> Vec<f64> {
    vec![1.0, 20000.0]
}
fn default_fit_points() -> usize {
    20000
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
    #[serde(default)]
    pub spring_by_speed: Vec<SpringBySpeedFile>,
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
