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
//! The same analysis runs on a job's group ([`JobRecord::read`]) or on a finished run in memory
//! ([`Analyser::run`], on the worker that ran it: [`JobRecord::of_run`] gives each value as the
//! group would give it back, the runout channels in the group's link order), so the file is the
//! same bit for bit wherever a job was analysed. [`Prepared`]: jobs analysed as a run saves them
//! (`study::run`'s stream), with their order tracking at a constant speed (`orders`), kept
//! until the study-wide analysis, which then reads only the jobs it was not given. Memory per
//! job: its lines and its spectra up to the cap, not its samples.

use std::borrow::Cow;
use std::collections::BTreeMap;

use rustfft::num_complex::Complex64;

use super::request::{analysis_of_text, AnalysisSpec, LabelledAxis, StudyAnalysis, ORDER_MARGIN};
use crate::dynamics::simulation::Channel;
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

/// What the analysis reads of one job (module doc), from its group ([`JobRecord::read`]) or
/// from a finished run in memory ([`JobRecord::of_run`]): the same values either way, so the
/// file is the same wherever a job was analysed.
pub struct JobRecord<'a> {
    id: &'a str,
    values: BTreeMap<String, String>,
    labels: BTreeMap<String, String>,
    /// Its constant speed [Hz] when it ended ok ([`analysable_speed`]).
    speed: Option<f64>,
    /// Its `speed_hz` attribute (NaN when absent).
    speed_attr: f64,
    /// θ = Ω t + δ: δ [rad].
    delta: f64,
    /// Samples [s] and runout channels ("sensor/dir", [µm]) of an analysable job (of no other).
    time: Cow<'a, [f64]>,
    channels: Vec<(String, Cow<'a, [f64]>)>,
    /// The roll angle [rad] recorded beside (`speed/roll_angle`), if any.
    roll_angle: Option<Cow<'a, [f64]>>,
}

impl<'a> JobRecord<'a> {
    /// The job `id` as its group `g` holds it.
    pub fn read(
        g: &hdf5::Group,
        id: &'a str,
        (varying, axes): (&[String], &[LabelledAxis]),
    ) -> JobRecord<'a> {
        let values = varying
            .iter()
            .filter_map(|k| Some((k.clone(), param_text(&store::read_param(g, k).ok()?))))
            .collect();
        let labels = axes
            .iter()
            .filter_map(|a| {
                let k = &a.keys[0];
                Some((k.clone(), store::read_str(g, &format!("label:{k}")).ok()?))
            })
            .collect();
        let speed = analysable_speed(g);
        let (time, channels, roll_angle) = match speed {
            Some(_) => (
                (g.dataset("time").and_then(|d| d.read_raw::<f64>())).unwrap_or_default(),
                store::runout_channels(g),
                g.dataset("speed/roll_angle")
                    .and_then(|d| d.read_raw::<f64>())
                    .ok(),
            ),
            None => (Vec::new(), Vec::new(), None),
        };
        JobRecord {
            id,
            values,
            labels,
            speed,
            speed_attr: store::read_num(g, "speed_hz").unwrap_or(f64::NAN),
            delta: store::read_num(g, "roll_angle_offset_rad").unwrap_or(0.0),
            time: Cow::Owned(time),
            channels: (channels.into_iter())
                .map(|(n, x)| (n, Cow::Owned(x)))
                .collect(),
            roll_angle: roll_angle.map(Cow::Owned),
        }
    }

    /// The run `id` as `store::write_job` writes it from its attributes `params`, its status
    /// name and its result's `time` and `channels`: each value as reading it back gives it
    /// (`store::read_param`), the runout channels in the order the group lists them
    /// ([`link_order`]); `None` when that order is not known without the file.
    pub fn of_run(
        id: &'a str,
        params: &[(String, Param)],
        status: &str,
        (time, channels): (&'a [f64], &'a [Channel]),
        (varying, axes): (&[String], &[LabelledAxis]),
    ) -> Option<JobRecord<'a>> {
        let param = |k: &str| params.iter().find(|(n, _)| n == k).map(|(_, v)| v);
        let number = |k: &str| match param(k) {
            Some(Param::Number(x)) => Some(*x),
            Some(Param::Count(n)) => Some(*n as f64),
            _ => None,
        };
        let values = varying
            .iter()
            .filter_map(|k| Some((k.clone(), param_text(&as_read_back(param(k)?)))))
            .collect();
        let labels = axes
            .iter()
            .filter_map(|a| {
                let k = &a.keys[0];
                match param(&format!("label:{k}"))? {
                    Param::Text(t) => Some((k.clone(), t.clone())),
                    _ => None,
                }
            })
            .collect();
        let speed_attr = number("speed_hz").unwrap_or(f64::NAN);
        let ok = Status::name_completed(status);
        let speed = (ok && speed_attr > 0.0 && speed_attr.is_finite()).then_some(speed_attr);
        let runout = match speed {
            Some(_) => link_order(channels)?,
            None => Vec::new(),
        };
        let roll_angle = speed.and(
            (channels.iter())
                .find(|c| c.name == "speed/roll_angle")
                .map(|c| Cow::Borrowed(&c.data[..])),
        );
        Some(JobRecord {
            id,
            values,
            labels,
            speed,
            speed_attr,
            delta: number("roll_angle_offset_rad").unwrap_or(0.0),
            time: Cow::Borrowed(if speed.is_some() { time } else { &[] }),
            channels: (runout.into_iter())
                .map(|(name, x)| (name, Cow::Borrowed(x)))
                .collect(),
            roll_angle,
        })
    }
}

