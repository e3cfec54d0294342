//! Tables of a study results file, for `rotorsweep report`.
//!
//! In: an assembled results file of `rotorsweep run` or `merge`, or of `rotorsweep linear -o`
//! (only read): the `/jobs/<id>` attributes (status, cause, integrator, statistics, errors
//! against the reference, the varying keys and axis labels), `/linear/<id>` (Campbell data,
//! critical speeds, first bending frequencies; threshold and Floquet ranges where stored),
//! `/analysis/sweeps/<n>` (line amplitudes over speed) and `/analysis/trial_mass`.
//! Out: a [`Report`] of neutral [`Table`]s (a short title, a legend with the units, columns and
//! rows), rendered as markdown, CSV, JSON or one self-contained HTML page with the figures
//! ([`Report::render_html`]). Long forms (CSV, JSON) carry `job_id` and one column per varying
//! parameter; markdown and HTML show each job by its setting (labels, `key=value`). Numbers as
//! text are written one way ([`number_text`], [`significant`]: scientific below 1e-3 and from 1e6).
//! - `solver`: per job, CPU time [s], CPU time relative to the cheapest ok job, Newton iterations
//!   per step, steps, rejected steps, max, RMS and peak-amplitude runout error against the reference [µm]
//!   (the thesis's Tables 5.2–5.4; transposed in markdown up to 8 jobs);
//! - `resonances`: per speed sweep, direction and integer order k ≥ 2, the speed [Hz] where
//!   order k of the centre runout peaks nearest to (within 10 % of) the model's critical
//!   speed / k, the sweep's step there [Hz] and the flags `coarse` / `edge`
//!   (`signal::resolution`; markdown rounds the speed to the step), and the amplitude [µm] of
//!   order k at each sensor's own such peak (the thesis's Table 5.1);
//! - `trial_mass`: per trial-mass job, the vertical 1× amplitude change and vector change
//!   against the baseline [µm] at each sensor;
//! - `stability`: per integrator and other setting, the status, max error [µm], its class
//!   ([`error_class`]) and CPU time [s] (a matrix in markdown and HTML, long form in CSV and
//!   JSON);
//! - `linear`: per linearised system (`/linear/<id>` of a study, `/linear/<scene>` of a
//!   `rotorsweep linear -o` file, which the report also reads), long form: the lateral modes at
//!   every stored speed (damped frequency [Hz]; damping ratio, log decrement and whirl where
//!   stored, as `linear -o` does and a study's Campbell data does not), the critical speeds
//!   [Hz] with their whirl and log decrement, the stability threshold [Hz] and the
//!   Floquet-unstable ranges [Hz] (in markdown a grid of speeds × lowest modes);
//! - `orders`, `order_resonances`: order tracking (`/analysis/orders`, module `orders`), when
//!   some job's speed changed while it recorded;
//! - `balancing`, `balancing_residual`: for trial-mass runs on a masses axis, the influence
//!   coefficients' correction masses and the model-based ("ideal") reference, and the 1×
//!   predicted after each (module `balancing`).
//!
//! Each table appears only when the file holds what it needs.
//! `compare` and `compare_resonances` (module `compare`, `report --compare`): a measured file's orders and resonances against a
//! simulated file's, side by side.

mod balancing;
mod compare;
mod orders;
pub use compare::compare;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use hdf5::types::VarLenUnicode;
use hdf5::{File, Group};
use serde::Serialize;

use crate::error::InputError;
use crate::integrators::Status;
use crate::results::request::{analysis_of_text, LabelledAxis, StudyAnalysis};
use crate::signal;
use crate::store::{self, Param};
use crate::text::{number_text, significant};

/// The key that names the integrator.
const INTEGRATOR_KEY: &str = "solver.integrator";

/// Up to this many jobs, markdown shows the solver table transposed (one column per job).
const TRANSPOSE_MAX: usize = 8;

/// Causes longer than this are cut in the stability matrix.
const SHORT_CAUSE: usize = 40;

/// One cell of a table.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// Text.
    Text(String),
    /// A measured value; NaN when there is none (empty in CSV, `–` in markdown, null in JSON).
    Number(f64),
    /// A count.
    Count(u64),
}

impl Serialize for Cell {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Cell::Text(t) => s.serialize_str(t),
            Cell::Number(x) if x.is_finite() => s.serialize_f64(*x),
            Cell::Number(_) => s.serialize_none(),
            Cell::Count(n) => s.serialize_u64(*n),
        }
    }
}

/// A grid of text: how markdown and HTML show a table whose long form reads badly there.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Column headings.
    pub columns: Vec<String>,
    /// Rows of cell text.
    pub rows: Vec<Vec<String>>,
    /// Per row, each cell's class ([`error_class`]) by which HTML colours it; empty: none.
    pub classes: Vec<Vec<String>>,
}

/// A figure of the HTML report: its file name and PNG bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The file name `scripts/plots.py` gave it (`spectral_map-0.png`, …).
    pub name: String,
    /// The PNG.
    pub png: Vec<u8>,
}

/// The marker every HTML report carries in its head: `report -o --overwrite` replaces only a
/// file that has it.
pub const HTML_MARKER: &str = "<meta name=\"generator\" content=\"rotorsweep report\">";

/// Background colour of each class of [`error_class`] in the HTML stability matrix (the same as
/// `scripts/plots.py`'s).
const CLASS_COLOURS: [(&str, &str); 8] = [
    ("< 1 µm", "#a5d6a7"),
    ("1–10 µm", "#fff59d"),
    ("10–100 µm", "#ffcc80"),
    ("≥ 100 µm", "#ef9a9a"),
    ("no reference", "#b3e5fc"),
    ("untrusted", "#80cbc4"),
    ("diverged", "#ce93d8"),
    ("budget", "#bdbdbd"),
];

/// A table: named columns (units in the names), rows of cells.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// Short name (`--table NAME`).
    pub name: String,
    /// A short heading.
    pub title: String,
    /// What the columns hold, with units.
    pub legend: String,
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, one cell per column.
    pub rows: Vec<Vec<Cell>>,
    /// The markdown form when it differs from the rows (transposed, or a matrix).
    #[serde(skip)]
    pub markdown: Option<Grid>,
}

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Markdown tables under headings.
    Markdown,
    /// CSV, each table after a `# title` and a `# legend` line, tables apart by a blank line.
    Csv,
    /// One JSON object `{"study", "tables": [{"name", "title", "legend", "columns", "rows"}]}`.
    Json,
    /// One self-contained HTML page: the tables and the figures ([`Report::render_html`]).
    Html,
}

impl FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "md" | "markdown" => Ok(Format::Markdown),
            "csv" => Ok(Format::Csv),
            "json" => Ok(Format::Json),
            "html" => Ok(Format::Html),
            _ => Err(format!("unknown format `{s}` (md, csv, json or html)")),
        }
    }
}

/// The tables of one results file.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The file read.
    pub file: PathBuf,
    /// The study's name.
    pub study: String,
    /// One line: job count by status, and the varying keys.
    pub overview: String,
    /// The tables the file has data for.
    pub tables: Vec<Table>,
}

