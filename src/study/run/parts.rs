//! Part files: finished runs saved in batches as they finish, until the output is assembled.
//!
//! In: finished runs (result and attributes) and the study's digest ([`Identity`]). Out:
//! `OUT.h5.parts/batch-<first id>-<count>.journal` (`journal`: written whole under a `.tmp`
//! name and renamed), each tagged with the study's digest and its inputs (which files, so a
//! resume after an edit knows its own earlier parts), and where each run is saved in it
//! ([`Saved`]). The saving thread (`schedule`) writes a batch when it holds [`BATCH_RUNS`] runs
//! or [`BATCH_SAMPLES`] samples, or [`BATCH_SECONDS`] after its first run arrived: one file per
//! batch, not per run, so a `kill -9` loses the runs still going and those finished in the last
//! [`BATCH_SECONDS`], which `--resume` runs again. Also: which saved runs a resumed run reuses
//! (those of its own runs with its digest: in journals, and in the HDF5 part files that earlier
//! versions wrote, a batch `batch-….h5` with a `jobs` group or one run `<id>.h5` with a `job`
//! group), a saved run put into the results file ([`OpenParts`]), and the removal of a parts
//! folder, which removes only files rotorsweep wrote (judged by content, not only by name) and
//! refuses anything else.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::error::{describe_io, CampaignError};
use super::journal::{self, Header, Place};
use crate::dynamics::simulation::JobResult;
use crate::results::job_analysis::Analysed;
use crate::store::output::{self, OutputError};
use crate::store::{self, Param};
use crate::study::identity::Identity;

/// Where a run on `out` keeps its finished jobs until the file is assembled.
pub fn parts_dir(out: &Path) -> PathBuf {
    store::with_suffix(out, ".parts")
}

/// A batch is written when it holds this many runs…
pub(super) const BATCH_RUNS: usize = 256;
/// …or this many recorded samples (time points × channels, all its runs)…
pub(super) const BATCH_SAMPLES: usize = 4_000_000;
/// …or this long after its first run arrived [s].
pub(super) const BATCH_SECONDS: f64 = 1.0;

/// One finished run to save: its id, its part-file attributes, its integrator's name, the name
/// its progress line gives it, its result, and (a job's) its analysis, made on the worker that
/// ran it (not saved: a resumed run is analysed again when it is written).
pub(super) struct Finished<'a> {
    pub(super) id: &'a str,
    pub(super) params: Vec<(String, Param)>,
    pub(super) integrator: &'a str,
    pub(super) name: String,
    pub(super) result: JobResult,
    pub(super) analysed: Option<Analysed>,
}

/// Where a saved run is.
#[derive(Debug, Clone)]
pub(super) enum Saved {
    /// In a journal, at its place there.
    Journal { file: PathBuf, place: Place },
    /// In an HDF5 part file of an earlier version: the path of its group there.
    Part { file: PathBuf, group: String },
}

impl Saved {
    /// The part file it is in.
    fn file(&self) -> &PathBuf {
        match self {
            Saved::Journal { file, .. } | Saved::Part { file, .. } => file,
        }
    }
}

impl Finished<'_> {
    /// What the journal saves of it.
    fn entry(&self) -> journal::Entry<'_> {
        (self.id, &self.params, self.integrator, &self.result)
    }

    /// Writes it into `dst` under its id (the layout of `store::write_job`).
    pub(super) fn write(&self, dst: &hdf5::Group) -> hdf5::Result<()> {
        store::write_job(dst, self.id, &self.params, self.integrator, &self.result)
    }
}

/// Writes a batch of finished runs (non-empty) to one journal, atomically, tagged with the
/// study's digest; where each run is saved.
pub(super) fn save_batch(
    dir: &Path,
    runs: &[Finished],
    identity: &Identity,
) -> Result<Vec<Saved>, CampaignError> {
    let first = runs.first().map_or("empty", |r| r.id);
    let name = format!("batch-{first}-{}{}", runs.len(), journal::EXTENSION);
    let tmp = dir.join(format!("{name}.tmp"));
    let fin = dir.join(&name);
    output::check_working_file_of(&tmp, journal::is_own_leftover)?;
    let header = Header {
        tool_version: env!("CARGO_PKG_VERSION").into(),
        study_digest: identity.digest.clone(),
        study_inputs: identity.inputs_text(),
        runs: runs.len() as u64,
    };
    let entries: Vec<journal::Entry> = runs.iter().map(Finished::entry).collect();
    let (bytes, places) =
        journal::encode(&header, &entries).map_err(|e| CampaignError::io(&tmp, e))?;
    if let Err((e, renaming)) = journal::write(&tmp, &fin, &bytes) {
        let _ = std::fs::remove_file(&tmp);
        let at = if renaming { &fin } else { &tmp };
        return Err(CampaignError::io(at, describe_io(at, &e)));
    }
    Ok(places
        .into_iter()
        .map(|place| Saved::Journal {
            file: fin.clone(),
            place,
        })
        .collect())
}