/// A named channel's samples.
pub(super) type Named<'a> = (&'a str, &'a [f64]);

/// Links a group holds in the compact form HDF5 lists in the order they were made; from the
/// ninth on it stores them densely and lists them in the order of its name index (the default
/// link phase change, `H5Pset_link_phase_change`: 8).
const COMPACT_LINKS: usize = 8;

/// The runout channels `runout/<sensor>/<dir>` of a result in the order `store::runout_channels`
/// reads them back from the group `store::write_job` writes: sensors in the order their groups
/// were made (their first channel's), each sensor's directions in the order written (the `time`
/// axis linked beside them afterwards is not a channel); `None` when a group would hold more
/// than [`COMPACT_LINKS`] links (dense: the order is the library's name index's).
fn link_order(channels: &[Channel]) -> Option<Vec<(String, &[f64])>> {
    let mut sensors: Vec<(&str, Vec<Named>)> = Vec::new();
    for c in channels {
        let Some((sensor, dir)) = (c.name.strip_prefix("runout/")).and_then(|r| r.split_once('/'))
        else {
            continue;
        };
        if dir.contains('/') {
            // A group below the sensor's, which the reading skips.
            return None;
        }
        match sensors.iter_mut().find(|(s, _)| *s == sensor) {
            Some((_, dirs)) => dirs.push((dir, &c.data)),
            None => sensors.push((sensor, vec![(dir, &c.data)])),
        }
    }
    // The sensor groups, and in each its directions and the `time` link.
    if sensors.len() > COMPACT_LINKS || sensors.iter().any(|(_, d)| d.len() + 1 > COMPACT_LINKS) {
        return None;
    }
    Some(
        (sensors.into_iter())
            .flat_map(|(s, dirs)| dirs.into_iter().map(move |(d, x)| (format!("{s}/{d}"), x)))
            .collect(),
    )
}

/// A parameter as reading its attribute back gives it (a count through f64).
fn as_read_back(p: &Param) -> Param {
    match p {
        Param::Count(n) => Param::Count(*n as f64 as u64),
        other => other.clone(),
    }
}

/// A job tracked at a constant speed in memory (on the worker that ran it; `orders` tracks the
/// others from the file): its
/// runout channels' names ("sensor/dir") and its one block (none: nothing to track).
pub struct Tracked {
    pub(super) names: Vec<String>,
    pub(super) blocks: Vec<signal::orders::Block>,
}

/// The order tracking of a job that ended ok at a constant speed (`rec`; `orders`' module doc);
/// `None` when it cannot be tracked (left out of the tables, as `orders::write` leaves it).
fn track_constant(rec: &JobRecord, spec: &AnalysisSpec) -> Option<Tracked> {
    let (time, channels, theta) = rec.angle_inputs();
    let signals: Vec<&[f64]> = channels.iter().map(|(_, x)| *x).collect();
    let blocks = signal::orders::whole(time, &theta, &signals, &spec.orders).ok()?;
    Some(Tracked {
        names: channels.iter().map(|(n, _)| n.to_string()).collect(),
        blocks: blocks.into_iter().collect(),
    })
}

/// One job analysed (module doc): its constant speed when it ended ok (what sets the study's
/// cap), its [`Entry`] (of an analysable job: its spectra up to the larger of its own cap and
/// the kept one, until [`Analysed::write_into`]), how many spectrum bins its group gets (its own
/// cap's), and its order tracking at a constant speed (`None` when the speed changes: tracked
/// from the file, `results::orders`).
pub struct Analysed {
    speed: Option<f64>,
    entry: Entry,
    own_bins: usize,
    tracked: Option<Tracked>,
}

