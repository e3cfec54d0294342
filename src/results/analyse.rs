//! Post-processing of an assembled results file (physics.md §8), after `run` assembles it, after
//! `merge`, and after `simulate -o`: it reads only the file, so shards merged later get the same
//! analysis.
//!
//! In: `/jobs/<id>` groups (status, `speed_hz`, `time` [s], `runout/<sensor>/<dir>` [µm], the
//! varying keys and `label:<key>` as attributes; [`job_attrs`] gives the attributes a job's
//! scene decides), the file's `varying_keys`, and its `study_text` (the `[analysis]` table, the
//! labelled axes; a file without one, as `simulate -o` writes, gets the default orders 1–4).
//! Out, in the same file (every job that ended ok at a constant speed):
//! - `/jobs/<id>/runout_mean/<sensor>/<dir>` [µm, scalar]: the record's mean (static sag and
//!   offset), removed before the spectrum;
//! - `/jobs/<id>/spectrum/freq_hz` [Hz], `/jobs/<id>/spectrum/<sensor>/<dir>` [µm]: the
//!   amplitude-correct Hanning spectrum of the record minus its mean, up to `max_freq_hz`
//!   (default [`ORDER_MARGIN`](super::request::ORDER_MARGIN) × the highest order × the speed);
//! - `/analysis/lines`: table job_id, channel, order, speed_hz, freq_hz, amplitude_um, phase_deg
//!   (the line at order × speed, all orders fitted together, `signal::lines`; phase relative
//!   to roll angle 0). A job is analysed when it ended ok and its speed was constant while it
//!   recorded (a ramp or speed step may end before `settle_s`): attributes `speed_hz` and
//!   `roll_angle_offset_rad` (θ = Ω t + δ) say so;
//! - `/analysis/sweeps/<n>` for each set of ≥ 3 jobs that differ only in `speed.hz`: `speed_hz`,
//!   `job_ids`, `orders`, `lines/<sensor>/<dir>` [speeds × orders, µm], `mean/<sensor>/<dir>`
//!   [speeds, µm] (the static part over speed) and, when the records match, `freq_hz` and
//!   `map/<sensor>/<dir>` [speeds × frequencies, µm] (spectra of the fluctuating part, up to the
//!   study's cap: `max_freq_hz`, default [`ORDER_MARGIN`](super::request::ORDER_MARGIN) × the highest order × the top speed);
//!   attribute `fixed` (the other keys' values); `skipped_speed_hz` and `skipped_job_ids` when
//!   some of its jobs could not be analysed (failed, or no runout); the axes `freq_hz`,
//!   `speed_hz` and `orders` are dimension scales (`store::scales`);
//! - `/analysis/resonances`: table sweep, fixed, channel, order, rank, speed_hz, amplitude_um,
//!   step_hz, note (the three highest interior peaks of each order's amplitude over speed, the
//!   sweep's spacing there and `coarse` / `edge` flags, `signal::resolution`);
//! - `/analysis/trial_mass`, with an `[analysis] baseline`: table job_id, baseline_id, label,
//!   channel, speed_hz, amplitude_um, baseline_amplitude_um, amplitude_change_um,
//!   vector_change_um, vector_phase_deg (1× change against the baseline job);
//! - `/analysis/orders`, `/analysis/order_resonances` and each ramp's `/jobs/<id>/waterfall`:
//!   order tracking of every job with a roll angle, ramps included (`results::orders`).

use std::collections::BTreeMap;

use super::job_analysis::{
    analysable_speed, analyse_job, default_cap, Entry, JobData, Prepared, Skipped,
};
use super::request::{analysis_of_text, AnalysisSpec, LabelledAxis, StudyAnalysis};
use crate::scene::{RollerPhase, Scene, SupportModel};
use crate::signal;
use crate::store::{self, Column, Param};

/// The key a spectral map sweeps.
pub const SWEEP_KEY: &str = "speed.hz";

/// Peaks kept per order and channel in the resonance table.
const RANKS: usize = 3;

/// Prefix of the job attributes that give each roller's line ratio (`roller_ratio:<node>/<roller>`).
pub const ROLLER_RATIO: &str = "roller_ratio:";

/// Prefix of the job attributes that name a nip's rolls (`nip_roll_a:<nip>`, `nip_roll_b:<nip>`).
pub const NIP_ROLL: &str = "nip_roll_";

/// Prefix of the job attributes that give a nip's rolls' speeds [Hz] (`nip_speed_a_hz:<nip>`).
pub const NIP_SPEED: &str = "nip_speed_";