/// The saved parts of a run: where each run saved with the study's digest is, and the number
/// of saved runs made from other inputs (or unreadable), which are run again: among them the
/// parts of this study before an edit (the same study file, another digest), whose ids are no
/// longer jobs when the edit changed a scene. A file there that rotorsweep did not write (not
/// HDF5 with `tool = rotorsweep` and saved runs), or a saved run of another study or another
/// shard on the same output, is refused: nothing in the folder is replaced or removed that is
/// not this run's own.
pub(super) fn saved_parts(
    dir: &Path,
    identity: &Identity,
    wanted: &BTreeSet<&str>,
) -> Result<(BTreeMap<String, Saved>, usize), CampaignError> {
    let digest = identity.digest.as_str();
    let study_file = identity.inputs.iter().find(|f| f.role == "study");
    // A part of this study's earlier inputs: the same study file, edited (or what it reads).
    let earlier = |p: &PartFile| {
        !p.digest.is_empty()
            && p.digest != digest
            && Identity::parse_inputs(&p.inputs)
                .iter()
                .any(|i| study_file.is_some_and(|s| s.role == i.role && s.path == i.path))
    };
    let mut done = BTreeMap::new();
    let mut stale = 0;
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Ok((done, 0));
    };
    for e in rd.filter_map(|e| e.ok()) {
        let name = e.file_name().to_string_lossy().into_owned();
        if !name.ends_with(".h5") && !name.ends_with(journal::EXTENSION) {
            continue;
        }
        let path = e.path();
        let part = read_part(&path).map_err(|why| {
            let what = if journal::has_tag(&path) {
                "it is a journal of saved runs that cannot be read; move it away (its runs then \
                 run again)"
            } else {
                "it is not a saved job of rotorsweep's; move it away"
            };
            OutputError::Refused(path.clone(), format!("{why}: {what}"))
        })?;
        let same = part.digest == digest;
        let is_earlier = earlier(&part);
        for (id, saved) in part.runs {
            if !wanted.contains(id.as_str()) {
                if is_earlier {
                    stale += 1;
                    continue;
                }
                return Err(CampaignError::Usage(format!(
                    "{}: a saved job ({id}) that is not in this run (another shard's, or another \
                     study's, on the same output): finish that run into this output, or choose \
                     another -o, or run with --overwrite instead of --resume to discard the \
                     saved jobs",
                    path.display()
                )));
            }
            if same {
                done.insert(id, saved);
            } else {
                stale += 1;
            }
        }
    }
    Ok((done, stale))
}

/// A part file read: the study digest and inputs it is tagged with, and its runs.
struct PartFile {
    digest: String,
    inputs: String,
    runs: Vec<(String, Saved)>,
}

/// Reads a journal, or an HDF5 part file of an earlier version.
fn read_part(path: &Path) -> Result<PartFile, String> {
    if path.to_string_lossy().ends_with(journal::EXTENSION) {
        let (header, runs) = journal::read_index(path)?;
        return Ok(PartFile {
            digest: header.study_digest,
            inputs: header.study_inputs,
            runs: runs
                .into_iter()
                .map(|(id, place)| {
                    let file = path.to_path_buf();
                    (id, Saved::Journal { file, place })
                })
                .collect(),
        });
    }
    let (f, runs) = open_part(path)?;
    Ok(PartFile {
        digest: store::read_str(&f, "study_digest").unwrap_or_default(),
        inputs: store::read_str(&f, "study_inputs").unwrap_or_default(),
        runs: runs
            .into_iter()
            .map(|(id, group)| {
                let file = path.to_path_buf();
                (id, Saved::Part { file, group })
            })
            .collect(),
    })
}

