//! The analysis of one job of a results file: what the study-wide analysis (`analyse`) needs
//! of it, and what it writes into the job's own group.
//!
//! In: a `/jobs/<id>` group (status, `speed_hz`, `roll_angle_offset_rad`, `time` [s],
//! `runout/<sensor>/<dir>` [µm], the varying keys and `label:<key>` attributes), the study's
//! varying keys, labelled axes and [`AnalysisSpec`], and the highest frequency [Hz] whose
//! spectrum bins to keep. Out: an [`Entry`]: of a job that ended ok at a constant speed with
//! runout recorded, its lines at the study's orders (all fitted together with 1×,
//! `signal::lines`; phases against the roll angle; NaN above the Nyquist frequency), each
//! channel's mean and Hanning spectrum (`signal::mean_and_spectrum`) up to that frequency; of
//! any other job, what a sweep needs to name it as skipped. Written into the job's group (unless
//! there already, as in a merged shard's): `runout_mean/<sensor>/<dir>` [µm] and
//! `spectrum/freq_hz` [Hz], `spectrum/<sensor>/<dir>` [µm] up to the job's own cap (the study's
//! `max_freq_hz`, else [`ORDER_MARGIN`] × the highest order × its speed).
//!
//! [`Prepared`]: jobs analysed as a run saves them (`study::run`'s stream), kept until the
//! study-wide analysis, which then reads only the jobs it was not given. Memory per job: its
//! lines and its spectra up to the cap, not its samples.

use std::collections::BTreeMap;

use rustfft::num_complex::Complex64;

use super::request::{analysis_of_text, AnalysisSpec, LabelledAxis, StudyAnalysis, ORDER_MARGIN};
use crate::integrators::Status;
use crate::signal;
use crate::store::{self, Param};
use crate::text::number_text;

/// The default highest frequency [Hz] of a spectrum at `speed_hz` (module doc).
pub(super) fn default_cap(orders: &[f64], speed_hz: f64) -> f64 {
    let top = orders.iter().copied().fold(1.0, f64::max);
    ORDER_MARGIN * top * speed_hz
}

/// One job as the analysis sees it: its lines and its spectra up to the study's frequency cap
/// (not its samples: memory stays small however long the records and large the study).
pub(super) struct JobData {
    pub(super) id: String,
    pub(super) speed_hz: f64,
    /// Samples per channel and sample rate [Hz] of the record.
    pub(super) samples: usize,
    pub(super) rate_hz: f64,
    /// Runout channel names ("sensor/dir").
    pub(super) names: Vec<String>,
    /// Spectrum bins [Hz] up to the study's cap, and each channel's amplitudes there [µm].
    pub(super) freq_hz: Vec<f64>,
    pub(super) spectra: Vec<Vec<f64>>,
    /// Each channel's mean [µm] (removed before the spectrum).
    pub(super) means: Vec<f64>,
    /// Varying key → value as text.
    pub(super) values: BTreeMap<String, String>,
    /// Label per labelled axis key.
    pub(super) labels: BTreeMap<String, String>,
    /// Complex line amplitude per channel and order (orders of the spec).
    pub(super) lines: Vec<Vec<Complex64>>,
    /// The 1× line per channel.
    pub(super) one_x: Vec<Complex64>,
}

impl JobData {
    /// Keeps the spectrum bins at or below `cap_hz` (the study's cap, at most the one it was
    /// analysed with).
    pub(super) fn keep_below(&mut self, cap_hz: f64) {
        let keep = bins_below(&self.freq_hz, cap_hz);
        self.freq_hz.truncate(keep);
        for s in &mut self.spectra {
            s.truncate(keep);
        }
    }
}

/// The constant speed [Hz] of a job that ended ok, if it has one.
pub(super) fn analysable_speed(g: &hdf5::Group) -> Option<f64> {
    let speed_hz = store::read_num(g, "speed_hz").ok()?;
    let ok = Status::name_completed(&store::read_str(g, "status").ok()?);
    (ok && speed_hz > 0.0 && speed_hz.is_finite()).then_some(speed_hz)
}

