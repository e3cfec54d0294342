//! Measured runout in (`rotorsweep import`): a CSV or HDF5 record turned into a results file
//! that the analysis, `report` and the plots read like a simulated job's.
//!
//! In, the same columns in either format (the format is told by the file's first bytes: the
//! HDF5 signature, else CSV); one rule set (`layout`, `assemble`) checks both:
//! - `time_s`: sample times [s], strictly ascending and uniform: every interval within 50 % of
//!   the median one ([`MAX_STEP_DEVIATION`]; the spectra expect uniform sampling);
//! - `runout/<sensor>/<vertical|horizontal>`: runout [µm], one column per sensor and direction
//!   (at least one);
//! - the roll angle: `roll_angle_rad` (unwrapped, 0 at the keyphasor mark, non-decreasing) or
//!   `keyphasor`, a once-per-revolution pulse signal (any units: each rising crossing of half
//!   its range is θ = 2πn, linear in time between pulses; `signal::orders`);
//! - optional `speed_hz` [Hz] (stored as a channel; the speed the analysis uses comes from the
//!   roll angle).
//!
//! CSV: UTF-8; lines starting with `#` are comments and blank lines are skipped; the first other
//! line is the header (the names above); comma-separated numbers, one line per sample. Records
//! are split by the `csv` crate (quoted fields allowed, a byte-order mark ignored) through
//! `rotor::wall::data_rows`, which names each record's line.
//!
//! HDF5: 1-D numeric datasets (any float or integer type) at the file's root named `time_s`,
//! `roll_angle_rad` or `keyphasor`, optional `speed_hz`, and `runout/<sensor>/<direction>` in
//! groups; nothing else at the root; all of one length. An optional string attribute `units`
//! per dataset: `s` for `time_s`, `rad` for `roll_angle_rad`, `Hz` for `speed_hz`, anything for
//! `keyphasor`, and `um` (also `µm`, `micrometre`, `micrometer`), `mm` or `m` for runout (scaled
//! to µm); without it the units above are taken; any other value is an error.
//!
//! Out: a results file with `study_name` = `import:<file stem>`, `study_text` holding an
//! `[analysis]` table with the orders asked for, and one job `/jobs/<stem>` (status `ok`,
//! `time`, `runout/...`, `speed/roll_angle`, `speed/hz` when given; `speed_hz` attribute the
//! mean speed when it varies by less than 0.1 % over the record, else NaN), then the
//! post-processing (`post::analyse`: lines and spectra at a constant speed, order tracking and
//! a waterfall otherwise). Errors name the file and the line and column (CSV: the file's line,
//! header and comment lines counted) or the dataset and sample (HDF5). The record must be a
//! regular file (a FIFO or directory is refused before it is opened, as scenes are).

use std::path::Path;

use crate::dynamics::simulation::{Channel, JobResult};
use crate::error::InputError;
use crate::rotor::wall::data_rows;
use crate::signal::orders;
use crate::store::{self, Param};
use crate::text::number_text;

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

/// Which columns (CSV) or datasets (HDF5) hold what, by index into the list of names.
struct Layout {
    time: usize,
    angle: Option<usize>,
    keyphasor: Option<usize>,
    speed: Option<usize>,
    runout: Vec<usize>,
}

/// Sorts the names of a record's columns or datasets (`kind`: "column" or "dataset") into a
/// [`Layout`]; the same rules for both formats (module doc).
fn layout(names: &[String], kind: &str) -> Result<Layout, String> {
    let find = |n: &str| names.iter().position(|c| c == n);
    let time = find("time_s").ok_or_else(|| format!("no `time_s` {kind}"))?;
    let angle = find("roll_angle_rad");
    let keyphasor = find("keyphasor");
    if angle.is_some() == keyphasor.is_some() {
        return Err(format!(
            "needs exactly one of the {kind}s `roll_angle_rad` and `keyphasor`"
        ));
    }
    let speed = find("speed_hz");
    let mut runout = Vec::new();
    for (i, n) in names.iter().enumerate() {
        if [Some(time), angle, keyphasor, speed].contains(&Some(i)) {
            continue;
        }
        let parts = n.strip_prefix("runout/").and_then(|r| r.rsplit_once('/'));
        let ok = parts.is_some_and(|(_, d)| d == "vertical" || d == "horizontal");
        if let (true, Some((sensor, _))) = (ok, parts) {
            crate::error::safe_name(sensor).map_err(|r| format!("{kind} `{n}`: {r}"))?;
        }
        if !ok {
            return Err(format!(
                "{kind} `{n}`: expected time_s, roll_angle_rad or keyphasor, speed_hz, or \
                 runout/<sensor>/<vertical|horizontal>"
            ));
        }
        if names[..i].contains(n) {
            return Err(format!("{kind} `{n}` appears twice"));
        }
        runout.push(i);
    }
    if runout.is_empty() {
        return Err(format!("no runout/<sensor>/<direction> {kind}"));
    }
    Ok(Layout {
        time,
        angle,
        keyphasor,
        speed,
        runout,
    })
}

