//! A calibration file read and checked: the study whose jobs are the experiment, the free
//! parameters and the target rows.
//!
//! In: the path of a calibration `.toml` (docs/calibration.md; `studies/calibrate-table51.toml`
//! is a commented example): `study` (a study file, relative to the calibration file), `[fit]`,
//! `[[parameters]]` (`key` or `keys`, `lower`, `upper`, `initial`, `scale` = `linear` | `log`,
//! `name`), and target rows as `[[targets]]` (any output of the statistics table, by name),
//! `[[resonances]]` (a resonance table's row: an order's peak speed [Hz] and amplitude [µm] at a
//! sensor in a run-up) and `[[frequencies]]` (a critical speed or bending frequency [Hz] of the
//! job's linear system). Every value has a standard deviation (`std`, `speed_std_hz`,
//! `amplitude_std_um`, `std_hz`) in its own unit and an optional `weight` (default 1).
//! Out: a [`Calibration`]: the loaded base [`Study`], the [`Parameter`]s and the [`Row`]s, each
//! with the line it was written on. Errors name the file, the key and the line: unknown keys,
//! a base study with `[sample]`, bounds not ordered or excluding the initial
//! value, a log scale with a bound ≤ 0, a key freed twice, a key (or a table holding it) the
//! study sets per job on an axis or in `[[jobs]]`, a parameter key the study's scene
//! refuses, a job index beyond the study's jobs, a sensor or direction the job's scene does not
//! have, an unknown output, a standard deviation that is not positive, a negative weight,
//! fewer target rows than parameters.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::record::{record_rows, RecordFile};
use super::row::Ctx;
pub use super::row::Row;
use crate::error::InputError;
use crate::scene::locate;
use crate::scene::Scene;
use crate::study::{value_text, Study};

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    name: Option<String>,
    description: Option<String>,
    study: String,
    #[serde(default)]
    fit: FitFile,
    #[serde(default)]
    parameters: Vec<ParameterFile>,
    #[serde(default)]
    targets: Vec<TargetFile>,
    #[serde(default)]
    resonances: Vec<ResonanceFile>,
    #[serde(default)]
    frequencies: Vec<FrequencyFile>,
    #[serde(default)]
    records: Vec<RecordFile>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct FitFile {
    max_iterations: Option<usize>,
    tolerance: Option<f64>,
    step: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParameterFile {
    name: Option<String>,
    key: Option<String>,
    keys: Option<Vec<String>>,
    lower: f64,
    upper: f64,
    initial: f64,
    #[serde(default)]
    scale: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetFile {
    output: String,
    #[serde(default)]
    job: usize,
    value: f64,
    std: f64,
    weight: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ResonanceFile {
    #[serde(default)]
    job: usize,
    order: f64,
    sensor: String,
    direction: Option<String>,
    speed_hz: Option<f64>,
    speed_std_hz: Option<f64>,
    amplitude_um: Option<f64>,
    amplitude_std_um: Option<f64>,
    weight: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FrequencyFile {
    #[serde(default)]
    job: usize,
    critical: Option<usize>,
    bending: Option<String>,
    hz: f64,
    std_hz: f64,
    weight: Option<f64>,
}

/// Defaults and limits of `[fit]`.
pub const MAX_ITERATIONS: usize = 20;
/// Largest `max_iterations` accepted.
pub const MAX_ITERATIONS_LIMIT: usize = 100;
/// Default relative cost decrease that stops the fit.
pub const TOLERANCE: f64 = 1e-4;
/// Default relative finite-difference step.
pub const STEP: f64 = 0.02;

/// Parameter scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// The fit moves the value itself.
    Linear,
    /// The fit moves its base-10 logarithm.
    Log,
}

impl Scale {
    /// As written.
    pub fn name(&self) -> &'static str {
        match self {
            Scale::Linear => "linear",
            Scale::Log => "log",
        }
    }

    /// The fit's coordinate of a value.
    pub fn to_internal(&self, v: f64) -> f64 {
        match self {
            Scale::Linear => v,
            Scale::Log => v.log10(),
        }
    }

    /// The value of a fit coordinate.
    pub fn to_value(&self, u: f64) -> f64 {
        match self {
            Scale::Linear => u,
            Scale::Log => 10f64.powf(u),
        }
    }
}

/// A free parameter.
#[derive(Debug, Clone)]
pub struct Parameter {
    /// Name (default: the first key).
    pub name: String,
    /// Scene keys set to its value.
    pub keys: Vec<String>,
    /// Bounds and start, in the keys' unit.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// Start value.
    pub initial: f64,
    /// Scale.
    pub scale: Scale,
    /// Its table's key in the file (`parameters[2]`) and line.
    pub at: (String, Option<usize>),
}

/// Iteration settings of `[fit]`.
#[derive(Debug, Clone, Copy)]
pub struct FitSettings {
    /// Accepted steps at most.
    pub max_iterations: usize,
    /// Relative cost decrease that stops the fit.
    pub tolerance: f64,
    /// Relative finite-difference step (of the value; a factor 1 + step on a log scale).
    pub step: f64,
}

/// A checked calibration (module doc).
#[derive(Debug, Clone)]
pub struct Calibration {
    /// Name.
    pub name: String,
    /// Free text.
    pub description: String,
    /// The calibration file.
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// The base study.
    pub study: Study,
    /// Free parameters.
    pub parameters: Vec<Parameter>,
    /// Target rows.
    pub rows: Vec<Row>,
    /// `[fit]`.
    pub fit: FitSettings,
}

/// Output kinds a target may name (the statistics table's, `report::tables::outputs`), and
/// whether the part after the first colon starts with `sensor/direction`.
const OUTPUTS: [(&str, bool); 12] = [
    ("runout_mean_um", true),
    ("line_amplitude_um", true),
    ("peak_speed_hz", true),
    ("peak_amplitude_um", true),
    ("critical_speed_hz", false),
    ("critical_log_dec", false),
    ("nip_static_n", false),
    ("nip_amplitude_n", false),
    ("bending_vertical_hz", false),
    ("bending_horizontal_hz", false),
    ("sag_vertical_um", false),
    ("sag_horizontal_um", false),
];

impl Calibration {
    /// Reads and checks a calibration file (module doc).
    pub fn load(path: &Path) -> Result<Calibration, InputError> {
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot read the calibration file: {e}")))?;
        let raw: CalibrationFile =
            toml::from_str(&text).map_err(|e| locate::toml_error(path, &text, &e))?;
        let c = Ctx { path, text: &text };
        let study_path = path.parent().unwrap_or(Path::new(".")).join(&raw.study);
        let study_raw: toml::Table = crate::error::read_text(&study_path)
            .ok()
            .and_then(|t| toml::from_str(&t).ok())
            .unwrap_or_default();
        if study_raw.contains_key("sample") {
            return Err(c.err(
                "study",
                format!(
                    "{}: a calibrated study may not have [sample] (its jobs are the experiment, \
                     the same at every parameter point: a scene with `[[axes]]` and \
                     `[[jobs]]`, not random draws)",
                    study_path.display()
                ),
            ));
        }
        let study = Study::load(&study_path)?;
        let fit = fit_settings(&c, &raw.fit)?;
        let parameters = parameters(&c, &raw.parameters, &study, &study_raw)?;
        let mut rows = Vec::new();
        for (i, t) in raw.targets.iter().enumerate() {
            rows.push(row(
                &c,
                &format!("targets[{i}]"),
                ("value", "std"),
                t.output.clone(),
                t.job,
                (t.value, t.std),
                t.weight,
            )?);
        }
        for (i, r) in raw.resonances.iter().enumerate() {
            rows.extend(resonance_rows(&c, i, r)?);
        }
        for (i, f) in raw.frequencies.iter().enumerate() {
            let at = format!("frequencies[{i}]");
            let output =
                match (f.critical, f.bending.as_deref()) {
                    (Some(k), None) if k >= 1 => format!("critical_speed_hz:{k}"),
                    (None, Some(d @ ("vertical" | "horizontal"))) => format!("bending_{d}_hz"),
                    (Some(_), None) => {
                        return Err(c.err(&format!("{at}.critical"), "critical speeds count from 1"))
                    }
                    (None, Some(d)) => {
                        return Err(c.err(
                            &format!("{at}.bending"),
                            format!("`{d}`: bending is `vertical` or `horizontal`"),
                        ))
                    }
                    _ => return Err(c.err(
                        &at,
                        "give exactly one of `critical` (a critical speed, from 1) and `bending` \
                         (vertical or horizontal)",
                    )),
                };
            rows.push(row(
                &c,
                &at,
                ("hz", "std_hz"),
                output,
                f.job,
                (f.hz, f.std_hz),
                f.weight,
            )?);
        }
        for (i, r) in raw.records.iter().enumerate() {
            rows.extend(record_rows(&c, i, r)?);
        }
        if rows.is_empty() {
            return Err(c.err(
                "targets",
                "no target rows: add [[targets]], [[resonances]], [[frequencies]] or [[records]]",
            ));
        }
        if rows.len() < parameters.len() {
            return Err(c.err(
                "parameters",
                format!(
                    "{} parameters and only {} target rows: a fit needs at least as many rows as \
                     parameters (more, for standard errors)",
                    parameters.len(),
                    rows.len()
                ),
            ));
        }
        for r in &rows {
            check_row(&c, r, &study)?;
        }
        Ok(Calibration {
            name: raw.name.unwrap_or_else(|| {
                path.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default()
            }),
            description: raw.description.unwrap_or_default(),
            path: path.to_path_buf(),
            text: text.clone(),
            study,
            parameters,
            rows,
            fit,
        })
    }
}

fn fit_settings(c: &Ctx, f: &FitFile) -> Result<FitSettings, InputError> {
    let max_iterations = f.max_iterations.unwrap_or(MAX_ITERATIONS);
    if max_iterations > MAX_ITERATIONS_LIMIT {
        return Err(c.err(
            "fit.max_iterations",
            format!("{max_iterations}: at most {MAX_ITERATIONS_LIMIT}"),
        ));
    }
    let tolerance = f.tolerance.unwrap_or(TOLERANCE);
    if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0) {
        return Err(c.err("fit.tolerance", "must lie in (0, 1)"));
    }
    let step = f.step.unwrap_or(STEP);
    if !(step.is_finite() && (1e-6..=0.5).contains(&step)) {
        return Err(c.err(
            "fit.step",
            "must lie in [1e-6, 0.5] (a fraction of the value)",
        ));
    }
    Ok(FitSettings {
        max_iterations,
        tolerance,
        step,
    })
}

fn parameters(
    c: &Ctx,
    raw: &[ParameterFile],
    study: &Study,
    study_raw: &toml::Table,
) -> Result<Vec<Parameter>, InputError> {
    if raw.is_empty() {
        return Err(c.err(
            "parameters",
            "no [[parameters]]: name at least one free parameter",
        ));
    }
    let mut out: Vec<Parameter> = Vec::new();
    for (i, p) in raw.iter().enumerate() {
        let at = format!("parameters[{i}]");
        let keys = match (&p.key, &p.keys) {
            (Some(k), None) => vec![k.clone()],
            (None, Some(ks)) if !ks.is_empty() => ks.clone(),
            _ => {
                return Err(c.err(
                    &at,
                    "give exactly one of `key` and `keys` (a non-empty list)",
                ))
            }
        };
        let keys_at = format!("{at}.key{}", if p.keys.is_some() { "s" } else { "" });
        for k in &keys {
            if let Some(q) = out.iter().find(|q| q.keys.contains(k)) {
                return Err(c.err(&keys_at, format!("`{k}` is already freed by {}", q.at.0)));
            }
            if let Some(v) = study.varying.iter().find(|v| overlaps(k, v)) {
                return Err(c.err(
                    &keys_at,
                    format!(
                        "`{k}`: the study {} sets `{v}` per job ({}); a freed key takes the \
                         fit's one value in every job, so leave it out of the study's axes and \
                         jobs",
                        study.path.display(),
                        setter(study_raw, v)
                    ),
                ));
            }
        }
        let scale = match p.scale.as_deref() {
            None | Some("linear") => Scale::Linear,
            Some("log") => Scale::Log,
            Some(s) => {
                return Err(c.err(
                    &format!("{at}.scale"),
                    format!("`{s}`: the scale is `linear` or `log`"),
                ))
            }
        };
        if !(p.lower.is_finite() && p.upper.is_finite() && p.lower < p.upper) {
            return Err(c.err(
                &format!("{at}.upper"),
                format!("lower {} must be below upper {}", p.lower, p.upper),
            ));
        }
        if scale == Scale::Log && p.lower <= 0.0 {
            return Err(c.err(
                &format!("{at}.lower"),
                format!("{}: a log scale needs positive bounds", p.lower),
            ));
        }
        if !(p.initial >= p.lower && p.initial <= p.upper) {
            return Err(c.err(
                &format!("{at}.initial"),
                format!(
                    "{} lies outside the bounds [{}, {}]",
                    p.initial, p.lower, p.upper
                ),
            ));
        }
        // The study's scene must take every key at the initial value (and at both bounds).
        let job = &study.jobs[0];
        for v in [p.initial, p.lower, p.upper] {
            let mut over: Vec<String> = job
                .overrides
                .iter()
                .map(|(k, v)| format!("{k}={}", value_text(v)))
                .collect();
            over.extend(
                keys.iter()
                    .map(|k| format!("{k}={}", value_text(&v.into()))),
            );
            let scene_text = crate::error::read_text(&study.scene_path)
                .map_err(|e| InputError::new(&study.scene_path, e.to_string()))?;
            Scene::from_text(&study.scene_path, &scene_text, &over).map_err(|e| {
                c.err(
                    &format!("{at}.key{}", if p.keys.is_some() { "s" } else { "" }),
                    format!(
                        "the study's scene refuses {} = {v}: {}",
                        keys.join(", "),
                        e.reason
                    ),
                )
            })?;
        }
        out.push(Parameter {
            name: p.name.clone().unwrap_or_else(|| keys[0].clone()),
            keys,
            lower: p.lower,
            upper: p.upper,
            initial: p.initial,
            scale,
            at: (at.clone(), c.line(&at)),
        });
    }
    Ok(out)
}

/// Whether two dotted keys name the same value or one holds the other (`damping.bands` holds
/// `damping.bands[0].ratio`).
fn overlaps(a: &str, b: &str) -> bool {
    let within = |inner: &str, outer: &str| {
        inner
            .strip_prefix(outer)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
    };
    within(a, b) || within(b, a)
}

/// Which table of the study sets a varying key: `axes[i]`, else `[[jobs]]` (the keys of
/// explicit jobs are all that is left).
fn setter(study_raw: &toml::Table, key: &str) -> String {
    let axes = study_raw.get("axes").and_then(|a| a.as_array());
    for (i, a) in axes.into_iter().flatten().enumerate() {
        let named = |v: &toml::Value| v.as_str() == Some(key);
        let hit = a.get("key").is_some_and(named)
            || a.get("keys")
                .and_then(|k| k.as_array())
                .is_some_and(|ks| ks.iter().any(named));
        if hit {
            return format!("axes[{i}]");
        }
    }
    "its [[jobs]]".into()
}

/// Largest |value|/σ (√weight times) of a target row: a residual of this size squares to
/// 1e300, so the cost ½ Σ r² of up to 1e8 such rows stays below f64's largest number (1.8e308).
const MAX_SCALED_VALUE: f64 = 1e150;

/// A row from a value and its standard deviation, checked.
fn row(
    c: &Ctx,
    at: &str,
    (value_key, std_key): (&str, &str),
    output: String,
    job: usize,
    (value, std): (f64, f64),
    weight: Option<f64>,
) -> Result<Row, InputError> {
    if !value.is_finite() {
        return Err(c.err(&format!("{at}.{value_key}"), "must be a finite number"));
    }
    if !(std.is_finite() && std > 0.0) {
        return Err(c.err(
            &format!("{at}.{std_key}"),
            format!("{std}: a standard deviation must be positive"),
        ));
    }
    let weight = weight.unwrap_or(1.0);
    if !(weight.is_finite() && weight >= 0.0) {
        return Err(c.err(
            &format!("{at}.weight"),
            format!("{weight}: a weight must be ≥ 0"),
        ));
    }
    let scaled = weight.sqrt() * value.abs() / std;
    if scaled > MAX_SCALED_VALUE {
        return Err(c.err(
            &format!("{at}.{value_key}"),
            format!(
                "{value} is {scaled:e} standard deviations ({std_key} = {std}) from 0: the fit's \
                 cost ½ Σ residual² would overflow; give the value and its standard deviation \
                 in the output's unit"
            ),
        ));
    }
    Ok(Row {
        at: format!("{at}.{value_key}"),
        line: c.line(&format!("{at}.{value_key}")).or_else(|| c.line(at)),
        output,
        job,
        value,
        std,
        weight,
        point: None,
    })
}

fn resonance_rows(c: &Ctx, i: usize, r: &ResonanceFile) -> Result<Vec<Row>, InputError> {
    let at = format!("resonances[{i}]");
    let dir = r.direction.clone().unwrap_or_else(|| "vertical".into());
    if !(r.order.is_finite() && r.order > 0.0) {
        return Err(c.err(&format!("{at}.order"), "must be a positive order"));
    }
    let place = format!("{}/{dir}:{}x", r.sensor, crate::text::number_text(r.order));
    let mut rows = Vec::new();
    for (kind, value, std, vk, sk) in [
        (
            "peak_speed_hz",
            r.speed_hz,
            r.speed_std_hz,
            "speed_hz",
            "speed_std_hz",
        ),
        (
            "peak_amplitude_um",
            r.amplitude_um,
            r.amplitude_std_um,
            "amplitude_um",
            "amplitude_std_um",
        ),
    ] {
        match (value, std) {
            (Some(v), Some(s)) => rows.push(row(
                c,
                &at,
                (vk, sk),
                format!("{kind}:{place}"),
                r.job,
                (v, s),
                r.weight,
            )?),
            (None, None) => {}
            (Some(_), None) => {
                return Err(c.err(
                    &format!("{at}.{vk}"),
                    format!("needs `{sk}`, its standard deviation"),
                ))
            }
            (None, Some(_)) => return Err(c.err(&format!("{at}.{sk}"), format!("without `{vk}`"))),
        }
    }
    if rows.is_empty() {
        return Err(c.err(
            &at,
            "give `speed_hz` or `amplitude_um` (or both), each with its std",
        ));
    }
    Ok(rows)
}

/// A row's job exists, its output is known and its sensor and direction are the job's scene's.
fn check_row(c: &Ctx, r: &Row, study: &Study) -> Result<(), InputError> {
    // The row's table, `targets[0]` of `targets[0].value` or `records[1]` of a record's row.
    let table = r.at.find(']').map_or(r.at.as_str(), |e| &r.at[..=e]);
    let Some(job) = study.jobs.get(r.job) else {
        return Err(c.err(
            &format!("{table}.job"),
            format!(
                "job {} does not exist: the study has {} job(s), counted from 0",
                r.job,
                study.jobs.len()
            ),
        ));
    };
    // The job's sensors, from its scene (validated when the study was loaded), built only
    // where a row names a sensor.
    let sensors_of = || study.scene_of(&job.overrides).map(|s| s.sensors);
    if let Some(p) = &r.point {
        let sensors = sensors_of()?;
        if !sensors.contains(&p.sensor) {
            return Err(c.err(
                &format!("{table}.file"),
                format!(
                    "the record's sensor `{}` is not in the scene {} (its sensors: {}): leave \
                     its channels out with `channels`",
                    p.sensor,
                    study.scene_path.display(),
                    sensors.join(", ")
                ),
            ));
        }
        return Ok(());
    }
    let (kind, rest) = r.output.split_once(':').unwrap_or((r.output.as_str(), ""));
    let Some((_, placed)) = OUTPUTS.iter().find(|(k, _)| *k == kind) else {
        let known: Vec<&str> = OUTPUTS.iter().map(|o| o.0).collect();
        return Err(c.err(
            &format!("{table}.output"),
            format!("unknown output `{kind}` (known: {})", known.join(", ")),
        ));
    };
    if *placed || kind.starts_with("sag_") {
        let place = rest.split(':').next().unwrap_or("");
        let (sensor, dir) = place.split_once('/').unwrap_or((place, ""));
        let sensors = sensors_of()?;
        if !sensors.iter().any(|s| s == sensor) {
            let key = if table.starts_with("resonances") {
                format!("{table}.sensor")
            } else {
                format!("{table}.output")
            };
            return Err(c.err(
                &key,
                format!(
                    "sensor `{sensor}` is not in the scene {} (its sensors: {})",
                    study.scene_path.display(),
                    sensors.join(", ")
                ),
            ));
        }
        if *placed && !matches!(dir, "vertical" | "horizontal") {
            let key = if table.starts_with("resonances") {
                format!("{table}.direction")
            } else {
                format!("{table}.output")
            };
            return Err(c.err(&key, format!("direction `{dir}`: vertical or horizontal")));
        }
    }
    Ok(())
}