/// The spin speed Ω [rad/s] over a scene's record and the roll angle's offset δ [rad] in
/// θ = Ω t + δ; `None` when the speed changes while recording.
pub fn record_spin(scene: &Scene) -> Option<(f64, f64)> {
    let sim = &scene.simulation;
    scene.speed.constant_over(sim.settle, sim.t_end)
}

/// The spin speed [Hz] over a scene's record and the roll angle's offset δ [rad] in
/// θ = Ω t + δ, both NaN when the speed changes while recording.
pub fn record_speed(scene: &Scene) -> (f64, f64) {
    record_spin(scene).map_or((f64::NAN, f64::NAN), |(omega, d)| {
        (omega / std::f64::consts::TAU, d)
    })
}

/// The attributes of a job that its scene decides and the analysis reads, for `run` and
/// `simulate -o` alike:
/// - `speed_hz` and `roll_angle_offset_rad`: the spin speed [Hz] over the record and δ in
///   θ = Ω t + δ [rad] (NaN when the speed changes while recording);
/// - `roller_ratio:<support node>/<roller>`: the roller's roundness lines lie at k × this ×
///   the spin frequency: the journal/roller diameter ratio when the roundness follows the
///   roller's own angle (`roller_phase = "roller-angle"`), 1 when it follows the roll angle;
/// - on a machine, per nip: `nip_roll_a:<nip>` and `nip_roll_b:<nip>` (the two rolls' names)
///   and `nip_speed_a_hz:<nip>`, `nip_speed_b_hz:<nip>` (their spin speeds over the record
///   [Hz], magnitudes: a roll turning the other way counts as positive; NaN when its speed
///   changes while recording), the orders of each roll in the `nips` table.
pub fn job_attrs(scene: &Scene) -> Vec<(String, Param)> {
    let (speed, offset) = record_speed(scene);
    let mut out = vec![
        ("speed_hz".to_string(), Param::Number(speed)),
        ("roll_angle_offset_rad".to_string(), Param::Number(offset)),
    ];
    for s in &scene.supports {
        if let SupportModel::Rollers(rs) = &s.model {
            for r in &rs.rollers {
                let ratio = match rs.roller_phase {
                    RollerPhase::RollAngle => 1.0,
                    RollerPhase::RollerAngle => rs.journal_diameter / r.diameter,
                };
                out.push((
                    format!("{ROLLER_RATIO}{}/{}", s.node, r.name),
                    Param::Number(ratio),
                ));
            }
        }
    }
    if let Some(machine) = &scene.machine {
        for nip in &machine.nips {
            let rolls = [("a", nip.rolls.0), ("b", nip.rolls.1)];
            for (side, i) in rolls {
                let roll = &machine.rolls[i];
                let name = &nip.name;
                out.push((
                    format!("{NIP_ROLL}{side}:{name}"),
                    Param::Text(roll.name.clone()),
                ));
                // The machine's record window is the first roll's (this scene's).
                let sim = &scene.simulation;
                let hz = (roll.scene.speed.constant_over(sim.settle, sim.t_end))
                    .map_or(f64::NAN, |(omega, _)| omega.abs() / std::f64::consts::TAU);
                out.push((format!("{NIP_SPEED}{side}_hz:{name}"), Param::Number(hz)));
            }
        }
    }
    out
}

/// The values of the varying keys other than the sweep key and its `partners` (the other keys
/// of its zipped axis), labels where the axis has them: what the jobs of one speed sweep share.
fn fixed_text(
    values: &BTreeMap<String, String>,
    labels: &BTreeMap<String, String>,
    partners: &[String],
) -> String {
    let fixed: Vec<String> = values
        .iter()
        .filter(|(k, _)| k.as_str() != SWEEP_KEY && !partners.contains(k))
        .map(|(k, v)| match labels.get(k) {
            Some(l) => format!("{k}={l}"),
            None => format!("{k}={v}"),
        })
        .collect();
    fixed.join("; ")
}

