//! The `nips` table of `rotorsweep report`: per job and nip of a machine's run, the static nip
//! load, its dynamic amplitude at the study's orders and the nip width, for the whole nip and per
//! contact segment (the cross-machine nip profile).
//!
//! In: `/jobs/<id>/nips/<nip>/force` [segments × time] [N] with its axes `z_mm` (segment
//! centres [mm]) and `time` [s], `width` [segments × time] [mm] where the law has a band (hertz,
//! cover), the job's `speed_hz` attribute (the first roll's speed [Hz]) and the study's
//! `[analysis] orders` (default 1, 2, 3, 4; orders of the first roll's speed).
//!
//! Out: long form, per job and nip a `total` row (the force summed over the segments) and then
//! one row per segment (`segment` 1…n): `z_mm` [mm] (empty for the total), `length_mm` (the
//! segment's length, the centres' spacing; for the total the contact length n × that) [mm],
//! `static_n` [N], `line_load_kn_per_m` (static_n / length [kN/m]), `width_mm` (the band width's
//! time mean [mm]; for the total the widest segment's; empty for a linear law), and
//! `amplitude_<k>x_n` [N] per order k: the amplitude of the line at k × speed (the first roll's);
//! then per roll of the nip (side `a` = `roll_a`, `b` = `roll_b`) `roll_<side>` (its name),
//! `speed_<side>_hz` (its spin speed over the record [Hz], a magnitude) and
//! `amplitude_<side>_<k>x_n` [N]: the line at k × that roll's speed, so a roll's own runout
//! orders show at its own speed (from the job attributes `nip_roll_<side>:<nip>` and
//! `nip_speed_<side>_hz:<nip>`, `results::analyse::job_attrs`; empty in files written before
//! them). Markdown and HTML show the totals only, one row per job and nip. None when no job has
//! a nip.
//!
//! Method: the static load and the lines of all these orders are fitted together by
//! Hann-weighted least squares (`signal::spectrum::weighted_fit`, as the runout's lines), each
//! frequency once (an order of one roll at the frequency of another's is the same line, in
//! both columns), so lines closer than the record's resolution (the covered roll's orders next
//! to the first roll's) are told apart, and the static part is exact over a few periods. The amplitudes of the total
//! are those of the summed force (segments in phase add, out of phase cancel), not the sum of
//! the segments' amplitudes. A job whose speed changes while it records gets its lines at its
//! `speed_hz` attribute all the same (the table is for steady runs; ramps have `orders`).

use hdf5::{File, Group};

use crate::report::jobs::{job_columns, Job};
use crate::report::table::{md_cell, Cell, Grid, Table};
use crate::results::analyse::{NIP_ROLL, NIP_SPEED};
use crate::signal::spectrum::{hanning, weighted_fit};
use crate::store;
use crate::text::number_text;

/// The sides of a nip, as in the keys `roll_a`, `roll_b`.
const SIDES: [&str; 2] = ["a", "b"];

/// One nip of one job: the static load, the order amplitudes and the band width of each
/// segment and of the total.
struct NipRows {
    nip: String,
    /// Per side (roll_a, roll_b): its name ("" unknown) and speed [Hz] (NaN unknown).
    rolls: [(String, f64); 2],
    z_mm: Vec<f64>,
    length_mm: f64,
    /// Per segment, then the total last: (static [N], amplitudes [N], width [mm]); the
    /// amplitudes at the orders of the first roll, then of roll_a, then of roll_b.
    segments: Vec<(f64, Vec<f64>, f64)>,
    total: (f64, Vec<f64>, f64),
}

/// The lines to fit for the frequencies `freqs` [Hz]: each finite frequency once, and per entry
/// of `freqs` the index of its line (None for a frequency that is not finite). Frequencies equal
/// to a relative 1e-9 are one line.
fn distinct(freqs: &[f64]) -> (Vec<f64>, Vec<Option<usize>>) {
    let mut lines: Vec<f64> = Vec::new();
    let index = freqs
        .iter()
        .map(|&f| {
            if !f.is_finite() {
                return None;
            }
            let at = lines.iter().position(|&g| (g - f).abs() <= 1e-9 * f.abs());
            Some(at.unwrap_or_else(|| {
                lines.push(f);
                lines.len() - 1
            }))
        })
        .collect();
    (lines, index)
}

