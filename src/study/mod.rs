//! Study files: a base scene and sweep axes → a list of fully resolved jobs.
//!
//! In: a study `.toml` (the commented `studies/smoke.toml` documents the format): a base scene,
//! overrides for every job (`[set]`), sweep axes (cartesian product; an axis with several `keys`
//! moves them together, i.e. zipped), explicit `[[jobs]]`, a `[reference]` solver setting, a
//! per-job `[budget]`, and optional strain-energy pruning (the pseudo-key
//! `reduction.prune_threshold`, swept like any other key; 0 means the unpruned pilot).
//! Out: a [`Study`] with its [`Job`]s — each the scene's key=value overrides, a stable id (a hash
//! of every input that defines the job), the id of the reduced model it needs and of the
//! reference run it is compared with. Errors name the study file, the line, the key and the
//! reason; every job's scene, every reference's and every pruning pilot's is validated before
//! anything runs. Also errors: more than [`MAX_JOBS`] jobs (counted before the axes are
//! expanded), an axis value given twice (`10` and `10.0` alike), a key of [set], the axes,
//! [[jobs]], [budget], [reference] or [pruning] that replaces one applied before it
//! (`speed.hz` after `speed.hz.x`),
//! [pruning] without pruned jobs or with model keys. The study's [budget] binds the reference
//! runs too, unless [reference] sets `solver.cpu_budget_s` / `solver.max_steps` itself.

pub mod balancing;
pub mod campaign;
pub mod identity;
pub mod overview;
pub mod progress;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::InputError;
use crate::results::request::{axis_keys, default_orders, AnalysisSpec};
use crate::scene::source::Source;
use crate::scene::{locate, replaces, set_path, Scene};

/// The pseudo-key that asks for strain-energy pruning (not a scene key).
pub const PRUNE_KEY: &str = "reduction.prune_threshold";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    name: Option<String>,
    description: Option<String>,
    scene: String,
    #[serde(default)]
    set: toml::Table,
    #[serde(default)]
    axes: Vec<AxisFile>,
    #[serde(default)]
    jobs: Vec<toml::Table>,
    #[serde(default)]
    reference: toml::Table,
    #[serde(default)]
    budget: BudgetFile,
    #[serde(default)]
    pruning: toml::Table,
    #[serde(default)]
    analysis: AnalysisSpec,
    #[serde(default)]
    linear: LinearFile,
}

/// The study's `[linear]` table: the linear analyses stored per distinct linear system under
/// `/linear/<id>` (module doc of [`crate::linear::request`]). The damped modes over `speeds`
/// always; the rest when set to `true`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct LinearFile {
    /// Spin speeds `START:STOP:COUNT` [Hz] (default [`LINEAR_SPEEDS`]).
    speeds: Option<String>,
    /// List modes up to this damped frequency [Hz] (default: all).
    max_freq_hz: Option<f64>,
    /// Unbalance response at the sensors and named nodes.
    #[serde(default)]
    unbalance_response: bool,
    /// The response's unbalance `MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM` (default: the scene's own).
    unbalance: Option<String>,
    /// Floquet stability at every positive speed.
    #[serde(default)]
    floquet: bool,
    /// Floquet: keep only the modes below this frequency [Hz].
    floquet_cutoff_hz: Option<f64>,
    /// Static sag and support forces.
    #[serde(default, rename = "static")]
    statics: bool,
    /// Undamped critical speeds against the support stiffness.
    #[serde(default)]
    critical_map: bool,
    /// Mode shapes at the nodes.
    #[serde(default)]
    shapes: bool,
}

/// The default speeds of a study's linear analyses [Hz] (the `modes` command's default range).
pub const LINEAR_SPEEDS: &str = "0:100:201";

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFile {
    key: Option<String>,
    keys: Option<Vec<String>>,
    values: Option<Vec<toml::Value>>,
    range: Option<RangeFile>,
    labels: Option<Vec<String>>,
}

