//! The `resonances` table (the thesis's Table 5.1): per speed sweep, direction and integer order
//! k ≥ 2, the speed [Hz] where order k of the centre runout peaks nearest to (within
//! [`RESONANCE_WINDOW`] of) the model's critical speed / k, the sweep's step there [Hz] and the
//! flags `coarse` / `edge` (`signal::resolution`; markdown rounds the speed to the step,
//! [`to_step`]), and the amplitude [µm] of order k at each sensor's own such peak.
//!
//! In: `/analysis/sweeps/<n>` (`speed_hz`, `orders`, `fixed`, `job_ids`, `lines/<sensor>/<dir>`:
//! line amplitudes [µm] per speed and order) and, through the sweep's first job's `linear_id`,
//! `/linear/<id>` (`critical_speeds_hz`, the first vertical and horizontal bending frequencies
//! `vertical_hz`, `horizontal_hz`). Out: the table, or none when no sweep has lines.

use hdf5::types::VarLenUnicode;
use hdf5::{File, Group};

use crate::report::table::{md_cell, sensor_rank, Cell, Grid, Table};
use crate::signal;
use crate::store;
use crate::text::{number_text, significant};

/// How far [share of the expected speed] a peak may lie from critical/k and still be taken as
/// that sub-critical resonance (10 %: the horizontal and vertical lines of a roll lie 5–7 %
/// apart, so a peak further off belongs to something else).
const RESONANCE_WINDOW: f64 = 0.1;

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

/// The peak nearest to `near` [Hz] within [`RESONANCE_WINDOW`] of it, or the highest one
/// without `near`.
pub(crate) fn pick(peaks: Vec<signal::Peak>, near: Option<f64>) -> Option<signal::Peak> {
    match near {
        Some(c) => peaks
            .into_iter()
            .filter(|p| (p.speed_hz - c).abs() <= RESONANCE_WINDOW * c)
            .min_by(|a, b| (a.speed_hz - c).abs().total_cmp(&(b.speed_hz - c).abs())),
        None => peaks.into_iter().next(),
    }
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

/// A peak of a line's amplitude over speed and the sweep's resolution there.
type Found = Option<(signal::Peak, signal::Resolution)>;

/// Per sensor (`data`: its line amplitudes per speed and order, if stored), the peak of order
/// number `k` (of `n_orders`) over `speeds` picked near `expected`.
fn order_peaks(
    data: &[Option<Vec<f64>>],
    speeds: &[f64],
    n_orders: usize,
    k: usize,
    expected: Option<f64>,
) -> Vec<Found> {
    data.iter()
        .map(|m| {
            let m = m.as_ref()?;
            let amp: Vec<f64> = (0..speeds.len())
                .map(|s| m.get(s * n_orders + k).copied().unwrap_or(f64::NAN))
                .collect();
            let p = pick(signal::peaks(speeds, &amp), expected)?;
            Some((p, signal::resolution(speeds, &amp, &p)))
        })
        .collect()
}

/// The row of one sweep, direction and order (the first sensor's peak gives the speed, step and
/// note) and its markdown line (the speed rounded to the step, the step to 3 digits).
fn order_row(
    sweep: &str,
    dir: &str,
    order: f64,
    expected: Option<f64>,
    found: &[Found],
) -> (Vec<Cell>, Vec<String>) {
    let centre = found[0];
    let mut row = vec![
        Cell::Text(sweep.to_string()),
        Cell::Text(dir.to_string()),
        Cell::Count(order as u64),
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
    (row, line)
}

/// The rows and markdown lines of sweep number `n` (group `sg`); the sensors of the first sweep
/// with lines set `names` (centre first).
fn sweep_rows(
    f: &File,
    n: usize,
    sg: &Group,
    names: &mut Vec<String>,
    rows: &mut Vec<Vec<Cell>>,
    md: &mut Vec<Vec<String>>,
) -> hdf5::Result<()> {
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
        return Ok(());
    };
    if names.is_empty() {
        *names = lines.member_names()?;
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
            let found = order_peaks(&data, &speeds, orders.len(), k, expected);
            let (row, line) = order_row(&sweep, dir, *order, expected, &found);
            md.push(line);
            rows.push(row);
        }
    }
    Ok(())
}

/// A column of the long form as markdown heads it (units in brackets).
fn md_column(c: &str) -> String {
    match c {
        "expected_hz" => "expected [Hz]".to_string(),
        "speed_hz" => "speed [Hz]".to_string(),
        "step_hz" => "step [Hz]".to_string(),
        other => match other.strip_suffix("_um") {
            Some(sensor) => format!("{sensor} [µm]"),
            None => other.to_string(),
        },
    }
}

/// The `resonances` table of `f` (module doc); None when no sweep has lines.
pub(crate) fn resonance_table(f: &File) -> hdf5::Result<Option<Table>> {
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
        sweep_rows(f, n, sg, &mut names, &mut rows, &mut md)?;
    }
    if rows.is_empty() {
        return Ok(None);
    }
    columns.extend(names.iter().map(|s| format!("{s}_um")));
    let md_columns = columns.iter().map(|c| md_column(c)).collect();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speeds_are_rounded_to_the_sweeps_step() {
        // 0.2 Hz steps (16.2 − 16.0 is 0.19999… in floating point): one decimal; a 4 Hz step
        // (a 4-speed sweep 10…22 Hz): none; 0.05 Hz: two.
        assert_eq!(to_step(16.17835, 16.2 - 16.0), "16.2");
        assert_eq!(to_step(15.59, 4.0), "16");
        assert_eq!(to_step(16.17835, 0.05), "16.18");
        assert_eq!(to_step(16.17835, f64::NAN), "16.18");
    }
}
