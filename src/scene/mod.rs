//! Scene files: one rotor on its supports, in TOML, parsed strictly into SI values.
//!
//! In: a `.toml` scene (the commented `studies/scenes/reference-roll.toml` is the documentation's
//! spine; every key is in `docs/scene-keys.md`, from [`keys`]), the scenes it `extends`
//! ([`source`]), and optional dotted-key overrides (`--set roll.shell.elements=60`). Axial
//! positions may be written relative to the shell ([`position`]).
//! Out: a validated [`Scene`] in SI units (m, kg, N, s, rad), or an [`InputError`] naming the file,
//! the line, the key and the reason. Units live in key names (`length_mm`, `mass_kg`) and are
//! converted here, once.
//!
//! Unknown keys, missing keys, wrong types, out-of-range values and inconsistent geometry are all
//! errors; nothing panics on bad input. So is anything that would change the physics silently or
//! exhaust the machine: a nominal wall next to a thickness map, a map that does not cover the
//! shell, masses outside the material (in the bore, beyond the outer surface), no supports,
//! an override that replaces an earlier one (`speed.hz` after `speed.hz.x`), a mesh above [`MAX_FE_NODES`], a record
//! above [`MAX_SAMPLES_PER_CHANNEL`] or [`MAX_RECORD_VALUES`].

mod file;
pub mod keys;
mod keys_docs;
pub mod locate;
pub mod position;
mod settings;
pub mod source;
mod speed;

pub use settings::{DampingBands, Outputs, SimulationSettings};
pub use speed::{SpeedProfile, MAX_SPEED_HZ};

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::InputError;
use crate::integrators::SolverSettings;
use crate::rotor::fe::{
    BalancingSpec, DiskSpec, Material, PointMassSpec, RotorSpec, SectionSpec, SegmentSpec,
};
use crate::rotor::reduction::ModeSelection;
use crate::rotor::wall::{AxialShape, HarmonicSpec, SyntheticSpec, ThicknessMap};

use file::*;
use position::{Frame, Position};
use source::Source;

/// A validated scene in SI units.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// Free text from the scene file.
    pub description: String,
    /// The file it came from.
    pub source: PathBuf,
    /// The files it extends (`extends`), nearest first.
    pub bases: Vec<PathBuf>,
    /// The rotor to mesh.
    pub rotor: RotorSpec,
    /// Thickness map of the shell, if the rotor is a roll with a map.
    pub thickness_map: Option<Arc<ThicknessMap>>,
    /// Names of the Craig–Bampton boundary (journal) nodes.
    pub boundary: Vec<String>,
    /// Modes to keep.
    pub modes: ModeSelection,
    /// Sensor planes: (name, named node).
    pub sensors: Vec<String>,
    /// Supports.
    pub supports: Vec<Support>,
    /// Axial drive spring.
    pub drive: Option<Drive>,
    /// Spin speed profile.
    pub speed: SpeedProfile,
    /// Modal damping by frequency band.
    pub damping: DampingBands,
    /// Run window and sampling.
    pub simulation: SimulationSettings,
    /// Integrator settings.
    pub solver: SolverSettings,
    /// What a run records.
    pub outputs: Outputs,
}

/// A support at a named node.
#[derive(Debug, Clone)]
pub struct Support {
    /// Named node of the rotor.
    pub node: String,
    /// The support's model.
    pub model: SupportModel,
}

impl Support {
    /// Whether the support has its own moving mass (a stand, or a linear support's mass): two
    /// more coordinates (x, y) in the dynamic system.
    pub fn has_mass(&self) -> bool {
        match &self.model {
            SupportModel::Rollers(_) => true,
            SupportModel::Linear(l) => l.mass.is_some(),
        }
    }
}

/// Support models.
#[derive(Debug, Clone)]
pub enum SupportModel {
    /// Linear spring–dampers per direction, optionally through a support mass.
    Linear(LinearSupport),
    /// The journal on two rollers on a stand (contact, roundness).
    Rollers(RollerSupport),
}

/// Stiffness and damping in the inertial (x horizontal, y vertical) plane [N/m, Ns/m]: the
/// force on the rotor is −K w − C ẇ with K = [[kx, kxy], [kyx, ky]] and C likewise.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpringDamper {
    /// Horizontal stiffness.
    pub kx: f64,
    /// Vertical stiffness.
    pub ky: f64,
    /// Cross stiffness, x force per y displacement.
    pub kxy: f64,
    /// Cross stiffness, y force per x displacement.
    pub kyx: f64,
    /// Horizontal damping.
    pub cx: f64,
    /// Vertical damping.
    pub cy: f64,
    /// Cross damping, x force per y velocity.
    pub cxy: f64,
    /// Cross damping, y force per x velocity.
    pub cyx: f64,
}

impl SpringDamper {
    /// The stiffness matrix K.
    pub fn k_matrix(&self) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(self.kx, self.kxy, self.kyx, self.ky)
    }

    /// The damping matrix C.
    pub fn c_matrix(&self) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(self.cx, self.cxy, self.cyx, self.cy)
    }
}

/// A linear support: rotor node —(spring)— [support mass —(ground spring)—] ground.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSupport {
    /// Between the rotor node and the support mass (or the ground).
    pub spring: SpringDamper,
    /// Speed-dependent values: (Ω [rad/s], spring), ascending; linear between the points and
    /// constant beyond them. Empty: `spring` at every speed.
    pub by_speed: Vec<(f64, SpringDamper)>,
    /// Optional support mass [kg] with its spring to the ground.
    pub mass: Option<(f64, SpringDamper)>,
}

impl LinearSupport {
    /// The spring at spin speed Ω [rad/s].
    pub fn spring_at(&self, omega: f64) -> SpringDamper {
        let t = &self.by_speed;
        if t.is_empty() {
            return self.spring;
        }
        if omega <= t[0].0 {
            return t[0].1;
        }
        for w in t.windows(2) {
            let ((w0, a), (w1, b)) = (w[0], w[1]);
            if omega <= w1 {
                let x = (omega - w0) / (w1 - w0);
                let mix = |p: f64, q: f64| p + x * (q - p);
                return SpringDamper {
                    kx: mix(a.kx, b.kx),
                    ky: mix(a.ky, b.ky),
                    kxy: mix(a.kxy, b.kxy),
                    kyx: mix(a.kyx, b.kyx),
                    cx: mix(a.cx, b.cx),
                    cy: mix(a.cy, b.cy),
                    cxy: mix(a.cxy, b.cxy),
                    cyx: mix(a.cyx, b.cyx),
                };
            }
        }
        t[t.len() - 1].1
    }
}