/// One job as the tables see it.
struct Job {
    id: String,
    /// The job's label (its labelled axes' labels), "" without.
    label: String,
    /// One cell per varying key (the file's `varying_keys`, in order).
    params: Vec<Cell>,
    status: String,
    cause: String,
    integrator: String,
    /// The labels and other varying values that tell this job from the others.
    setting: String,
    /// The same without the integrator.
    other: String,
    cpu_time_s: f64,
    iterations_per_step: f64,
    steps: f64,
    rejected_steps: f64,
    error_max_um: f64,
    error_rms_um: f64,
    error_peak_um: f64,
}

/// The labels of the job's labelled axes and `key=value` of its other varying keys, in axis
/// order; without the integrator when `skip_integrator` (the other keys of a labelled axis
/// that holds it then show as `key=value`).
fn setting(g: &Group, varying: &[String], axes: &[LabelledAxis], skip_integrator: bool) -> String {
    let mut parts = Vec::new();
    let mut labelled_done: Vec<usize> = Vec::new();
    for k in varying {
        if skip_integrator && k == INTEGRATOR_KEY {
            continue;
        }
        if let Some(a) = axes.iter().position(|a| a.keys.contains(k)) {
            let with_integrator = axes[a].keys.iter().any(|x| x == INTEGRATOR_KEY);
            if !(skip_integrator && with_integrator) {
                if !labelled_done.contains(&a) {
                    labelled_done.push(a);
                    let attr = format!("label:{}", axes[a].keys[0]);
                    if let Ok(l) = store::read_str(g, &attr) {
                        parts.push(l);
                    }
                }
                continue;
            }
        }
        match store::read_param(g, k) {
            Ok(Param::Number(x)) => parts.push(format!("{k}={}", number_text(x))),
            Ok(Param::Text(t)) => parts.push(format!("{k}={t}")),
            Ok(Param::Count(n)) => parts.push(format!("{k}={n}")),
            Err(_) => {}
        }
    }
    parts.join(", ")
}

