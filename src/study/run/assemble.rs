//! Assembly: the finished runs of a run joined into its results file.
//!
//! In: the results file the run filled with its runs as they were saved (`stream`), if it has
//! one, the saved part files (where each run is), the models the run built and the pruning pilots' shares, the jobs
//! whose linearised systems it stores, and the shared references file (if any). Out: `OUT.h5`,
//! written under `OUT.h5.tmp` and renamed over the output when complete and read back: the
//! study's attributes (digest, inputs, name, path, text, varying keys, shard, threads),
//! `/models/<id>` (mode table and pilot shares), `/linear/<id>` (`rotorsweep linear`'s layout
//! of each distinct linearised system), `/references/<id>`, `/jobs/<id>` with the errors
//! against their reference runs (`references`), then the analysis and `/summary`
//! (`results::write`, as `merge` and `simulate -o` write theirs). Shared references, their
//! models and linearised systems are copied from the references file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use super::error::{describe_hdf5, free_bytes, CampaignError};
use super::linear::Systems;
use super::models::Models;
use super::options::RunOptions;
use super::parts::{OpenParts, Saved};
use super::references::write_errors;
use super::stream::Stream;
use crate::dynamics::model::Model;
use crate::linear::request::Results;
use crate::results::write::{complete, write_whole, Analysis};
use crate::store::{self, output};
use crate::study::identity::Identity;
use crate::study::{Job, Reference, Study};

/// What a run assembles its file from: the saved parts, the jobs whose linearised systems it
/// stores, the shared references file (if any), the models it built and the pruning pilots'
/// shares.
pub(super) struct Sources<'a> {
    pub(super) linear: &'a [&'a Job],
    pub(super) shared: Option<&'a hdf5::File>,
    pub(super) models: &'a Models<'a>,
    /// The linear systems the run computed (`linear`).
    pub(super) systems: &'a Systems,
    /// Where each saved run is (`parts`).
    pub(super) saved: &'a BTreeMap<String, Saved>,
}

/// Builds the final file (module doc) under a temporary name: the `stream` this run filled
/// with its runs, completed, or (when it has none) a new file.
pub(super) fn assemble(
    study: &Study,
    opts: &RunOptions,
    identity: &Identity,
    jobs: &[&Job],
    refs: &[&Reference],
    src: &Sources,
    stream: Stream,
) -> Result<(), CampaignError> {
    let tmp = store::with_suffix(&opts.output, ".tmp");
    let analysis = Analysis::Noted {
        output: &opts.output,
    };
    let (open, copied) = match stream.take() {
        Some((f, copied, prepared)) => (Some((f, prepared)), copied),
        None => (None, BTreeSet::new()),
    };
    let body = |f: &hdf5::File| {
        store::provenance(f, &opts.command)?;
        store::attr_str(f, "study_digest", &identity.digest)?;
        store::attr_str(f, "study_inputs", &identity.inputs_text())?;
        store::attr_u64(f, "threads", opts.threads as u64)?;
        store::attr_str(f, "study_name", &study.name)?;
        store::attr_str(f, "study_path", &study.path.display().to_string())?;
        store::attr_str(f, "study_text", &study.text)?;
        store::attr_str(f, "varying_keys", &study.varying.join("\n"))?;
        store::attr_str(f, "shard", &opts.shard_text())?;
        write_models(f, refs, src)?;
        write_linear_systems(f, src)?;
        write_runs(f, study, jobs, refs, src, &copied)?;
        Ok(study.varying.clone())
    };
    let written = match open {
        Some((f, prepared)) => complete(f, analysis, Some(prepared), body),
        None => write_whole(&tmp, analysis, body),
    };
    finish_output(&tmp, &opts.output, written)
}

/// `/models`: every model the run built, then the shared references' models it did not
/// build (a model that failed to build is absent there too).
fn write_models(f: &hdf5::File, refs: &[&Reference], src: &Sources) -> hdf5::Result<()> {
    let models = &src.models.built;
    let mg = f.create_group("models")?;
    for (id, m) in models {
        if let Ok(m) = m {
            write_model(&mg, id, m, src.models.shares.get(*id))?;
        }
    }
    if let Some(shared) = src.shared {
        let sm = shared.group("models")?;
        let wanted: BTreeSet<&str> = refs.iter().map(|r| r.model_id.as_str()).collect();
        for id in wanted {
            if !models.contains_key(id) && sm.link_exists(id) {
                store::copy_object(&sm, id, &mg, id)?;
            }
        }
    }
    Ok(())
}

