//! Influence-coefficient balancing from a study's trial-mass runs (`rotorsweep balance`).
//!
//! In: an assembled study results file whose `[analysis] baseline` labels the reference runs
//! (no trial mass) on a labelled `roll.masses` (or `rotor.masses`) axis, with one trial-mass
//! run per plane at each speed: a job whose masses are the reference's plus exactly one
//! (its z [mm] names the plane); the 1× of every job from `/analysis/lines` [µm, phase against
//! roll angle 0]; optional constraints (hole angles, a maximum mass per plane).
//! Out: a [`Balance`]: the corrections per plane (z [mm], mass [g], angle [deg] at the trial
//! mass's radius, scene angle convention), the reference's 1× and the predicted residual per
//! speed, sensor and direction [µm] (`signal::influence`: influence coefficients and least
//! squares over all planes and speeds at once), and with [`check`] the 1× of the corrected roll
//! run again: the reference job's scene with the corrections added to its masses, the same
//! record, 1× by `signal::lines`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;
use rustfft::num_complex::Complex64;
use serde::Serialize;

use nalgebra::DMatrix;

use super::{value_text, Study};
use crate::dynamics::model::Model;
use crate::error::InputError;
use crate::results::request::analysis_of_text;
use crate::scene::Scene;
use crate::signal::influence::{self, PlaneLimits};
use crate::store;

/// One correction mass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Correction {
    /// Plane [mm] (as the masses axis gives z).
    pub z_mm: f64,
    /// Radius [mm] (the plane's trial mass's).
    pub radius_mm: f64,
    /// Mass [g].
    pub mass_g: f64,
    /// Body angle [deg] in [0, 360), the scene's convention.
    pub angle_deg: f64,
}

/// The 1× amplitude before and after at one speed, sensor and direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residual {
    /// Speed [Hz].
    pub speed_hz: f64,
    /// Sensor.
    pub sensor: String,
    /// Direction.
    pub direction: String,
    /// Reference run's 1× [µm].
    pub before_um: f64,
    /// After the corrections [µm] (predicted, or the check run's).
    pub after_um: f64,
}

/// The outcome (module doc).
#[derive(Debug, Clone, Serialize)]
pub struct Balance {
    /// The corrections.
    pub corrections: Vec<Correction>,
    /// Predicted residual 1× per row.
    pub predicted: Vec<Residual>,
    /// The check run's 1× per row (with `check`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub check: Option<Vec<Residual>>,
    /// Planes (z [mm]) in column order.
    #[serde(skip)]
    planes: Vec<f64>,
    /// Per speed, the reference job's id.
    #[serde(skip)]
    references: Vec<(f64, String)>,
    /// The masses axis key and the reference's masses (TOML).
    #[serde(skip)]
    masses: (String, Vec<toml::Value>),
    /// The study file as the run named it, and its text then.
    #[serde(skip)]
    study: (PathBuf, String),
    /// The influence matrix [rows × planes], the reference 1× per row and the planes' radii
    /// [mm] (for the model-based reference, [`ideal`]).
    #[serde(skip)]
    influence: (DMatrix<Complex64>, Vec<Complex64>, Vec<f64>),
}

/// The model's own ("ideal") balancing of the reference roll in the trial planes, for
/// comparison with the influence coefficients' corrections: the masses the scene's
/// `roll.balancing` computes from the model's unbalance (its sections' centroid offsets, the
/// thickness map's eccentric bore; not point masses: static, moment and, with three planes,
/// the first bending mode's share cancelled, `fe`), at the trial masses' radii, and their
/// predicted residual 1× through the same influence coefficients. Two or three planes.
#[derive(Debug, Clone, Serialize)]
pub struct Ideal {
    /// The model-based masses per plane.
    pub corrections: Vec<Correction>,
    /// Their predicted residual 1× per row (the same rows as [`Balance::predicted`]).
    pub predicted: Vec<Residual>,
}