/// The jobs in job order.
fn read_jobs(f: &File, varying: &[String], axes: &[LabelledAxis]) -> hdf5::Result<Vec<Job>> {
    let jobs = f.group("jobs")?;
    let mut out = Vec::new();
    for id in jobs.member_names()? {
        let g = jobs.group(&id)?;
        let num = |name: &str| store::read_num(&g, name).unwrap_or(f64::NAN);
        let text = |name: &str| store::read_str(&g, name).unwrap_or_default();
        let mut all = setting(&g, varying, axes, false);
        if all.is_empty() {
            all = format!("job {id}");
        }
        let params = varying
            .iter()
            .map(|k| match store::read_param(&g, k) {
                Ok(Param::Number(x)) => Cell::Number(x),
                Ok(Param::Count(n)) => Cell::Count(n),
                Ok(Param::Text(t)) => Cell::Text(t),
                Err(_) => Cell::Number(f64::NAN),
            })
            .collect();
        let job = Job {
            id: id.clone(),
            label: text("label"),
            params,
            status: text("status"),
            cause: text("cause"),
            integrator: text("integrator"),
            setting: all,
            other: setting(&g, varying, axes, true),
            cpu_time_s: num("cpu_time_s"),
            iterations_per_step: num("iterations_per_step"),
            steps: num("steps"),
            rejected_steps: num("rejected_steps"),
            error_max_um: num("error_max_um"),
            error_rms_um: num("error_rms_um"),
            error_peak_um: num("error_peak_um"),
        };
        out.push((num("job_index"), id, job));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    Ok(out.into_iter().map(|(_, _, j)| j).collect())
}

/// A count stored as a float attribute; NaN (missing) reads as a missing number.
fn count(x: f64) -> Cell {
    if x.is_finite() && x >= 0.0 {
        Cell::Count(x as u64)
    } else {
        Cell::Number(f64::NAN)
    }
}

/// The long form's identifying columns of every job: `job_id`, `label` (when any job has one)
/// and one per varying key (without `skip`); their names and each job's cells.
fn job_columns(jobs: &[Job], varying: &[String], skip: &str) -> (Vec<String>, Vec<Vec<Cell>>) {
    let labelled = jobs.iter().any(|j| !j.label.is_empty());
    let keep: Vec<usize> = (0..varying.len()).filter(|&k| varying[k] != skip).collect();
    let mut names = vec!["job_id".to_string()];
    if labelled {
        names.push("label".into());
    }
    names.extend(keep.iter().map(|&k| varying[k].clone()));
    let cells = jobs
        .iter()
        .map(|j| {
            let mut row = vec![Cell::Text(j.id.clone())];
            if labelled {
                row.push(Cell::Text(j.label.clone()));
            }
            row.extend(
                keep.iter()
                    .map(|&k| j.params.get(k).cloned().unwrap_or(Cell::Number(f64::NAN))),
            );
            row
        })
        .collect();
    (names, cells)
}

fn solver_table(jobs: &[Job], varying: &[String]) -> Table {
    let cheapest = jobs
        .iter()
        .filter(|j| Status::name_completed(&j.status) && j.cpu_time_s > 0.0)
        .map(|j| j.cpu_time_s)
        .fold(f64::NAN, f64::min);
    let measured = [
        "status",
        "cpu_time_s",
        "relative",
        "iterations_per_step",
        "steps",
        "rejected_steps",
        "error_max_um",
        "error_rms_um",
        "error_peak_um",
        "cause",
    ];
    let (mut columns, ids) = job_columns(jobs, varying, "");
    let first = columns.len();
    columns.extend(measured.iter().map(|c| c.to_string()));
    let rows: Vec<Vec<Cell>> = jobs
        .iter()
        .zip(ids)
        .map(|(j, mut row)| {
            row.extend([
                Cell::Text(j.status.clone()),
                Cell::Number(j.cpu_time_s),
                Cell::Number(j.cpu_time_s / cheapest),
                Cell::Number(j.iterations_per_step),
                count(j.steps),
                count(j.rejected_steps),
                Cell::Number(j.error_max_um),
                Cell::Number(j.error_rms_um),
                Cell::Number(j.error_peak_um),
                Cell::Text(if j.status == "ok" {
                    String::new()
                } else {
                    j.cause.clone()
                }),
            ]);
            row
        })
        .collect();
    let mut shown = vec![
        ("CPU time [s]", "cpu_time_s"),
        ("relative", "relative"),
        ("iterations/step", "iterations_per_step"),
        ("max error [µm]", "error_max_um"),
        ("RMS error [µm]", "error_rms_um"),
        ("peak amplitude error [µm]", "error_peak_um"),
        ("status", "status"),
    ];
    if !jobs.iter().any(|j| j.error_max_um.is_finite()) {
        // No reference run: no errors to show.
        shown.retain(|(_, name)| !name.starts_with("error_"));
    }
    if jobs.iter().any(|j| j.status != "ok") {
        shown.push(("cause", "cause"));
    }
    let at = |name: &str| first + measured.iter().position(|x| *x == name).unwrap_or(0);
    let markdown = if jobs.len() <= TRANSPOSE_MAX {
        Grid {
            columns: std::iter::once("setting".to_string())
                .chain(jobs.iter().map(|j| j.setting.clone()))
                .collect(),
            rows: shown
                .iter()
                .map(|(heading, name)| {
                    std::iter::once(heading.to_string())
                        .chain(rows.iter().map(|r| md_cell(&r[at(name)])))
                        .collect()
                })
                .collect(),
            classes: Vec::new(),
        }
    } else {
        Grid {
            columns: std::iter::once("setting")
                .chain(shown.iter().map(|(h, _)| *h))
                .map(str::to_string)
                .collect(),
            rows: jobs
                .iter()
                .zip(&rows)
                .map(|(j, r)| {
                    std::iter::once(j.setting.clone())
                        .chain(shown.iter().map(|(_, name)| md_cell(&r[at(name)])))
                        .collect()
                })
                .collect(),
            classes: Vec::new(),
        }
    };
    Table {
        name: "solver".into(),
        title: "Solver cost and accuracy".into(),
        legend: "Per job (thesis Tables 5.2–5.4): CPU time [s]; relative: CPU time over the \
                 cheapest ok job's; Newton iterations per step; steps and rejected steps; max, \
                 RMS and peak-amplitude runout error against the reference run [µm] (– without \
                 a reference); cause of a job that did not end ok."
            .into(),
        columns,
        rows,
        markdown: Some(markdown),
    }
}

/// `text` cut to `n` characters with an ellipsis.
fn cut(text: &str, n: usize) -> String {
    if text.chars().count() <= n {
        text.to_string()
    } else {
        format!("{}…", text.chars().take(n).collect::<String>())
    }
}

/// The class of a job's outcome, by which the stability matrix is coloured: its status when it
/// did not end ok (`untrusted`, `diverged`, `budget`), `no reference` without an error against one, else the decade of its max
/// runout error: `< 1 µm`, `1–10 µm`, `10–100 µm`, `≥ 100 µm` (a runout of a paper roll is
/// specified to a few µm: from 10 µm on a solver's error is as large as what is measured, from
/// 100 µm the run is wrong whatever its status). `scripts/plots.py` uses the same classes.
pub fn error_class(status: &str, error_max_um: f64) -> &str {
    match status {
        "ok" if !error_max_um.is_finite() => "no reference",
        "ok" if error_max_um < 1.0 => "< 1 µm",
        "ok" if error_max_um < 10.0 => "1–10 µm",
        "ok" if error_max_um < 100.0 => "10–100 µm",
        "ok" => "≥ 100 µm",
        other => other,
    }
}

/// The matrix cell of one job: `ok 1.2 µm 0.48 s`, `diverged: cause`, `budget 30 s`.
fn outcome(j: &Job) -> String {
    match j.status.as_str() {
        "ok" if j.error_max_um.is_finite() => format!(
            "ok {} µm {} s",
            significant(j.error_max_um, 2),
            significant(j.cpu_time_s, 2)
        ),
        "ok" => format!("ok {} s", significant(j.cpu_time_s, 2)),
        "untrusted" => format!(
            "untrusted {} µm {} s",
            significant(j.error_max_um, 2),
            significant(j.cpu_time_s, 2)
        ),
        "budget" => format!("budget {} s", significant(j.cpu_time_s, 2)),
        s => format!("{s}: {}", cut(&j.cause, SHORT_CAUSE)),
    }
}

fn stability_table(jobs: &[Job], varying: &[String]) -> Table {
    let mut integrators: Vec<&str> = Vec::new();
    let mut settings: Vec<&str> = Vec::new();
    let mut cells: BTreeMap<(usize, usize), Vec<String>> = BTreeMap::new();
    let mut worst: BTreeMap<(usize, usize), (usize, &str)> = BTreeMap::new();
    let (mut columns, ids) = job_columns(jobs, varying, INTEGRATOR_KEY);
    columns.splice(1..1, ["integrator".to_string()]);
    columns.extend(
        [
            "status",
            "error_max_um",
            "error_class",
            "cpu_time_s",
            "cause",
        ]
        .iter()
        .map(|c| c.to_string()),
    );
    let mut rows = Vec::new();
    for (j, mut row) in jobs.iter().zip(ids) {
        let i = position_or_push(&mut integrators, &j.integrator);
        let s = position_or_push(&mut settings, &j.other);
        cells.entry((i, s)).or_default().push(outcome(j));
        let class = error_class(&j.status, j.error_max_um);
        let rank = CLASS_COLOURS
            .iter()
            .position(|(c, _)| *c == class)
            .unwrap_or(CLASS_COLOURS.len());
        let w = worst.entry((i, s)).or_insert((rank, class));
        if rank > w.0 {
            *w = (rank, class);
        }
        row.insert(1, Cell::Text(j.integrator.clone()));
        row.extend([
            Cell::Text(j.status.clone()),
            Cell::Number(j.error_max_um),
            Cell::Text(error_class(&j.status, j.error_max_um).to_string()),
            Cell::Number(j.cpu_time_s),
            Cell::Text(j.cause.clone()),
        ]);
        rows.push(row);
    }
    let grid = Grid {
        columns: std::iter::once("integrator")
            .chain(settings.iter().copied())
            .map(str::to_string)
            .collect(),
        rows: integrators
            .iter()
            .enumerate()
            .map(|(i, name)| {
                std::iter::once(name.to_string())
                    .chain(
                        (0..settings.len())
                            .map(|s| cells.get(&(i, s)).map(|v| v.join("; ")).unwrap_or_default()),
                    )
                    .collect()
            })
            .collect(),
        classes: (0..integrators.len())
            .map(|i| {
                std::iter::once(String::new())
                    .chain((0..settings.len()).map(|s| {
                        worst
                            .get(&(i, s))
                            .map_or_else(String::new, |w| w.1.to_string())
                    }))
                    .collect()
            })
            .collect(),
    };
    Table {
        name: "stability".into(),
        title: "Stability and accuracy per integrator".into(),
        legend: "Per integrator (rows) and other setting (columns): status, max runout error \
                 against the reference [µm] and CPU time [s]; error class by decade (< 1 µm, \
                 1–10 µm, 10–100 µm, ≥ 100 µm; no reference; or the status of a job that did \
                 not end ok)."
            .into(),
        columns,
        rows,
        markdown: Some(grid),
    }
}

/// The index of `item` in `list`, appending it first when absent.
fn position_or_push<'a>(list: &mut Vec<&'a str>, item: &'a str) -> usize {
    list.iter().position(|x| *x == item).unwrap_or_else(|| {
        list.push(item);
        list.len() - 1
    })
}

/// The vertical and horizontal critical speeds [Hz] of a linearised system (`/linear/<id>`): of
/// its `critical_speeds_hz`, the ones nearest to its first vertical and horizontal bending
/// frequencies.
fn criticals(f: &File, linear_id: &str) -> [Option<f64>; 2] {
    let Ok(g) = f.group(&format!("linear/{linear_id}")) else {
        return [None, None];
    };
    let crit: Vec<f64> = g
        .dataset("critical_speeds_hz")
        .and_then(|d| d.read_raw::<f64>())
        .unwrap_or_default();
    ["vertical_hz", "horizontal_hz"].map(|attr| {
        let first = store::read_num(&g, attr).ok().filter(|x| x.is_finite())?;
        crit.iter()
            .copied()
            .min_by(|a, b| (a - first).abs().total_cmp(&(b - first).abs()))
    })
}

