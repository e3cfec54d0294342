//! The texts the figures write, computed here once so that Python never formats a number or
//! classes a job itself: `rotorsweep report FILE --format json --labels` adds them to the JSON
//! document as `"labels"`, and `report --format html` hands the same document to the figures
//! (`python -m rotorsweep.figures --tables`).
//!
//! In: one results file, or with `--compare` the measured one and the simulated one. Out:
//! [`Labels`]: `numbers`, the [`number_text`] of every distinct finite value a label shows (each
//! job's numeric varying keys and its `speed.hz`, the orders of every speed sweep
//! `/analysis/sweeps/<n>/orders`, the `order` column of `/analysis/orders`), as stored (f64,
//! so the JSON number reads back to the same value); `roller_ratios`, each finite
//! `roller_ratio:<node>/<roller>` job attribute with its text to 4 decimals; `error_classes`,
//! every class of [`error_class`](super::error_class) with its colour, best to worst.

use std::path::Path;

use hdf5::File;
use serde::Serialize;

use super::classes::CLASS_COLOURS;
use super::tables::orders::{records, OrderRow};
use crate::error::InputError;
use crate::results::analyse::ROLLER_RATIO;
use crate::store::{self, Param};
use crate::text::number_text;

/// What the figures' labels say (module doc); serialised as `[[value, text], …]` lists.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Labels {
    /// Each number a label shows, with its text.
    pub numbers: Vec<(f64, String)>,
    /// Each roller's line ratio, with its text to 4 decimals.
    pub roller_ratios: Vec<(f64, String)>,
    /// Each error class with its fill colour (`#rrggbb`), best to worst.
    pub error_classes: Vec<(&'static str, &'static str)>,
}

/// The labels of the results files `files` (module doc); an error names the file that cannot be
/// read.
pub fn labels(files: &[&Path]) -> Result<Labels, InputError> {
    let mut numbers = Vec::new();
    let mut ratios = Vec::new();
    for path in files {
        let failed = |e: hdf5::Error| InputError::new(path, format!("cannot read its labels: {e}"));
        let f = File::open(path).map_err(failed)?;
        job_values(&f, &mut numbers, &mut ratios).map_err(failed)?;
        analysis_values(&f, &mut numbers).map_err(failed)?;
    }
    let texts = |values: Vec<f64>, text: fn(f64) -> String| {
        let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| a.to_bits() == b.to_bits());
        v.into_iter().map(|x| (x, text(x))).collect()
    };
    Ok(Labels {
        numbers: texts(numbers, number_text),
        roller_ratios: texts(ratios, |x| {
            number_text(format!("{x:.4}").parse().unwrap_or(x))
        }),
        error_classes: CLASS_COLOURS.to_vec(),
    })
}

/// Each job's numeric varying keys, its `speed.hz` and its roller ratios.
fn job_values(f: &File, numbers: &mut Vec<f64>, ratios: &mut Vec<f64>) -> hdf5::Result<()> {
    let Ok(jobs) = f.group("jobs") else {
        return Ok(());
    };
    let varying = store::varying_keys(f);
    for id in jobs.member_names()? {
        let g = jobs.group(&id)?;
        for k in varying.iter().map(String::as_str).chain(["speed.hz"]) {
            match store::read_param(&g, k) {
                Ok(Param::Number(x)) => numbers.push(x),
                Ok(Param::Count(n)) => numbers.push(n as f64),
                _ => {}
            }
        }
        for name in g.attr_names()? {
            if name.starts_with(ROLLER_RATIO) {
                ratios.push(store::read_num(&g, &name)?);
            }
        }
    }
    Ok(())
}

/// The orders of every speed sweep and of the order tracking.
fn analysis_values(f: &File, numbers: &mut Vec<f64>) -> hdf5::Result<()> {
    if let Ok(sweeps) = f.group("analysis/sweeps") {
        for n in sweeps.member_names()? {
            if let Ok(ds) = sweeps.dataset(&format!("{n}/orders")) {
                numbers.extend(ds.read_raw::<f64>()?);
            }
        }
    }
    if let Some(rows) = records::<OrderRow>(f, "analysis/orders")? {
        numbers.extend(rows.iter().map(|r| r.order));
    }
    Ok(())
}