/// The largest HDF5 record read: 16 GiB (a CSV record is read as text, within
/// [`MAX_INPUT_BYTES`](crate::error::MAX_INPUT_BYTES)); HDF5 reads only the datasets.
pub const MAX_HDF5_BYTES: u64 = 16 << 30;

/// Reads a measured record: HDF5 when the file starts with the HDF5 signature, else CSV (module
/// doc).
pub fn read(path: &Path) -> Result<Record, InputError> {
    // Checked before the signature is read: opening a FIFO would block.
    crate::error::regular_file(path, MAX_HDF5_BYTES)
        .map_err(|e| InputError::new(path, format!("cannot read the measured record: {e}")))?;
    let mut sig = [0u8; 8];
    let is_h5 = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut sig))
        .is_ok()
        && sig == store::output::HDF5_SIGNATURE;
    if is_h5 {
        read_hdf5(path)
    } else {
        read_csv(path)
    }
}

/// Reads a measured CSV record (module doc).
pub fn read_csv(path: &Path) -> Result<Record, InputError> {
    let text = crate::error::read_text(path).map_err(|e| InputError::new(path, e.to_string()))?;
    let at = |line: usize, reason: String| InputError::new(path, reason).at_line(line);
    let mut rows = data_rows(path, &text);
    let (hline, header) = rows
        .next()
        .ok_or_else(|| InputError::new(path, "no header line"))??;
    let names: Vec<String> = header.iter().map(|s| s.trim().to_string()).collect();
    let lay = layout(&names, "column").map_err(|e| at(hline, e))?;
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut lines = Vec::new();
    for row in rows {
        let (ln, cells) = row?;
        lines.push(ln);
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
    assemble(path, &names, cols, &lay, Some(&lines))
}

/// The `units` attributes an HDF5 record may carry per dataset, with the factor to the
/// record's own units (s, µm, rad, Hz); a dataset without `units` is taken in those units.
fn unit_factor(name: &str, units: &str) -> Option<f64> {
    match (name, units) {
        ("time_s", "s") | ("roll_angle_rad", "rad") | ("speed_hz", "Hz") => Some(1.0),
        ("keyphasor", _) => Some(1.0),
        (n, "um" | "µm" | "micrometre" | "micrometer") if n.starts_with("runout/") => Some(1.0),
        (n, "mm") if n.starts_with("runout/") => Some(1e3),
        (n, "m") if n.starts_with("runout/") => Some(1e6),
        _ => None,
    }
}

/// Reads a measured HDF5 record (module doc): the datasets at the file's root, runout under
/// `runout/<sensor>/<direction>`.
pub fn read_hdf5(path: &Path) -> Result<Record, InputError> {
    let err = |reason: String| InputError::new(path, reason);
    let f = hdf5::File::open(path).map_err(|e| err(format!("not a readable HDF5 file: {e}")))?;
    let h5 = |e: hdf5::Error| err(e.to_string());
    let mut names = Vec::new();
    for n in f.member_names().map_err(h5)? {
        if n == "runout" {
            let g = f
                .group("runout")
                .map_err(|_| err("`runout` must be a group of <sensor> groups".into()))?;
            for s in g.member_names().map_err(h5)? {
                let sg = g.group(&s).map_err(|_| {
                    err(format!(
                        "`runout/{s}` must be a group of vertical/horizontal datasets"
                    ))
                })?;
                for d in sg.member_names().map_err(h5)? {
                    names.push(format!("runout/{s}/{d}"));
                }
            }
        } else {
            names.push(n);
        }
    }
    let lay = layout(&names, "dataset").map_err(err)?;
    let mut cols = Vec::with_capacity(names.len());
    for n in &names {
        let at = |reason: String| err(format!("dataset `{n}`: {reason}"));
        let ds = f.dataset(n).map_err(|_| at("not a dataset".into()))?;
        if ds.ndim() != 1 {
            return Err(at(format!("{} dimensions, expected 1", ds.ndim())));
        }
        let factor = match store::read_str(&ds, "units") {
            Ok(u) => unit_factor(n, &u).ok_or_else(|| at(format!("units `{u}` not accepted")))?,
            Err(_) if ds.attr("units").is_ok() => {
                return Err(at("the `units` attribute is not a string".into()))
            }
            Err(_) => 1.0,
        };
        let mut v: Vec<f64> = ds.read_raw().map_err(|e| at(format!("not numbers: {e}")))?;
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(at(format!("sample {}: {} is not finite", i + 1, v[i])));
        }
        v.iter_mut().for_each(|x| *x *= factor);
        cols.push(v);
    }
    let nt = cols[lay.time].len();
    if let Some(i) = cols.iter().position(|c| c.len() != nt) {
        return Err(err(format!(
            "dataset `{}`: {} samples, time_s has {nt}",
            names[i],
            cols[i].len()
        )));
    }
    assemble(path, &names, cols, &lay, None)
}