/// Every job's [`Entry`], in the file's order: those `prepared` as the run saved them (when
/// they were prepared for this study and its cap) taken as they are, the others analysed now
/// (`job_analysis`); the analysable ones' spectra kept up to the study's cap (module doc).
fn read_jobs(
    f: &hdf5::File,
    (varying, axes, spec): (&[String], &[LabelledAxis], &AnalysisSpec),
    (keep_cap, prepared): (f64, BTreeMap<String, (Option<f64>, Entry)>),
) -> hdf5::Result<(Vec<JobData>, Vec<Skipped>)> {
    let mut prepared = prepared;
    let jobs = f.group("jobs")?;
    let ids = jobs.member_names()?;
    let top_speed = ids
        .iter()
        .filter_map(|id| match prepared.get(id) {
            Some((speed, _)) => *speed,
            None => analysable_speed(&jobs.group(id).ok()?),
        })
        .fold(0.0, f64::max);
    let study_cap = spec
        .max_freq_hz
        .unwrap_or_else(|| default_cap(&spec.orders, top_speed));
    if keep_cap < study_cap {
        prepared.clear();
    }
    let mut out = Vec::new();
    let mut skipped = Vec::new();
    for id in ids {
        let entry = match prepared.remove(&id) {
            Some((_, e)) => e,
            None => analyse_job(&jobs.group(&id)?, &id, (varying, axes, spec), study_cap)?.1,
        };
        match entry {
            Entry::Data(mut d) => {
                d.keep_below(study_cap);
                out.push(d);
            }
            Entry::Skipped(s) => skipped.push(s),
        }
    }
    Ok((out, skipped))
}

/// Rows of the lines table.
fn lines_table(g: &hdf5::Group, jobs: &[JobData], orders: &[f64]) -> hdf5::Result<()> {
    let mut id = Vec::new();
    let mut channel = Vec::new();
    let (mut order, mut speed, mut freq, mut amp, mut phase) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for j in jobs {
        for (c, name) in j.names.iter().enumerate() {
            for (k, o) in orders.iter().enumerate() {
                let z = j.lines[c][k];
                id.push(j.id.clone());
                channel.push(name.clone());
                order.push(*o);
                speed.push(j.speed_hz);
                freq.push(o * j.speed_hz);
                amp.push(z.norm());
                phase.push(z.arg().to_degrees());
            }
        }
    }
    store::compound_table(
        g,
        "lines",
        &[
            Column::text("job_id", id),
            Column::text("channel", channel),
            Column::number("order", "1", order),
            Column::number("speed_hz", "Hz", speed),
            Column::number("freq_hz", "Hz", freq),
            Column::number("amplitude_um", "um", amp),
            Column::number("phase_deg", "deg", phase),
        ],
    )
}

/// Jobs that differ only in the sweep key (and the keys zipped with it, `partners`), each set
/// ordered by speed (≥ 3 distinct speeds).
fn sweeps<'a>(
    jobs: &'a [JobData],
    varying: &[String],
    partners: &[String],
) -> Vec<(String, Vec<&'a JobData>)> {
    if !varying.iter().any(|k| k == SWEEP_KEY) {
        return Vec::new();
    }
    let mut sets: BTreeMap<String, Vec<&JobData>> = BTreeMap::new();
    for j in jobs {
        sets.entry(fixed_text(&j.values, &j.labels, partners))
            .or_default()
            .push(j);
    }
    sets.into_iter()
        .filter_map(|(fixed, mut v)| {
            v.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz).then(a.id.cmp(&b.id)));
            v.dedup_by(|a, b| a.speed_hz == b.speed_hz);
            (v.len() >= 3).then_some((fixed, v))
        })
        .collect()
}

struct ResonanceRows {
    sweep: Vec<f64>,
    fixed: Vec<String>,
    channel: Vec<String>,
    order: Vec<f64>,
    rank: Vec<f64>,
    speed: Vec<f64>,
    amp: Vec<f64>,
    step: Vec<f64>,
    note: Vec<String>,
}