/// A stand: rigid upper part on springs to the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stand {
    /// Mass of the moving upper part [kg].
    pub mass: f64,
    /// Its springs and dampers to the ground.
    pub spring: SpringDamper,
}

/// The IMPACT contact law of `thesis-data.md` §3 in SI: F = k δ^e − step(δ; 0, d) c_max δ̇.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// k [N/m^e].
    pub k: f64,
    /// Exponent e [-].
    pub exponent: f64,
    /// Full damping c_max [Ns/m].
    pub c_max: f64,
    /// Penetration at which the damping reaches c_max [m].
    pub d: f64,
}

impl ContactLaw {
    /// Penetration [m] that carries the force `f` [N] statically.
    pub fn penetration(&self, f: f64) -> f64 {
        (f.max(0.0) / self.k).powf(1.0 / self.exponent)
    }

    /// Tangent stiffness dF/dδ [N/m] at penetration δ.
    pub fn tangent(&self, delta: f64) -> f64 {
        if delta <= 0.0 {
            0.0
        } else {
            self.exponent * self.k * delta.powf(self.exponent - 1.0)
        }
    }
}

/// One roundness harmonic H = c cos(k α + φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Harmonic {
    /// Order k.
    pub order: u32,
    /// Amplitude c [m].
    pub amplitude: f64,
    /// Phase φ [rad].
    pub phase: f64,
}

/// A support roller.
#[derive(Debug, Clone, PartialEq)]
pub struct Roller {
    /// Name (front, rear).
    pub name: String,
    /// Angle of the roller centre from straight below the journal, positive toward +x [rad].
    pub angle: f64,
    /// Diameter [m].
    pub diameter: f64,
    /// Roundness harmonics.
    pub roundness: Vec<Harmonic>,
}

/// How roller roundness is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RollerPhase {
    /// H_r as a function of the roller's own angle (roll angle × R_j/R_r).
    RollerAngle,
    /// As the source did: H_r as a function of the roll angle, no phase.
    RollAngle,
}

/// A journal on two rollers on a stand.
#[derive(Debug, Clone, PartialEq)]
pub struct RollerSupport {
    /// Journal diameter [m].
    pub journal_diameter: f64,
    /// Journal roundness H_j(α).
    pub journal_roundness: Vec<Harmonic>,
    /// The rollers.
    pub rollers: Vec<Roller>,
    /// Roller roundness drive.
    pub roller_phase: RollerPhase,
    /// Contact law.
    pub contact: ContactLaw,
    /// The stand.
    pub stand: Stand,
}

/// The drive's axial spring on the rotor.
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    /// Named node it acts on.
    pub node: String,
    /// Axial stiffness [N/m].
    pub axial_stiffness: f64,
    /// Axial damping [Ns/m].
    pub axial_damping: f64,
}

/// Checks values and reports errors at their key and line, in the file that wrote the key.
struct Check<'a> {
    file: &'a Path,
    source: &'a Source,
    overridden: &'a [String],
}

impl Check<'_> {
    fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        if self.overridden.iter().any(|k| key.starts_with(k.as_str())) {
            return InputError::new(Path::new("<command line --set>"), reason).with_key(key);
        }
        self.source.err(key, reason)
    }

    /// An axial position (`position.rs`) in mm on the scene's axis.
    fn position(&self, key: &str, p: &Position, frame: &Frame) -> Result<f64, InputError> {
        p.mm(frame).map_err(|r| self.err(key, r))
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be a positive number, got {v}")))
        }
    }

    fn non_negative(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be zero or positive, got {v}")))
        }
    }

    fn finite(&self, key: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be a finite number, got {v}")))
        }
    }

    fn range(&self, key: &str, v: f64, lo: f64, hi: f64) -> Result<f64, InputError> {
        if v.is_finite() && v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(self.err(key, format!("must lie in [{lo}, {hi}], got {v}")))
        }
    }

    fn count(&self, key: &str, v: usize, lo: usize, hi: usize) -> Result<usize, InputError> {
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(self.err(key, format!("must be an integer in [{lo}, {hi}], got {v}")))
        }
    }
}

