//! Reference runs: the references file shared by shards, the identity a results file was made
//! with, and each job's runout error against its reference run.
//!
//! In: a references file ([`ReferenceSource::File`](super::ReferenceSource::File)), a results
//! file, a job's group and its reference run's group in the file being assembled. Out: the
//! references file opened once it is checked (its `shard` is `references`, its study digest is
//! the run's, it holds every reference run the run needs); a file's stored (digest, inputs,
//! shard); the job attributes `reference_id`, `error_max_um`, `error_rms_um`, `error_peak_um`
//! [µm] (the worst channel) and the same per channel as `error_*_um:<channel>` (NaN when
//! nothing compares), or `error_cause` when the reference run did not end ok.

use std::path::Path;

use super::error::{hdf5_at, CampaignError};
use super::options::REFERENCES_SHARD;
use crate::error::InputError;
use crate::integrators::Status;
use crate::store::{self, output};
use crate::study::identity::{describe_mismatch, Identity};
use crate::study::Reference;

/// A results file's identity attributes: (digest, inputs text, shard).
pub(crate) fn stored_identity(
    path: &Path,
) -> Result<(String, Option<String>, String), CampaignError> {
    let f = hdf5::File::open(path).map_err(hdf5_at(path))?;
    Ok((
        store::read_str(&f, "study_digest").unwrap_or_default(),
        store::read_str(&f, "study_inputs").ok(),
        store::read_str(&f, "shard").unwrap_or_default(),
    ))
}

/// Whether two paths name one existing file.
pub(super) fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => (x.dev(), x.ino()) == (y.dev(), y.ino()),
        _ => false,
    }
}

/// A references file for a shard ([`ReferenceSource::File`](super::ReferenceSource::File)): a
/// rotorsweep results file written by a references-only run of the same study digest, holding
/// every run of `refs`.
pub(super) fn open_references(
    path: &Path,
    identity: &Identity,
    refs: &[&Reference],
) -> Result<hdf5::File, CampaignError> {
    let f = output::open_results_file(path).map_err(|why| InputError::new(path, why))?;
    let shard = store::read_str(&f, "shard").unwrap_or_default();
    if shard != REFERENCES_SHARD {
        return Err(InputError::new(
            path,
            format!(
                "is not a references file (its shard is `{shard}`): write one with \
                 `rotorsweep run STUDY --references-only -o FILE`"
            ),
        )
        .into());
    }
    let digest = store::read_str(&f, "study_digest").unwrap_or_default();
    if digest != identity.digest {
        let inputs = store::read_str(&f, "study_inputs").ok();
        return Err(InputError::new(
            path,
            format!(
                "holds the reference runs of other inputs ({}): compute them again with \
                 --references-only",
                describe_mismatch(identity, &digest, inputs.as_deref())
            ),
        )
        .into());
    }
    let g = f.group("references").map_err(hdf5_at(path))?;
    if let Some(r) = refs.iter().find(|r| !g.link_exists(&r.id)) {
        return Err(InputError::new(path, format!("has no reference run {}", r.id)).into());
    }
    Ok(f)
}

/// A job's runout error against its reference [µm] (physics.md §8): the max and RMS of the
/// difference over the common samples, and the error of the peak amplitude (half the
/// peak-to-peak runout).
#[derive(Clone, Copy)]
struct RunoutError {
    max: f64,
    rms: f64,
    peak: f64,
}

impl RunoutError {
    const NONE: Self = Self {
        max: f64::NAN,
        rms: f64::NAN,
        peak: f64::NAN,
    };
}

/// The runout error per channel and the worst over channels; NaN when nothing compares.
fn errors_against(
    job: &hdf5::Group,
    reference: &hdf5::Group,
) -> (RunoutError, Vec<(String, RunoutError)>) {
    let a = store::runout_channels(job);
    let b = store::runout_channels(reference);
    let half_pp = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(*x), h.max(*x))
            });
        0.5 * (hi - lo)
    };
    let mut per = Vec::new();
    for (name, x) in &a {
        if let Some((_, y)) = b.iter().find(|(n, _)| n == name) {
            let n = x.len().min(y.len());
            if n == 0 {
                continue;
            }
            let d: Vec<f64> = (0..n).map(|i| x[i] - y[i]).collect();
            per.push((
                name.clone(),
                RunoutError {
                    max: d.iter().map(|v| v.abs()).fold(0.0, f64::max),
                    rms: (d.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt(),
                    peak: (half_pp(&x[..n]) - half_pp(&y[..n])).abs(),
                },
            ));
        }
    }
    let worst = |f: fn(&RunoutError) -> f64| per.iter().map(|p| f(&p.1)).fold(f64::NAN, f64::max);
    let all = RunoutError {
        max: worst(|e| e.max),
        rms: worst(|e| e.rms),
        peak: worst(|e| e.peak),
    };
    (all, per)
}

/// Writes a job's `reference_id` and its errors against that reference run (module doc);
/// `reference` is the run's group in the file, `None` when the study has no reference runs.
pub(super) fn write_errors(
    g: &hdf5::Group,
    reference_id: &str,
    reference: Option<&hdf5::Group>,
) -> hdf5::Result<()> {
    let (err, per) = match reference {
        Some(rgp) => {
            let status = store::read_str(rgp, "status").unwrap_or_default();
            if Status::name_completed(&status) {
                errors_against(g, rgp)
            } else {
                let cause = store::read_str(rgp, "cause").unwrap_or_default();
                store::attr_str(g, "error_cause", &format!("reference {status}: {cause}"))?;
                (RunoutError::NONE, Vec::new())
            }
        }
        None => (RunoutError::NONE, Vec::new()),
    };
    store::attr_str(g, "reference_id", reference_id)?;
    for (suffix, e) in std::iter::once((String::new(), err))
        .chain(per.into_iter().map(|(n, e)| (format!(":{n}"), e)))
    {
        store::attr_f64(g, &format!("error_max_um{suffix}"), e.max)?;
        store::attr_f64(g, &format!("error_rms_um{suffix}"), e.rms)?;
        store::attr_f64(g, &format!("error_peak_um{suffix}"), e.peak)?;
    }
    Ok(())
}