/// How far [share of the expected speed] a peak may lie from critical/k and still be taken as
/// that sub-critical resonance (10 %: the horizontal and vertical lines of a roll lie 5–7 %
/// apart, so a peak further off belongs to something else).
const RESONANCE_WINDOW: f64 = 0.1;

/// The peak nearest to `near` [Hz] within [`RESONANCE_WINDOW`] of it, or the highest one
/// without `near`.
fn pick(peaks: Vec<signal::Peak>, near: Option<f64>) -> Option<signal::Peak> {
    match near {
        Some(c) => peaks
            .into_iter()
            .filter(|p| (p.speed_hz - c).abs() <= RESONANCE_WINDOW * c)
            .min_by(|a, b| (a.speed_hz - c).abs().total_cmp(&(b.speed_hz - c).abs())),
        None => peaks.into_iter().next(),
    }
}

/// The order sensors are shown in: `centre` first, then by name.
fn sensor_rank(name: &str) -> (bool, &str) {
    (name != "centre", name)
}

/// The sweep groups in number order.
fn sweep_groups(f: &File) -> hdf5::Result<Vec<Group>> {
    let Ok(g) = f.group("analysis/sweeps") else {
        return Ok(Vec::new());
    };
    let mut names = g.member_names()?;
    names.sort_by_key(|n| n.parse::<u64>().unwrap_or(u64::MAX));
    names.iter().map(|n| g.group(n)).collect()
}

fn resonance_table(f: &File) -> hdf5::Result<Option<Table>> {
    let mut columns: Vec<String> = [
        "sweep",
        "direction",
        "order",
        "expected_hz",
        "speed_hz",
        "step_hz",
        "note",
    ]
    .iter()
    .map(|c| c.to_string())
    .collect();
    let mut names: Vec<String> = Vec::new();
    let mut rows = Vec::new();
    let mut md = Vec::new();
    for (n, sg) in sweep_groups(f)?.iter().enumerate() {
        let speeds: Vec<f64> = sg.dataset("speed_hz")?.read_raw()?;
        let orders: Vec<f64> = sg.dataset("orders")?.read_raw()?;
        let fixed = store::read_str(sg, "fixed").unwrap_or_default();
        let sweep = if fixed.is_empty() {
            format!("sweep {n}")
        } else {
            fixed
        };
        let ids: Vec<VarLenUnicode> = sg.dataset("job_ids")?.read_raw()?;
        let crit = ids
            .first()
            .and_then(|id| f.group(&format!("jobs/{id}")).ok())
            .and_then(|g| store::read_str(&g, "linear_id").ok())
            .map_or([None, None], |m| criticals(f, &m));
        // A sweep without runout channels has no lines.
        let Ok(lines) = sg.group("lines") else {
            continue;
        };
        if names.is_empty() {
            names = lines.member_names()?;
            names.sort_by(|a, b| sensor_rank(a).cmp(&sensor_rank(b)));
        }
        for (d, dir) in ["vertical", "horizontal"].iter().enumerate() {
            let data: Vec<Option<Vec<f64>>> = names
                .iter()
                .map(|s| {
                    lines
                        .dataset(&format!("{s}/{dir}"))
                        .and_then(|ds| ds.read_raw::<f64>())
                        .ok()
                })
                .collect();
            for (k, order) in orders.iter().enumerate() {
                if order.fract() != 0.0 || *order < 2.0 {
                    continue;
                }
                let expected = crit[d].map(|c| c / order);
                let found: Vec<Option<(signal::Peak, signal::Resolution)>> = data
                    .iter()
                    .map(|m| {
                        let m = m.as_ref()?;
                        let amp: Vec<f64> = (0..speeds.len())
                            .map(|s| m.get(s * orders.len() + k).copied().unwrap_or(f64::NAN))
                            .collect();
                        let p = pick(signal::peaks(&speeds, &amp), expected)?;
                        Some((p, signal::resolution(&speeds, &amp, &p)))
                    })
                    .collect();
                let centre = found[0];
                let mut row = vec![
                    Cell::Text(sweep.clone()),
                    Cell::Text(dir.to_string()),
                    Cell::Count(*order as u64),
                    Cell::Number(expected.unwrap_or(f64::NAN)),
                    Cell::Number(centre.map_or(f64::NAN, |p| p.0.speed_hz)),
                    Cell::Number(centre.map_or(f64::NAN, |p| p.1.step_hz)),
                    Cell::Text(centre.map_or_else(String::new, |p| p.1.note())),
                ];
                row.extend(
                    found
                        .iter()
                        .map(|p| Cell::Number(p.map_or(f64::NAN, |p| p.0.amplitude))),
                );
                let mut line: Vec<String> = row.iter().map(md_cell).collect();
                if let Some((p, r)) = centre {
                    line[4] = to_step(p.speed_hz, r.step_hz);
                    line[5] = number_text(significant(r.step_hz, 3).parse().unwrap_or(r.step_hz));
                }
                md.push(line);
                rows.push(row);
            }
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    columns.extend(names.iter().map(|s| format!("{s}_um")));
    let md_columns = columns
        .iter()
        .map(|c| match c.as_str() {
            "expected_hz" => "expected [Hz]".to_string(),
            "speed_hz" => "speed [Hz]".to_string(),
            "step_hz" => "step [Hz]".to_string(),
            other => match other.strip_suffix("_um") {
                Some(sensor) => format!("{sensor} [µm]"),
                None => other.to_string(),
            },
        })
        .collect();
    Ok(Some(Table {
        name: "resonances".into(),
        title: "Harmonic resonances".into(),
        legend: format!(
            "Per speed sweep, direction and order k (thesis Table 5.1): the speed [Hz] where \
             order k of the {} runout peaks nearest to the model's critical speed / k \
             (expected, within 10 %; – when no peak is that close); the sweep's step there \
             [Hz]: the speed is uncertain by up to half of it (markdown rounds to it); note: \
             `coarse` when the step exceeds {:.0} % of the speed (too coarse to tell a roll's \
             vertical and horizontal resonances apart), `edge` when the curve's largest value \
             lies at an end of the sweep (the strongest response may lie outside it); then the \
             amplitude [µm] of order k at each sensor's own such peak.",
            names[0],
            100.0 * signal::COARSE_STEP
        ),
        columns,
        rows,
        markdown: Some(Grid {
            columns: md_columns,
            rows: md,
            classes: Vec::new(),
        }),
    }))
}

/// `x` rounded to the resolution of a sweep with step `step` (to the decimal of half a step: 16.2
/// for a 0.2 Hz step, 16 for a 4 Hz one).
fn to_step(x: f64, step: f64) -> String {
    if !(step > 0.0 && x.is_finite()) {
        return significant(x, 4);
    }
    // A step of 16.2 − 16.0 is 0.19999…: its decimal is that of 0.2.
    let decimals = (-(0.5 * step).log10() - 1e-6).ceil().max(0.0) as usize;
    format!("{x:.decimals$}")
}

/// The columns of `/analysis/trial_mass` the table uses (HDF5 converts records member by member
/// by name).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct TrialRow {
    job_id: VarLenUnicode,
    label: VarLenUnicode,
    channel: VarLenUnicode,
    speed_hz: f64,
    amplitude_change_um: f64,
    vector_change_um: f64,
}

/// The trial-mass table; the labels come from the jobs' `label:<label_key>` attributes when
/// there, else from the table.
fn trial_mass_table(f: &File, label_key: Option<&str>) -> hdf5::Result<Option<Table>> {
    let Ok(ds) = f.dataset("analysis/trial_mass") else {
        return Ok(None);
    };
    let records: Vec<TrialRow> = ds.read_raw()?;
    let mut sensors: Vec<&str> = Vec::new();
    // Job → (label, speed, job index, sensor index → (amplitude change, vector change)).
    type Changes = BTreeMap<usize, (f64, f64)>;
    let mut per_job: BTreeMap<&str, (String, f64, f64, Changes, String)> = BTreeMap::new();
    for r in &records {
        let Some(sensor) = r.channel.as_str().strip_suffix("/vertical") else {
            continue;
        };
        let s = position_or_push(&mut sensors, sensor);
        per_job
            .entry(r.job_id.as_str())
            .or_insert_with(|| {
                let g = f.group(&format!("jobs/{}", r.job_id.as_str())).ok();
                let label = label_key
                    .and_then(|k| store::read_str(g.as_ref()?, &format!("label:{k}")).ok())
                    .unwrap_or_else(|| r.label.as_str().to_string());
                let index = g
                    .and_then(|g| store::read_num(&g, "job_index").ok())
                    .unwrap_or(f64::NAN);
                (
                    label,
                    r.speed_hz,
                    index,
                    BTreeMap::new(),
                    r.job_id.as_str().to_string(),
                )
            })
            .3
            .insert(s, (r.amplitude_change_um, r.vector_change_um));
    }
    if per_job.is_empty() {
        return Ok(None);
    }
    let mut jobs: Vec<_> = per_job.into_values().collect();
    // The labels in the study's order (that of their first job), each by speed.
    let mut first: BTreeMap<String, f64> = BTreeMap::new();
    for j in &jobs {
        let e = first.entry(j.0.clone()).or_insert(j.2);
        *e = e.min(j.2);
    }
    jobs.sort_by(|a, b| {
        first[&a.0]
            .total_cmp(&first[&b.0])
            .then(a.1.total_cmp(&b.1))
    });
    let mut shown: Vec<usize> = (0..sensors.len()).collect();
    shown.sort_by(|a, b| sensor_rank(sensors[*a]).cmp(&sensor_rank(sensors[*b])));
    let mut columns = vec![
        "job_id".to_string(),
        "label".to_string(),
        "speed_hz".to_string(),
    ];
    for s in &shown {
        columns.push(format!("{}_amplitude_change_um", sensors[*s]));
        columns.push(format!("{}_vector_change_um", sensors[*s]));
    }
    let rows = jobs
        .iter()
        .map(|(label, speed, _, ch, id)| {
            let mut row = vec![
                Cell::Text(id.clone()),
                Cell::Text(label.clone()),
                Cell::Number(*speed),
            ];
            for s in &shown {
                let (a, v) = ch.get(s).copied().unwrap_or((f64::NAN, f64::NAN));
                row.extend([Cell::Number(a), Cell::Number(v)]);
            }
            row
        })
        .collect();
    Ok(Some(Table {
        name: "trial_mass".into(),
        title: "Trial-mass response".into(),
        legend: "Per trial-mass job: the vertical 1× runout against the baseline job's at the \
                 same speed [µm]: amplitude change |A|−|A₀| and vector change |A−A₀| per sensor."
            .into(),
        columns,
        rows,
        markdown: None,
    }))
}

/// Most speeds the markdown form of the `linear` table shows per system (evenly picked, the
/// first and last included; CSV and JSON hold every stored speed).
const LINEAR_MD_SPEEDS: usize = 11;

/// Most modes per speed the markdown form of the `linear` table shows (the lowest).
const LINEAR_MD_MODES: usize = 6;

/// A float dataset of `g` as (values, columns: 1 for 1-D), if there.
fn read_matrix(g: &Group, name: &str) -> Option<(Vec<f64>, usize)> {
    let ds = g.dataset(name).ok()?;
    let cols = match ds.shape().as_slice() {
        [_] => 1,
        [_, c] => *c,
        _ => return None,
    };
    Some((ds.read_raw::<f64>().ok()?, cols))
}

/// The whirl of a `campbell/whirl` code (its `codes` attribute: 1 forward, −1 backward, 0 mixed).
fn whirl_name(code: f64) -> &'static str {
    if code > 0.5 {
        "forward"
    } else if code < -0.5 {
        "backward"
    } else {
        "mixed"
    }
}