/// The largest share by which a sampling interval may differ from the record's median one
/// (module doc: the spectra expect uniform sampling; a time of 1e308 at the end was read as a
/// record of 1e308 s).
pub const MAX_STEP_DEVIATION: f64 = 0.5;

/// The checks both formats share, then the record: times ascending and uniform, roll angle from
/// the angle or the keyphasor, unwrapped. `lines`: the CSV line of each sample (errors name it;
/// without, an HDF5 record, the sample's 1-based index).
fn assemble(
    path: &Path,
    names: &[String],
    mut cols: Vec<Vec<f64>>,
    lay: &Layout,
    lines: Option<&[usize]>,
) -> Result<Record, InputError> {
    let at_sample = |i: usize, reason: String| match lines {
        Some(l) => InputError::new(path, reason).at_line(l[i]),
        None => InputError::new(path, format!("sample {}: {reason}", i + 1)),
    };
    let time = std::mem::take(&mut cols[lay.time]);
    if time.len() < 3 {
        return Err(InputError::new(path, "fewer than three samples"));
    }
    if let Some(i) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(at_sample(
            i + 1,
            format!(
                "time_s {} does not follow {} (times must be strictly ascending)",
                number_text(time[i + 1]),
                number_text(time[i])
            ),
        ));
    }
    uniform_steps(&time).map_err(|(i, r)| at_sample(i, r))?;
    let roll_angle = match (lay.angle, lay.keyphasor) {
        (Some(c), _) => std::mem::take(&mut cols[c]),
        (_, Some(c)) => {
            let pulses = orders::pulse_times(&time, &cols[c]);
            orders::angle_from_pulses(&time, &pulses).map_err(|e| {
                let kind = if lines.is_some() { "column" } else { "dataset" };
                InputError::new(path, format!("{kind} `keyphasor`: {e}"))
            })?
        }
        _ => unreachable!("one of the two is there (checked by `layout`)"),
    };
    if let Some(i) = roll_angle.windows(2).position(|w| w[1] < w[0]) {
        return Err(at_sample(
            i + 1,
            format!(
                "roll_angle_rad decreases from {} to {}: it must be unwrapped",
                number_text(roll_angle[i]),
                number_text(roll_angle[i + 1])
            ),
        ));
    }
    Ok(Record {
        speed_hz: lay.speed.map(|c| std::mem::take(&mut cols[c])),
        runout: lay
            .runout
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

/// Every sampling interval of the ascending `time` lies within [`MAX_STEP_DEVIATION`] of the
/// median one; else the sample that ends the first one that does not, and why.
fn uniform_steps(time: &[f64]) -> Result<(), (usize, String)> {
    let mut steps: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    let i = steps.len() / 2;
    let median = *steps.select_nth_unstable_by(i, f64::total_cmp).1;
    let (lo, hi) = (1.0 - MAX_STEP_DEVIATION, 1.0 + MAX_STEP_DEVIATION);
    match time
        .windows(2)
        .position(|w| !(lo * median..=hi * median).contains(&(w[1] - w[0])))
    {
        None => Ok(()),
        Some(k) => Err((
            k + 1,
            format!(
                "time_s {} is {} s after {}, the record samples every {} s (median): the \
                 spectra need uniform sampling (a gap, or a time that is not the sample's)",
                number_text(time[k + 1]),
                number_text(time[k + 1] - time[k]),
                number_text(time[k]),
                number_text(median)
            ),
        )),
    }
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
        fields: Vec::new(),
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
        super::analyse::analyse(&f)?;
        store::finish_file(path, f, jobs).map_err(|e| hdf5::Error::from(e.to_string().as_str()))
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(store::with_suffix(path, ".tmp"));
        e.to_string()
    })
}
