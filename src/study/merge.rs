//! Merging shard files of one study into one results file.
//!
//! In: the results files of the shards of one run (`rotorsweep run --shard i/n`), and
//! [`MergeOptions`]. Out: one file, written under `OUT.h5.tmp` and renamed when complete, with
//! every job, reference run, model and linearised system once (deep copies, `H5Ocopy`), the
//! root attributes of the first input, `shard` (the shards it holds, `i/n,…`), `partial`
//! (0/1: fewer than the split has) and `merged_from` (the inputs, one a line), then the
//! analysis and a new `/summary` over all jobs. Refused: no input, an input given twice or
//! that is the output, a file that is not a study's results file, inputs of other study
//! digests (naming the input files that differ), a references file, two splits, a shard twice,
//! and missing shards unless `partial`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::identity::{compare, Identity};
use super::run::{finish_output, stored_identity, CampaignError, REFERENCES_SHARD};
use crate::error::InputError;
use crate::results::write::{write_whole, Analysis};
use crate::store;
use crate::store::output::{self, OutputLock};

/// How to merge shard files.
#[derive(Debug, Clone, Default)]
pub struct MergeOptions {
    /// Replace an existing output (only a rotorsweep results file).
    pub overwrite: bool,
    /// Merge an incomplete set of shards (the merged file records it).
    pub partial: bool,
}

/// What a merge did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MergeOutcome {
    /// Jobs in the merged file.
    pub jobs: usize,
    /// The shards it holds, `i/n`.
    pub shards: Vec<String>,
    /// The shards of the split it lacks (only with `partial`).
    pub missing: Vec<String>,
}

/// The shards a results file holds: its `shard` attribute, `i/n` or a comma-separated list.
pub(crate) fn parse_shards(text: &str) -> Option<Vec<(usize, usize)>> {
    text.split(',')
        .map(|s| {
            let (i, n) = s.trim().split_once('/')?;
            let (i, n): (usize, usize) = (i.parse().ok()?, n.parse().ok()?);
            (n > 0 && i < n).then_some((i, n))
        })
        .collect()
}