/// A mode as the markdown grid shows it: `44.378 δ 0.0137 forward`, or the frequency alone.
fn md_mode(freq: f64, log_dec: f64, whirl: &str) -> String {
    let mut t = significant(freq, 5);
    if log_dec.is_finite() {
        let _ = write!(t, " δ {}", significant(log_dec, 3));
    }
    if !whirl.is_empty() {
        let _ = write!(t, " {whirl}");
    }
    t
}

/// The rows and markdown lines of one `/linear/<name>` group (a system without Campbell data
/// gives none).
fn linear_system(
    name: &str,
    g: &Group,
    rows: &mut Vec<Vec<Cell>>,
    md: &mut Vec<Vec<String>>,
) -> hdf5::Result<()> {
    let Some((speeds, _)) = read_matrix(g, "campbell/speed_hz") else {
        return Ok(());
    };
    let (freq, nb) = read_matrix(g, "campbell/whirl_hz").unwrap_or_default();
    let stored = |name: &str| read_matrix(g, name).map(|m| m.0);
    let (log_dec, zeta, whirl) = (
        stored("campbell/log_dec"),
        stored("campbell/damping_ratio"),
        stored("campbell/whirl"),
    );
    let at = |v: &Option<Vec<f64>>, i: usize| v.as_ref().and_then(|v| v.get(i).copied());
    let text = |s: &str| Cell::Text(s.to_string());
    let row =
        |quantity: &str, speed: f64, end: f64, mode: Cell, f: f64, z: f64, d: f64, w: &str| {
            vec![
                text(name),
                text(quantity),
                Cell::Number(speed),
                Cell::Number(end),
                mode,
                Cell::Number(f),
                Cell::Number(z),
                Cell::Number(d),
                text(w),
            ]
        };
    let nan = f64::NAN;
    let step = speeds
        .len()
        .saturating_sub(1)
        .div_ceil(LINEAR_MD_SPEEDS - 1)
        .max(1);
    for (s, speed) in speeds.iter().enumerate() {
        let mut line = vec![name.to_string(), format!("{speed:.2}")];
        for k in 0..nb {
            let i = s * nb + k;
            let w = at(&whirl, i).map_or("", whirl_name);
            let d = at(&log_dec, i).unwrap_or(nan);
            rows.push(row(
                "mode",
                *speed,
                nan,
                Cell::Count(k as u64 + 1),
                freq[i],
                at(&zeta, i).unwrap_or(nan),
                d,
                w,
            ));
            if k < LINEAR_MD_MODES {
                line.push(md_mode(freq[i], d, w));
            }
        }
        if s % step == 0 || s + 1 == speeds.len() {
            md.push(line);
        }
    }
    let crit = stored("critical_speeds_hz").unwrap_or_default();
    let crit_dec = stored("critical_log_dec");
    let crit_whirl: Vec<String> = g
        .dataset("critical_whirl")
        .and_then(|d| d.read_raw::<VarLenUnicode>())
        .map(|v| v.iter().map(|w| w.to_string()).collect())
        .unwrap_or_default();
    let mut line = vec![name.to_string(), "critical speeds [Hz]".to_string()];
    for (i, c) in crit.iter().enumerate() {
        let w = crit_whirl.get(i).map_or("", String::as_str);
        let d = at(&crit_dec, i).unwrap_or(nan);
        rows.push(row("critical_speed", *c, nan, text(""), *c, nan, d, w));
        line.push(md_mode(*c, d, w));
    }
    if crit.is_empty() {
        line.push("none in the range".into());
    }
    md.push(line);
    // The stability threshold is computed with the damped modes only (their log decrements).
    if log_dec.is_some() {
        let top = speeds.last().copied().unwrap_or(nan);
        let threshold = store::read_num(g, "stability_threshold_hz").ok();
        rows.push(row(
            "stability_threshold",
            threshold.unwrap_or(nan),
            nan,
            text(""),
            nan,
            nan,
            nan,
            "",
        ));
        md.push(vec![
            name.to_string(),
            "stability threshold [Hz]".into(),
            threshold.map_or_else(
                || match speeds.as_slice() {
                    [one] => format!("none (stable at {one:.2} Hz)"),
                    _ => format!("none (stable over {:.2}–{top:.2} Hz)", speeds[0]),
                },
                |t| significant(t, 6),
            ),
        ]);
    }
    if let Some((ranges, _)) = read_matrix(g, "floquet/unstable_ranges_hz") {
        let pairs: Vec<[f64; 2]> = ranges.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
        for [a, b] in &pairs {
            rows.push(row("floquet_unstable", *a, *b, text(""), nan, nan, nan, ""));
        }
        let shown: Vec<String> = pairs
            .iter()
            .map(|[a, b]| format!("{}–{}", significant(*a, 6), significant(*b, 6)))
            .collect();
        md.push(vec![
            name.to_string(),
            "Floquet unstable [Hz]".into(),
            if shown.is_empty() {
                "none in the range".into()
            } else {
                shown.join(", ")
            },
        ]);
    }
    Ok(())
}