/// The static load and the amplitudes at `freqs` [Hz] of one force record (NaN at a frequency
/// that is not finite).
fn fit(x: &[f64], t: &[f64], w: &[f64], freqs: &[f64]) -> (f64, Vec<f64>) {
    let (lines, index) = distinct(freqs);
    let (mean, fitted) = weighted_fit(x, t, w, &lines);
    let amps = index
        .iter()
        .map(|i| i.map_or(f64::NAN, |i| fitted[i].norm()))
        .collect();
    (mean, amps)
}

/// The names and speeds [Hz] of the nip `nip`'s rolls from the job group `g`'s attributes
/// (module doc); "" and NaN where the file has none.
fn nip_rolls(g: &Group, nip: &str) -> [(String, f64); 2] {
    SIDES.map(|side| {
        let name = store::read_str(g, &format!("{NIP_ROLL}{side}:{nip}")).unwrap_or_default();
        let speed = store::read_num(g, &format!("{NIP_SPEED}{side}_hz:{nip}")).unwrap_or(f64::NAN);
        (name, speed)
    })
}

/// A 2-D dataset as rows.
fn rows_of(g: &Group, name: &str) -> hdf5::Result<Option<Vec<Vec<f64>>>> {
    let Ok(ds) = g.dataset(name) else {
        return Ok(None);
    };
    let shape = ds.shape();
    let data: Vec<f64> = ds.read_raw()?;
    let cols = shape.get(1).copied().unwrap_or(0);
    if shape.len() != 2 || cols == 0 {
        return Ok(Some(Vec::new()));
    }
    Ok(Some(data.chunks(cols).map(<[f64]>::to_vec).collect()))
}

/// The rows of the nip `nip` of the job group `job` (module doc); `None` when it holds no force
/// record.
fn nip_rows(job: &Group, nip: &str, orders: &[f64]) -> hdf5::Result<Option<NipRows>> {
    let g = job.group(&format!("nips/{nip}"))?;
    let speed_hz = store::read_num(job, "speed_hz").unwrap_or(f64::NAN);
    let rolls = nip_rolls(job, nip);
    let Some(force) = rows_of(&g, "force")? else {
        return Ok(None);
    };
    let t: Vec<f64> = g.dataset("time")?.read_raw()?;
    let z_mm: Vec<f64> = g.dataset("z_mm")?.read_raw()?;
    if force.is_empty() || force[0].len() != t.len() {
        return Ok(None);
    }
    let width = rows_of(&g, "width")?;
    let w = hanning(t.len());
    let freqs: Vec<f64> = [speed_hz, rolls[0].1, rolls[1].1]
        .iter()
        .flat_map(|f| orders.iter().map(move |k| k * f))
        .collect();
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let mut segments = Vec::with_capacity(force.len());
    for (s, x) in force.iter().enumerate() {
        let (stat, amps) = fit(x, &t, &w, &freqs);
        let band = width
            .as_ref()
            .and_then(|wd| wd.get(s))
            .map_or(f64::NAN, |b| mean(b));
        segments.push((stat, amps, band));
    }
    let sum: Vec<f64> = (0..t.len())
        .map(|i| force.iter().map(|x| x[i]).sum())
        .collect();
    let (stat, amps) = fit(&sum, &t, &w, &freqs);
    let widest = segments
        .iter()
        .map(|s| s.2)
        .filter(|b| b.is_finite())
        .fold(f64::NAN, f64::max);
    let length_mm = if z_mm.len() >= 2 {
        (z_mm[z_mm.len() - 1] - z_mm[0]) / (z_mm.len() - 1) as f64
    } else {
        f64::NAN
    };
    Ok(Some(NipRows {
        nip: nip.to_string(),
        rolls,
        z_mm,
        length_mm,
        segments,
        total: (stat, amps, widest),
    }))
}

/// Per nip of the job group `g` (`/jobs/<id>`): its name, the total force's static load [N]
/// and its amplitude [N] at each of `orders` of the job's speed (the first roll's), as in the
/// table's `total` row; empty without nips. The statistics' nip outputs (`super::outputs`).
pub(crate) fn nip_totals(g: &Group, orders: &[f64]) -> hdf5::Result<Vec<(String, f64, Vec<f64>)>> {
    let Ok(nips) = g.group("nips") else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for name in nips.member_names()? {
        if let Some(n) = nip_rows(g, &name, orders)? {
            let mut amps = n.total.1;
            amps.truncate(orders.len());
            out.push((n.nip, n.total.0, amps));
        }
    }
    Ok(out)
}