/// `/linear`: one linearised system per distinct model, supports, drive and gravity; copied
/// when the references file holds it.
fn write_linear_systems(f: &hdf5::File, src: &Sources) -> hdf5::Result<()> {
    let lg = f.create_group("linear")?;
    let ids: BTreeSet<&str> = src.linear.iter().map(|j| j.linear_id.as_str()).collect();
    let shared_linear = src.shared.map(|s| s.group("linear")).transpose()?;
    for lid in ids {
        if let Some(sl) = shared_linear.as_ref().filter(|g| g.link_exists(lid)) {
            store::copy_object(sl, lid, &lg, lid)?;
        } else if let Some((model_id, results)) = src.systems.get(lid) {
            write_linear(&lg.create_group(lid)?, model_id, results)?;
        }
    }
    Ok(())
}

/// `/references` (from the parts, or copied from the shared references file) and `/jobs`
/// (from the parts, with their errors against their reference runs), in plan order, except
/// the runs the stream already `copied` into the file.
fn write_runs(
    f: &hdf5::File,
    study: &Study,
    jobs: &[&Job],
    refs: &[&Reference],
    src: &Sources,
    copied: &BTreeSet<String>,
) -> hdf5::Result<()> {
    let mut parts = OpenParts::default();
    let group = |name: &str| f.group(name).or_else(|_| f.create_group(name));
    let rg = group("references")?;
    for r in refs.iter().filter(|r| !copied.contains(&r.id)) {
        match src.shared {
            Some(shared) => {
                let g = shared.group("references")?;
                store::copy_object(&g, &r.id, &rg, &r.id)?
            }
            None => parts.copy(src.saved, &r.id, &rg)?,
        }
    }
    let jg = group("jobs")?;
    for j in jobs {
        if !copied.contains(&j.id) {
            parts.copy(src.saved, &j.id, &jg)?;
        }
        let g = jg.group(&j.id)?;
        let reference = rg
            .group(&j.reference_id)
            .ok()
            .filter(|_| study.has_reference);
        write_errors(&g, &j.reference_id, reference.as_ref())?;
    }
    Ok(())
}

/// A job's model on its linearised supports (`/linear/<linear_id>`): the analyses the study's
/// `[linear]` table asks for in the layout of `rotorsweep linear -o`
/// ([`crate::linear::request::Results::write`], without wall times), and the attribute
/// `model_id`; a failure is stored as the attribute `linear_error`.
fn write_linear(
    g: &hdf5::Group,
    model_id: &str,
    results: &Result<Results, String>,
) -> hdf5::Result<()> {
    store::attr_str(g, "model_id", model_id)?;
    match results {
        Ok(r) => r.write(g, false),
        Err(e) => store::attr_str(g, "linear_error", e),
    }
}

fn write_model(
    group: &hdf5::Group,
    id: &str,
    m: &Model,
    shares: Option<&Vec<f64>>,
) -> hdf5::Result<()> {
    let g = group.create_group(id)?;
    let r = &m.full;
    store::attr_str(&g, "modes", &m.reduced.counts_label())?;
    store::attr_u64(&g, "elements", m.rotor.elements.len() as u64)?;
    store::attr_f64(&g, "mass_kg", m.rotor.mass())?;
    store::dataset(&g, "freq_hz", &r.freq_hz, "Hz")?;
    let idx: Vec<f64> = r.index.iter().map(|&i| i as f64).collect();
    store::dataset(&g, "index", &idx, "1")?;
    store::string_dataset(
        &g,
        "labels",
        &r.labels.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
    )?;
    store::string_dataset(
        &g,
        "kinds",
        &r.kinds.iter().map(|k| k.to_string()).collect::<Vec<_>>(),
    )?;
    if let Some(s) = shares {
        // Shares are per mode of the pilot's set; scatter them onto the full set's indices.
        let mut full = vec![f64::NAN; r.len()];
        for (i, &idx) in m.reduced.index.iter().enumerate() {
            if let (Some(slot), Some(v)) = (full.get_mut(idx), s.get(i)) {
                *slot = *v;
            }
        }
        store::dataset(&g, "strain_energy_share", &full, "1")?;
    }
    Ok(())
}

/// Ends the writing of an output: on success the temporary file is renamed over the output
/// (checked again: only a results file is ever replaced); on failure it is removed and the
/// error names it with its cause.
pub(crate) fn finish_output(
    tmp: &Path,
    out: &Path,
    written: hdf5::Result<()>,
) -> Result<(), CampaignError> {
    if let Err(e) = written {
        let reason = describe_hdf5(tmp, &e);
        let _ = std::fs::remove_file(tmp);
        return Err(CampaignError::io(tmp, reason));
    }
    if let Err(why) = output::verify_written(tmp) {
        let _ = std::fs::remove_file(tmp);
        let dir = tmp
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let free = free_bytes(dir).map_or(String::new(), |b| {
            format!("; {b} bytes free in {}", dir.display())
        });
        return Err(CampaignError::io(
            tmp,
            format!("{why}: the write failed (disk full or a file-size limit?){free}"),
        ));
    }
    if let Err(e) = output::check_replace(out, true) {
        let _ = std::fs::remove_file(tmp);
        return Err(e.into());
    }
    std::fs::rename(tmp, out).map_err(|e| CampaignError::io(out, e))
}
