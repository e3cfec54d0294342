//! Reading a results file into a [`Report`]: which kind of file it is, its jobs, and every
//! table it holds data for, in the report's order (`solver`, `resonances`, `trial_mass`,
//! `balancing` and `balancing_residual`, `orders`, `order_resonances`, `stability`, `nips`,
//! `linear`,
//! and of a sampled study `statistics`, `sensitivity` and `samples`), or of a calibration its
//! four `calibration_*` tables.
//!
//! In: an assembled results file of `rotorsweep run` or `merge` (attribute `study_name`, group
//! `jobs`; the stored study text gives the `[analysis]` baseline and the labelled axes), or of
//! `rotorsweep linear -o` (a `linear` group without `study_name`; its study name is its
//! systems' names), or of `rotorsweep calibrate -o` (attribute `kind = "calibration"`; its
//! name, the fit's summary as the overview, `tables/calibration.rs`). Out: the [`Report`] with a one-line overview (job count by status, the
//! varying keys). Errors name the file: missing, not HDF5, not a results file, or unreadable.

use std::path::Path;

use hdf5::File;

use super::jobs::{read_jobs, Job, INTEGRATOR_KEY};
use super::table::{position_or_push, Report};
use super::tables::{
    balancing_tables, calibration_overview, calibration_tables, is_calibration, linear_table,
    nips_table, order_resonance_table, orders_table, per_grid_point, resonance_table,
    samples_table, sensitivity_table, solver_table, stability_table, statistics_table,
    trial_mass_table, Builder,
};
use crate::error::InputError;
use crate::results::request::{analysis_of_text, StudyAnalysis};
use crate::store;

/// The overview line: the job count by status and the varying keys (of a `linear -o` file: that
/// it has no jobs; of an empty shard's file: that it is one).
fn overview(jobs: &[Job], varying: &[String], linear_only: bool) -> String {
    let (mut names, mut counts): (Vec<&str>, Vec<usize>) = (Vec::new(), Vec::new());
    for j in jobs {
        let i = position_or_push(&mut names, &j.status);
        counts.resize(names.len(), 0);
        counts[i] += 1;
    }
    let statuses: Vec<String> = names
        .iter()
        .zip(&counts)
        .map(|(s, n)| format!("{n} {s}"))
        .collect();
    let varying = if varying.is_empty() {
        "nothing".to_string()
    } else {
        varying.join(", ")
    };
    if linear_only {
        "linear analysis (`rotorsweep linear -o`), no jobs".to_string()
    } else if jobs.is_empty() {
        // A shard that held no job (`run --shard i/n --allow-empty`), or a merge of such.
        format!("0 jobs (an empty shard: none of the study's jobs is in it); varying: {varying}")
    } else {
        format!(
            "{} job{} ({}); varying: {varying}",
            jobs.len(),
            if jobs.len() == 1 { "" } else { "s" },
            statuses.join(", "),
        )
    }
}

/// Reads the tables of the results file at `path`. Errors name the file.
pub fn read(path: &Path) -> Result<Report, InputError> {
    // A regular file: opening a FIFO would block.
    crate::error::regular_file(path, u64::MAX)
        .map_err(|e| InputError::new(path, format!("cannot be read: {e}")))?;
    let f =
        File::open(path).map_err(|e| InputError::new(path, format!("not an HDF5 file ({e})")))?;
    let not_results = || {
        InputError::new(
            path,
            "not a study results file of `rotorsweep run` (no `study_name` attribute or no \
             `jobs` group), a `rotorsweep linear -o` file (no `linear` group) nor a `rotorsweep \
             calibrate -o` file (no `kind = \"calibration\"` attribute)",
        )
    };
    let failed = |e: hdf5::Error| InputError::new(path, format!("reading the results: {e}"));
    if is_calibration(&f) {
        return Ok(Report {
            file: path.to_path_buf(),
            study: store::read_str(&f, "name").map_err(failed)?,
            overview: calibration_overview(&f).map_err(failed)?,
            tables: calibration_tables(&f).map_err(failed)?,
        });
    }
    let linear_only = store::read_str(&f, "study_name").is_err() && f.group("linear").is_ok();
    let study = if linear_only {
        let names = f.group("linear").and_then(|g| g.member_names());
        format!(
            "{} (rotorsweep linear)",
            names.unwrap_or_default().join(", ")
        )
    } else {
        store::read_str(&f, "study_name").map_err(|_| not_results())?
    };
    if f.group("jobs").is_err() {
        return Err(not_results());
    }
    let text = store::read_str(&f, "study_text").unwrap_or_default();
    let StudyAnalysis {
        spec,
        labelled: axes,
        ..
    } = analysis_of_text(&text).unwrap_or_default();
    let label_key = spec.baseline.as_ref().and_then(|b| {
        axes.iter()
            .find(|a| a.labels.contains(b))
            .map(|a| a.keys[0].as_str())
    });
    let varying = store::varying_keys(&f);
    let jobs = read_jobs(&f, &varying, &axes).map_err(failed)?;
    let mut tables = Vec::new();
    if !jobs.is_empty() {
        tables.push(solver_table(&jobs, &varying));
    }
    tables.extend(resonance_table(&f).map_err(failed)?);
    tables.extend(trial_mass_table(&f, label_key).map_err(failed)?);
    if label_key.is_some_and(|k| k.ends_with(".masses")) {
        tables.extend(balancing_tables(path).into_iter().flatten());
    }
    tables.extend(orders_table(&f, &jobs, &varying).map_err(failed)?);
    tables.extend(order_resonance_table(&f, &jobs, &varying).map_err(failed)?);
    if varying.iter().any(|k| k == INTEGRATOR_KEY) && varying.len() >= 2 {
        tables.push(stability_table(&jobs, &varying));
    }
    tables.extend(nips_table(&f, &jobs, &varying, &spec.orders).map_err(failed)?);
    tables.extend(linear_table(&f).map_err(failed)?);
    for build in [statistics_table as Builder, sensitivity_table] {
        tables.extend(per_grid_point(&f, &jobs, &text, &varying, build).map_err(failed)?);
    }
    tables.extend(samples_table(&f, &jobs, &text, &varying).map_err(failed)?);
    Ok(Report {
        file: path.to_path_buf(),
        study,
        overview: overview(&jobs, &varying, linear_only),
        tables,
    })
}