/// The `nips` table of the jobs (module doc); none when no job has a nip.
pub(crate) fn nips_table(
    f: &File,
    jobs: &[Job],
    varying: &[String],
    orders: &[f64],
) -> hdf5::Result<Option<Table>> {
    let (id_columns, id_cells) = job_columns(jobs, varying, "");
    let mut rows = Vec::new();
    let mut md = Vec::new();
    for (job, ids) in jobs.iter().zip(&id_cells) {
        let Ok(g) = f.group(&format!("jobs/{}", job.id)) else {
            continue;
        };
        let Ok(nips) = g.group("nips") else {
            continue;
        };
        for name in nips.member_names()? {
            let Some(n) = nip_rows(&g, &name, orders)? else {
                continue;
            };
            let count = n.segments.len() as f64;
            let row =
                |segment: Cell, z: f64, length: f64, (stat, amps, band): &(f64, Vec<f64>, f64)| {
                    let mut r = ids.clone();
                    r.extend([
                        Cell::Text(n.nip.clone()),
                        segment,
                        Cell::Number(z),
                        Cell::Number(length),
                        Cell::Number(*stat),
                        Cell::Number(stat / length),
                        Cell::Number(*band),
                    ]);
                    let (first, per_roll) = amps.split_at(orders.len());
                    r.extend(first.iter().map(|a| Cell::Number(*a)));
                    for ((name, speed), amps) in n.rolls.iter().zip(per_roll.chunks(orders.len())) {
                        r.push(Cell::Text(name.clone()));
                        r.push(Cell::Number(*speed));
                        r.extend(amps.iter().map(|a| Cell::Number(*a)));
                    }
                    r
                };
            let total = row(
                Cell::Text("total".into()),
                f64::NAN,
                n.length_mm * count,
                &n.total,
            );
            let mut line = vec![job.setting.clone(), n.nip.clone()];
            line.extend(total[ids.len() + 4..].iter().map(md_cell));
            md.push(line);
            rows.push(total);
            for (s, seg) in n.segments.iter().enumerate() {
                rows.push(row(Cell::Count(s as u64 + 1), n.z_mm[s], n.length_mm, seg));
            }
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let measured = ["static_n", "line_load_kn_per_m", "width_mm"];
    let mut amp_columns: Vec<String> = orders
        .iter()
        .map(|k| format!("amplitude_{}x_n", number_text(*k)))
        .collect();
    for side in SIDES {
        amp_columns.push(format!("roll_{side}"));
        amp_columns.push(format!("speed_{side}_hz"));
        amp_columns.extend(
            orders
                .iter()
                .map(|k| format!("amplitude_{side}_{}x_n", number_text(*k))),
        );
    }
    let mut columns = id_columns;
    columns.extend(["nip", "segment", "z_mm", "length_mm"].map(String::from));
    columns.extend(measured.map(String::from));
    columns.extend(amp_columns.iter().cloned());
    let mut md_columns: Vec<String> = ["job", "nip"].map(String::from).to_vec();
    md_columns.extend(measured.map(String::from));
    md_columns.extend(amp_columns);
    Ok(Some(Table {
        name: "nips".into(),
        title: "Nip loads".into(),
        legend: format!(
            "Per job and nip, the whole nip (segment `total`: the force summed over the \
             segments) and then each contact segment at z_mm (its centre) of length_mm [mm]: \
             static_n, the static load [N], fitted with the lines; line_load_kn_per_m, it per \
             length [kN/m]; width_mm, the band width's time mean [mm] (total: the widest \
             segment's; none for a linear law); amplitude_<k>x_n, the amplitude [N] of the \
             line at order k of the first roll's speed (orders {}), of the summed force for \
             the total; roll_a and roll_b, the nip's rolls, with speed_<side>_hz, each one's \
             speed [Hz], and amplitude_<side>_<k>x_n, the line [N] at order k of that roll's \
             speed (side a or b). Markdown shows the totals.",
            orders
                .iter()
                .map(|k| number_text(*k))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        columns,
        rows,
        markdown: Some(Grid::plain(md_columns, md)),
    }))
}
