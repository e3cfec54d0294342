//! `rotorsweep report MEASURED.h5 --compare SIMULATED.h5`: measured against simulated order
//! amplitudes and phases side by side, with differences.
//!
//! In: two results files with `/analysis/orders` (written by `results::orders`): the measured one
//! (`rotorsweep import`, or any results file) and the simulated one (a run-up of the model, or
//! a constant-speed sweep: one row per job). Out: one [`Table`] `compare`, one row per measured
//! row (job, order, block, sensor, direction) with the measured amplitude [µm] and phase [deg],
//! the simulated ones at the same order, sensor, direction and speed, and the differences
//! measured − simulated (phase wrapped to (−180, 180]).
//!
//! Method: the simulated rows of one order, sensor and direction, sorted by speed, are
//! interpolated linearly in speed — the amplitude as such, the phase through the complex
//! amplitude A e^{iφ} (so that it does not jump across ±180°). A measured speed outside the
//! simulated rows' range, or a sensor/direction/order the simulation lacks, has no simulated
//! value (NaN: empty in CSV, `–` in markdown, null in JSON). Two simulated rows at one speed
//! (several jobs at one speed: pick one job with the study's own filters first) are an error.
//!
//! A second table `compare_resonances` (the thesis's Table 5.1 side by side), present whatever
//! the orders (empty when no measured curve has a resonance): per measured job, order, sensor
//! and direction whose curve over speed has a resonance — its highest interior peak
//! (`signal::curve_peaks`, parabola-refined) at least [`PROMINENCE`] × the curve's median and
//! above the record's noise floor there (`results::noise`: the amplitude that the record's
//! broadband noise alone exceeds in one tracked block with probability 1e-4, from the median of
//! its waterfall's bins off the tracked lines; none known for a job without a waterfall) — the
//! measured resonance speed [Hz] and amplitude [µm], the simulated curve's peak nearest to it
//! within 10 % of its speed (the `resonances` table's window; none: empty), the differences
//! measured − simulated in Hz, in % of the simulated speed and in µm, and the noise floor at
//! the measured peak [µm]. A flat order (an out-of-roundness line) or one of noise alone (an
//! order with nothing in it but the sensor's noise, whose highest block is a few times its
//! median) has no resonance and no row.

use std::collections::BTreeMap;
use std::path::Path;

use rustfft::num_complex::Complex64;

use super::table::{Cell, Report, Table};
use super::tables::{pick, records, OrderRow};
use crate::error::InputError;
use crate::numerics::median::median;
use crate::results::noise::{noise_floors, NoiseFloor};
use crate::results::request::{analysis_of_text, DEFAULT_ORDER_REVOLUTIONS};
use crate::signal;
use crate::store;
use crate::text::significant;

/// Simulated points of one (order, sensor, direction): (speed [Hz], complex amplitude [µm]).
pub(crate) type Curve = Vec<(f64, Complex64)>;

/// How far a resonance's peak must rise above its curve's median amplitude to count (module
/// doc): a resonance of light damping rises many times over its skirts (the Jeffcott's 1× run
/// through its critical: 4×; the reference roll's half-critical 2×: 8×), a flat line and its
/// noise peaks stay within tens of percent.
pub const PROMINENCE: f64 = 2.0;

/// A (job, sensor, direction, order) key of the order rows.
type Channel = (String, String, String, u64);

/// (speed, amplitude) points per job, sensor, direction and order, in the rows' order.
fn amplitude_curves(rows: &[OrderRow], by_job: bool) -> BTreeMap<Channel, Vec<(f64, f64)>> {
    let mut out: BTreeMap<Channel, Vec<(f64, f64)>> = BTreeMap::new();
    for r in rows {
        let job = if by_job {
            r.job_id.to_string()
        } else {
            String::new()
        };
        let key = (
            job,
            r.sensor.to_string(),
            r.direction.to_string(),
            r.order.to_bits(),
        );
        out.entry(key)
            .or_default()
            .push((r.speed_hz, r.amplitude_um));
    }
    out
}

/// The noise floor of each measured (job, "sensor/direction") with a waterfall (module doc),
/// tracked at the orders of `rows` in the blocks of the file's `[analysis] order_revolutions`.
type Floors = BTreeMap<(String, String), NoiseFloor>;

/// The noise floors of the measured file `f` whose order rows are `rows` (module doc).
fn measured_floors(f: &hdf5::File, rows: &[OrderRow]) -> Floors {
    let text = store::read_str(f, "study_text").unwrap_or_default();
    let revs = analysis_of_text(&text)
        .and_then(|a| a.spec.order_revolutions)
        .unwrap_or(DEFAULT_ORDER_REVOLUTIONS);
    let mut orders: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for r in rows {
        let o = orders.entry(r.job_id.to_string()).or_default();
        if !o.contains(&r.order) {
            o.push(r.order);
        }
    }
    let mut out = Floors::new();
    for (job, ks) in orders {
        let Ok(g) = f.group(&format!("jobs/{job}")) else {
            continue;
        };
        for (channel, floor) in noise_floors(&g, &ks, revs) {
            out.insert((job.clone(), channel), floor);
        }
    }
    out
}