impl AxisFile {
    /// The axis's keys: `key`, or a non-empty `keys` list; `None` for neither or both.
    fn key_list(&self) -> Option<Vec<String>> {
        axis_keys(&self.key, &self.keys)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RangeFile {
    start: f64,
    stop: f64,
    step: f64,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct BudgetFile {
    cpu_s: Option<f64>,
    steps: Option<u64>,
}

/// One job: the overrides that make it, and its identities.
#[derive(Debug, Clone)]
pub struct Job {
    /// Position in the study's job list (shards split on it).
    pub index: usize,
    /// Stable id: hash of the scene files and all resolved overrides.
    pub id: String,
    /// Scene overrides (dotted key, value), base `[set]` first; without the prune pseudo-key.
    pub overrides: Vec<(String, toml::Value)>,
    /// Strain-energy pruning threshold, if this job asks for pruning (0 = the pilot's full set).
    pub prune: Option<f64>,
    /// Id of the unpruned reduced model this job starts from.
    pub model_id: String,
    /// Id of the reference run this job is compared with.
    pub reference_id: String,
    /// Id of the job's linearised system (its model on its supports, drive and gravity): the
    /// Campbell data and critical speeds stored under `/linear/<id>`.
    pub linear_id: String,
    /// Labels of the job's rows on labelled axes: (the axis's first key, label).
    pub labels: Vec<(String, String)>,
    /// The validated scene.
    pub scene: Scene,
}

/// A reference run: the job's physics with the study's reference solver setting.
#[derive(Debug, Clone)]
pub struct Reference {
    /// Stable id.
    pub id: String,
    /// Scene overrides.
    pub overrides: Vec<(String, toml::Value)>,
    /// Id of the (unpruned) model it runs on.
    pub model_id: String,
    /// The validated scene.
    pub scene: Scene,
}

/// An expanded, validated study.
#[derive(Debug, Clone)]
pub struct Study {
    /// Study name.
    pub name: String,
    /// Free text.
    pub description: String,
    /// The study file.
    pub path: PathBuf,
    /// Its text (stored in the results).
    pub text: String,
    /// The base scene file.
    pub scene_path: PathBuf,
    /// Keys that vary between jobs, in axis order.
    pub varying: Vec<String>,
    /// The jobs.
    pub jobs: Vec<Job>,
    /// The reference runs, one per distinct physics.
    pub references: Vec<Reference>,
    /// Overrides of the pruning pilot runs.
    pub pilot_overrides: Vec<(String, toml::Value)>,
    /// Whether the study names a reference setting (otherwise no errors are computed).
    pub has_reference: bool,
    /// The linear analyses of every distinct linear system (`[linear]`).
    pub linear: crate::linear::request::Request,
}

/// The pilot overrides as one canonical text (for ids).
pub(crate) fn pilot_text(pilot: &[(String, toml::Value)]) -> String {
    pilot
        .iter()
        .map(|(k, v)| format!("{k}={}", value_text(v)))
        .collect::<Vec<_>>()
        .join(";")
}

/// FNV-1a 64-bit: a stable hash for ids (the same on every machine and run).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn flatten(prefix: &str, t: &toml::Table, out: &mut Vec<(String, toml::Value)>) {
    for (k, v) in t {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(sub) => flatten(&key, sub, out),
            other => out.push((key, other.clone())),
        }
    }
}

pub(crate) fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

/// The text of every file a scene reads (the scene, the scenes it extends and its thickness
/// map), for hashing.
fn scene_inputs(source: &Source, merged: &toml::Value) -> String {
    let scene_path = source.path();
    let mut text: String = source.layers.iter().map(|l| l.text.as_str()).collect();
    if let Some(csv) = merged
        .get("roll")
        .and_then(|r| r.get("shell"))
        .and_then(|s| s.get("thickness_map"))
        .and_then(|m| m.as_str())
    {
        let p = scene_path.parent().unwrap_or(Path::new(".")).join(csv);
        text.push_str(&crate::error::read_text(&p).unwrap_or_default());
    }
    text
}

fn hash_id(prefix: char, parts: &[&str]) -> String {
    let joined = parts.join("\u{1f}");
    format!("{prefix}{:016x}", fnv1a(joined.as_bytes()))
}

/// Subtree of a merged scene table, serialised canonically.
fn canonical(merged: &toml::Value, keep: &[&str], drop: &[&str]) -> String {
    let mut t = merged.as_table().cloned().unwrap_or_default();
    t.retain(|k, _| {
        let k: &str = k;
        (keep.is_empty() || keep.contains(&k)) && !drop.contains(&k)
    });
    toml::to_string(&t).unwrap_or_default()
}

struct Ctx<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Ctx<'_> {
    fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        let e = InputError::new(self.path, reason).with_key(key);
        match locate::line_of(self.text, key) {
            Some(l) => e.at_line(l),
            None => e,
        }
    }
}