fn write_sweep(
    g: &hdf5::Group,
    (n, fixed): (usize, &str),
    set: &[&JobData],
    (skipped, partners): (&[Skipped], &[String]),
    spec: &AnalysisSpec,
    res: &mut ResonanceRows,
) -> hdf5::Result<()> {
    let sg = g.create_group(&n.to_string())?;
    store::attr_str(&sg, "fixed", fixed)?;
    // The sweep's jobs that the analysis left out: their speeds are gaps in the curves.
    let mut gaps: Vec<&Skipped> = skipped
        .iter()
        .filter(|s| fixed_text(&s.values, &s.labels, partners) == fixed)
        .collect();
    gaps.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz).then(a.id.cmp(&b.id)));
    if !gaps.is_empty() {
        let speeds: Vec<f64> = gaps.iter().map(|s| s.speed_hz).collect();
        store::dataset(&sg, "skipped_speed_hz", &speeds, "Hz")?;
        let ids: Vec<String> = gaps.iter().map(|s| s.id.clone()).collect();
        store::string_dataset(&sg, "skipped_job_ids", &ids)?;
    }
    let speeds: Vec<f64> = set.iter().map(|j| j.speed_hz).collect();
    store::dataset(&sg, "speed_hz", &speeds, "Hz")?;
    store::string_dataset(
        &sg,
        "job_ids",
        &set.iter().map(|j| j.id.clone()).collect::<Vec<_>>(),
    )?;
    store::dataset(&sg, "orders", &spec.orders, "1")?;
    let names = &set[0].names;
    // Spectral maps only when every record has the same length and rate.
    let same = set.iter().all(|j| {
        j.samples == set[0].samples
            && (j.rate_hz - set[0].rate_hz).abs() <= 1e-9 * set[0].rate_hz
            && j.names.len() == names.len()
    });
    let max_speed = speeds.iter().copied().fold(0.0, f64::max);
    let cap = spec
        .max_freq_hz
        .unwrap_or_else(|| default_cap(&spec.orders, max_speed));
    for (c, name) in names.iter().enumerate() {
        if !set.iter().all(|j| j.names.get(c) == Some(name)) {
            continue;
        }
        let no = spec.orders.len();
        let mut lines = Vec::with_capacity(set.len() * no);
        for j in set {
            lines.extend(j.lines[c].iter().map(|z| z.norm()));
        }
        store::dataset_2d(&sg, &format!("lines/{name}"), (set.len(), no), &lines, "um")?;
        let means: Vec<f64> = set.iter().map(|j| j.means[c]).collect();
        store::dataset(&sg, &format!("mean/{name}"), &means, "um")?;
        for (k, o) in spec.orders.iter().enumerate() {
            let amp: Vec<f64> = (0..set.len()).map(|s| lines[s * no + k]).collect();
            for (r, p) in signal::peaks(&speeds, &amp)
                .into_iter()
                .take(RANKS)
                .enumerate()
            {
                let fit = signal::resolution(&speeds, &amp, &p);
                res.step.push(fit.step_hz);
                res.note.push(fit.note());
                res.sweep.push(n as f64);
                res.fixed.push(fixed.to_string());
                res.channel.push(name.to_string());
                res.order.push(*o);
                res.rank.push((r + 1) as f64);
                res.speed.push(p.speed_hz);
                res.amp.push(p.amplitude);
            }
        }
        if same {
            let freq = &set[0].freq_hz;
            let bins = freq.iter().take_while(|f| **f <= cap + 1e-9).count();
            if c == 0 {
                store::dataset(&sg, "freq_hz", &freq[..bins], "Hz")?;
            }
            let mut map = Vec::with_capacity(set.len() * bins);
            for j in set {
                map.extend_from_slice(&j.spectra[c][..bins]);
            }
            store::dataset_2d(&sg, &format!("map/{name}"), (set.len(), bins), &map, "um")?;
        }
    }
    // The axes of the lines (speed × order) and maps (speed × frequency), for netCDF readers.
    store::scales::attach_axis(&sg, "speed_hz", &["lines", "map", "job_ids"], 0)?;
    store::scales::attach_axis(&sg, "orders", &["lines"], 1)?;
    if sg.link_exists("freq_hz") {
        store::scales::attach_axis(&sg, "freq_hz", &["map"], 1)?;
    }
    Ok(())
}

/// The trial-mass table: each job on the baseline's axis against the job with the baseline
/// label and the same other keys.
fn trial_mass_table(
    g: &hdf5::Group,
    jobs: &[JobData],
    baseline: &str,
    axes: &[LabelledAxis],
) -> hdf5::Result<()> {
    let Some(axis) = axes.iter().find(|a| a.labels.iter().any(|l| l == baseline)) else {
        return Ok(());
    };
    let key = &axis.keys[0];
    let others = |j: &JobData| -> Vec<(String, String)> {
        j.values
            .iter()
            .filter(|(k, _)| !axis.keys.contains(k))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect()
    };
    // The baseline jobs by their other keys (the first in file order where several match).
    let mut baselines: BTreeMap<Vec<(String, String)>, &JobData> = BTreeMap::new();
    for b in jobs {
        if b.labels.get(key).map(String::as_str) == Some(baseline) {
            baselines.entry(others(b)).or_insert(b);
        }
    }
    let mut cols: [Vec<f64>; 6] = Default::default();
    let (mut id, mut base_id, mut label, mut channel) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for j in jobs {
        let Some(l) = j.labels.get(key).filter(|l| l.as_str() != baseline) else {
            continue;
        };
        let Some(b) = baselines.get(&others(j)) else {
            continue;
        };
        for (c, name) in j.names.iter().enumerate() {
            let Some(bc) = b.names.iter().position(|n| n == name) else {
                continue;
            };
            let r = signal::trial_response(j.one_x[c], b.one_x[bc]);
            id.push(j.id.clone());
            base_id.push(b.id.clone());
            label.push(l.clone());
            channel.push(name.clone());
            let row = [
                j.speed_hz,
                j.one_x[c].norm(),
                b.one_x[bc].norm(),
                r.amplitude_change,
                r.vector_change,
                r.vector_phase.to_degrees(),
            ];
            for (col, v) in cols.iter_mut().zip(row) {
                col.push(v);
            }
        }
    }
    let [speed, amp, base_amp, change, vector, phase] = cols;
    store::compound_table(
        g,
        "trial_mass",
        &[
            Column::text("job_id", id),
            Column::text("baseline_id", base_id),
            Column::text("label", label),
            Column::text("channel", channel),
            Column::number("speed_hz", "Hz", speed),
            Column::number("amplitude_um", "um", amp),
            Column::number("baseline_amplitude_um", "um", base_amp),
            Column::number("amplitude_change_um", "um", change),
            Column::number("vector_change_um", "um", vector),
            Column::number("vector_phase_deg", "deg", phase),
        ],
    )
}