/// The legend's sentence on the noise floors: each channel's noise RMS per sample σ [µm].
fn noise_note(floors: &Floors) -> String {
    if floors.is_empty() {
        return "No measured curve has a noise floor.".into();
    }
    let each: Vec<String> = floors
        .iter()
        .map(|((job, c), f)| format!("{job} {c} {} µm", significant(f.sigma_um, 3)))
        .collect();
    format!("Noise RMS per sample σ: {}.", each.join(", "))
}

/// The `compare_resonances` table (module doc): empty when no measured curve has a resonance,
/// which its legend then says.
fn resonance_table(meas: &[OrderRow], sim: &[OrderRow], floors: &Floors, legend: String) -> Table {
    let simulated = amplitude_curves(sim, false);
    let mut rows = Vec::new();
    for ((job, sensor, dir, order), points) in amplitude_curves(meas, true) {
        let med = median(points.iter().map(|p| p.1));
        let floor = floors.get(&(job.clone(), format!("{sensor}/{dir}")));
        let Some((m, noise)) = signal::curve_peaks(points)
            .into_iter()
            .next()
            .map(|p| (p, floor.map_or(f64::NAN, |f| f.at(p.speed_hz))))
            .filter(|(p, noise)| {
                p.amplitude >= PROMINENCE * med && (noise.is_nan() || p.amplitude > *noise)
            })
        else {
            continue;
        };
        let s = simulated
            .get(&(String::new(), sensor.clone(), dir.clone(), order))
            .and_then(|c| pick(signal::curve_peaks(c.clone()), Some(m.speed_hz)));
        let (ss, sa) = s.map_or((f64::NAN, f64::NAN), |p| (p.speed_hz, p.amplitude));
        rows.push(vec![
            Cell::Text(job),
            Cell::Number(f64::from_bits(order)),
            Cell::Text(sensor),
            Cell::Text(dir),
            Cell::Number(m.speed_hz),
            Cell::Number(ss),
            Cell::Number(m.speed_hz - ss),
            Cell::Number(100.0 * (m.speed_hz - ss) / ss),
            Cell::Number(m.amplitude),
            Cell::Number(sa),
            Cell::Number(m.amplitude - sa),
            Cell::Number(noise),
        ]);
    }
    let legend = if rows.is_empty() {
        format!("{legend} None here: no measured order rises to a resonance above its noise floor.")
    } else {
        legend
    };
    Table {
        name: "compare_resonances".into(),
        title: "Measured vs simulated resonances".into(),
        legend,
        columns: [
            "job_id",
            "order",
            "sensor",
            "direction",
            "measured_hz",
            "simulated_hz",
            "difference_hz",
            "difference_pct",
            "measured_um",
            "simulated_um",
            "difference_um",
            "noise_floor_um",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        markdown: None,
    }
}

/// The results file at `path`, open, and its order rows; an error naming it when it has none.
fn order_rows(path: &Path) -> Result<(hdf5::File, Vec<OrderRow>), InputError> {
    let f = store::output::open_results_file(path).map_err(|e| InputError::new(path, e))?;
    let none = || {
        InputError::new(
            path,
            "no `/analysis/orders` table (no job with a roll angle)",
        )
    };
    let rows = records::<OrderRow>(&f, "analysis/orders")
        .map_err(|e| InputError::new(path, e.to_string()))?
        .ok_or_else(none)?;
    Ok((f, rows))
}

/// `c` interpolated linearly at speed `s`; None outside its range.
pub(crate) fn at_speed(c: &Curve, s: f64) -> Option<Complex64> {
    let i = c.partition_point(|(x, _)| *x < s);
    if i < c.len() && c[i].0 == s {
        return Some(c[i].1);
    }
    if i == 0 || i == c.len() {
        return None;
    }
    let ((x0, y0), (x1, y1)) = (c[i - 1], c[i]);
    let w = (s - x0) / (x1 - x0);
    Some(y0 * (1.0 - w) + y1 * w)
}

/// The angle `d` [deg] wrapped to (−180, 180].
fn wrap_deg(d: f64) -> f64 {
    let w = d.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// The (sensor, direction, order) a row of the order table belongs to.
type CurveKey = (String, String, u64);

/// The key of row `r`.
fn curve_key(r: &OrderRow) -> CurveKey {
    (
        r.sensor.to_string(),
        r.direction.to_string(),
        r.order.to_bits(),
    )
}

/// The simulated rows as curves over speed, sorted by speed; an error naming `simulated` when
/// one curve has two rows at one speed.
fn simulated_curves(
    sim: &[OrderRow],
    simulated: &Path,
) -> Result<BTreeMap<CurveKey, Curve>, InputError> {
    let mut curves: BTreeMap<CurveKey, Curve> = BTreeMap::new();
    for r in sim {
        let v = Complex64::from_polar(r.amplitude_um, r.phase_deg.to_radians());
        curves
            .entry(curve_key(r))
            .or_default()
            .push((r.speed_hz, v));
    }
    for ((sensor, dir, order), c) in curves.iter_mut() {
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(w) = c.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(InputError::new(
                simulated,
                format!(
                    "two rows of order {} at {sensor}/{dir} at {} Hz (several jobs at one \
                     speed): compare against one run-up or one speed sweep",
                    f64::from_bits(*order),
                    w[0].0
                ),
            ));
        }
    }
    Ok(curves)
}

/// The comparison report of `measured` against `simulated` (module doc).
pub fn compare(measured: &Path, simulated: &Path) -> Result<Report, InputError> {
    let (meas_file, meas) = order_rows(measured)?;
    let sim = order_rows(simulated)?.1;
    let floors = measured_floors(&meas_file, &meas);
    let curves = simulated_curves(&sim, simulated)?;
    let rows = meas
        .iter()
        .map(|r| {
            let s = curves
                .get(&curve_key(r))
                .and_then(|c| at_speed(c, r.speed_hz));
            let (sa, sp) = s.map_or((f64::NAN, f64::NAN), |v| (v.norm(), v.arg().to_degrees()));
            vec![
                Cell::Text(r.job_id.to_string()),
                Cell::Number(r.order),
                Cell::Count(r.block),
                Cell::Number(r.speed_hz),
                Cell::Text(r.sensor.to_string()),
                Cell::Text(r.direction.to_string()),
                Cell::Number(r.amplitude_um),
                Cell::Number(sa),
                Cell::Number(r.amplitude_um - sa),
                Cell::Number(r.phase_deg),
                Cell::Number(sp),
                Cell::Number(wrap_deg(r.phase_deg - sp)),
            ]
        })
        .collect();
    let table = Table {
        name: "compare".into(),
        title: "Measured vs simulated orders".into(),
        legend: format!(
            "Per measured job, order k, block (mean speed [Hz]), sensor and direction: the \
             amplitude [µm] and phase [deg] of A cos(kθ + φ) measured (`{}`) and simulated \
             (`{}`, interpolated linearly in speed; none outside its speeds), and measured − \
             simulated",
            measured.display(),
            simulated.display()
        ),
        columns: [
            "job_id",
            "order",
            "block",
            "speed_hz",
            "sensor",
            "direction",
            "measured_um",
            "simulated_um",
            "difference_um",
            "measured_phase_deg",
            "simulated_phase_deg",
            "phase_difference_deg",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        markdown: None,
    };
    let resonances = resonance_table(
        &meas,
        &sim,
        &floors,
        format!(
            "Per measured job, order k, sensor and direction with a resonance — the highest \
             peak of order k's amplitude over speed, at least {PROMINENCE} × its median and \
             above the record's noise floor there (`noise_floor_um`: the amplitude its \
             broadband noise alone exceeds in one tracked block with probability 1e-4, \
             4.29 √(3/M) σ for a block of M samples, σ the noise's RMS per sample estimated \
             from the median of the waterfall's bins off the tracked lines; empty: no waterfall, \
             no floor applied): its speed [Hz] and amplitude [µm] measured (`{}`) and at the \
             simulated peak nearest to it within 10 % (`{}`; none: empty), and measured − \
             simulated [Hz, % of the simulated speed, µm]. {}",
            measured.display(),
            simulated.display(),
            noise_note(&floors),
        ),
    );
    Ok(Report {
        file: measured.to_path_buf(),
        study: format!("{} vs {}", measured.display(), simulated.display()),
        overview: format!(
            "{} measured order rows against {} simulated",
            meas.len(),
            sim.len()
        ),
        tables: vec![table, resonances],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_and_phase_wrap() {
        // Two points 1 µm at 0° (10 Hz) and 1 µm at 90° (20 Hz): at 15 Hz the chord's midpoint,
        // |(1 + i)/2| = √2/2 at 45°; outside 10..20 Hz nothing.
        let c: Curve = vec![
            (10.0, Complex64::new(1.0, 0.0)),
            (20.0, Complex64::new(0.0, 1.0)),
        ];
        let m = at_speed(&c, 15.0).unwrap();
        assert!((m.norm() - 0.5f64.sqrt()).abs() < 1e-15);
        assert!((m.arg().to_degrees() - 45.0).abs() < 1e-12);
        assert_eq!(at_speed(&c, 20.0), Some(Complex64::new(0.0, 1.0)));
        assert_eq!(at_speed(&c, 9.9), None);
        assert_eq!(at_speed(&c, 20.1), None);
        assert_eq!(wrap_deg(190.0), -170.0);
        assert_eq!(wrap_deg(-190.0), 170.0);
        assert_eq!(wrap_deg(180.0), 180.0);
    }
}
