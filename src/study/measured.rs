//! Measured runout in (`rotorsweep import`): a CSV record turned into a results file that the
//! analysis, `report` and the plots read like a simulated job's.
//!
//! In: a CSV file (UTF-8; lines starting with `#` are comments; the first other line is the
//! header; comma-separated numbers, one line per sample). Columns:
//! - `time_s`: sample times [s], strictly ascending (uniform sampling expected by the spectra);
//! - `runout/<sensor>/<vertical|horizontal>`: runout [µm], one column per sensor and direction
//!   (at least one);
//! - the roll angle: `roll_angle_rad` (unwrapped, 0 at the keyphasor mark, non-decreasing) or
//!   `keyphasor`, a once-per-revolution pulse signal (any units: each rising crossing of half
//!   its range is θ = 2πn, linear in time between pulses; `analysis::orders`);
//! - optional `speed_hz` [Hz] (stored as a channel; the speed the analysis uses comes from the
//!   roll angle).
//!
//! Out: a results file with `study_name` = `import:<file stem>`, `study_text` holding an
//! `[analysis]` table with the orders asked for, and one job `/jobs/<stem>` (status `ok`,
//! `time`, `runout/...`, `speed/roll_angle`, `speed/hz` when given; `speed_hz` attribute the
//! mean speed when it varies by less than 0.1 % over the record, else NaN), then the
//! post-processing (`post::analyse`: lines and spectra at a constant speed, order tracking and
//! a waterfall otherwise). Errors name the file, line and column.

use std::path::Path;

use crate::analysis::orders;
use crate::error::InputError;
use crate::job::{Channel, JobResult};
use crate::store::{self, Param};

/// A measured record.
#[derive(Debug, Clone)]
pub struct Record {
    /// Sample times [s].
    pub time: Vec<f64>,
    /// Roll angle per sample [rad].
    pub roll_angle: Vec<f64>,
    /// Speed per sample [Hz], when given.
    pub speed_hz: Option<Vec<f64>>,
    /// Runout channels ("sensor/direction", µm).
    pub runout: Vec<(String, Vec<f64>)>,
}

/// Reads a measured CSV record (module doc).
pub fn read_csv(path: &Path) -> Result<Record, InputError> {
    let text = crate::error::read_text(path).map_err(|e| InputError::new(path, e.to_string()))?;
    let at = |line: usize, reason: String| {
        let mut e = InputError::new(path, reason);
        e.line = Some(line);
        e
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (hline, header) = lines
        .next()
        .ok_or_else(|| InputError::new(path, "no header line"))?;
    let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
    let find = |n: &str| names.iter().position(|c| c == n);
    let t_col = find("time_s").ok_or_else(|| at(hline, "no `time_s` column".into()))?;
    let angle_col = find("roll_angle_rad");
    let key_col = find("keyphasor");
    if angle_col.is_some() == key_col.is_some() {
        return Err(at(
            hline,
            "needs exactly one of the columns `roll_angle_rad` and `keyphasor`".into(),
        ));
    }
    let speed_col = find("speed_hz");
    let mut runout_cols = Vec::new();
    for (i, n) in names.iter().enumerate() {
        if Some(i) == Some(t_col)
            || Some(i) == angle_col
            || Some(i) == key_col
            || Some(i) == speed_col
        {
            continue;
        }
        let ok = n
            .strip_prefix("runout/")
            .and_then(|r| r.split_once('/'))
            .is_some_and(|(s, d)| !s.is_empty() && (d == "vertical" || d == "horizontal"));
        if !ok {
            return Err(at(
                hline,
                format!(
                    "column `{n}`: expected time_s, roll_angle_rad or keyphasor, speed_hz, or \
                     runout/<sensor>/<vertical|horizontal>"
                ),
            ));
        }
        if names[..i].contains(n) {
            return Err(at(hline, format!("column `{n}` appears twice")));
        }
        runout_cols.push(i);
    }
    if runout_cols.is_empty() {
        return Err(at(hline, "no runout/<sensor>/<direction> column".into()));
    }
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for (ln, l) in lines {
        let cells: Vec<&str> = l.split(',').collect();
        if cells.len() != names.len() {
            return Err(at(
                ln,
                format!("{} values for {} columns", cells.len(), names.len()),
            ));
        }
        for (c, cell) in cells.iter().enumerate() {
            let v: f64 = cell.trim().parse().map_err(|_| {
                at(
                    ln,
                    format!("column `{}`: `{}` is not a number", names[c], cell.trim()),
                )
            })?;
            if !v.is_finite() {
                return Err(at(ln, format!("column `{}`: {v} is not finite", names[c])));
            }
            cols[c].push(v);
        }
    }
    let time = std::mem::take(&mut cols[t_col]);
    if time.len() < 3 {
        return Err(InputError::new(path, "fewer than three samples"));
    }
    if let Some(i) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(InputError::new(
            path,
            format!("time_s not strictly ascending at sample {}", i + 2),
        ));
    }
    let roll_angle = match (angle_col, key_col) {
        (Some(c), _) => std::mem::take(&mut cols[c]),
        (_, Some(c)) => {
            let pulses = orders::pulse_times(&time, &cols[c]);
            orders::angle_from_pulses(&time, &pulses)
                .map_err(|e| InputError::new(path, format!("keyphasor: {e}")))?
        }
        _ => unreachable!("one of the two columns is there (checked above)"),
    };
    if let Some(i) = roll_angle.windows(2).position(|w| w[1] < w[0]) {
        return Err(InputError::new(
            path,
            format!(
                "roll_angle_rad decreases at sample {}: it must be unwrapped",
                i + 2
            ),
        ));
    }
    Ok(Record {
        speed_hz: speed_col.map(|c| std::mem::take(&mut cols[c])),
        runout: runout_cols
            .iter()
            .map(|&c| {
                let n = names[c]["runout/".len()..].to_string();
                (n, std::mem::take(&mut cols[c]))
            })
            .collect(),
        time,
        roll_angle,
    })
}

