//! How many jobs a study may have, counted before anything is expanded.
//!
//! In: every axis's rows (its values or the points of its range) and the number of explicit
//! `[[jobs]]`. Out: an error naming the axis (or `jobs`) at which the count passes
//! [`MAX_JOBS`]; the product of the axes is counted axis by axis (saturating, as a `u128`), so
//! a study of many long axes is refused without building its jobs.

use super::context::Ctx;
use crate::error::InputError;

/// Most jobs a study may expand to. `plan` and `run` validate every job's scene before anything
/// runs and hold every job: measured, 4901 jobs of the reference roll took 4.3 s and 274 MB to
/// load (0.9 ms and 56 KB each); `plan` of 100 000 Jeffcott jobs took 15 s and 0.93 GB, and
/// their run on 2 threads 10.4 min at 2.2 GB peak (2026-12-03). So the limit loads in about
/// 1.5 min and 6 GB for jobs the size of the reference roll; beyond it, split the study (shards
/// of several studies).
pub const MAX_JOBS: usize = 100_000;

/// The number of jobs, the product of the axes (each counted before any is expanded) plus the
/// explicit jobs, stays within [`MAX_JOBS`].
pub(super) fn job_count(
    c: &Ctx,
    axes: &[(Vec<String>, Vec<Vec<toml::Value>>)],
    explicit: usize,
) -> Result<(), InputError> {
    let limit = |n: u128| {
        format!(
            "{n} jobs, more than the limit of {MAX_JOBS}: every job is validated (and held) \
             before anything runs, about 1 ms and 60 KB each"
        )
    };
    let mut product: u128 = 1;
    for (i, (_, rows)) in axes.iter().enumerate() {
        product = product.saturating_mul(rows.len() as u128);
        if product > MAX_JOBS as u128 {
            return Err(c.err(
                &format!("axes[{i}]"),
                format!("the axes up to this one already make {}", limit(product)),
            ));
        }
    }
    let from_axes = if axes.is_empty() && explicit > 0 {
        0
    } else {
        product
    };
    let total = from_axes + explicit as u128;
    if total > MAX_JOBS as u128 {
        return Err(c.err(
            "jobs",
            format!("the axes and [[jobs]] make {}", limit(total)),
        ));
    }
    Ok(())
}