/// The `linear` table of every `/linear/<name>` group with Campbell data.
fn linear_table(f: &File) -> hdf5::Result<Option<Table>> {
    let Ok(lg) = f.group("linear") else {
        return Ok(None);
    };
    let mut rows = Vec::new();
    let mut md = Vec::new();
    for name in lg.member_names()? {
        linear_system(&name, &lg.group(&name)?, &mut rows, &mut md)?;
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let width = md.iter().map(Vec::len).max().unwrap_or(2);
    let columns = ["system", "speed [Hz]"]
        .iter()
        .map(|c| c.to_string())
        .chain((1..width - 1).map(|k| format!("mode {k}")))
        .collect();
    Ok(Some(Table {
        name: "linear".into(),
        title: "Linear systems".into(),
        legend: format!(
            "Damped lateral modes per spin speed (quantity `mode`: damped frequency [Hz], \
             damping ratio, log decrement δ, whirl, where stored; rank from 1 upwards), critical \
             speeds [Hz] with their whirl and δ, the stability threshold [Hz] (empty: stable \
             over the range) and the Floquet-unstable speed ranges [Hz]; in markdown and HTML \
             at most {LINEAR_MD_SPEEDS} evenly spaced speeds and the lowest {LINEAR_MD_MODES} \
             modes per system (CSV and JSON: all)."
        ),
        columns: [
            "system",
            "quantity",
            "speed_hz",
            "speed_end_hz",
            "mode",
            "freq_hz",
            "damping_ratio",
            "log_dec",
            "whirl",
        ]
        .iter()
        .map(|c| c.to_string())
        .collect(),
        rows,
        markdown: Some(Grid {
            columns,
            rows: md,
            classes: Vec::new(),
        }),
    }))
}

/// Reads the tables of the results file at `path`. Errors name the file.
pub fn read(path: &Path) -> Result<Report, InputError> {
    std::fs::metadata(path).map_err(|e| InputError::new(path, e.to_string()))?;
    let f =
        File::open(path).map_err(|e| InputError::new(path, format!("not an HDF5 file ({e})")))?;
    let not_results = || {
        InputError::new(
            path,
            "not a study results file of `rotorsweep run` (no `study_name` attribute or no \
             `jobs` group) nor a `rotorsweep linear -o` file (no `linear` group)",
        )
    };
    let linear_only = store::read_str(&f, "study_name").is_err() && f.group("linear").is_ok();
    let study = if linear_only {
        let names = f.group("linear").and_then(|g| g.member_names());
        format!(
            "{} (rotorsweep linear)",
            names.unwrap_or_default().join(", ")
        )
    } else {
        store::read_str(&f, "study_name").map_err(|_| not_results())?
    };
    if f.group("jobs").is_err() {
        return Err(not_results());
    }
    let text = store::read_str(&f, "study_text").unwrap_or_default();
    let StudyAnalysis {
        spec,
        labelled: axes,
        ..
    } = analysis_of_text(&text).unwrap_or_default();
    let label_key = spec.baseline.as_ref().and_then(|b| {
        axes.iter()
            .find(|a| a.labels.contains(b))
            .map(|a| a.keys[0].as_str())
    });
    let varying = store::varying_keys(&f);
    let failed = |e: hdf5::Error| InputError::new(path, format!("reading the results: {e}"));
    let jobs = read_jobs(&f, &varying, &axes).map_err(failed)?;
    let mut tables = Vec::new();
    if !jobs.is_empty() {
        tables.push(solver_table(&jobs, &varying));
    }
    tables.extend(resonance_table(&f).map_err(failed)?);
    tables.extend(trial_mass_table(&f, label_key).map_err(failed)?);
    if label_key.is_some_and(|k| k.ends_with(".masses")) {
        tables.extend(balancing::tables(path).into_iter().flatten());
    }
    tables.extend(orders::orders_table(&f).map_err(failed)?);
    tables.extend(orders::order_resonance_table(&f).map_err(failed)?);
    if varying.iter().any(|k| k == INTEGRATOR_KEY) && varying.len() >= 2 {
        tables.push(stability_table(&jobs, &varying));
    }
    tables.extend(linear_table(&f).map_err(failed)?);
    let (mut names, mut counts): (Vec<&str>, Vec<usize>) = (Vec::new(), Vec::new());
    for j in &jobs {
        let i = position_or_push(&mut names, &j.status);
        counts.resize(names.len(), 0);
        counts[i] += 1;
    }
    let statuses: Vec<String> = names
        .iter()
        .zip(&counts)
        .map(|(s, n)| format!("{n} {s}"))
        .collect();
    let overview = if linear_only {
        "linear analysis (`rotorsweep linear -o`), no jobs".to_string()
    } else {
        format!(
            "{} job{} ({}); varying: {}",
            jobs.len(),
            if jobs.len() == 1 { "" } else { "s" },
            statuses.join(", "),
            if varying.is_empty() {
                "nothing".to_string()
            } else {
                varying.join(", ")
            }
        )
    };
    Ok(Report {
        file: path.to_path_buf(),
        study,
        overview,
        tables,
    })
}

/// A cell as markdown shows it: 4 significant digits, `–` for no value.
fn md_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) => t.clone(),
        Cell::Number(x) => significant(*x, 4),
        Cell::Count(n) => n.to_string(),
    }
}

