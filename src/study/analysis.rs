//! The checks of a study's `[analysis]` table (the request itself, [`AnalysisSpec`], belongs to
//! the results stage, which computes it).
//!
//! In: `[analysis]`: `orders` (of the spin frequency), `max_freq_hz` [Hz], `order_revolutions`
//! [revolutions], `baseline` (a label); the study's axes; its expanded jobs. Out: errors for
//! orders outside [`ORDER_RANGE`](crate::results::request::ORDER_RANGE) or given twice, a frequency that is not positive, a block
//! length outside [1, 100000] revolutions, a baseline that no axis labels, and (when the study
//! names its orders) an order whose line in a job of constant speed lies at or above the
//! Nyquist frequency of that job's record (with the default orders, such lines are stored as
//! NaN).

use super::context::Ctx;
use super::file::AxisFile;
use super::jobs::Job;
use crate::error::InputError;
use crate::results::request::{check_orders, default_orders, AnalysisSpec};

/// The `[analysis]` values: distinct orders within the range, a positive frequency, a block length in
/// [1, 100000] revolutions, a baseline that an axis labels.
pub(super) fn check(c: &Ctx, a: &AnalysisSpec, axes: &[AxisFile]) -> Result<(), InputError> {
    check_orders(&a.orders).map_err(|r| c.err("analysis.orders", r))?;
    if a.max_freq_hz.is_some_and(|f| !(f.is_finite() && f > 0.0)) {
        return Err(c.err("analysis.max_freq_hz", "must be a positive frequency"));
    }
    if a.order_revolutions
        .is_some_and(|r| !(r.is_finite() && (1.0..=1e5).contains(&r)))
    {
        return Err(c.err(
            "analysis.order_revolutions",
            "must lie in [1, 100000] revolutions",
        ));
    }
    if let Some(b) = &a.baseline {
        let found = axes
            .iter()
            .any(|x| x.labels.as_ref().is_some_and(|l| l.contains(b)));
        if !found {
            return Err(c.err(
                "analysis.baseline",
                format!("no axis has the label `{b}` (axes need `labels` for a baseline)"),
            ));
        }
    }
    Ok(())
}

/// Every line a study asks for must lie below the Nyquist frequency of its job's record
/// (with the default orders, lines above it are stored as NaN).
pub(super) fn below_nyquist(c: &Ctx, a: &AnalysisSpec, jobs: &[Job]) -> Result<(), InputError> {
    let top = a.orders.iter().copied().fold(0.0, f64::max);
    let explicit = a.orders != default_orders();
    for j in jobs.iter().filter(|_| explicit) {
        let rate = j.facts.sample_rate_hz;
        if let Some(w) = j.facts.record_omega {
            let f = top * w / std::f64::consts::TAU;
            if f >= 0.5 * rate {
                return Err(c.err(
                    "analysis.orders",
                    format!(
                        "job {}: order {top} at {:.4} Hz is {f:.4} Hz, at or above the Nyquist \
                         frequency {:.1} Hz of simulation.sample_rate_hz",
                        j.index,
                        w / std::f64::consts::TAU,
                        0.5 * rate
                    ),
                ));
            }
        }
    }
    Ok(())
}