/// Parses `key=value` of `--set`: the value as a TOML value, or as a string if it is not one.
pub fn parse_override(s: &str) -> Result<(String, toml::Value), String> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}`: expected key=value"))?;
    let k = k.trim().to_string();
    let v = v.trim();
    let value = toml::from_str::<toml::Table>(&format!("v = {v}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(v.to_string()));
    Ok((k, value))
}

/// Whether setting dotted key `later` after `earlier` replaces it: `earlier` lies strictly inside
/// `later` (`speed.hz` after `speed.hz.x`), so the earlier value would be dropped.
pub fn replaces(later: &str, earlier: &str) -> bool {
    let (l, e) = (locate::parse_path(later), locate::parse_path(earlier));
    l.len() < e.len() && e[..l.len()] == l[..]
}

/// Sets a dotted key (with `[i]` indices) in a TOML value, creating tables on the way.
pub fn set_path(root: &mut toml::Value, key: &str, value: toml::Value) -> Result<(), String> {
    fn set_in(
        v: &mut toml::Value,
        steps: &[locate::Step],
        value: toml::Value,
        key: &str,
    ) -> Result<(), String> {
        use locate::Step;
        let Some((first, rest)) = steps.split_first() else {
            *v = value;
            return Ok(());
        };
        let child = match (first, v) {
            (Step::Key(k), toml::Value::Table(t)) => t
                .entry(k.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new())),
            (Step::Index(i), toml::Value::Array(a)) => {
                let len = a.len();
                a.get_mut(*i)
                    .ok_or_else(|| format!("`{key}`: index {i} out of range (length {len})"))?
            }
            (Step::Key(k), toml::Value::Array(a)) => {
                // `supports.0.x` for `supports[0].x`: say how arrays are indexed.
                let hint = match k.parse::<usize>() {
                    Ok(i) => format!(
                        "; arrays are indexed with brackets: write `…[{i}]…` (e.g. `supports[0].stand.mass_kg`)"
                    ),
                    Err(_) => format!(" (an array of {} entries: index it as `[i]`)", a.len()),
                };
                return Err(format!(
                    "`{key}`: the path does not match the file's structure{hint}"
                ));
            }
            _ => {
                return Err(format!(
                    "`{key}`: the path does not match the file's structure"
                ))
            }
        };
        set_in(child, rest, value, key)
    }
    let steps = locate::parse_path(key);
    if steps.is_empty() {
        return Err("empty key".into());
    }
    set_in(root, &steps, value, key)
}

/// The merged table of a scene (`source`) with `key=value` overrides applied in order, and the
/// keys they set. An override that replaces an earlier one, or whose path does not fit the
/// table, is an error at the command line.
pub fn with_overrides(
    source: &Source,
    overrides: &[String],
) -> Result<(toml::Value, Vec<String>), InputError> {
    let cli = Path::new("<command line --set>");
    let mut table = toml::Value::Table(source.table.clone());
    let mut keys: Vec<String> = Vec::new();
    for o in overrides {
        let (k, v) = parse_override(o).map_err(|r| InputError::new(cli, r))?;
        if let Some(other) = keys.iter().find(|p| replaces(&k, p)) {
            return Err(InputError::new(
                cli,
                format!(
                    "`{k}` would replace `{other}`, given before it: `{other}` would be dropped"
                ),
            )
            .with_key(k));
        }
        set_path(&mut table, &k, v).map_err(|r| InputError::new(cli, r).with_key(k.clone()))?;
        keys.push(k);
    }
    Ok((table, keys))
}

/// The dotted key a deserialisation error of the overridden scene `table` is about.
fn override_error_key(table: &toml::Value) -> Option<String> {
    let text = toml::to_string(table).ok()?;
    let e = toml::from_str::<SceneFile>(&text).err()?;
    locate::key_at(&text, e.span()?.start)
}

impl Scene {
    /// Reads, overrides (`key=value`) and validates a scene file (and the files it extends).
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, InputError> {
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot read the scene file: {e}")))?;
        Self::from_text(path, &text, overrides)
    }

    /// Validates a scene given as text (`path` names it in errors and anchors relative paths).
    pub fn from_text(path: &Path, text: &str, overrides: &[String]) -> Result<Scene, InputError> {
        Self::from_source(&Source::from_text(path, text)?, overrides)
    }

    /// Validates a scene read with its bases ([`Source`]), with `key=value` overrides.
    pub fn from_source(source: &Source, overrides: &[String]) -> Result<Scene, InputError> {
        let path = source.path();
        let not_study = |e: InputError| {
            if crate::error::toml_kind(&source.layers[0].text) == Some("study") {
                InputError::new(
                    path,
                    "this is a study file (it names a `scene`), not a scene: run it with \
                     `rotorsweep plan` or `rotorsweep run`",
                )
            } else {
                e
            }
        };
        let mut raw: SceneFile = match source.layers.as_slice() {
            // One file: its own spans give the line of a schema error.
            [only] => toml::from_str(&only.text)
                .map_err(|e| not_study(locate::toml_error(path, &only.text, &e)))?,
            _ => {
                let table = toml::Value::Table(source.table.clone());
                table.clone().try_into().map_err(|e: toml::de::Error| {
                    not_study(match override_error_key(&table) {
                        Some(k) => source.err(&k, e.message().to_string()),
                        None => InputError::new(path, e.message().to_string()),
                    })
                })?
            }
        };
        let (table, keys) = with_overrides(source, overrides)?;
        if !overrides.is_empty() {
            let cli = Path::new("<command line --set>");
            raw = table.clone().try_into().map_err(|e: toml::de::Error| {
                let err = InputError::new(cli, e.message().to_string());
                match override_error_key(&table) {
                    Some(k) => err.with_key(k),
                    None => err,
                }
            })?;
        }
        let check = Check {
            file: path,
            source,
            overridden: &keys,
        };
        let mut scene = build(&check, raw)?;
        scene.bases = source.layers[1..].iter().map(|l| l.path.clone()).collect();
        Ok(scene)
    }
}

fn material(c: &Check, key: &str, m: &MaterialFile) -> Result<Material, InputError> {
    let nu = c.range(&format!("{key}.poisson"), m.poisson, -0.99, 0.499)?;
    Ok(Material {
        youngs_modulus: 1e9
            * c.positive(&format!("{key}.youngs_modulus_gpa"), m.youngs_modulus_gpa)?,
        poisson: nu,
        density: c.positive(&format!("{key}.density_kg_m3"), m.density_kg_m3)?,
    })
}

fn build(c: &Check, raw: SceneFile) -> Result<Scene, InputError> {
    let mut materials = BTreeMap::new();
    for (name, m) in &raw.materials {
        materials.insert(name.clone(), material(c, &format!("materials.{name}"), m)?);
    }
    let find_mat = |key: &str, name: &str| {
        materials.get(name).copied().ok_or_else(|| {
            c.err(
                key,
                format!(
                    "unknown material `{name}` (defined: {})",
                    materials.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            )
        })
    };
    let (rotor, map, sensors, default_boundary) = match (&raw.roll, &raw.rotor) {
        (Some(roll), None) => build_roll(c, roll, &find_mat)?,
        (None, Some(rotor)) => build_rotor(c, rotor, &find_mat)?,
        _ => return Err(c.err(
            "roll",
            "a scene needs exactly one of [roll] (the roll builder) or [rotor] (a general rotor)",
        )),
    };
    let named: Vec<&str> = rotor.named_points.iter().map(|(n, _)| n.as_str()).collect();
    let node_exists = |key: &str, n: &str| {
        if named.contains(&n) {
            Ok(n.to_string())
        } else {
            Err(c.err(
                key,
                format!("unknown node `{n}` (named nodes: {})", named.join(", ")),
            ))
        }
    };
    if raw.supports.is_empty() {
        return Err(c.err(
            "supports",
            "a scene needs at least one support ([[supports]]): without supports the rotor falls",
        ));
    }
    let mut supports = Vec::new();
    for (i, s) in raw.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        let node = node_exists(&format!("{key}.node"), &s.node)?;
        if supports.iter().any(|x: &Support| x.node == node) {
            return Err(c.err(
                &format!("{key}.node"),
                format!("node `{node}` already has a support"),
            ));
        }
        let model = support_model(c, &key, s, roll_journal(&raw))?;
        supports.push(Support { node, model });
    }
    let drive = match &raw.drive {
        Some(d) => Some(Drive {
            node: node_exists("drive.node", &d.node)?,
            axial_stiffness: c
                .positive("drive.axial_stiffness_n_per_m", d.axial_stiffness_n_per_m)?,
            axial_damping: c
                .non_negative("drive.axial_damping_ns_per_m", d.axial_damping_ns_per_m)?,
        }),
        None => None,
    };
    let boundary = match &raw.reduction.boundary {
        Some(b) => b
            .iter()
            .enumerate()
            .map(|(i, n)| node_exists(&format!("reduction.boundary[{i}]"), n))
            .collect::<Result<Vec<_>, _>>()?,
        None if !default_boundary.is_empty() => default_boundary,
        None => supports.iter().map(|s| s.node.clone()).collect(),
    };
    if boundary.is_empty() {
        return Err(c.err(
            "reduction.boundary",
            "no boundary nodes: name them here or add supports",
        ));
    }
    let modes =
        ModeSelection::parse(&raw.reduction.modes).map_err(|r| c.err("reduction.modes", r))?;
    let speed = speed::profile(c, &raw.speed)?;
    let simulation = settings::simulation(c, &raw.simulation)?;
    let scene = Scene {
        name: raw.name.clone().unwrap_or_else(|| {
            c.file
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        }),
        description: raw.description.clone().unwrap_or_default(),
        source: c.file.to_path_buf(),
        bases: Vec::new(),
        rotor,
        thickness_map: map,
        boundary,
        modes,
        sensors,
        supports,
        drive,
        outputs: settings::outputs(&raw.outputs, &speed, &simulation),
        speed,
        damping: settings::damping(c, &raw.damping)?,
        simulation,
        solver: settings::solver(c, &raw.solver)?,
    };
    record_size(c, &scene)?;
    Ok(scene)
}

/// Most samples one output channel of a run may hold, (t_end − settle) × sample_rate + 1: 80 MB
/// per channel (10 000 s at 1 kHz, 100 s at 100 kHz). The analysis needs far fewer (the source's
/// spectra use 8192 samples); a record this long is almost surely a typo in t_end_s or
/// sample_rate_hz, and an unbounded one exhausts the memory.
pub const MAX_SAMPLES_PER_CHANNEL: f64 = 1e7;

/// Most values (samples × channels, time included, 8 bytes each) one run may record: 2 GB, so
/// that a long record with every output on (the modal coordinates too) still fits in memory.
pub const MAX_RECORD_VALUES: f64 = 2.5e8;

/// A run's record stays within [`MAX_SAMPLES_PER_CHANNEL`] and [`MAX_RECORD_VALUES`]. The error
/// names `simulation.t_end_s` when the window alone is too long at the default 1 kHz, else
/// `simulation.sample_rate_hz`.
fn record_size(c: &Check, scene: &Scene) -> Result<(), InputError> {
    let sim = &scene.simulation;
    let samples = scene.samples();
    let channels = scene.channels() + 1;
    let values = samples * channels as f64;
    let basis = format!(
        "(t_end_s − settle_s) × sample_rate_hz = ({} − {}) s × {} Hz gives {samples:.4e} samples \
         per channel",
        sim.t_end, sim.settle, sim.sample_rate
    );
    let reason = if samples > MAX_SAMPLES_PER_CHANNEL {
        format!(
            "{basis}, more than the limit of {MAX_SAMPLES_PER_CHANNEL:e} (80 MB per channel; the \
             analysis needs thousands, not millions)"
        )
    } else if values > MAX_RECORD_VALUES {
        format!(
            "{basis}, × {channels} channels (time, runout, outputs.*) = {values:.4e} values, more \
             than the limit of {MAX_RECORD_VALUES:e} (2 GB) one run may record"
        )
    } else {
        return Ok(());
    };
    let key = if (sim.t_end - sim.settle) * 1e3 > MAX_SAMPLES_PER_CHANNEL {
        "simulation.t_end_s"
    } else {
        "simulation.sample_rate_hz"
    };
    Err(c.err(key, reason))
}

impl Scene {
    /// Modal coordinates of the scene's reduced model: the five rigid modes and the elastic
    /// modes its selection keeps (`reduction.modes`; a pruned run keeps fewer).
    pub fn modal_coordinates(&self) -> usize {
        match &self.modes {
            ModeSelection::Counts { normal, statics } => 5 + normal + statics.saturating_sub(6),
            ModeSelection::List(l) => {
                let elastic: std::collections::BTreeSet<usize> =
                    l.iter().copied().filter(|&i| i >= 5).collect();
                5 + elastic.len()
            }
        }
    }

    /// Output channels a run records (the time axis not counted): two runout directions per
    /// sensor, and as `[outputs]` asks two journal and two stand directions per support, a
    /// contact force per roller, the modal coordinates.
    pub fn channels(&self) -> usize {
        let o = &self.outputs;
        let mut n = 0;
        if o.runout {
            n += 2 * self.sensors.len();
        }
        for s in &self.supports {
            if o.journal_orbits {
                n += 2;
            }
            if o.stand_motion && s.has_mass() {
                n += 2;
            }
            if let (true, SupportModel::Rollers(r)) = (o.contact_forces, &s.model) {
                n += r.rollers.len();
            }
        }
        if o.modal {
            n += self.modal_coordinates();
        }
        if o.speed {
            n += 2;
        }
        n
    }

    /// Most FE nodes the scene's mesh can have (6 DOFs each), as [`MAX_FE_NODES`] counts them.
    pub fn max_nodes(&self) -> usize {
        let r = &self.rotor;
        node_bound(
            r.segments.iter().map(|s| s.elements),
            r.named_points.len() + r.disks.len(),
        )
    }

    /// Samples per channel of a run: one every 1 / sample_rate from settle_s to t_end_s.
    pub fn samples(&self) -> f64 {
        let sim = &self.simulation;
        ((sim.t_end - sim.settle) * sim.sample_rate).floor() + 1.0
    }
}

fn roll_journal(raw: &SceneFile) -> Option<f64> {
    raw.roll.as_ref().map(|r| r.journal.diameter_mm * 1e-3)
}

type Built = (
    RotorSpec,
    Option<Arc<ThicknessMap>>,
    Vec<String>,
    Vec<String>,
);

fn build_roll(
    c: &Check,
    roll: &RollFile,
    find_mat: &dyn Fn(&str, &str) -> Result<Material, InputError>,
) -> Result<Built, InputError> {
    let mat = find_mat("roll.material", &roll.material)?;
    let sh = &roll.shell;
    let outer = 1e-3 * c.positive("roll.shell.outer_diameter_mm", sh.outer_diameter_mm)?;
    let length = 1e-3 * c.positive("roll.shell.length_mm", sh.length_mm)?;
    let elements = c.count("roll.shell.elements", sh.elements, 1, 2000)?;
    // The wall is either nominal (uniform) or a map, never both: with a map, a nominal wall would
    // be ignored in favour of the map's, a silent change of the roll's mass and stiffness.
    let wall = match (sh.wall_thickness_mm, &sh.thickness_map, &sh.synthetic_map) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(c.err(
                "roll.shell.wall_thickness_mm",
                "give either a nominal wall (wall_thickness_mm) or a thickness map \
                 (thickness_map or synthetic_map), not both: with a map the wall, and so the \
                 shell's mass and stiffness, come from the map",
            ))
        }
        (Some(w), None, None) => {
            let wall = 1e-3 * c.positive("roll.shell.wall_thickness_mm", w)?;
            if 2.0 * wall >= outer {
                return Err(c.err(
                    "roll.shell.wall_thickness_mm",
                    format!(
                        "a wall of {} mm does not fit in a {} mm tube",
                        wall * 1e3,
                        outer * 1e3
                    ),
                ));
            }
            Some(wall)
        }
        (None, _, _) => None,
    };
    let map = match (&sh.thickness_map, &sh.synthetic_map) {
        (Some(_), Some(_)) => {
            return Err(c.err(
                "roll.shell.synthetic_map",
                "give either thickness_map (a CSV file) or synthetic_map, not both",
            ))
        }
        (Some(csv), None) => {
            let p = c.file.parent().unwrap_or(Path::new(".")).join(csv);
            // Errors inside the CSV name the CSV and its line, and where the scene names it; an
            // unreadable file is reported where the scene names it.
            let key = "roll.shell.thickness_map";
            let map = ThicknessMap::from_csv(&p, length).map_err(|mut e| match e.line {
                Some(_) => {
                    let at = c.err(key, "");
                    let line = at.line.map(|l| format!(":{l}")).unwrap_or_default();
                    e.reason += &format!(" (the map of `{key}`, {}{line})", at.file.display());
                    e
                }
                None => c.err(key, format!("{}: {}", p.display(), e.reason)),
            })?;
            Some(map)
        }
        (None, Some(s)) => {
            let spec = synthetic_spec(c, s)?;
            spec.validate(length)
                .map_err(|r| c.err("roll.shell.synthetic_map", r))?;
            Some(ThicknessMap::synthetic(&spec, length))
        }
        (None, None) => None,
    };
    if let Some(m) = &map {
        let st = m.stats();
        if st.min_m <= 0.0 || st.max_m >= 0.5 * outer {
            let source = match &sh.thickness_map {
                Some(csv) => format!(
                    " ({})",
                    c.file
                        .parent()
                        .unwrap_or(Path::new("."))
                        .join(csv)
                        .display()
                ),
                None => String::new(),
            };
            return Err(c.err(
                "roll.shell.thickness_map",
                format!(
                    "map thickness {:.3}..{:.3} mm{source} does not fit a {} mm tube",
                    st.min_m * 1e3,
                    st.max_m * 1e3,
                    outer * 1e3
                ),
            ));
        }
    }
    let map = map.map(Arc::new);
    let head_t = 1e-3 * c.positive("roll.heads.thickness_mm", roll.heads.thickness_mm)?;
    let head_mat = match &roll.heads.material {
        Some(m) => find_mat("roll.heads.material", m)?,
        None => mat,
    };
    let head_el = c.count("roll.heads.elements", roll.heads.elements, 1, 100)?;
    let mut shafts = Vec::new();
    for (i, s) in roll.shafts.iter().enumerate() {
        shafts.push(shaft(c, &format!("roll.shafts[{i}]"), s, outer, mat)?);
    }
    let journal = shaft(c, "roll.journal", &roll.journal, outer, mat)?;
    let outboard: f64 = head_t + shafts.iter().map(|s| s.length).sum::<f64>() + journal.length;
    let z_start = -outboard;
    let head = SegmentSpec {
        length: head_t,
        section: SectionSpec::Tube { outer, inner: 0.0 },
        elements: head_el,
        material: head_mat,
    };
    let shell = SegmentSpec {
        length,
        section: match (&map, wall) {
            (Some(m), _) => SectionSpec::Mapped {
                outer,
                map: Arc::clone(m),
                map_z0: 0.0,
            },
            (None, Some(w)) => SectionSpec::Tube {
                outer,
                inner: outer - 2.0 * w,
            },
            (None, None) => {
                return Err(c.err(
                    "roll.shell",
                    "the shell needs its wall: wall_thickness_mm (uniform) or a thickness map \
                     (thickness_map or synthetic_map)",
                ))
            }
        },
        elements,
        material: mat,
    };
    let mut segments = vec![journal.clone()];
    segments.extend(shafts.iter().rev().cloned());
    segments.push(head.clone());
    segments.push(shell);
    segments.push(head);
    segments.extend(shafts.iter().cloned());
    segments.push(journal.clone());
    let mut named_points = vec![
        (
            "journal_tending".to_string(),
            z_start + 0.5 * journal.length,
        ),
        (
            "journal_drive".to_string(),
            length + outboard - 0.5 * journal.length,
        ),
        ("shell_tending_end".to_string(), 0.0),
        ("shell_drive_end".to_string(), length),
    ];
    let shell_frame = Frame {
        start_mm: 0.0,
        length_mm: length * 1e3,
        ends: ("tending", "drive"),
        what: "the shell",
    };
    let mut sensors = Vec::new();
    for (i, s) in roll.sensors.iter().enumerate() {
        let key = format!("roll.sensors[{i}]");
        let zk = format!("{key}.z_mm");
        let z = 1e-3
            * c.range(
                &zk,
                c.position(&zk, &s.z_mm, &shell_frame)?,
                0.0,
                length * 1e3,
            )?;
        if named_points.iter().any(|(n, _)| n == &s.name) {
            return Err(c.err(
                &format!("{key}.name"),
                format!("duplicate node name `{}`", s.name),
            ));
        }
        named_points.push((s.name.clone(), z));
        sensors.push(s.name.clone());
    }
    let mut written = vec![("roll.shell.elements".to_string(), elements)];
    for (i, s) in shafts.iter().enumerate() {
        written.push((format!("roll.shafts[{i}].elements"), 2 * s.elements));
    }
    written.push(("roll.heads.elements".to_string(), 2 * head_el));
    written.push(("roll.journal.elements".to_string(), 2 * journal.elements));
    mesh_size(c, &written, named_points.len())?;
    let body = Body {
        segments: &segments,
        z_start,
        disks: &[],
    };
    let point_masses = masses(c, "roll.masses", &roll.masses, &body, &shell_frame)?;
    let balancing = match &roll.balancing {
        // No planes: no balancing masses (the roll with its own unbalance, as trial-mass
        // balancing starts from).
        Some(b) if b.planes_mm.is_empty() => None,
        Some(b) => {
            let key = "roll.balancing.planes_mm";
            if !(2..=3).contains(&b.planes_mm.len()) {
                return Err(c.err(
                    key,
                    "two planes (rigid balancing) or three (modal) are needed (or none: no balancing)",
                ));
            }
            let mut planes = Vec::new();
            for (i, z) in b.planes_mm.iter().enumerate() {
                let lo = z_start * 1e3;
                let hi = (length + outboard) * 1e3;
                let k = format!("{key}[{i}]");
                let z = c.position(&k, z, &shell_frame)?;
                planes.push(1e-3 * c.range(&k, z, lo, hi)?);
            }
            let mut sorted = planes.clone();
            sorted.sort_by(f64::total_cmp);
            if sorted.windows(2).any(|w| w[1] - w[0] < 1e-3) {
                return Err(c.err(key, "the planes must be at least 1 mm apart"));
            }
            let rk = "roll.balancing.radius_mm";
            let radius = 1e-3 * c.positive(rk, b.radius_mm)?;
            for (i, &z) in planes.iter().enumerate() {
                let what = format!("the balancing mass of plane {}", i + 1);
                in_material(c, rk, &what, radius, (z, None), &body)?;
            }
            Some(BalancingSpec { planes, radius })
        }
        None => None,
    };
    let rotor = RotorSpec {
        z_start,
        segments,
        disks: Vec::new(),
        point_masses,
        named_points,
        balancing,
    };
    let boundary = vec!["journal_tending".to_string(), "journal_drive".to_string()];
    Ok((rotor, map, sensors, boundary))
}

fn shaft(
    c: &Check,
    key: &str,
    s: &ShaftFile,
    shell_outer: f64,
    mat: Material,
) -> Result<SegmentSpec, InputError> {
    let d = 1e-3 * c.positive(&format!("{key}.diameter_mm"), s.diameter_mm)?;
    if d > shell_outer {
        return Err(c.err(
            &format!("{key}.diameter_mm"),
            "a shaft cannot be thicker than the shell",
        ));
    }
    Ok(SegmentSpec {
        length: 1e-3 * c.positive(&format!("{key}.length_mm"), s.length_mm)?,
        section: SectionSpec::Tube {
            outer: d,
            inner: 0.0,
        },
        elements: c.count(&format!("{key}.elements"), s.elements, 1, 1000)?,
        material: mat,
    })
}

/// Most FE nodes a model may have (6 DOFs each). The reduction solves dense eigenproblems of the
/// interior DOFs and holds the assembled matrices densely: memory grows with DOFs² and time with
/// DOFs³. Measured with `rotorsweep modes` on the 2-core machine of the README (busy with other
/// builds): the reference roll at the limit (`roll.shell.elements = 482`, 493 nodes, 2958 DOFs)
/// built in 13.8 s with a peak of 0.74 GB, the Jeffcott rotor at it (2 × 243 elements, 487
/// nodes) in 18.0 s and 0.72 GB; at 600 shell elements it took 28.6 s and 1.1 GB, at 800 74 s
/// and 1.9 GB, and 2000 would need about 60 times the time of the limit and 16 times its memory.
pub const MAX_FE_NODES: usize = 500;

/// The mesh stays within [`MAX_FE_NODES`]: one node more than the elements as written (`written`:
/// the elements key of each segment and the elements it adds) plus one per named point or disk
/// (`extra`), which may each add a node. Too many: an error at the key that adds the most.
fn mesh_size(c: &Check, written: &[(String, usize)], extra: usize) -> Result<(), InputError> {
    let nodes = node_bound(written.iter().map(|(_, e)| *e), extra);
    if nodes <= MAX_FE_NODES {
        return Ok(());
    }
    let worst = written
        .iter()
        .max_by_key(|(_, e)| *e)
        .map_or("elements", |(k, _)| k.as_str());
    Err(c.err(
        worst,
        format!(
            "the mesh would have up to {nodes} nodes ({} DOFs), more than the limit of \
             {MAX_FE_NODES} nodes ({} DOFs): the reduction solves dense eigenproblems of that \
             size (memory grows with DOFs², time with DOFs³; at the limit a model takes about \
             15-20 s and 0.75 GB to build)",
            6 * nodes,
            6 * MAX_FE_NODES
        ),
    ))
}

/// The rotor's material as far as masses go: its segments from `z_start` on, and the axial
/// positions of its rigid disks.
struct Body<'a> {
    segments: &'a [SegmentSpec],
    z_start: f64,
    disks: &'a [DiskSpec],
}

/// Most nodes a mesh of segments of `elements` can have: one more than the elements, plus one
/// per named point or disk (`extra`) that may fall between nodes.
fn node_bound(elements: impl Iterator<Item = usize>, extra: usize) -> usize {
    elements.fold(1 + extra, usize::saturating_add)
}

/// A mass at `radius` [m] from the axis at `(z, phi)` (axial position [m], body angle [rad]) must
/// sit in the rotor's material there: between the bore and the outer surface of a segment that
/// holds z (either one at a joint), or on a rigid disk at that z (a disk's radius is not part of
/// the scene: any radius). Without an angle (a balancing mass, placed later at any angle) a
/// mapped shell's bore is its widest at that z.
fn in_material(
    c: &Check,
    key: &str,
    what: &str,
    radius: f64,
    (z, phi): (f64, Option<f64>),
    body: &Body,
) -> Result<(), InputError> {
    // Radii compare to 1 nm: a mass on the surface, written in mm, is on it.
    const SLACK_M: f64 = 1e-9;
    if body.disks.iter().any(|d| (d.z - z).abs() <= SLACK_M) {
        return Ok(());
    }
    let mut spans = Vec::new();
    let mut z0 = body.z_start;
    for s in body.segments {
        let z1 = z0 + s.length;
        if z >= z0 - SLACK_M && z <= z1 + SLACK_M {
            spans.push(match &s.section {
                SectionSpec::Tube { outer, inner } => (0.5 * inner, 0.5 * outer),
                SectionSpec::Mapped { outer, map, map_z0 } => {
                    let t = match phi {
                        Some(p) => map.thickness(p, z - map_z0),
                        None => map.min_thickness_at(z - map_z0),
                    };
                    (0.5 * outer - t, 0.5 * outer)
                }
            });
        }
        z0 = z1;
    }
    if spans
        .iter()
        .any(|&(a, b)| radius >= a - SLACK_M && radius <= b + SLACK_M)
    {
        return Ok(());
    }
    let inner = spans.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
    let outer = spans.iter().map(|s| s.1).fold(0.0, f64::max);
    let place = if radius < inner {
        "inside the bore"
    } else {
        "outside the rotor"
    };
    Err(c.err(
        key,
        format!(
            "{what} at radius {} mm (z = {} mm) lies {place}: the material there spans {:.3} \
             ... {:.3} mm from the axis",
            radius * 1e3,
            z * 1e3,
            inner * 1e3,
            outer * 1e3
        ),
    ))
}

/// Point masses on the rotor: each within its length and in its material.
fn masses(
    c: &Check,
    key: &str,
    list: &[MassFile],
    body: &Body,
    frame: &Frame,
) -> Result<Vec<PointMassSpec>, InputError> {
    let z_start = body.z_start;
    let z_end = z_start + body.segments.iter().map(|s| s.length).sum::<f64>();
    list.iter()
        .enumerate()
        .map(|(i, m)| {
            let k = format!("{key}[{i}]");
            let zk = format!("{k}.z_mm");
            let z_mm = c.position(&zk, &m.z_mm, frame)?;
            let z = 1e-3 * c.range(&zk, z_mm, z_start * 1e3, z_end * 1e3)?;
            let radius = 1e-3 * c.non_negative(&format!("{k}.radius_mm"), m.radius_mm)?;
            let angle =
                c.range(&format!("{k}.angle_deg"), m.angle_deg, -360.0, 360.0)? * PI / 180.0;
            let rk = format!("{k}.radius_mm");
            in_material(c, &rk, "the mass", radius, (z, Some(angle)), body)?;
            Ok(PointMassSpec {
                z,
                radius,
                angle,
                mass: 1e-3 * c.positive(&format!("{k}.mass_g"), m.mass_g)?,
            })
        })
        .collect()
}

fn synthetic_spec(c: &Check, s: &SyntheticMapFile) -> Result<SyntheticSpec, InputError> {
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

fn build_rotor(
    c: &Check,
    r: &RotorFile,
    find_mat: &dyn Fn(&str, &str) -> Result<Material, InputError>,
) -> Result<Built, InputError> {
    let mut segments = Vec::new();
    for (i, s) in r.segments.iter().enumerate() {
        let k = format!("rotor.segments[{i}]");
        let outer = 1e-3 * c.positive(&format!("{k}.outer_diameter_mm"), s.outer_diameter_mm)?;
        let inner =
            1e-3 * c.non_negative(&format!("{k}.inner_diameter_mm"), s.inner_diameter_mm)?;
        if inner >= outer {
            return Err(c.err(
                &format!("{k}.inner_diameter_mm"),
                "the inner diameter must be smaller than the outer one",
            ));
        }
        segments.push(SegmentSpec {
            length: 1e-3 * c.positive(&format!("{k}.length_mm"), s.length_mm)?,
            section: SectionSpec::Tube { outer, inner },
            elements: c.count(&format!("{k}.elements"), s.elements, 1, 2000)?,
            material: find_mat(&format!("{k}.material"), &s.material)?,
        });
    }
    if segments.is_empty() {
        return Err(c.err("rotor.segments", "a rotor needs at least one segment"));
    }
    let z0 = 1e-3 * c.finite("rotor.z_start_mm", r.z_start_mm)?;
    let z1 = z0 + segments.iter().map(|s| s.length).sum::<f64>();
    let frame = Frame {
        start_mm: z0 * 1e3,
        length_mm: (z1 - z0) * 1e3,
        ends: ("start", "end"),
        what: "the rotor",
    };
    let in_rotor = |key: &str, z: &Position| {
        let z_mm = c.position(key, z, &frame)?;
        c.range(key, z_mm, z0 * 1e3, z1 * 1e3).map(|z| z * 1e-3)
    };
    let mut named_points = Vec::new();
    for (name, z) in &r.nodes {
        named_points.push((name.clone(), in_rotor(&format!("rotor.nodes.{name}"), z)?));
    }
    let mut sensors = Vec::new();
    for (i, s) in r.sensors.iter().enumerate() {
        let k = format!("rotor.sensors[{i}]");
        if named_points.iter().any(|(n, _)| n == &s.name) {
            return Err(c.err(
                &format!("{k}.name"),
                format!("duplicate node name `{}`", s.name),
            ));
        }
        named_points.push((s.name.clone(), in_rotor(&format!("{k}.z_mm"), &s.z_mm)?));
        sensors.push(s.name.clone());
    }
    let mut disks = Vec::new();
    for (i, d) in r.disks.iter().enumerate() {
        let k = format!("rotor.disks[{i}]");
        let disk = DiskSpec {
            z: in_rotor(&format!("{k}.z_mm"), &d.z_mm)?,
            mass: c.positive(&format!("{k}.mass_kg"), d.mass_kg)?,
            polar: c.non_negative(&format!("{k}.polar_kg_m2"), d.polar_kg_m2)?,
            diametral: c.non_negative(&format!("{k}.diametral_kg_m2"), d.diametral_kg_m2)?,
        };
        disk_inertia(c, &k, &disk, z1 - z0)?;
        disks.push(disk);
    }
    let written: Vec<(String, usize)> = segments
        .iter()
        .enumerate()
        .map(|(i, s)| (format!("rotor.segments[{i}].elements"), s.elements))
        .collect();
    mesh_size(c, &written, named_points.len() + disks.len())?;
    let body = Body {
        segments: &segments,
        z_start: z0,
        disks: &disks,
    };
    let point_masses = masses(c, "rotor.masses", &r.masses, &body, &frame)?;
    Ok((
        RotorSpec {
            z_start: z0,
            segments,
            disks,
            point_masses,
            named_points,
            balancing: None,
        },
        None,
        sensors,
        Vec::new(),
    ))
}

/// A rigid disk's inertias must be those of a body: the polar moment at most twice the diametral
/// one (an axisymmetric body: I_p = ∫r² dm ≤ 2 I_d = ∫r² dm + 2∫z² dm), and its size, the radius
/// √(2 I_p / m) of a uniform disk with these values, at most ten rotor lengths (a mass of
/// 1e-308 kg with the inertia of a 12 kg disk makes the eigen-solvers fail).
fn disk_inertia(c: &Check, key: &str, d: &DiskSpec, length: f64) -> Result<(), InputError> {
    if d.polar > 2.0 * d.diametral * (1.0 + 1e-9) {
        return Err(c.err(
            &format!("{key}.polar_kg_m2"),
            format!(
                "a polar moment of {} kg m² cannot exceed twice the diametral one ({} kg m²)",
                d.polar, d.diametral
            ),
        ));
    }
    let radius = (2.0 * d.polar.max(d.diametral) / d.mass).sqrt();
    if radius > 10.0 * length {
        return Err(c.err(
            &format!("{key}.mass_kg"),
            format!(
                "{:e} kg with these inertias is a disk of radius {radius:.3e} m (√(2 I / m)), \
                 more than ten times the rotor's {:.1} mm length",
                d.mass,
                length * 1e3
            ),
        ));
    }
    Ok(())
}

fn spring(c: &Check, key: &str, s: &SpringFile) -> Result<SpringDamper, InputError> {
    Ok(SpringDamper {
        kx: c.non_negative(&format!("{key}.kx_n_per_m"), s.kx_n_per_m)?,
        ky: c.non_negative(&format!("{key}.ky_n_per_m"), s.ky_n_per_m)?,
        kxy: c.finite(&format!("{key}.kxy_n_per_m"), s.kxy_n_per_m)?,
        kyx: c.finite(&format!("{key}.kyx_n_per_m"), s.kyx_n_per_m)?,
        cx: c.non_negative(&format!("{key}.cx_ns_per_m"), s.cx_ns_per_m)?,
        cy: c.non_negative(&format!("{key}.cy_ns_per_m"), s.cy_ns_per_m)?,
        cxy: c.finite(&format!("{key}.cxy_ns_per_m"), s.cxy_ns_per_m)?,
        cyx: c.finite(&format!("{key}.cyx_ns_per_m"), s.cyx_ns_per_m)?,
    })
}

fn harmonics(c: &Check, key: &str, list: &[HarmonicFile]) -> Result<Vec<Harmonic>, InputError> {
    list.iter()
        .enumerate()
        .map(|(i, h)| {
            let k = format!("{key}[{i}]");
            Ok(Harmonic {
                order: c.count(&format!("{k}.order"), h.order as usize, 1, 256)? as u32,
                amplitude: 1e-6 * c.non_negative(&format!("{k}.amplitude_um"), h.amplitude_um)?,
                phase: c.finite(&format!("{k}.phase_rad"), h.phase_rad)?,
            })
        })
        .collect()
}

fn support_model(
    c: &Check,
    key: &str,
    s: &SupportFile,
    roll_journal: Option<f64>,
) -> Result<SupportModel, InputError> {
    match s.kind.as_str() {
        "linear" => {
            let spring_f = s
                .spring
                .as_ref()
                .ok_or_else(|| c.err(key, "a linear support needs a `spring` table"))?;
            let spring_v = spring(c, &format!("{key}.spring"), spring_f)?;
            let mass = match (&s.mass_kg, &s.ground) {
                (Some(m), Some(g)) => Some((
                    c.positive(&format!("{key}.mass_kg"), *m)?,
                    spring(c, &format!("{key}.ground"), g)?,
                )),
                (None, None) => None,
                _ => {
                    return Err(c.err(
                        key,
                        "a support mass needs both `mass_kg` and a `ground` spring table",
                    ))
                }
            };
            let mut by_speed = Vec::new();
            for (i, sp) in s.spring_by_speed.iter().enumerate() {
                let k = format!("{key}.spring_by_speed[{i}]");
                let hz = c.non_negative(&format!("{k}.hz"), sp.hz)?;
                if by_speed.last().is_some_and(|(w, _)| 2.0 * PI * hz <= *w) {
                    return Err(c.err(&format!("{k}.hz"), "speeds must ascend"));
                }
                by_speed.push((2.0 * PI * hz, spring(c, &k, &sp.spring)?));
            }
            Ok(SupportModel::Linear(LinearSupport {
                spring: spring_v,
                by_speed,
                mass,
            }))
        }
        "rollers" => {
            let need = |what: &str| c.err(key, format!("a rollers support needs `{what}`"));
            let stand = s.stand.as_ref().ok_or_else(|| need("stand"))?;
            let contact = s.contact.as_ref().ok_or_else(|| need("contact"))?;
            if s.rollers.is_empty() {
                return Err(need("rollers"));
            }
            let ck = format!("{key}.contact");
            let e = c.range(&format!("{ck}.exponent"), contact.exponent, 1.0, 3.0)?;
            let k_mm = c.positive(&format!("{ck}.k_n_per_mm_e"), contact.k_n_per_mm_e)?;
            let journal_diameter = match (s.journal_diameter_mm, roll_journal) {
                (Some(d), _) => 1e-3 * c.positive(&format!("{key}.journal_diameter_mm"), d)?,
                (None, Some(d)) => d,
                (None, None) => return Err(need("journal_diameter_mm")),
            };
            let mut rollers = Vec::new();
            for (i, r) in s.rollers.iter().enumerate() {
                let rk = format!("{key}.rollers[{i}]");
                if s.rollers[..i].iter().any(|o| o.name == r.name) {
                    return Err(c.err(
                        &format!("{rk}.name"),
                        format!("roller name `{}` is used twice in this support", r.name),
                    ));
                }
                rollers.push(Roller {
                    name: r.name.clone(),
                    angle: c.range(&format!("{rk}.angle_deg"), r.angle_deg, -89.0, 89.0)? * PI
                        / 180.0,
                    diameter: 1e-3 * c.positive(&format!("{rk}.diameter_mm"), r.diameter_mm)?,
                    roundness: harmonics(c, &format!("{rk}.roundness"), &r.roundness)?,
                });
            }
            Ok(SupportModel::Rollers(RollerSupport {
                journal_diameter,
                journal_roundness: harmonics(
                    c,
                    &format!("{key}.journal_roundness"),
                    &s.journal_roundness,
                )?,
                rollers,
                roller_phase: match s.roller_phase.as_deref().unwrap_or("roll-angle") {
                    "roll-angle" => RollerPhase::RollAngle,
                    "roller-angle" => RollerPhase::RollerAngle,
                    other => {
                        return Err(c.err(
                            &format!("{key}.roller_phase"),
                            format!("`{other}`: expected roll-angle or roller-angle"),
                        ))
                    }
                },
                contact: ContactLaw {
                    // N/mm^e → N/m^e: F = k (1000 δ)^e.
                    k: k_mm * 1000f64.powf(e),
                    exponent: e,
                    c_max: 1e3
                        * c.non_negative(
                            &format!("{ck}.c_max_ns_per_mm"),
                            contact.c_max_ns_per_mm,
                        )?,
                    d: 1e-6 * c.positive(&format!("{ck}.d_um"), contact.d_um)?,
                },
                stand: Stand {
                    mass: c.positive(&format!("{key}.stand.mass_kg"), stand.mass_kg)?,
                    spring: SpringDamper {
                        kx: c.positive(&format!("{key}.stand.kx_n_per_m"), stand.kx_n_per_m)?,
                        ky: c.positive(&format!("{key}.stand.ky_n_per_m"), stand.ky_n_per_m)?,
                        cx: c
                            .non_negative(&format!("{key}.stand.cx_ns_per_m"), stand.cx_ns_per_m)?,
                        cy: c
                            .non_negative(&format!("{key}.stand.cy_ns_per_m"), stand.cy_ns_per_m)?,
                        ..SpringDamper::default()
                    },
                },
            }))
        }
        other => Err(c.err(
            &format!("{key}.type"),
            format!("`{other}`: expected `linear` or `rollers`"),
        )),
    }
}