/// The `[linear]` table as a request, its values checked.
fn linear_request(c: &Ctx, l: &LinearFile) -> Result<crate::linear::request::Request, InputError> {
    use crate::linear::request::{parse_speeds, PointUnbalance, Request};
    let positive = |key: &str, v: Option<f64>| match v {
        Some(f) if !(f.is_finite() && f > 0.0) => Err(c.err(key, "must be a positive frequency")),
        _ => Ok(v),
    };
    Ok(Request {
        speeds_hz: parse_speeds(l.speeds.as_deref().unwrap_or(LINEAR_SPEEDS))
            .map_err(|e| c.err("linear.speeds", e))?,
        max_freq_hz: positive("linear.max_freq_hz", l.max_freq_hz)?,
        unbalance: l
            .unbalance
            .as_deref()
            .map(PointUnbalance::parse)
            .transpose()
            .map_err(|e| c.err("linear.unbalance", e))?,
        response: l.unbalance_response,
        floquet: l.floquet,
        floquet_cutoff_hz: positive("linear.floquet_cutoff_hz", l.floquet_cutoff_hz)?,
        statics: l.statics,
        critical_map: l.critical_map,
        shapes: l.shapes,
    })
}

fn axis_values(
    c: &Ctx,
    i: usize,
    a: &AxisFile,
) -> Result<(Vec<String>, Vec<Vec<toml::Value>>), InputError> {
    let key = format!("axes[{i}]");
    let keys = a.key_list().ok_or_else(|| {
        c.err(
            &key,
            "an axis needs either `key` or a non-empty `keys` list",
        )
    })?;
    let rows: Vec<Vec<toml::Value>> = match (&a.values, &a.range) {
        (Some(vals), None) => {
            if vals.is_empty() {
                return Err(c.err(&format!("{key}.values"), "an axis needs at least one value"));
            }
            if keys.len() == 1 {
                vals.iter().map(|v| vec![v.clone()]).collect()
            } else {
                vals.iter()
                    .enumerate()
                    .map(|(j, v)| match v.as_array() {
                        Some(row) if row.len() == keys.len() => Ok(row.clone()),
                        _ => Err(c.err(
                            &format!("{key}.values"),
                            format!(
                                "value {j} must be a list of {} values, one per key",
                                keys.len()
                            ),
                        )),
                    })
                    .collect::<Result<_, _>>()?
            }
        }
        (None, Some(r)) => {
            if a.labels.is_some() {
                return Err(c.err(&format!("{key}.labels"), "labels go with `values`"));
            }
            if keys.len() != 1 {
                return Err(c.err(&format!("{key}.range"), "a range goes with a single `key`"));
            }
            if !(r.step > 0.0 && r.stop >= r.start && r.start.is_finite() && r.stop.is_finite()) {
                return Err(c.err(&format!("{key}.range"), "needs start <= stop and step > 0"));
            }
            // Counted as a float first: (stop − start) / step may be far beyond any integer (or
            // infinite for a subnormal step).
            let count = ((r.stop - r.start) / r.step + 1e-9).floor() + 1.0;
            if count > MAX_JOBS as f64 {
                return Err(c.err(
                    &format!("{key}.range"),
                    format!("{count:e} values, more than the {MAX_JOBS} jobs a study may have"),
                ));
            }
            let n = count as usize;
            (0..n)
                .map(|j| {
                    // Rounded to 12 significant digits so that 7.2 + 3·0.2 reads as 7.8.
                    let v = r.start + j as f64 * r.step;
                    let v: f64 = format!("{v:.12e}").parse().unwrap_or(v);
                    vec![toml::Value::Float(v)]
                })
                .collect()
        }
        _ => return Err(c.err(&key, "an axis needs either `values` or `range`")),
    };
    Ok((keys, rows))
}

/// Most jobs a study may expand to. `plan` and `run` validate every job's scene before anything
/// runs: measured, 4901 jobs of the reference roll took 4.3 s and 274 MB to load (0.9 ms and
/// 56 KB each), so the limit loads in about 10 s and 0.6 GB; that many jobs of a second of CPU
/// each are already a night on a workstation (use shards of several studies beyond that).
pub const MAX_JOBS: usize = 10_000;

/// Scene tables that make the reduced model (a pruning pilot runs on its jobs' model).
const MODEL_TABLES: [&str; 4] = ["materials", "roll", "rotor", "reduction"];