/// A cell as CSV holds it: full precision, empty for no value, quoted when needed.
fn csv_cell(c: &Cell) -> String {
    match c {
        Cell::Text(t) if t.contains([',', '"', '\n', '\r']) => {
            format!("\"{}\"", t.replace('"', "\"\""))
        }
        Cell::Text(t) => t.clone(),
        Cell::Number(x) if x.is_finite() => format!("{x}"),
        Cell::Number(_) => String::new(),
        Cell::Count(n) => n.to_string(),
    }
}

/// A markdown table, columns padded; `right` aligns the numeric columns right.
fn md_grid(out: &mut String, columns: &[String], rows: &[Vec<String>], right: &[bool]) {
    let clean = |s: &str| s.replace('|', "\\|").replace(['\n', '\r'], " ");
    let head: Vec<String> = columns.iter().map(|c| clean(c)).collect();
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| r.iter().map(|c| clean(c)).collect())
        .collect();
    let width: Vec<usize> = (0..head.len())
        .map(|c| {
            body.iter()
                .filter_map(|r| r.get(c))
                .chain(std::iter::once(&head[c]))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
                .max(3)
        })
        .collect();
    let line = |out: &mut String, cells: &[String]| {
        out.push('|');
        for (c, w) in width.iter().enumerate() {
            let s = cells.get(c).map_or("", String::as_str);
            if right.get(c) == Some(&true) {
                let _ = write!(out, " {s:>w$} |");
            } else {
                let _ = write!(out, " {s:<w$} |");
            }
        }
        out.push('\n');
    };
    line(out, &head);
    out.push('|');
    for (c, w) in width.iter().enumerate() {
        let dashes = "-".repeat(*w);
        if right.get(c) == Some(&true) {
            let _ = write!(out, " {}: |", &dashes[1..]);
        } else {
            let _ = write!(out, " {dashes} |");
        }
    }
    out.push('\n');
    for r in &body {
        line(out, r);
    }
}

fn markdown(out: &mut String, t: &Table) {
    let _ = writeln!(out, "## {} (`{}`)\n\n{}\n", t.title, t.name, t.legend);
    match &t.markdown {
        Some(g) => md_grid(out, &g.columns, &g.rows, &[]),
        None => {
            let right: Vec<bool> = (0..t.columns.len())
                .map(|c| {
                    t.rows
                        .iter()
                        .all(|r| !matches!(r.get(c), Some(Cell::Text(_))))
                })
                .collect();
            let rows: Vec<Vec<String>> = t
                .rows
                .iter()
                .map(|r| r.iter().map(md_cell).collect())
                .collect();
            md_grid(out, &t.columns, &rows, &right);
        }
    }
}

fn csv(out: &mut String, t: &Table) {
    let header: Vec<String> = t
        .columns
        .iter()
        .map(|c| csv_cell(&Cell::Text(c.clone())))
        .collect();
    let _ = writeln!(out, "{}", header.join(","));
    for r in &t.rows {
        let cells: Vec<String> = r.iter().map(csv_cell).collect();
        let _ = writeln!(out, "{}", cells.join(","));
    }
}

