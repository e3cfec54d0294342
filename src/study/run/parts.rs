//! Part files: each finished run saved at once to its own file, until the output is assembled.
//!
//! In: a finished run's result and attributes, and the study's digest ([`Identity`]). Out:
//! `OUT.h5.parts/<id>.h5`, written under `<id>.h5.tmp` and renamed, so a `kill -9` at any
//! moment loses only the runs still going; a rotorsweep results file with the run as its `job`
//! group and the root attributes `study_digest` and `study_inputs` (which files, so a resume
//! after an edit knows its own earlier parts). Also: which saved parts a resumed run reuses
//! (those of its own runs with its digest), and the removal of a parts folder, which removes
//! only files rotorsweep wrote (judged by content, not only by name) and refuses anything else.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use super::error::{describe_hdf5, CampaignError};
use crate::dynamics::simulation::JobResult;
use crate::store::output::{self, OutputError};
use crate::store::{self, Param};
use crate::study::identity::Identity;

/// Where a run on `out` keeps its finished jobs until the file is assembled.
pub fn parts_dir(out: &Path) -> PathBuf {
    store::with_suffix(out, ".parts")
}

/// Writes one finished run `id` (its attributes `params`) to its own part file, atomically,
/// tagged with the study's digest.
pub(super) fn save_part(
    dir: &Path,
    id: &str,
    params: &[(String, Param)],
    integrator: &str,
    r: &JobResult,
    identity: &Identity,
) -> Result<(), CampaignError> {
    let tmp = dir.join(format!("{id}.h5.tmp"));
    let fin = dir.join(format!("{id}.h5"));
    output::check_working_file(&tmp)?;
    let write = || -> hdf5::Result<()> {
        let f = hdf5::File::create(&tmp)?;
        store::attr_str(&f, "tool", "rotorsweep")?;
        store::attr_str(&f, "tool_version", env!("CARGO_PKG_VERSION"))?;
        store::attr_str(&f, "study_digest", &identity.digest)?;
        store::attr_str(&f, "study_inputs", &identity.inputs_text())?;
        store::write_job(&f, "job", params, integrator, r)?;
        f.close()
    };
    if let Err(e) = write() {
        let reason = describe_hdf5(&tmp, &e);
        let _ = std::fs::remove_file(&tmp);
        return Err(CampaignError::io(&tmp, reason));
    }
    std::fs::rename(&tmp, &fin).map_err(|e| CampaignError::io(&fin, e))?;
    Ok(())
}

/// The saved parts of a run: ids whose part file carries the study's digest, and the number of
/// parts made from other inputs (or unreadable), which are run again: among them the parts of
/// this study before an edit (the same study file, another digest), whose ids are no longer
/// jobs when the edit changed a scene. A file there that rotorsweep did not write (not HDF5
/// with `tool = rotorsweep` and a `job` group), or a saved job of another study or another
/// shard on the same output, is refused: nothing in the folder is replaced or removed that is
/// not this run's own.
pub(super) fn saved_parts(
    dir: &Path,
    identity: &Identity,
    wanted: &BTreeSet<&str>,
) -> Result<(BTreeSet<String>, usize), CampaignError> {
    let digest = identity.digest.as_str();
    let study_file = identity.inputs.iter().find(|f| f.role == "study");
    // A part of this study's earlier inputs: the same study file, edited (or what it reads).
    let earlier = |f: &hdf5::File| {
        let d = store::read_str(f, "study_digest").unwrap_or_default();
        let inputs = store::read_str(f, "study_inputs").unwrap_or_default();
        !d.is_empty()
            && d != digest
            && Identity::parse_inputs(&inputs)
                .iter()
                .any(|i| study_file.is_some_and(|s| s.role == i.role && s.path == i.path))
    };
    let mut done = BTreeSet::new();
    let mut stale = 0;
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Ok((done, 0));
    };
    for e in rd.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(id) = name.strip_suffix(".h5") else {
            continue;
        };
        let path = e.path();
        let f = open_part(&path).map_err(|why| {
            OutputError::Refused(
                path.clone(),
                format!("{why}: it is not a saved job of rotorsweep's; move it away"),
            )
        })?;
        if !wanted.contains(id) {
            if earlier(&f) {
                stale += 1;
                continue;
            }
            return Err(CampaignError::Usage(format!(
                "{}: a saved job that is not in this run (another shard's, or another study's, \
                 on the same output): finish that run into this output, or choose another -o, \
                 or run with --overwrite instead of --resume to discard the saved jobs",
                path.display()
            )));
        }
        if store::read_str(&f, "study_digest").is_ok_and(|d| d == digest) {
            done.insert(id.to_string());
        } else {
            stale += 1;
        }
    }
    Ok((done, stale))
}

/// A saved job's part file, opened: a rotorsweep results file with a `job` group.
fn open_part(path: &Path) -> Result<hdf5::File, String> {
    let f = output::open_results_file(path)?;
    match f.group("job") {
        Ok(_) => Ok(f),
        Err(_) => Err("has no `job` group".into()),
    }
}

/// Whether a file in a parts folder is one of rotorsweep's: a part file (a rotorsweep HDF5 file
/// with a `job` group), a part's temporary name (empty or HDF5), or pilot shares (one number a
/// line), judged by content, not only by name. Parts of the `known` ids (saved or checked by
/// this run) are not opened again.
fn is_own_part(path: &Path, known: &BTreeSet<&str>) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.ends_with(".h5.tmp") {
        output::is_own_leftover(path)
    } else if let Some(id) = name.strip_suffix(".h5") {
        known.contains(id) || open_part(path).is_ok()
    } else if name.ends_with(".shares") {
        std::fs::read_to_string(path)
            .is_ok_and(|t| t.lines().all(|l| l.trim().parse::<f64>().is_ok()))
    } else {
        false
    }
}

/// Removes a parts folder: only rotorsweep's own regular files, then the folder; anything
/// else in it is refused (nothing a user put there is removed). `known`: ids whose part files
/// this run saved or checked itself.
pub fn remove_parts(dir: &Path, known: &BTreeSet<&str>) -> Result<(), CampaignError> {
    let meta = std::fs::symlink_metadata(dir).map_err(|e| CampaignError::io(dir, e))?;
    if !meta.is_dir() {
        return Err(OutputError::Refused(
            dir.to_path_buf(),
            "is not a folder, where rotorsweep keeps the saved jobs of a run".into(),
        )
        .into());
    }
    let entries: Vec<std::fs::DirEntry> = std::fs::read_dir(dir)
        .map_err(|e| CampaignError::io(dir, e))?
        .filter_map(|e| e.ok())
        .collect();
    if let Some(bad) = entries
        .iter()
        .find(|e| !e.file_type().is_ok_and(|t| t.is_file()) || !is_own_part(&e.path(), known))
    {
        return Err(OutputError::Refused(
            dir.to_path_buf(),
            format!(
                "holds {}, which rotorsweep did not write",
                bad.path().display()
            ),
        )
        .into());
    }
    for e in entries {
        std::fs::remove_file(e.path()).map_err(|x| CampaignError::io(&e.path(), x))?;
    }
    std::fs::remove_dir(dir).map_err(|e| CampaignError::io(dir, e))
}