/// A job the analysis leaves out (it did not end ok, its speed changed while recording, or it
/// recorded no runout), so that a sweep can say which of its speeds are missing.
pub(super) struct Skipped {
    pub(super) id: String,
    pub(super) values: BTreeMap<String, String>,
    pub(super) labels: BTreeMap<String, String>,
    pub(super) speed_hz: f64,
}

/// One job analysed: its data, or why it is left out.
pub(super) enum Entry {
    Data(JobData),
    Skipped(Skipped),
}

/// Analyses the job `id` in group `g` (module doc), keeping its spectrum bins up to
/// `keep_cap` [Hz]; with its constant speed [Hz] when it ended ok ([`analysable_speed`], what
/// sets the study's cap).
pub(super) fn analyse_job(
    g: &hdf5::Group,
    id: &str,
    (varying, axes, spec): (&[String], &[LabelledAxis], &AnalysisSpec),
    keep_cap: f64,
) -> hdf5::Result<(Option<f64>, Entry)> {
    let orders = &spec.orders;
    let values: BTreeMap<String, String> = varying
        .iter()
        .filter_map(|k| Some((k.clone(), param_text(&store::read_param(g, k).ok()?))))
        .collect();
    let labels: BTreeMap<String, String> = axes
        .iter()
        .filter_map(|a| {
            let k = &a.keys[0];
            Some((k.clone(), store::read_str(g, &format!("label:{k}")).ok()?))
        })
        .collect();
    // The samples of a job that ended ok at a constant speed (of no other: not read).
    let speed = analysable_speed(g);
    let (time, channels) = match speed {
        Some(_) => (
            g.dataset("time")
                .and_then(|d| d.read_raw::<f64>())
                .unwrap_or_default(),
            store::runout_channels(g),
        ),
        None => (Vec::new(), Vec::new()),
    };
    let speed_hz = match speed {
        Some(s) if time.len() >= 2 && time[time.len() - 1] > time[0] && !channels.is_empty() => s,
        _ => {
            return Ok((
                speed,
                Entry::Skipped(Skipped {
                    values,
                    labels,
                    speed_hz: store::read_num(g, "speed_hz").unwrap_or(f64::NAN),
                    id: id.to_string(),
                }),
            ));
        }
    };
    // The study's orders, and 1× for the trial-mass response, fitted together.
    let mut freqs: Vec<f64> = orders.iter().map(|o| o * speed_hz).collect();
    let one = orders.iter().position(|o| *o == 1.0).unwrap_or_else(|| {
        freqs.push(speed_hz);
        orders.len()
    });
    let n = time.len();
    let rate_hz = (n - 1) as f64 / (time[n - 1] - time[0]);
    // Phases against the roll angle θ = Ω t + δ: a line at order o turns back by o·δ.
    let delta = store::read_num(g, "roll_angle_offset_rad").unwrap_or(0.0);
    let (lines, one_x) = channels
        .iter()
        .map(|(_, x)| {
            let mut z = signal::lines(x, &time, &freqs);
            for (zk, fk) in z.iter_mut().zip(&freqs) {
                *zk = if *fk < 0.5 * rate_hz {
                    *zk * Complex64::from_polar(1.0, -fk / speed_hz * delta)
                } else {
                    // Above the Nyquist frequency the record cannot tell the line.
                    Complex64::new(f64::NAN, f64::NAN)
                };
            }
            let one_x = z[one];
            z.truncate(orders.len());
            (z, one_x)
        })
        .unzip();
    let (means, full): (Vec<f64>, Vec<signal::Spectrum>) = channels
        .iter()
        .map(|(_, x)| signal::mean_and_spectrum(x, rate_hz))
        .unzip();
    let names: Vec<String> = channels.into_iter().map(|(name, _)| name).collect();
    if !g.link_exists("spectrum") {
        let cap = spec
            .max_freq_hz
            .unwrap_or_else(|| default_cap(orders, speed_hz));
        let own = bins_below(&full[0].freq_hz, cap);
        store::dataset(g, "spectrum/freq_hz", &full[0].freq_hz[..own], "Hz")?;
        for (name, s) in names.iter().zip(&full) {
            store::dataset(g, &format!("spectrum/{name}"), &s.amplitude[..own], "um")?;
        }
        store::scales::attach_axis(&g.group("spectrum")?, "freq_hz", &[""], 0)?;
    }
    if !g.link_exists("runout_mean") {
        for (name, m) in names.iter().zip(&means) {
            scalar_dataset(g, &format!("runout_mean/{name}"), *m, "um")?;
        }
    }
    let keep = bins_below(&full[0].freq_hz, keep_cap);
    Ok((
        speed,
        Entry::Data(JobData {
            id: id.to_string(),
            speed_hz,
            samples: n,
            rate_hz,
            freq_hz: full[0].freq_hz[..keep].to_vec(),
            spectra: full.iter().map(|s| s.amplitude[..keep].to_vec()).collect(),
            means,
            names,
            values,
            labels,
            lines,
            one_x,
        }),
    ))
}