/// A row of `/analysis/lines`.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct LineRow {
    job_id: VarLenUnicode,
    channel: VarLenUnicode,
    order: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

/// A mass of a masses axis value: (z [mm], radius [mm], angle [deg], mass [g]).
fn mass_of(v: &toml::Value) -> Option<(f64, f64, f64, f64)> {
    let t = v.as_table()?;
    let num = |k: &str| {
        t.get(k)
            .and_then(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
    };
    Some((
        num("z_mm")?,
        num("radius_mm")?,
        num("angle_deg")?,
        num("mass_g")?,
    ))
}

/// Computes the corrections from the results file at `path` with `limits` applied to every
/// plane (module doc): the masses axis of the reference runs, every job's speed, label and
/// masses, the 1× of every job and channel, the trial runs per plane and speed and the rows of
/// the influence coefficients; then the least-squares corrections and their predicted residual.
pub fn balance(path: &Path, limits: &PlaneLimits) -> Result<Balance, InputError> {
    let err = |r: String| InputError::new(path, r);
    let f = store::output::open_results_file(path).map_err(&err)?;
    let text = store::read_str(&f, "study_text")
        .map_err(|_| err("not a study results file (no study_text)".into()))?;
    let (baseline, key) = masses_axis(&text, path)?;
    let all = read_jobs(&f, &key, path)?;
    let one = read_one_x(&f, path)?;
    let trials = Trials::of(&all, &baseline, path)?;
    let Rows {
        rows,
        b,
        resp,
        units,
    } = Rows::of(&trials, &one, path)?;
    let Trials {
        planes,
        references,
        ref_masses,
        ..
    } = trials;
    let alpha = influence::influence(&b, &resp, &units);
    let radii: Vec<f64> = planes.iter().map(|p| p.1).collect();
    let masses = influence::corrections(&alpha, &b, &vec![limits.clone(); planes.len()]);
    let w: Vec<Complex64> = masses.iter().map(|m| influence::unbalance(m)).collect();
    let after = influence::predicted(&alpha, &b, &w);
    let corrections = planes
        .iter()
        .zip(&masses)
        .flat_map(|((z, r), ms)| {
            ms.iter().map(move |(m, a)| Correction {
                z_mm: *z,
                radius_mm: *r,
                mass_g: *m,
                angle_deg: a.to_degrees(),
            })
        })
        .collect();
    let predicted = rows
        .iter()
        .zip(b.iter().zip(&after))
        .map(|((s, c), (bb, aa))| residual(*s, c, bb.norm(), aa.norm()))
        .collect();
    let study = (
        PathBuf::from(store::read_str(&f, "study_path").unwrap_or_default()),
        text.clone(),
    );
    Ok(Balance {
        corrections,
        predicted,
        check: None,
        planes: planes.iter().map(|p| p.0).collect(),
        references,
        masses: (key, ref_masses),
        study,
        influence: (alpha, b, radii),
    })
}

/// The baseline label of the reference runs and the key of the masses axis that has it, from
/// the study text stored in the results file at `path`.
fn masses_axis(text: &str, path: &Path) -> Result<(String, String), InputError> {
    let err = |r: String| InputError::new(path, r);
    let sa = analysis_of_text(text).unwrap_or_default();
    let baseline = sa.spec.baseline.clone().ok_or_else(|| {
        err("the study has no [analysis] baseline: the reference runs are not named".into())
    })?;
    let axis = sa
        .labelled
        .iter()
        .find(|a| a.labels.contains(&baseline))
        .ok_or_else(|| err(format!("no labelled axis has the baseline `{baseline}`")))?;
    let key = axis.keys[0].clone();
    if !key.ends_with(".masses") {
        return Err(err(format!(
            "the baseline's axis `{key}` is not a masses axis (roll.masses or rotor.masses)"
        )));
    }
    Ok((baseline, key))
}

/// A job of the results file: its id, speed [Hz], label on the masses axis and masses.
struct Job {
    id: String,
    speed: f64,
    label: String,
    masses: Vec<toml::Value>,
}

/// Every job of the results file `f` (at `path`) with its masses on the axis `key`; each must
/// have ended ok at a constant speed.
fn read_jobs(f: &hdf5::File, key: &str, path: &Path) -> Result<Vec<Job>, InputError> {
    let err = |r: String| InputError::new(path, r);
    let jobs = f
        .group("jobs")
        .map_err(|e| err(format!("no jobs group: {e}")))?;
    let mut all = Vec::new();
    for id in jobs.member_names().unwrap_or_default() {
        let Ok(g) = jobs.group(&id) else { continue };
        let status = store::read_str(&g, "status").unwrap_or_default();
        let speed = store::read_num(&g, "speed_hz").unwrap_or(f64::NAN);
        let label = store::read_str(&g, &format!("label:{key}")).unwrap_or_default();
        if !crate::integrators::Status::name_completed(&status) || !speed.is_finite() {
            return Err(err(format!(
                "job {id} ({label}) did not end ok at a constant speed ({status}): balancing \
                 needs every run"
            )));
        }
        let raw = store::read_param(&g, key)
            .map(|p| p.to_string())
            .map_err(|_| err(format!("job {id} has no `{key}` value")))?;
        let value: toml::Value = toml::from_str::<toml::Table>(&format!("v = {raw}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .ok_or_else(|| err(format!("job {id}: `{key}` = {raw} is not a list of masses")))?;
        let masses = value.as_array().cloned().unwrap_or_default();
        all.push(Job {
            id,
            speed,
            label,
            masses,
        });
    }
    Ok(all)
}

/// The 1× of each job and channel [µm, phase against roll angle 0] from `/analysis/lines` of
/// the results file `f` (at `path`).
fn read_one_x(
    f: &hdf5::File,
    path: &Path,
) -> Result<BTreeMap<(String, String), Complex64>, InputError> {
    let lines: Vec<LineRow> = f
        .dataset("analysis/lines")
        .and_then(|d| d.read_raw())
        .map_err(|e| InputError::new(path, format!("no /analysis/lines table ({e})")))?;
    let mut one: BTreeMap<(String, String), Complex64> = BTreeMap::new();
    for l in lines.iter().filter(|l| l.order == 1.0) {
        one.insert(
            (l.job_id.as_str().into(), l.channel.as_str().into()),
            Complex64::from_polar(l.amplitude_um, l.phase_deg.to_radians()),
        );
    }
    Ok(one)
}

/// The trial runs, each against the reference run at its speed.
struct Trials {
    /// The planes (z [mm], the trial mass's radius [mm]), by z.
    planes: Vec<(f64, f64)>,
    /// Per (speed index, plane z bits): the trial job's id and its mass U [g e^{iφ}].
    runs: BTreeMap<(usize, u64), (String, Complex64)>,
    /// Per speed [Hz], the reference job's id.
    references: Vec<(f64, String)>,
    /// The reference's masses (the last speed's).
    ref_masses: Vec<toml::Value>,
}

impl Trials {
    /// From the jobs `all`: per speed the one reference run (label `baseline`) and the trial
    /// runs, each the reference's masses plus exactly one (its z names the plane).
    fn of(all: &[Job], baseline: &str, path: &Path) -> Result<Trials, InputError> {
        let err = |r: String| InputError::new(path, r);
        let mut speeds: Vec<f64> = all.iter().map(|j| j.speed).collect();
        speeds.sort_by(f64::total_cmp);
        speeds.dedup();
        let mut planes: Vec<(f64, f64)> = Vec::new();
        let mut trials: BTreeMap<(usize, u64), (String, Complex64)> = BTreeMap::new();
        let mut references = Vec::new();
        let mut ref_masses = Vec::new();
        for (si, s) in speeds.iter().enumerate() {
            let refs: Vec<&Job> = all
                .iter()
                .filter(|j| j.speed == *s && j.label == baseline)
                .collect();
            let [r] = refs[..] else {
                return Err(err(format!(
                    "{} reference runs (`{baseline}`) at {s} Hz: one is needed",
                    refs.len()
                )));
            };
            references.push((*s, r.id.clone()));
            ref_masses = r.masses.clone();
            for j in all.iter().filter(|j| j.speed == *s && j.label != baseline) {
                let extra: Vec<&toml::Value> =
                    j.masses.iter().filter(|m| !r.masses.contains(m)).collect();
                let ([m], true) = (&extra[..], j.masses.len() == r.masses.len() + 1) else {
                    return Err(err(format!(
                        "job {} ({}) is not the reference's masses plus one trial mass",
                        j.id, j.label
                    )));
                };
                let (z, radius, angle, mass) = mass_of(m).ok_or_else(|| {
                    err(format!(
                        "job {}: a mass lacks z_mm/radius_mm/angle_deg/mass_g",
                        j.id
                    ))
                })?;
                if !planes.iter().any(|p| p.0 == z) {
                    planes.push((z, radius));
                }
                let u = Complex64::from_polar(mass, angle.to_radians());
                if trials
                    .insert((si, z.to_bits()), (j.id.clone(), u))
                    .is_some()
                {
                    return Err(err(format!("two trial runs at z = {z} mm and {s} Hz")));
                }
            }
        }
        planes.sort_by(|a, b| a.0.total_cmp(&b.0));
        if planes.is_empty() {
            return Err(err("no trial-mass runs".into()));
        }
        Ok(Trials {
            planes,
            runs: trials,
            references,
            ref_masses,
        })
    }
}

/// The least-squares rows of the influence coefficients: per speed, the reference's channels.
struct Rows {
    /// Speed [Hz] and channel per row.
    rows: Vec<(f64, String)>,
    /// The reference's 1× per row [µm].
    b: Vec<Complex64>,
    /// Per plane, its trial run's 1× per row [µm].
    resp: Vec<Vec<Complex64>>,
    /// Per plane, its trial mass U [g e^{iφ}] per row.
    units: Vec<Vec<Complex64>>,
}

impl Rows {
    /// The rows of `trials` with the 1× `one` of each job and channel.
    fn of(
        trials: &Trials,
        one: &BTreeMap<(String, String), Complex64>,
        path: &Path,
    ) -> Result<Rows, InputError> {
        let err = |r: String| InputError::new(path, r);
        let planes = &trials.planes;
        let mut rows: Vec<(f64, String)> = Vec::new();
        let mut b = Vec::new();
        let (mut resp, mut units) = (
            vec![Vec::new(); planes.len()],
            vec![Vec::new(); planes.len()],
        );
        for (si, (s, rid)) in trials.references.iter().enumerate() {
            let channels: Vec<String> = one
                .keys()
                .filter(|(j, _)| j == rid)
                .map(|(_, c)| c.clone())
                .collect();
            for c in channels {
                b.push(one[&(rid.clone(), c.clone())]);
                for (p, (z, _)) in planes.iter().enumerate() {
                    let (tid, u) = trials
                        .runs
                        .get(&(si, z.to_bits()))
                        .ok_or_else(|| err(format!("no trial run at z = {z} mm and {s} Hz")))?;
                    let a = one
                        .get(&(tid.clone(), c.clone()))
                        .ok_or_else(|| err(format!("job {tid} has no 1× of {c}")))?;
                    resp[p].push(*a);
                    units[p].push(*u);
                }
                rows.push((*s, c));
            }
        }
        Ok(Rows {
            rows,
            b,
            resp,
            units,
        })
    }
}

fn residual(speed_hz: f64, channel: &str, before: f64, after: f64) -> Residual {
    let (sensor, direction) = channel.rsplit_once('/').unwrap_or((channel, ""));
    Residual {
        speed_hz,
        sensor: sensor.into(),
        direction: direction.into(),
        before_um: before,
        after_um: after,
    }
}

/// The study the results were made from, its scene's text and the file's path: `study` when
/// given, else the path the run named (relative to the working directory, as `run` was given
/// it); it must be the text the run used. `what` names the use in the error.
fn run_study(
    b: &Balance,
    study: Option<&Path>,
    what: &str,
) -> Result<(Study, String, PathBuf), InputError> {
    let path = study.unwrap_or(&b.study.0).to_path_buf();
    let now = crate::error::read_text(&path).map_err(|e| {
        InputError::new(
            &path,
            format!("cannot read the study file for {what} ({e}): name it with --study"),
        )
    })?;
    if now != b.study.1 {
        return Err(InputError::new(
            &path,
            "is not the study text the results were made from (changed since the run?)",
        ));
    }
    let study = Study::load(&path)?;
    let scene_text = crate::error::read_text(&study.scene_path)
        .map_err(|e| InputError::new(&study.scene_path, e.to_string()))?;
    Ok((study, scene_text, path))
}

/// The overrides of the reference job `rid` without the masses key `key`.
fn reference_overrides(
    study: &Study,
    path: &Path,
    rid: &str,
    key: &str,
) -> Result<Vec<String>, InputError> {
    let job = study.jobs.iter().find(|j| j.id == rid).ok_or_else(|| {
        InputError::new(
            path,
            format!(
                "the study no longer has the reference job {rid}: its scene changed since the run"
            ),
        )
    })?;
    Ok(job
        .overrides
        .iter()
        .filter(|(k, _)| k != key)
        .map(|(k, v)| format!("{k}={}", value_text(v)))
        .collect())
}

/// The model-based balancing of the reference roll in the trial planes ([`Ideal`]); the study
/// file as for [`check`].
pub fn ideal(b: &Balance, study: Option<&Path>) -> Result<Ideal, InputError> {
    let (key, ref_masses) = &b.masses;
    if key != "roll.masses" {
        return Err(InputError::new(
            &b.study.0,
            format!(
                "the model-based balancing is a roll's (roll.balancing, from its sections' \
                 unbalance); the trial masses here are on `{key}`"
            ),
        ));
    }
    let (study, scene_text, path) = run_study(b, study, "the model-based balancing")?;
    let (alpha, reference, radii) = &b.influence;
    let rid = &b.references[0].1;
    let mut over = reference_overrides(&study, &path, rid, key)?;
    let planes: Vec<toml::Value> = b.planes.iter().map(|z| toml::Value::from(*z)).collect();
    over.push(format!(
        "roll.balancing.planes_mm={}",
        value_text(&toml::Value::Array(planes))
    ));
    over.push(format!("roll.balancing.radius_mm={}", radii[0]));
    over.push(format!(
        "{key}={}",
        value_text(&toml::Value::Array(ref_masses.clone()))
    ));
    let scene = Scene::from_text(&study.scene_path, &scene_text, &over)?;
    let rotor = crate::rotor::fe::Rotor::mesh(&scene.rotor)
        .map_err(|e| InputError::new(&study.scene_path, e.to_string()))?;
    let masses = &rotor.balancing_masses;
    if masses.len() != b.planes.len() {
        return Err(InputError::new(
            &study.scene_path,
            format!(
                "the model's balancing gives {} masses for {} trial planes (a plane needs none)",
                masses.len(),
                b.planes.len()
            ),
        ));
    }
    // At each plane's own trial radius: the same unbalance m·r.
    let corrections: Vec<Correction> = b
        .planes
        .iter()
        .zip(radii)
        .zip(masses)
        .map(|((z, r), m)| Correction {
            z_mm: *z,
            radius_mm: *r,
            mass_g: 1e3 * m.mass * radii[0] / r,
            angle_deg: m.angle.to_degrees().rem_euclid(360.0),
        })
        .collect();
    let w: Vec<Complex64> = corrections
        .iter()
        .map(|c| Complex64::from_polar(c.mass_g, c.angle_deg.to_radians()))
        .collect();
    let after = influence::predicted(alpha, reference, &w);
    let predicted = b
        .predicted
        .iter()
        .zip(&after)
        .map(|(p, a)| Residual {
            after_um: a.norm(),
            ..p.clone()
        })
        .collect();
    Ok(Ideal {
        corrections,
        predicted,
    })
}

/// Runs the corrected roll at every speed (module doc) and stores the 1× in `b.check`. The
/// study file is `study` when given, else the path the run named (relative to the working
/// directory, as `run` was given it); it must be the text the run used.
pub fn check(b: &mut Balance, study: Option<&Path>) -> Result<(), InputError> {
    let (study, scene_text, path) = run_study(b, study, "the check run")?;
    let (key, ref_masses) = &b.masses;
    let mut masses = ref_masses.clone();
    for c in &b.corrections {
        let mut t = toml::Table::new();
        t.insert("z_mm".into(), c.z_mm.into());
        t.insert("radius_mm".into(), c.radius_mm.into());
        t.insert("angle_deg".into(), c.angle_deg.into());
        t.insert("mass_g".into(), c.mass_g.into());
        masses.push(toml::Value::Table(t));
    }
    let corrected = format!("{key}={}", value_text(&toml::Value::Array(masses)));
    let mut out = Vec::new();
    for (speed, rid) in &b.references {
        let mut over = reference_overrides(&study, &path, rid, key)?;
        over.push(corrected.clone());
        let scene = Scene::from_text(&study.scene_path, &scene_text, &over)?;
        let model = Model::build(&scene, None)
            .map_err(|e| InputError::new(&study.scene_path, e.to_string()))?;
        let r = crate::dynamics::simulation::run(&scene, &model);
        if !r.stats.status.completed() {
            return Err(InputError::new(
                &study.scene_path,
                format!(
                    "the check run at {speed} Hz ended {}: {}",
                    r.stats.status.name(),
                    r.stats.cause
                ),
            ));
        }
        let sim = &scene.simulation;
        let (w, delta) = scene
            .speed
            .constant_over(sim.settle, sim.t_end)
            .unwrap_or((std::f64::consts::TAU * speed, 0.0));
        let f_hz = w / std::f64::consts::TAU;
        for c in r.channels.iter().filter(|c| c.name.starts_with("runout/")) {
            let z = crate::signal::lines(&c.data, &r.time, &[f_hz])[0]
                * Complex64::from_polar(1.0, -delta);
            let name = &c.name["runout/".len()..];
            let before = b
                .predicted
                .iter()
                .find(|p| p.speed_hz == *speed && format!("{}/{}", p.sensor, p.direction) == name)
                .map_or(f64::NAN, |p| p.before_um);
            out.push(residual(*speed, name, before, z.norm()));
        }
    }
    out.sort_by(|x, y| {
        x.speed_hz
            .total_cmp(&y.speed_hz)
            .then_with(|| (&x.sensor, &x.direction).cmp(&(&y.sensor, &y.direction)))
    });
    b.check = Some(out);
    Ok(())
}

impl Balance {
    /// The planes' z [mm].
    pub fn planes(&self) -> &[f64] {
        &self.planes
    }

    /// Where the 1× read from the results file is not a number: the first row (an index into
    /// [`Balance::predicted`]) whose reference 1× is not finite, `(row, None)`, or whose
    /// influence coefficient in a plane (an index into [`Balance::planes`]) is not, from that
    /// plane's trial run, `(row, Some(plane))`. The corrections are NaN then.
    pub fn non_finite(&self) -> Option<(usize, Option<usize>)> {
        let (alpha, b, _) = &self.influence;
        (0..b.len()).find_map(|r| {
            if !b[r].is_finite() {
                return Some((r, None));
            }
            (0..alpha.ncols())
                .find(|&p| !alpha[(r, p)].is_finite())
                .map(|p| (r, Some(p)))
        })
    }
}