/// The record's mean speed [Hz] when it varies by less than 0.1 % over the record.
fn constant_speed(r: &Record) -> Option<f64> {
    let n = r.time.len();
    let tau = std::f64::consts::TAU;
    let mean = (r.roll_angle[n - 1] - r.roll_angle[0]) / (tau * (r.time[n - 1] - r.time[0]));
    let (a, b) = (n / 2, n - 1);
    let half =
        |i: usize, j: usize| (r.roll_angle[j] - r.roll_angle[i]) / (tau * (r.time[j] - r.time[i]));
    let (s1, s2) = (half(0, a), half(a, b));
    ((s1 - s2).abs() < 1e-3 * mean && mean > 0.0).then_some(mean)
}

/// Writes `r` as job `name` into a results file at `path` (claimed by the caller) and analyses
/// it with `orders` (module doc).
pub fn write(
    path: &Path,
    name: &str,
    r: &Record,
    order_list: &[f64],
    command: &str,
) -> Result<(), String> {
    let speed = constant_speed(r);
    let mut channels: Vec<Channel> = r
        .runout
        .iter()
        .map(|(n, x)| Channel {
            name: format!("runout/{n}"),
            units: "um",
            data: x.clone(),
        })
        .collect();
    channels.push(Channel {
        name: "speed/roll_angle".into(),
        units: "rad",
        data: r.roll_angle.clone(),
    });
    if let Some(s) = &r.speed_hz {
        channels.push(Channel {
            name: "speed/hz".into(),
            units: "Hz",
            data: s.clone(),
        });
    }
    let job = JobResult {
        // A measurement: no solver, so no statistics; status ok, it ends at its last sample.
        stats: crate::integrators::Stats::unsolved(r.time[r.time.len() - 1]),
        modes: String::new(),
        coordinates: 0,
        time: r.time.clone(),
        channels,
        lift_off_s: None,
    };
    let orders_text: Vec<String> = order_list.iter().map(|o| format!("{o:?}")).collect();
    let study_text = format!(
        "# imported measurement\nname = \"import:{name}\"\nscene = \"(measured)\"\n[analysis]\norders = [{}]\n",
        orders_text.join(", ")
    );
    let write = || -> hdf5::Result<()> {
        let (f, jobs) = store::create_file(path, command, "")?;
        store::attr_str(&f, "study_name", &format!("import:{name}"))?;
        store::attr_str(&f, "study_text", &study_text)?;
        store::attr_str(&f, "varying_keys", "")?;
        let (omega, delta) = match speed {
            Some(s) => (s, r.roll_angle[0] - std::f64::consts::TAU * s * r.time[0]),
            None => (f64::NAN, f64::NAN),
        };
        let params = vec![
            ("speed_hz".to_string(), Param::Number(omega)),
            ("roll_angle_offset_rad".to_string(), Param::Number(delta)),
            ("kind".to_string(), Param::Text("measured".into())),
        ];
        store::write_job(&jobs, name, &params, "measured", &job)?;
        super::post::analyse(&f)?;
        store::finish_file(path, f, jobs).map_err(|e| hdf5::Error::from(e.to_string().as_str()))
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(store::with_suffix(path, ".tmp"));
        e.to_string()
    })
}