/// `text` with `&`, `<`, `>` and `"` escaped for HTML.
fn esc(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// `text` escaped for HTML, with `code` spans (between backticks) as `<code>`.
fn esc_code(text: &str) -> String {
    esc(text)
        .split('`')
        .enumerate()
        .map(|(i, part)| {
            if i % 2 == 1 {
                format!("<code>{part}</code>")
            } else {
                part.to_string()
            }
        })
        .collect()
}

/// What each figure of `scripts/plots.py` shows, by the start of its file name.
const FIGURE_CAPTIONS: [(&str, &str); 19] = [
    ("spectral_map", "Spectral map: amplitude of the runout's fluctuating part (mean removed) over frequency and speed, the roll's orders solid, the rollers' lines dashed"),
    ("harmonics", "Amplitude of each analysed order over speed"),
    ("trial_mass", "1× response to the trial masses against the baseline"),
    ("work_precision", "Work-precision: runout error against the reference over CPU time, per integrator and physics"),
    ("timing", "CPU time per job, Newton iterations per step on the bars"),
    ("stability", "Stability matrix: integrator × setting, coloured by error class"),
    ("campbell", "Campbell diagram on the linearised supports"),
    ("mode_shapes", "Lateral mode shapes"),
    ("bode", "Unbalance response (Bode)"),
    ("polar", "Unbalance response (polar)"),
    ("critical_map", "Critical-speed map"),
    ("floquet", "Floquet stability over one revolution"),
    ("mean", "Mean runout (static sag) over speed"),
    ("waterfall", "Waterfall of a run-up or coast-down: spectrum per time block, the tracked orders' lines k·speed(t)"),
    ("order_map", "Order map of a run-up or coast-down: amplitude of each tracked order over speed"),
    ("order_bode", "Tracked 1× amplitude and phase over speed, with the linear steady-state response where stored"),
    ("balancing", "Balancing: 1× before, predicted after and in the check run, per sensor and speed"),
    ("compare_waterfall", "Measured and simulated waterfalls side by side over frequency and speed, on one colour scale"),
    ("compare_orders", "Tracked order amplitudes over speed, measured solid, simulated dashed"),
];

/// The caption of a figure file.
fn caption(name: &str) -> &str {
    FIGURE_CAPTIONS
        .iter()
        .find(|(prefix, _)| name.starts_with(prefix))
        .map_or(name, |(_, c)| c)
}

/// One table as HTML: heading, legend, and its grid (or its rows as markdown shows them).
fn html_table(out: &mut String, t: &Table) {
    let _ = writeln!(
        out,
        "<section id=\"{name}\"><h2>{} <code>{name}</code></h2>\n<p class=\"legend\">{}</p>",
        esc(&t.title),
        esc_code(&t.legend),
        name = esc(&t.name)
    );
    let (columns, rows, classes): (&[String], Vec<Vec<String>>, &[Vec<String>]) = match &t.markdown
    {
        Some(g) => (&g.columns, g.rows.clone(), &g.classes),
        None => (
            &t.columns,
            t.rows
                .iter()
                .map(|r| r.iter().map(md_cell).collect())
                .collect(),
            &[],
        ),
    };
    out.push_str("<div class=\"scroll\"><table>\n<thead><tr>");
    for c in columns {
        let _ = write!(out, "<th>{}</th>", esc(c));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for (r, row) in rows.iter().enumerate() {
        out.push_str("<tr>");
        for (c, cell) in row.iter().enumerate() {
            let colour = classes
                .get(r)
                .and_then(|v| v.get(c))
                .and_then(|k| CLASS_COLOURS.iter().find(|(n, _)| n == k));
            match colour {
                Some((k, bg)) => {
                    let _ = write!(
                        out,
                        "<td style=\"background:{bg}\" title=\"{}\">{}</td>",
                        esc(k),
                        esc(cell)
                    );
                }
                None => {
                    let _ = write!(out, "<td>{}</td>", esc(cell));
                }
            }
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table></div>\n");
    if !classes.is_empty() {
        out.push_str("<p class=\"legend\">Colours: ");
        for (k, bg) in CLASS_COLOURS {
            let _ = write!(
                out,
                "<span class=\"swatch\" style=\"background:{bg}\">{}</span> ",
                esc(k)
            );
        }
        out.push_str("</p>\n");
    }
    out.push_str("</section>\n");
}

impl Report {
    /// The report as one self-contained HTML page: the overview, every figure (PNG embedded as
    /// base64, captioned) and every table with its legend. It carries [`HTML_MARKER`].
    pub fn render_html(&self, figures: &[Figure]) -> String {
        self.html(&self.tables.iter().collect::<Vec<_>>(), figures)
    }

    fn html(&self, tables: &[&Table], figures: &[Figure]) -> String {
        use base64::Engine as _;
        let mut out = String::new();
        let title = format!("Study {}", self.study);
        let _ = write!(
            out,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n{HTML_MARKER}\n\
             <title>{}</title>\n<style>\n\
             body {{ font-family: sans-serif; margin: 2em auto; max-width: 1400px; padding: 0 1em; color: #222; }}\n\
             table {{ border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }}\n\
             th, td {{ border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; white-space: nowrap; }}\n\
             th {{ background: #eee; }}\n\
             td:first-child, th:first-child {{ text-align: left; }}\n\
             .scroll {{ overflow-x: auto; }}\n\
             .legend {{ color: #444; font-size: 0.9em; max-width: 70em; }}\n\
             .swatch {{ padding: 0 0.4em; border: 1px solid #999; }}\n\
             figure {{ margin: 1em 0; }} figure img {{ max-width: 100%; border: 1px solid #ddd; }}\n\
             figcaption {{ color: #444; font-size: 0.9em; }}\n\
             nav li {{ display: inline; margin-right: 1em; }}\n\
             </style>\n</head>\n<body>\n<h1>{}</h1>\n<p><code>{}</code>: {}</p>\n<nav><ul>",
            esc(&title),
            esc(&title),
            esc(&self.file.display().to_string()),
            esc(&self.overview)
        );
        if !figures.is_empty() {
            out.push_str("<li><a href=\"#figures\">Figures</a></li>");
        }
        for t in tables {
            let _ = write!(
                out,
                "<li><a href=\"#{}\">{}</a></li>",
                esc(&t.name),
                esc(&t.title)
            );
        }
        out.push_str("</ul></nav>\n");
        if !figures.is_empty() {
            out.push_str("<section id=\"figures\"><h2>Figures</h2>\n");
            for f in figures {
                let data = base64::engine::general_purpose::STANDARD.encode(&f.png);
                let _ = writeln!(
                    out,
                    "<figure><img src=\"data:image/png;base64,{data}\" alt=\"{name}\">\
                     <figcaption><code>{name}</code>: {}</figcaption></figure>",
                    esc(caption(&f.name)),
                    name = esc(&f.name)
                );
            }
            out.push_str("</section>\n");
        }
        for t in tables {
            html_table(&mut out, t);
        }
        out.push_str("</body>\n</html>\n");
        out
    }

    /// The names of the tables this report has.
    pub fn table_names(&self) -> Vec<&str> {
        self.tables.iter().map(|t| t.name.as_str()).collect()
    }

    /// The report as text: every table, or only the table `only` (an error naming the file and
    /// the tables it has when there is no such table).
    pub fn render(&self, format: Format, only: Option<&str>) -> Result<String, InputError> {
        let tables: Vec<&Table> = match only {
            None => self.tables.iter().collect(),
            Some(name) => vec![self.tables.iter().find(|t| t.name == name).ok_or_else(|| {
                InputError::new(
                    &self.file,
                    format!(
                        "no table `{name}` in this file (it has: {})",
                        self.table_names().join(", ")
                    ),
                )
            })?],
        };
        let mut out = String::new();
        match format {
            Format::Markdown => {
                if only.is_none() {
                    let _ = writeln!(
                        out,
                        "# Study {}\n\n`{}`: {}\n",
                        self.study,
                        self.file.display(),
                        self.overview
                    );
                }
                for (i, t) in tables.iter().enumerate() {
                    if i > 0 {
                        out.push('\n');
                    }
                    markdown(&mut out, t);
                }
            }
            Format::Csv => {
                for (i, t) in tables.iter().enumerate() {
                    if i > 0 {
                        out.push('\n');
                    }
                    if only.is_none() {
                        let _ = writeln!(out, "# {}\n# {}", t.title, t.legend);
                    }
                    csv(&mut out, t);
                }
            }
            Format::Html => out = self.html(&tables, &[]),
            Format::Json => {
                #[derive(Serialize)]
                struct Doc<'a> {
                    study: &'a str,
                    tables: Vec<&'a Table>,
                }
                let doc = Doc {
                    study: &self.study,
                    tables,
                };
                out = serde_json::to_string(&doc)
                    .map_err(|e| InputError::new(&self.file, e.to_string()))?;
                out.push('\n');
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_written_one_way() {
        // Parameters: shortest form, scientific below 1e-3 and from 1e6; measured values to
        // their significant digits by the same rule.
        assert_eq!(number_text(1e-4), "1e-4");
        assert_eq!(number_text(16.4), "16.4");
        assert_eq!(number_text(10.0), "10");
        assert_eq!(number_text(2.5e7), "2.5e7");
        assert_eq!(significant(1.234e-4, 3), "1.23e-4");
        assert_eq!(significant(16.2345, 4), "16.23");
        assert_eq!(significant(f64::NAN, 4), "–");
    }

    #[test]
    fn speeds_are_rounded_to_the_sweeps_step() {
        // 0.2 Hz steps (16.2 − 16.0 is 0.19999… in floating point): one decimal; a 4 Hz step
        // (a 4-speed sweep 10…22 Hz): none; 0.05 Hz: two.
        assert_eq!(to_step(16.17835, 16.2 - 16.0), "16.2");
        assert_eq!(to_step(15.59, 4.0), "16");
        assert_eq!(to_step(16.17835, 0.05), "16.18");
        assert_eq!(to_step(16.17835, f64::NAN), "16.18");
    }

    #[test]
    fn error_classes_by_decade() {
        // The case: an ok job 1.2e4 µm off is in the worst class, not "ok".
        assert_eq!(error_class("ok", 1.2e4), "≥ 100 µm");
        assert_eq!(error_class("ok", 0.5), "< 1 µm");
        assert_eq!(error_class("ok", 5.0), "1–10 µm");
        assert_eq!(error_class("ok", 50.0), "10–100 µm");
        assert_eq!(error_class("ok", f64::NAN), "no reference");
        assert_eq!(error_class("diverged", 0.1), "diverged");
        assert_eq!(esc_code("a `b` <c>"), "a <code>b</code> &lt;c&gt;");
    }
}