impl Analysed {
    /// Writes its spectra and means into its group `g` (module doc) and keeps its spectrum bins
    /// up to `keep_cap` [Hz].
    fn write_into(&mut self, g: &hdf5::Group, keep_cap: f64) -> hdf5::Result<()> {
        if let Entry::Data(d) = &mut self.entry {
            write_analysed(g, d, self.own_bins)?;
            d.keep_below(keep_cap);
        }
        Ok(())
    }
}

/// Analyses one job's record (module doc), keeping its spectrum bins up to `keep_cap` [Hz].
pub fn analyse_record(rec: &JobRecord, spec: &AnalysisSpec, keep_cap: f64) -> Analysed {
    let orders = &spec.orders;
    let time = &rec.time[..];
    let tracked = (rec.speed.is_some() && time.len() >= 3 && !rec.channels.is_empty())
        .then(|| track_constant(rec, spec))
        .flatten();
    let speed_hz = match rec.speed {
        Some(s)
            if time.len() >= 2 && time[time.len() - 1] > time[0] && !rec.channels.is_empty() =>
        {
            s
        }
        _ => {
            return Analysed {
                speed: rec.speed,
                entry: Entry::Skipped(Skipped {
                    values: rec.values.clone(),
                    labels: rec.labels.clone(),
                    speed_hz: rec.speed_attr,
                    id: rec.id.to_string(),
                }),
                own_bins: 0,
                tracked,
            };
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
    let delta = rec.delta;
    let (lines, one_x) = (rec.channels.iter())
        .map(|(_, x)| {
            let mut z = signal::lines(x, time, &freqs);
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
    let (means, full): (Vec<f64>, Vec<signal::Spectrum>) = (rec.channels.iter())
        .map(|(_, x)| signal::mean_and_spectrum(x, rate_hz))
        .unzip();
    let names: Vec<String> = rec.channels.iter().map(|(name, _)| name.clone()).collect();
    let cap = spec
        .max_freq_hz
        .unwrap_or_else(|| default_cap(orders, speed_hz));
    let own = bins_below(&full[0].freq_hz, cap);
    let keep = bins_below(&full[0].freq_hz, keep_cap).max(own);
    Analysed {
        speed: rec.speed,
        entry: Entry::Data(JobData {
            id: rec.id.to_string(),
            speed_hz,
            samples: n,
            rate_hz,
            freq_hz: full[0].freq_hz[..keep].to_vec(),
            spectra: full.iter().map(|s| s.amplitude[..keep].to_vec()).collect(),
            means,
            names,
            values: rec.values.clone(),
            labels: rec.labels.clone(),
            lines,
            one_x,
        }),
        own_bins: own,
        tracked,
    }
}

impl JobRecord<'_> {
    /// Its samples [s], runout channels and roll angle (recorded, else θ = Ω t + δ) for order
    /// tracking at its constant speed (`results::orders`).
    pub(super) fn angle_inputs(&self) -> (&[f64], Vec<Named<'_>>, Cow<'_, [f64]>) {
        let theta = match (&self.roll_angle, self.speed) {
            (Some(t), _) => Cow::Borrowed(&t[..]),
            (None, s) => {
                let w = std::f64::consts::TAU * s.unwrap_or(f64::NAN);
                Cow::Owned(self.time.iter().map(|t| w * t + self.delta).collect())
            }
        };
        let channels = (self.channels.iter())
            .map(|(n, x)| (n.as_str(), &x[..]))
            .collect();
        (&self.time, channels, theta)
    }
}

/// Writes what the analysis puts into a job's group (unless there already, as in a merged
/// shard's): `spectrum/…` up to its first `own` bins and `runout_mean/…` (module doc).
fn write_analysed(g: &hdf5::Group, d: &JobData, own: usize) -> hdf5::Result<()> {
    if !g.link_exists("spectrum") {
        store::dataset(g, "spectrum/freq_hz", &d.freq_hz[..own], "Hz")?;
        for (name, s) in d.names.iter().zip(&d.spectra) {
            store::dataset(g, &format!("spectrum/{name}"), &s[..own], "um")?;
        }
        store::scales::attach_axis(&g.group("spectrum")?, "freq_hz", &[""], 0)?;
    }
    if !g.link_exists("runout_mean") {
        for (name, m) in d.names.iter().zip(&d.means) {
            scalar_dataset(g, &format!("runout_mean/{name}"), *m, "um")?;
        }
    }
    Ok(())
}

/// Analyses the job `id` in group `g` (module doc) and writes its spectra and means there,
/// keeping its spectrum bins up to `keep_cap` [Hz]; with its constant speed [Hz] when it ended
/// ok ([`analysable_speed`], what sets the study's cap).
pub(super) fn analyse_job(
    g: &hdf5::Group,
    id: &str,
    (varying, axes, spec): (&[String], &[LabelledAxis], &AnalysisSpec),
    keep_cap: f64,
) -> hdf5::Result<(Option<f64>, Entry)> {
    let rec = JobRecord::read(g, id, (varying, axes));
    let mut a = analyse_record(&rec, spec, keep_cap);
    a.write_into(g, keep_cap)?;
    Ok((a.speed, a.entry))
}

/// Jobs analysed as a run saved them (module doc): each job's [`Entry`] and its constant speed
/// (what sets the study's cap), and its order tracking at a constant speed, for the analysis of
/// the study `text` over the `varying` keys.
pub struct Prepared {
    pub(super) text: String,
    pub(super) varying: Vec<String>,
    analyser: Analyser,
    pub(super) entries: BTreeMap<String, (Option<f64>, Entry)>,
    /// Order tracking of the jobs at a constant speed (`None`: a job with nothing to track).
    pub(super) tracked: BTreeMap<String, Option<Tracked>>,
}

/// How a study's jobs are analysed one by one: its analysis request, labelled axes, varying
/// keys and the highest frequency [Hz] kept of each spectrum (the cap at the study's top speed).
/// Shared by the workers of a run, each analysing the job it ran ([`Analyser::run`]).
#[derive(Clone)]
pub struct Analyser {
    varying: Vec<String>,
    axes: Vec<LabelledAxis>,
    spec: AnalysisSpec,
    pub(super) keep_cap: f64,
}

impl Analyser {
    /// For a study of text `text`, the `varying` keys, and jobs of at most `top_speed_hz` [Hz]
    /// (over the record).
    pub fn new(text: &str, varying: &[String], top_speed_hz: f64) -> Analyser {
        let StudyAnalysis {
            spec,
            labelled: axes,
            ..
        } = analysis_of_text(text).unwrap_or_default();
        let keep_cap = spec
            .max_freq_hz
            .unwrap_or_else(|| default_cap(&spec.orders, top_speed_hz));
        Analyser {
            varying: varying.to_vec(),
            axes,
            spec,
            keep_cap,
        }
    }

    /// Analyses a finished run in memory ([`JobRecord::of_run`]; `None`: it is analysed when
    /// read back).
    pub fn run(
        &self,
        id: &str,
        params: &[(String, Param)],
        status: &str,
        (time, channels): (&[f64], &[Channel]),
    ) -> Option<Analysed> {
        let context = (self.varying.as_slice(), self.axes.as_slice());
        let rec = JobRecord::of_run(id, params, status, (time, channels), context)?;
        Some(analyse_record(&rec, &self.spec, self.keep_cap))
    }
}

impl Prepared {
    /// For a study of text `text` whose jobs the `analyser` analyses.
    pub fn new(text: &str, analyser: &Analyser) -> Prepared {
        Prepared {
            text: text.to_string(),
            varying: analyser.varying.clone(),
            analyser: analyser.clone(),
            entries: BTreeMap::new(),
            tracked: BTreeMap::new(),
        }
    }

    /// The highest frequency [Hz] kept of each spectrum.
    pub(super) fn keep_cap(&self) -> f64 {
        self.analyser.keep_cap
    }

    /// Analyses the job `id` just written to `g` (read back), writing its means and spectra
    /// there.
    pub fn add(&mut self, g: &hdf5::Group, id: &str) -> hdf5::Result<()> {
        let a = &self.analyser;
        let rec = JobRecord::read(g, id, (&a.varying, &a.axes));
        let analysed = analyse_record(&rec, &a.spec, a.keep_cap);
        self.add_analysed(g, id, analysed)
    }

    /// Keeps the job `id` analysed in memory (`analysed`, by [`Analyser::run`]) and writes its
    /// means and spectra into its group `g`.
    pub fn add_analysed(&mut self, g: &hdf5::Group, id: &str, mut a: Analysed) -> hdf5::Result<()> {
        a.write_into(g, self.analyser.keep_cap)?;
        if a.speed.is_some() {
            self.tracked.insert(id.to_string(), a.tracked);
        }
        self.entries.insert(id.to_string(), (a.speed, a.entry));
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