/// An HDF5 part file of an earlier version, opened, with its saved runs (id, group path): a
/// rotorsweep results file with a `jobs` group (a batch) or a `job` group (one run, `<id>.h5`).
fn open_part(path: &Path) -> Result<(hdf5::File, Vec<(String, String)>), String> {
    let f = output::open_results_file(path)?;
    if f.group("job").is_ok() {
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
        return Ok((f, vec![(stem.unwrap_or_default(), "job".into())]));
    }
    let runs = match f.group("jobs").and_then(|g| g.member_names()) {
        Ok(names) => names
            .into_iter()
            .map(|id| {
                let group = format!("jobs/{id}");
                (id, group)
            })
            .collect(),
        Err(_) => return Err("has no `jobs` or `job` group".into()),
    };
    Ok((f, runs))
}

/// Whether a file in a parts folder is one of rotorsweep's: a journal (its tag) or an earlier
/// version's part file (a rotorsweep HDF5 file with saved runs), a part's temporary name (empty,
/// tagged or HDF5), or pilot shares (one number a line), judged by content, not only by name. Parts of the `known` ids (saved or checked by
/// this run; one-run files are named by it) are not opened again.
fn is_own_part(path: &Path, known: &BTreeSet<&str>) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.ends_with(".h5.tmp") {
        output::is_own_leftover(path)
    } else if name.ends_with(&format!("{}.tmp", journal::EXTENSION)) {
        journal::is_own_leftover(path)
    } else if name.ends_with(journal::EXTENSION) {
        journal::has_tag(path)
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

/// The part files last read from, most recent last. Runs are batched in the order they finish,
/// which is close to plan order, so copying in plan order mostly stays in one batch and a few
/// open files spare reopening one per run.
#[derive(Default)]
pub(super) struct OpenParts {
    open: Vec<(PathBuf, Open)>,
}

/// An open part file.
enum Open {
    Journal(std::fs::File),
    Part(hdf5::File),
}

impl OpenParts {
    /// How many part files stay open at once.
    const KEEP: usize = 8;

    /// Puts the saved run `id` into `dst` under its id.
    pub(super) fn copy(
        &mut self,
        saved: &BTreeMap<String, Saved>,
        id: &str,
        dst: &hdf5::Group,
    ) -> hdf5::Result<()> {
        let s = saved.get(id).ok_or_else(|| {
            hdf5::Error::from(format!("run {id} is not saved in the parts").as_str())
        })?;
        self.copy_saved(s, id, dst)
    }

    /// Puts the run saved at `s` into `dst` under `id`: read from its journal and written, or
    /// copied as stored from an earlier version's HDF5 part file.
    pub(super) fn copy_saved(
        &mut self,
        s: &Saved,
        id: &str,
        dst: &hdf5::Group,
    ) -> hdf5::Result<()> {
        let file = s.file();
        let cannot = |e: &dyn std::fmt::Display| {
            hdf5::Error::from(format!("{}: {e}", file.display()).as_str())
        };
        let at = match self.open.iter().position(|(p, _)| p == file) {
            Some(i) => i,
            None => {
                let open = match s {
                    Saved::Journal { .. } => {
                        Open::Journal(std::fs::File::open(file).map_err(|e| cannot(&e))?)
                    }
                    Saved::Part { .. } => {
                        Open::Part(hdf5::File::open(file).map_err(|e| cannot(&e))?)
                    }
                };
                if self.open.len() == Self::KEEP {
                    self.open.remove(0);
                }
                self.open.push((file.clone(), open));
                self.open.len() - 1
            }
        };
        let mut entry = self.open.remove(at);
        let put = match (s, &mut entry.1) {
            (Saved::Journal { place, .. }, Open::Journal(f)) => {
                let run = journal::read_run(f, *place).map_err(|e| cannot(&e))?;
                if run.id != id {
                    return Err(cannot(&format!(
                        "holds run {} where {id} was saved",
                        run.id
                    )));
                }
                store::write_job(dst, id, &run.params, &run.integrator, &run.result)
            }
            (Saved::Part { group, .. }, Open::Part(f)) => store::copy_object(f, group, dst, id),
            _ => Err(cannot(&"is open as another kind of part file")),
        };
        self.open.push(entry);
        put
    }
}