/// Jobs analysed as a run saved them (module doc): each job's [`Entry`] and its constant speed
/// (what sets the study's cap), for the analysis of the study `text` over the `varying` keys.
pub struct Prepared {
    pub(super) text: String,
    pub(super) varying: Vec<String>,
    /// The highest frequency [Hz] kept of each spectrum: the cap at the study's top speed.
    pub(super) keep_cap: f64,
    axes: Vec<LabelledAxis>,
    spec: AnalysisSpec,
    pub(super) entries: BTreeMap<String, (Option<f64>, Entry)>,
}

impl Prepared {
    /// For a study of text `text`, the `varying` keys, and jobs of at most `top_speed_hz` [Hz]
    /// (over the record).
    pub fn new(text: &str, varying: &[String], top_speed_hz: f64) -> Prepared {
        let StudyAnalysis {
            spec,
            labelled: axes,
            ..
        } = analysis_of_text(text).unwrap_or_default();
        let keep_cap = spec
            .max_freq_hz
            .unwrap_or_else(|| default_cap(&spec.orders, top_speed_hz));
        Prepared {
            text: text.to_string(),
            varying: varying.to_vec(),
            keep_cap,
            axes,
            spec,
            entries: BTreeMap::new(),
        }
    }

    /// Analyses the job `id` just written to `g`, writing its means and spectra there.
    pub fn add(&mut self, g: &hdf5::Group, id: &str) -> hdf5::Result<()> {
        let context = (self.varying.as_slice(), self.axes.as_slice(), &self.spec);
        let analysed = analyse_job(g, id, context, self.keep_cap)?;
        self.entries.insert(id.to_string(), analysed);
        Ok(())
    }
}

/// A parameter as the analysis's texts show it (numbers as the report writes them).
pub(super) fn param_text(p: &Param) -> String {
    match p {
        Param::Number(x) => number_text(*x),
        other => other.to_string(),
    }
}

/// Writes a scalar float dataset with a `units` attribute, creating the intermediate groups of
/// a path-like name.
pub(super) fn scalar_dataset(
    group: &hdf5::Group,
    name: &str,
    value: f64,
    units: &str,
) -> hdf5::Result<()> {
    let (parent, leaf) = match name.rsplit_once('/') {
        Some((p, l)) => (store::subgroup(group, p)?, l),
        None => (group.clone(), name),
    };
    let ds = parent.new_dataset::<f64>().shape(()).create(leaf)?;
    ds.write_scalar(&value)?;
    store::attr_str(&ds, "units", units)
}

/// The number of spectrum bins at or below `max_hz`.
pub(super) fn bins_below(freq_hz: &[f64], max_hz: f64) -> usize {
    freq_hz.iter().take_while(|f| **f <= max_hz + 1e-9).count()
}