/// Joins shard files of one study: jobs, references and models (each once), file attributes of
/// the first file, and a new summary. The inputs must be distinct rotorsweep results files of
/// the same study digest and of one split into n shards, all of them unless `partial`; the
/// merged file's `shard` attribute lists the shards it holds, and `partial` (0/1) says
/// whether that is fewer than the split has.
pub fn merge(
    inputs: &[PathBuf],
    output: &Path,
    opts: &MergeOptions,
) -> Result<MergeOutcome, CampaignError> {
    use std::os::unix::fs::MetadataExt;
    if inputs.is_empty() {
        return Err(CampaignError::Usage(
            "merge needs at least one input file".into(),
        ));
    }
    let _lock = OutputLock::acquire(output)?;
    // Distinct regular results files, none of them the output.
    let out_inode = std::fs::metadata(output).ok().map(|m| (m.dev(), m.ino()));
    let mut seen: BTreeMap<(u64, u64), &PathBuf> = BTreeMap::new();
    for p in inputs {
        let m = std::fs::metadata(p)
            .map_err(|e| InputError::new(p, format!("cannot read this input: {e}")))?;
        if !m.is_file() {
            return Err(InputError::new(p, "is not a regular file").into());
        }
        let key = (m.dev(), m.ino());
        if let Some(first) = seen.insert(key, p) {
            return Err(CampaignError::Usage(format!(
                "{} is given twice (also as {}): each shard once",
                p.display(),
                first.display()
            )));
        }
        if Some(key) == out_inode {
            return Err(CampaignError::Usage(format!(
                "{}: is the output too; merge into a new file",
                p.display()
            )));
        }
        output::is_results_file(p).map_err(|why| InputError::new(p, why))?;
    }
    output::check_replace(output, opts.overwrite)?;
    output::check_working_file(&store::with_suffix(output, ".tmp"))?;
    // One study digest and one split.
    let mut shards: BTreeMap<(usize, usize), &PathBuf> = BTreeMap::new();
    let (digest0, inputs0, _) = stored_identity(&inputs[0])?;
    for p in inputs {
        let (digest, inputs_text, shard) = stored_identity(p)?;
        if digest.is_empty() {
            return Err(InputError::new(
                p,
                "has no study digest: not a study's results file (a `simulate` or `linear` \
                 file?), or written by an older rotorsweep (run its shard again)",
            )
            .into());
        }
        if digest != digest0 {
            let mine = Identity::parse_inputs(inputs_text.as_deref().unwrap_or_default());
            let theirs = Identity::parse_inputs(inputs0.as_deref().unwrap_or_default());
            let first_only = format!("read only by {}", inputs[0].display());
            let what = compare(&mine, &theirs, ["differs", "read only by it", &first_only]);
            return Err(InputError::new(
                p,
                format!(
                    "comes from other inputs than {} ({})",
                    inputs[0].display(),
                    if what.is_empty() {
                        "its study digest differs".into()
                    } else {
                        what.join(", ")
                    }
                ),
            )
            .into());
        }
        if shard == REFERENCES_SHARD {
            return Err(InputError::new(
                p,
                "is a references file (run --references-only), not a shard: merge the shard files",
            )
            .into());
        }
        let list = parse_shards(&shard).ok_or_else(|| {
            CampaignError::Usage(format!(
                "{}: its shard attribute `{shard}` is not i/n",
                p.display()
            ))
        })?;
        for s in list {
            if let Some(other) = shards.insert(s, p) {
                return Err(CampaignError::Usage(format!(
                    "shard {}/{} is in both {} and {}",
                    s.0,
                    s.1,
                    other.display(),
                    p.display()
                )));
            }
        }
    }
    let splits: BTreeSet<usize> = shards.keys().map(|s| s.1).collect();
    if splits.len() > 1 {
        let list: Vec<String> = shards
            .iter()
            .map(|(s, p)| format!("{} is shard {}/{}", p.display(), s.0, s.1))
            .collect();
        return Err(InputError::new(
            &inputs[0],
            format!("the inputs come from different splits: {}", list.join(", ")),
        )
        .into());
    }
    let n = *splits.iter().next().expect("at least one input");
    let missing: Vec<String> = (0..n)
        .filter(|i| !shards.contains_key(&(*i, n)))
        .map(|i| format!("{i}/{n}"))
        .collect();
    if !missing.is_empty() && !opts.partial {
        return Err(CampaignError::Usage(format!(
            "shards missing: {} (of {n}); add them, or --partial to merge without them",
            missing.join(", ")
        )));
    }
    let present: Vec<String> = shards.keys().map(|(i, n)| format!("{i}/{n}")).collect();
    let tmp = store::with_suffix(output, ".tmp");
    let mut jobs_n = 0;
    let written = write_whole(&tmp, Analysis::Noted { output }, |f| {
        write_merged(f, inputs, &present, &missing, &mut jobs_n)
    });
    finish_output(&tmp, output, written)?;
    Ok(MergeOutcome {
        jobs: jobs_n,
        shards: present,
        missing,
    })
}

/// The merged file's contents (module doc): the first input's root attributes (`shard`,
/// `threads`, `partial`, `merged_from` aside), the new `shard`, `partial` and `merged_from`,
/// and every input's models, linearised systems, reference runs and jobs, each once; the
/// number of jobs in `jobs_n`, and the varying keys (the first input's).
fn write_merged(
    f: &hdf5::File,
    inputs: &[PathBuf],
    present: &[String],
    missing: &[String],
    jobs_n: &mut usize,
) -> hdf5::Result<Vec<String>> {
    let first = hdf5::File::open(&inputs[0])?;
    let keys = store::varying_keys(&first);
    for name in first.attr_names()? {
        if matches!(
            name.as_str(),
            "shard" | "threads" | "partial" | "merged_from"
        ) {
            continue;
        }
        store::attr_str(
            f,
            &name,
            &store::read_str(&first, &name).unwrap_or_default(),
        )?;
    }
    store::attr_str(f, "shard", &present.join(","))?;
    store::attr_u64(f, "partial", u64::from(!missing.is_empty()))?;
    let sources: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
    store::attr_str(f, "merged_from", &sources.join("\n"))?;
    for group in ["models", "linear", "references", "jobs"] {
        let dst = f.create_group(group)?;
        let mut seen = BTreeSet::new();
        for p in inputs {
            let src = hdf5::File::open(p)?;
            // Files from before /linear existed have none to copy.
            let Ok(sg) = src.group(group) else { continue };
            for name in sg.member_names()? {
                if seen.insert(name.clone()) {
                    store::copy_object(&sg, &name, &dst, &name)
                        .map_err(|e| hdf5::Error::from(format!("{}: {e}", p.display()).as_str()))?;
                }
            }
        }
        if group == "jobs" {
            *jobs_n = seen.len();
        }
    }
    Ok(keys)
}