/// The number of jobs, the product of the axes (each counted before any is expanded) plus the
/// explicit jobs, stays within [`MAX_JOBS`].
fn job_count(
    c: &Ctx,
    axes: &[(Vec<String>, Vec<Vec<toml::Value>>)],
    explicit: usize,
) -> Result<(), InputError> {
    let limit = |n: u128| {
        format!(
            "{n} jobs, more than the limit of {MAX_JOBS}: every job is validated (and held) \
             before anything runs, about 1 ms and 60 KB each"
        )
    };
    let mut product: u128 = 1;
    for (i, (_, rows)) in axes.iter().enumerate() {
        product = product.saturating_mul(rows.len() as u128);
        if product > MAX_JOBS as u128 {
            return Err(c.err(
                &format!("axes[{i}]"),
                format!("the axes up to this one already make {}", limit(product)),
            ));
        }
    }
    let from_axes = if axes.is_empty() && explicit > 0 {
        0
    } else {
        product
    };
    let total = from_axes + explicit as u128;
    if total > MAX_JOBS as u128 {
        return Err(c.err(
            "jobs",
            format!("the axes and [[jobs]] make {}", limit(total)),
        ));
    }
    Ok(())
}

/// An axis must not list one value twice, even written differently (`10` and `10.0`, `[1, 2]`
/// and `[1.0, 2.0]`): that is two jobs of the same physics.
fn distinct_rows(
    c: &Ctx,
    at: &str,
    keys: &[String],
    rows: &[Vec<toml::Value>],
) -> Result<(), InputError> {
    let mut seen = BTreeMap::new();
    for (j, row) in rows.iter().enumerate() {
        let text: Vec<String> = row.iter().map(normal_value).collect();
        if let Some(first) = seen.insert(text.join(","), j) {
            let shown = |r: &[toml::Value]| {
                r.iter()
                    .map(toml::Value::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(c.err(
                at,
                format!(
                    "axis `{}`: values {first} ({}) and {j} ({}) are the same, so two jobs \
                     would have the same physics",
                    keys.join(", "),
                    shown(&rows[first]),
                    shown(row)
                ),
            ));
        }
    }
    Ok(())
}

/// A value as text that is the same for values of the same meaning: integers as the floats they
/// are read as (up to 2⁵³, where both are exact), −0 as 0, tables with sorted keys.
fn normal_value(v: &toml::Value) -> String {
    const EXACT: i64 = 1 << 53;
    match v {
        toml::Value::Integer(i) if i.abs() <= EXACT => format!("{:?}", *i as f64 + 0.0),
        toml::Value::Float(f) => format!("{:?}", f + 0.0),
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(normal_value).collect();
            format!("[{}]", items.join(","))
        }
        toml::Value::Table(t) => {
            let items: BTreeMap<&String, String> =
                t.iter().map(|(k, v)| (k, normal_value(v))).collect();
            let items: Vec<String> = items.iter().map(|(k, v)| format!("{k:?}={v}")).collect();
            format!("{{{}}}", items.join(","))
        }
        other => value_text(other),
    }
}

/// A job's overrides as normalised text, by key ([`normal_value`]).
fn normal_text(overrides: &[(String, toml::Value)]) -> String {
    let by_key: BTreeMap<&String, String> = overrides
        .iter()
        .map(|(k, v)| (k, normal_value(v)))
        .collect();
    let items: Vec<String> = by_key.iter().map(|(k, v)| format!("{k}={v}")).collect();
    items.join(";")
}

/// The dotted key a scene error from overrides is about: its own key, or (for an unknown field,
/// whose key is the table) the override whose last part the reason names.
fn override_key(e: &InputError, overrides: &[(String, toml::Value)]) -> String {
    e.key.clone().unwrap_or_else(|| {
        overrides
            .iter()
            .map(|(k, _)| k.as_str())
            .find(|k| {
                e.reason
                    .contains(&format!("`{}`", k.rsplit('.').next().unwrap_or(k)))
            })
            .unwrap_or_default()
            .to_string()
    })
}

/// No key a job applies may replace one applied before it (`speed.hz` on an axis after
/// `speed.hz.x` in [set]): the earlier would be dropped silently. A job applies [set] and
/// [budget], then every axis or one explicit job; its reference and its pruning pilot apply
/// [reference] or [pruning] after that. A later key inside an earlier one refines it.
fn replaced_keys(
    c: &Ctx,
    base: &[(String, toml::Value)],
    raw: &StudyFile,
    reference: &[(String, toml::Value)],
    pilot: &[(String, toml::Value)],
) -> Result<(), InputError> {
    let mut common: Vec<(String, String)> = Vec::new();
    common.extend(base.iter().map(|(k, _)| (k.clone(), format!("set.{k}"))));
    if raw.budget.cpu_s.is_some() {
        common.push(("solver.cpu_budget_s".into(), "budget.cpu_s".into()));
    }
    if raw.budget.steps.is_some() {
        common.push(("solver.max_steps".into(), "budget.steps".into()));
    }
    let mut jobs = Vec::new();
    let mut with_axes = common.clone();
    for (i, a) in raw.axes.iter().enumerate() {
        for k in a.key_list().unwrap_or_default() {
            with_axes.push((k, format!("axes[{i}]")));
        }
    }
    jobs.push(with_axes);
    for (j, t) in raw.jobs.iter().enumerate() {
        let mut o = Vec::new();
        flatten("", t, &mut o);
        let mut g = common.clone();
        g.extend(
            o.into_iter()
                .map(|(k, _)| (k.clone(), format!("jobs[{j}].{k}"))),
        );
        jobs.push(g);
    }
    let mut groups = Vec::new();
    for (table, after) in [("reference", reference), ("pruning", pilot)] {
        for g in &jobs {
            let mut g = g.clone();
            g.extend(
                after
                    .iter()
                    .map(|(k, _)| (k.clone(), format!("{table}.{k}"))),
            );
            groups.push(g);
        }
    }
    for g in &groups {
        for (n, (b, at_b)) in g.iter().enumerate() {
            if let Some((a, at_a)) = g[..n].iter().find(|(a, _)| replaces(b, a)) {
                return Err(c.err(
                    at_b,
                    format!(
                        "`{b}` would replace `{a}` (at {at_a}), which is inside it: `{a}` would \
                         be dropped"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Every pruning pilot's scene must load: the jobs' overrides, then [pruning], with the modal
/// coordinates recorded. [pruning] without a pruned job is an error, not a silent no-op.
fn pilots_load(
    c: &Ctx,
    source: &Source,
    jobs: &[Job],
    pilot: &[(String, toml::Value)],
) -> Result<(), InputError> {
    let pruned: std::collections::BTreeSet<&str> = jobs
        .iter()
        .filter(|j| j.prune.is_some())
        .map(|j| j.model_id.as_str())
        .collect();
    if pruned.is_empty() {
        if let Some((k, _)) = pilot.first() {
            return Err(c.err(
                &format!("pruning.{k}"),
                format!("no job asks for pruning (the pseudo-key `{PRUNE_KEY}`), so [pruning] would be ignored"),
            ));
        }
        return Ok(());
    }
    for j in jobs.iter().filter(|j| pruned.contains(j.model_id.as_str())) {
        let mut over: Vec<String> = j
            .overrides
            .iter()
            .chain(pilot)
            .map(|(k, v)| format!("{k}={}", value_text(v)))
            .collect();
        over.push("outputs.modal=true".into());
        Scene::from_source(source, &over).map_err(|e| {
            let key = override_key(&e, pilot);
            let at = if pilot.iter().any(|(k, _)| *k == key) {
                format!("pruning.{key}")
            } else {
                "pruning".to_string()
            };
            let mut err = c.err(
                &at,
                format!("the pruning pilot of job {}: {}", j.index, e.reason),
            );
            err.key = Some(at);
            err
        })?;
    }
    Ok(())
}

impl Study {
    /// Reads, expands and validates a study file.
    pub fn load(path: &Path) -> Result<Study, InputError> {
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot read the study file: {e}")))?;
        let c = Ctx { path, text: &text };
        let raw: StudyFile = toml::from_str(&text).map_err(|e| {
            if crate::error::toml_kind(&text) == Some("scene") {
                InputError::new(
                    path,
                    "this is a scene file, not a study: use it with `rotorsweep modes`, \
                     `simulate` or `linear`, or name it in a study as `scene = \"…\"`",
                )
            } else {
                locate::toml_error(path, &text, &e)
            }
        })?;
        let scene_path = path.parent().unwrap_or(Path::new(".")).join(&raw.scene);
        let scene_text = crate::error::read_text(&scene_path).map_err(|e| {
            c.err(
                "scene",
                format!("cannot read {}: {e}", scene_path.display()),
            )
        })?;
        let source = Source::from_text(&scene_path, &scene_text)?;
        let scene_table = source.table.clone();
        let mut base = Vec::new();
        flatten("", &raw.set, &mut base);
        let mut axes = Vec::new();
        for (i, a) in raw.axes.iter().enumerate() {
            let (keys, rows) = axis_values(&c, i, a)?;
            let at = if a.range.is_some() { "range" } else { "values" };
            distinct_rows(&c, &format!("axes[{i}].{at}"), &keys, &rows)?;
            axes.push((keys, rows));
        }
        job_count(&c, &axes, raw.jobs.len())?;
        // The product of the axes.
        type Combo = (Vec<(String, toml::Value)>, Vec<(String, String)>);
        let mut combos: Vec<Combo> = vec![(Vec::new(), Vec::new())];
        let mut varying = Vec::new();
        let mut axis_of_key = BTreeMap::new();
        for (i, (a, (keys, rows))) in raw.axes.iter().zip(axes).enumerate() {
            if let Some(l) = &a.labels {
                let key = format!("axes[{i}].labels");
                if l.len() != rows.len() {
                    return Err(c.err(
                        &key,
                        format!("{} labels for {} values", l.len(), rows.len()),
                    ));
                }
                let mut seen = std::collections::BTreeSet::new();
                if let Some(bad) = l.iter().find(|x| x.trim().is_empty() || !seen.insert(*x)) {
                    return Err(c.err(
                        &key,
                        format!("label `{bad}` is empty or given twice (labels name the rows)"),
                    ));
                }
            }
            for k in &keys {
                if axis_of_key.insert(k.clone(), i).is_some() {
                    return Err(c.err(&format!("axes[{i}]"), format!("key `{k}` is swept twice")));
                }
                varying.push(k.clone());
            }
            let mut next = Vec::with_capacity(combos.len() * rows.len());
            for combo in &combos {
                for (r, row) in rows.iter().enumerate() {
                    let mut c2 = combo.clone();
                    c2.0.extend(keys.iter().cloned().zip(row.iter().cloned()));
                    if let Some(l) = &a.labels {
                        c2.1.push((keys[0].clone(), l[r].clone()));
                    }
                    next.push(c2);
                }
            }
            combos = next;
        }
        if raw.axes.is_empty() && !raw.jobs.is_empty() {
            combos.clear();
        }
        let axis_combos = combos.len();
        for (j, t) in raw.jobs.iter().enumerate() {
            let mut o = Vec::new();
            flatten("", t, &mut o);
            for (k, _) in &o {
                if !varying.contains(k) {
                    varying.push(k.clone());
                }
            }
            if o.is_empty() {
                return Err(c.err(
                    &format!("jobs[{j}]"),
                    "an explicit job needs at least one key",
                ));
            }
            combos.push((o, Vec::new()));
        }
        let mut reference = Vec::new();
        flatten("", &raw.reference, &mut reference);
        if let Some((k, _)) = reference
            .iter()
            .find(|(k, _)| !k.starts_with("solver.") && k != "reduction.modes")
        {
            return Err(c.err(
                &format!("reference.{k}"),
                "the reference may only change solver.* keys and reduction.modes (same physics)",
            ));
        }
        // With its own mode set the reference is shared by jobs that differ only in their modes
        // (their error then includes the truncation); otherwise each mode set has its own.
        let ref_sets_modes = reference.iter().any(|(k, _)| k == "reduction.modes");
        let mut pilot = Vec::new();
        flatten("", &raw.pruning, &mut pilot);
        if let Some((k, _)) = pilot
            .iter()
            .find(|(k, _)| MODEL_TABLES.contains(&k.split('.').next().unwrap_or_default()))
        {
            return Err(c.err(
                &format!("pruning.{k}"),
                "the pilot runs on its jobs' reduced model: [pruning] may not change materials, \
                 roll, rotor or reduction keys",
            ));
        }
        let mut budget = Vec::new();
        if let Some(s) = raw.budget.cpu_s {
            if !(s > 0.0 && s.is_finite()) {
                return Err(c.err("budget.cpu_s", "must be a positive number"));
            }
            budget.push(("solver.cpu_budget_s".to_string(), toml::Value::Float(s)));
        }
        if let Some(n) = raw.budget.steps {
            budget.push((
                "solver.max_steps".to_string(),
                toml::Value::Integer(n as i64),
            ));
        }
        let name = raw.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        });
        let mut jobs = Vec::new();
        let mut references: BTreeMap<String, Reference> = BTreeMap::new();
        let a = &raw.analysis;
        if a.orders.is_empty() || a.orders.iter().any(|o| !(o.is_finite() && *o > 0.0)) {
            return Err(c.err("analysis.orders", "needs one or more positive orders"));
        }
        if (1..a.orders.len()).any(|i| a.orders[..i].contains(&a.orders[i])) {
            return Err(c.err("analysis.orders", "an order is given twice"));
        }
        if a.max_freq_hz.is_some_and(|f| !(f.is_finite() && f > 0.0)) {
            return Err(c.err("analysis.max_freq_hz", "must be a positive frequency"));
        }
        if a.order_revolutions
            .is_some_and(|r| !(r.is_finite() && (1.0..=1e5).contains(&r)))
        {
            return Err(c.err(
                "analysis.order_revolutions",
                "must lie in [1, 100000] revolutions",
            ));
        }
        if let Some(b) = &a.baseline {
            let found = raw
                .axes
                .iter()
                .any(|x| x.labels.as_ref().is_some_and(|l| l.contains(b)));
            if !found {
                return Err(c.err(
                    "analysis.baseline",
                    format!("no axis has the label `{b}` (axes need `labels` for a baseline)"),
                ));
            }
        }
        let linear = linear_request(&c, &raw.linear)?;
        replaced_keys(&c, &base, &raw, &reference, &pilot)?;
        let mut physics_of = BTreeMap::new();
        for (index, (combo, labels)) in combos.into_iter().enumerate() {
            // Where to point errors: the axis (or explicit job) that set a key.
            let locate_key = |k: &str| -> String {
                match axis_of_key.get(k) {
                    Some(i) => format!("axes[{i}].values"),
                    None if base.iter().any(|(b, _)| b == k) => format!("set.{k}"),
                    None => match index.checked_sub(axis_combos) {
                        Some(j) => format!("jobs[{j}].{k}"),
                        None => "jobs".to_string(),
                    },
                }
            };
            let mut overrides: Vec<(String, toml::Value)> = base.clone();
            overrides.extend(budget.iter().cloned());
            let mut prune = None;
            for (k, v) in combo {
                if k == PRUNE_KEY {
                    let t = v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
                    match t {
                        Some(t) if (0.0..1.0).contains(&t) => prune = Some(t),
                        _ => {
                            return Err(c.err(
                                &locate_key(&k),
                                format!("`{PRUNE_KEY}` must be a share in [0, 1), got {v}"),
                            ))
                        }
                    }
                } else {
                    overrides.retain(|(ok, _)| ok != &k);
                    overrides.push((k, v));
                }
            }
            let strings: Vec<String> = overrides
                .iter()
                .map(|(k, v)| format!("{k}={}", value_text(v)))
                .collect();
            let scene = Scene::from_source(&source, &strings).map_err(|mut e| {
                let key = override_key(&e, &overrides);
                if e.file.as_os_str() == "<command line --set>" {
                    let mut err = c.err(&locate_key(&key), format!("job {index}: {}", e.reason));
                    err.key = Some(key);
                    err
                } else {
                    // In the scene or its map: say which study and job read it.
                    e.reason += &format!(" (job {index} of {})", path.display());
                    e
                }
            })?;
            // The same physics written twice (`10` and `10.0`): one job.
            let written = normal_text(&overrides) + &format!("|{prune:?}");
            if let Some(first) = physics_of.insert(written, index) {
                let at = match index.checked_sub(axis_combos) {
                    Some(j) => format!("jobs[{j}]"),
                    None => "axes".to_string(),
                };
                return Err(c.err(
                    &at,
                    format!(
                        "jobs {first} and {index} have the same inputs (values that differ only \
                         in how they are written, such as 10 and 10.0, are the same)"
                    ),
                ));
            }
            let mut merged = toml::Value::Table(scene_table.clone());
            for (k, v) in &overrides {
                set_path(&mut merged, k, v.clone()).map_err(|r| c.err(&locate_key(k), r))?;
            }
            let inputs = scene_inputs(&source, &merged);
            let model_part = canonical(&merged, &["materials", "roll", "rotor", "reduction"], &[]);
            let model_id = hash_id('m', &[&inputs, &model_part]);
            let linear_part = canonical(
                &merged,
                &[
                    "materials",
                    "roll",
                    "rotor",
                    "reduction",
                    "supports",
                    "drive",
                ],
                &[],
            );
            let gravity = merged
                .get("simulation")
                .and_then(|s| s.get("gravity_m_s2"))
                .map(value_text)
                .unwrap_or_default();
            let linear_id = hash_id('l', &[&inputs, &linear_part, &gravity]);
            let physics = if ref_sets_modes {
                canonical(&merged, &[], &["solver", "reduction"])
            } else {
                canonical(&merged, &[], &["solver"])
            };
            // A pruned job also depends on how its pilot ran.
            let prune_text = prune
                .map(|p| format!("{p:e}|{}", pilot_text(&pilot)))
                .unwrap_or_default();
            let all = canonical(&merged, &[], &[]);
            let id = hash_id('j', &[&inputs, &all, &prune_text]);
            // Reference: the same physics with the reference solver keys. The study's budget
            // binds the reference too, unless [reference] sets its own.
            let mut ref_over = overrides.clone();
            for (k, v) in &reference {
                ref_over.retain(|(ok, _)| ok != k);
                ref_over.push((k.clone(), v.clone()));
            }
            let mut ref_merged = toml::Value::Table(scene_table.clone());
            for (k, v) in &ref_over {
                set_path(&mut ref_merged, k, v.clone()).map_err(|r| c.err("reference", r))?;
            }
            let reference_id = hash_id(
                'r',
                &[&inputs, &physics, &canonical(&ref_merged, &["solver"], &[])],
            );
            if !references.contains_key(&reference_id) {
                let rs: Vec<String> = ref_over
                    .iter()
                    .map(|(k, v)| format!("{k}={}", value_text(v)))
                    .collect();
                let rscene = Scene::from_source(&source, &rs).map_err(|e| {
                    let key = override_key(&e, &ref_over);
                    let at = if reference.iter().any(|(k, _)| *k == key) {
                        format!("reference.{key}")
                    } else {
                        "reference".to_string()
                    };
                    let mut err = c.err(&at, format!("the reference of job {index}: {}", e.reason));
                    err.key = Some(at);
                    err
                })?;
                let rmodel = canonical(
                    &ref_merged,
                    &["materials", "roll", "rotor", "reduction"],
                    &[],
                );
                references.insert(
                    reference_id.clone(),
                    Reference {
                        id: reference_id.clone(),
                        overrides: ref_over,
                        model_id: hash_id('m', &[&inputs, &rmodel]),
                        scene: rscene,
                    },
                );
            }
            jobs.push(Job {
                index,
                id,
                overrides,
                prune,
                model_id,
                reference_id,
                linear_id,
                labels,
                scene,
            });
        }
        if jobs.is_empty() {
            return Err(c.err("axes", "the study has no jobs: add axes or [[jobs]]"));
        }
        pilots_load(&c, &source, &jobs, &pilot)?;
        // Every line a study asks for must lie below the Nyquist frequency of its job's record
        // (with the default orders, lines above it are stored as NaN).
        let top = raw.analysis.orders.iter().copied().fold(0.0, f64::max);
        let explicit = raw.analysis.orders != default_orders();
        for j in jobs.iter().filter(|_| explicit) {
            let sim = &j.scene.simulation;
            if let Some((w, _)) = j.scene.speed.constant_over(sim.settle, sim.t_end) {
                let f = top * w / std::f64::consts::TAU;
                if f >= 0.5 * sim.sample_rate {
                    return Err(c.err(
                        "analysis.orders",
                        format!(
                            "job {}: order {top} at {:.4} Hz is {f:.4} Hz, at or above the Nyquist \
                             frequency {:.1} Hz of simulation.sample_rate_hz",
                            j.index,
                            w / std::f64::consts::TAU,
                            0.5 * sim.sample_rate
                        ),
                    ));
                }
            }
        }
        let mut seen = BTreeMap::new();
        for j in &jobs {
            if let Some(first) = seen.insert(j.id.clone(), j.index) {
                return Err(c.err(
                    "axes",
                    format!("jobs {first} and {} are identical (same inputs)", j.index),
                ));
            }
        }
        Ok(Study {
            name,
            description: raw.description.unwrap_or_default(),
            path: path.to_path_buf(),
            text: text.clone(),
            scene_path,
            varying,
            jobs,
            references: references.into_values().collect(),
            pilot_overrides: pilot,
            has_reference: !reference.is_empty(),
            linear,
        })
    }

    /// The value of a varying key in a job (as written), or `None`.
    pub fn value_of<'a>(&self, job: &'a Job, key: &str) -> Option<&'a toml::Value> {
        job.overrides
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v)
    }

    /// The value of a varying key in a job as text, the pruning pseudo-key included; `None`
    /// when the job does not set it.
    pub fn value_text(&self, job: &Job, key: &str) -> Option<String> {
        if key == PRUNE_KEY {
            job.prune.map(|p| p.to_string())
        } else {
            self.value_of(job, key).map(toml::Value::to_string)
        }
    }

    /// The jobs of shard `i` of `n` (by index modulo n).
    pub fn shard(&self, i: usize, n: usize) -> Vec<&Job> {
        self.jobs.iter().filter(|j| j.index % n == i).collect()
    }
}
