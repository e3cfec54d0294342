//! How many jobs a study may have, counted before anything is expanded.
//!
//! In: every axis's rows (its values or the points of its range) and the number of explicit
//! `[[jobs]]`. Out: an error naming the axis (or `jobs`) at which the count passes
//! [`MAX_JOBS`]; the product of the axes is counted axis by axis (saturating, as a `u128`), so
//! a study of many long axes is refused without building its jobs.

use super::context::Ctx;
use crate::error::InputError;

/// Most jobs a study may expand to. `plan` and `run` validate every job's scene before anything
/// runs and hold every job (its overrides, ids and a few numbers, about 1.2 KB): measured
/// (2026-12-04, 2 cores shared with other work), `plan` of 1 000 000 Jeffcott jobs took 21.4 s
/// of CPU and 0.79 GB at its peak, of 100 000 jobs 2.1 s and 0.12 GB. Beyond it, split the
/// study (several studies, each sharded).
pub const MAX_JOBS: usize = 1_000_000;

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
             before anything runs, about 20 µs of CPU and 1 KB each (split the study)"
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