/// Analyses an assembled file in place (module doc); replaces an earlier `/analysis`.
pub fn analyse(f: &hdf5::File) -> hdf5::Result<()> {
    analyse_prepared(f, None)
}

/// [`analyse`], given the jobs a run analysed as it saved them (used when they were prepared
/// for this file's study text and varying keys with a cap no lower than the study's).
pub fn analyse_prepared(f: &hdf5::File, prepared: Option<Prepared>) -> hdf5::Result<()> {
    let text = store::read_str(f, "study_text").unwrap_or_default();
    let StudyAnalysis {
        spec,
        labelled: axes,
        axis_keys,
    } = analysis_of_text(&text).unwrap_or_default();
    let varying = store::varying_keys(f);
    // Keys zipped with the speed (e.g. a record length scaled with it) vary along a sweep too,
    // unless a speed repeats on that axis (then they tell its rows apart).
    let partners: Vec<String> = axis_keys
        .into_iter()
        .find(|keys| keys.len() > 1 && keys.iter().any(|k| k == SWEEP_KEY))
        .map(|keys| keys.into_iter().filter(|k| k != SWEEP_KEY).collect())
        .unwrap_or_default();
    let (prepared, tracked) = prepared
        .filter(|p| p.text == text && p.varying == varying)
        .map(|p| ((p.keep_cap(), p.entries), p.tracked))
        .unwrap_or_default();
    let (jobs, skipped) = read_jobs(f, (&varying, &axes, &spec), prepared)?;
    let repeats = {
        let mut seen = std::collections::BTreeSet::new();
        jobs.iter().any(|j| {
            let key = (
                fixed_text(&j.values, &j.labels, &partners),
                j.speed_hz.to_bits(),
            );
            !seen.insert(key)
        })
    };
    let partners = if repeats { Vec::new() } else { partners };
    if f.link_exists("analysis") {
        f.unlink("analysis")?;
    }
    let g = f.create_group("analysis")?;
    store::attr_str(&g, "sweep_key", SWEEP_KEY)?;
    lines_table(&g, &jobs, &spec.orders)?;
    let sg = g.create_group("sweeps")?;
    let mut res = ResonanceRows {
        sweep: Vec::new(),
        fixed: Vec::new(),
        channel: Vec::new(),
        order: Vec::new(),
        rank: Vec::new(),
        speed: Vec::new(),
        amp: Vec::new(),
        step: Vec::new(),
        note: Vec::new(),
    };
    for (n, (fixed, set)) in sweeps(&jobs, &varying, &partners).iter().enumerate() {
        write_sweep(&sg, (n, fixed), set, (&skipped, &partners), &spec, &mut res)?;
    }
    store::compound_table(
        &g,
        "resonances",
        &[
            Column::count("sweep", res.sweep.iter().map(|&x| x as u64).collect()),
            Column::text("fixed", res.fixed),
            Column::text("channel", res.channel),
            Column::number("order", "1", res.order),
            Column::count("rank", res.rank.iter().map(|&x| x as u64).collect()),
            Column::number("speed_hz", "Hz", res.speed),
            Column::number("amplitude_um", "um", res.amp),
            Column::number("step_hz", "Hz", res.step),
            Column::text("note", res.note),
        ],
    )?;
    if let Some(b) = &spec.baseline {
        trial_mass_table(&g, &jobs, b, &axes)?;
    }
    super::orders::write(f, &g, &spec, tracked)
}
