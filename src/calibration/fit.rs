//! [`calibrate`]: a calibration from its output's lock to its written results, step by step
//! (the method is in the module doc of `calibration`): claim the output, open the evaluations
//! folder, fit, turn the fit coordinates' covariance into the values' errors and correlations,
//! collect the warnings, write `OUT.h5`.

use std::path::PathBuf;

use super::evaluate;
use super::file::{Calibration, Scale};
use super::outcome::{Fitted, Options, Outcome, RowResult};
use super::write;
use crate::error::InputError;
use crate::numerics::least_squares::{self, LmError, Settings};
use crate::study::run::CampaignError;

/// A target row that no parameter moves by more than this many of its standard deviations
/// over the parameter's whole range (the Jacobian at the fit times the range of the fit
/// coordinate) cannot be changed by the fit: a warning. An exact zero is too strict a test:
/// an output that does not depend on a parameter (the horizontal sag under vertical gravity)
/// still changes by round-off between two solutions of the model.
pub const UNMOVED_ROW: f64 = 1e-6;

/// The evaluations folder of an output.
pub fn evaluations_dir(output: &std::path::Path) -> PathBuf {
    crate::store::with_suffix(output, ".evaluations")
}

/// Runs a calibration (module doc) and writes its output.
pub fn calibrate(cal: &Calibration, opts: &Options) -> Result<Outcome, CampaignError> {
    let t0 = std::time::Instant::now();
    let c0 = cpu_time::ProcessTime::try_now().ok();
    let _lock = crate::store::output::claim(&opts.output, true)?;
    let dir = evaluations_dir(&opts.output);
    if opts.overwrite && dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| CampaignError::io(&dir, e))?;
    }
    let mut ev = evaluate::Evaluator::new(cal, &dir, opts.threads, &opts.command)?;
    let ps = &cal.parameters;
    let start: Vec<f64> = ps.iter().map(|p| p.scale.to_internal(p.initial)).collect();
    let lower: Vec<f64> = ps.iter().map(|p| p.scale.to_internal(p.lower)).collect();
    let upper: Vec<f64> = ps.iter().map(|p| p.scale.to_internal(p.upper)).collect();
    let steps: Vec<f64> = ps
        .iter()
        .map(|p| match p.scale {
            Scale::Log => (1.0 + cal.fit.step).log10(),
            Scale::Linear if p.initial != 0.0 => cal.fit.step * p.initial.abs(),
            Scale::Linear => cal.fit.step * (p.upper - p.lower),
        })
        .collect();
    let settings = Settings {
        max_iterations: cal.fit.max_iterations,
        tolerance: cal.fit.tolerance,
        lambda: 1e-2,
    };
    let fit = least_squares::minimize(&mut ev, &start, (&lower, &upper), &steps, settings)
        .map_err(|e| fit_error(cal, &ev, e))?;
    let values = ev.values(&fit.x);
    let n = ps.len();
    let m = cal.rows.len();
    // Delta method: d value / d coordinate.
    let scale: Vec<f64> = ps
        .iter()
        .zip(&values)
        .map(|(p, v)| match p.scale {
            Scale::Linear => 1.0,
            Scale::Log => v * std::f64::consts::LN_10,
        })
        .collect();
    let covariance: Vec<Vec<f64>> = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| fit.covariance[(a, b)] * scale[a] * scale[b])
                .collect()
        })
        .collect();
    let errors: Vec<f64> = (0..n).map(|k| covariance[k][k].sqrt()).collect();
    let correlation: Vec<Vec<f64>> = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| covariance[a][b] / (errors[a] * errors[b]))
                .collect()
        })
        .collect();
    let parameters: Vec<Fitted> = ps
        .iter()
        .enumerate()
        .map(|(k, p)| Fitted {
            name: p.name.clone(),
            keys: p.keys.clone(),
            scale: p.scale.name().into(),
            lower: p.lower,
            upper: p.upper,
            initial: p.initial,
            value: values[k],
            std_error: errors[k],
            at_bound: fit.x[k] <= lower[k] || fit.x[k] >= upper[k],
        })
        .collect();
    let first = &ev.evaluations[ev.find(&start).unwrap_or(0)];
    let best = &ev.evaluations[ev.find(&fit.x).unwrap_or(0)];
    let rows: Vec<RowResult> = cal
        .rows
        .iter()
        .enumerate()
        .map(|(i, r)| RowResult {
            target: r.at.clone(),
            line: r.line,
            output: r.output.clone(),
            job: r.job,
            measured: r.value,
            std: r.std,
            weight: r.weight,
            initial: first.outputs[i],
            model: best.outputs[i],
            residual: fit.residuals[i],
        })
        .collect();
    let mut warnings = Vec::new();
    for (k, p) in ps.iter().enumerate() {
        if fit.frozen[k] {
            warnings.push(warning(
                cal,
                &p.at.0,
                p.at.1,
                format!(
                    "`{}` moves no target row (its finite-difference column is zero at the fit): \
                     held at {}, no standard error",
                    p.name, values[k]
                ),
            ));
        }
    }
    for (i, r) in cal.rows.iter().enumerate() {
        let moved = |k: usize| (fit.jacobian[(i, k)] * (upper[k] - lower[k])).abs();
        if (0..n).all(|k| moved(k) < UNMOVED_ROW) {
            warnings.push(warning(
                cal,
                &r.at,
                r.line,
                format!(
                    "no parameter moves `{}` (over its whole range each moves it by less than \
                     {UNMOVED_ROW} of its standard deviation): the fit cannot change this row's \
                     residual",
                    r.output
                ),
            ));
        }
    }
    let free = fit.frozen.iter().filter(|f| !**f).count();
    let dof = m as i64 - free as i64;
    let outcome = Outcome {
        name: cal.name.clone(),
        stop: fit.stop.text().into(),
        iterations: fit.iterations,
        evaluations: ev.evaluations.len(),
        start_cost: fit.start_cost,
        cost: fit.cost,
        degrees_of_freedom: dof,
        reduced_chi_square: if dof > 0 {
            2.0 * fit.cost / dof as f64
        } else {
            f64::NAN
        },
        parameters,
        correlation,
        rows,
        warnings,
        cpu_s: c0.map_or(f64::NAN, |c| c.elapsed().as_secs_f64()),
        wall_s: t0.elapsed().as_secs_f64(),
        evaluation_list: ev.evaluations.clone(),
        jacobian: (0..m)
            .map(|i| (0..n).map(|k| fit.jacobian[(i, k)]).collect())
            .collect(),
        covariance,
    };
    write::write(cal, &outcome, opts).map_err(|e| CampaignError::io(&opts.output, e))?;
    Ok(outcome)
}

/// A warning in the calibration file's words: `FILE:LINE: key `KEY`: reason`.
fn warning(cal: &Calibration, key: &str, line: Option<usize>, reason: String) -> String {
    let e = InputError::new(&cal.path, reason).with_key(key);
    match line {
        Some(l) => e.at_line(l),
        None => e,
    }
    .to_string()
}

/// A fit that could not be made, as the campaign's error.
fn fit_error(
    cal: &Calibration,
    ev: &evaluate::Evaluator,
    e: LmError<CampaignError>,
) -> CampaignError {
    match e {
        LmError::Evaluate(e) => e,
        LmError::NothingMoves => InputError::new(
            &cal.path,
            "no parameter moves any target row (every finite-difference column is zero): \
             check that the parameters' keys act on the outputs the targets name",
        )
        .with_key("parameters")
        .into(),
        LmError::NotFinite(p) => {
            let Some(e) = ev.find(&p.x).map(|i| &ev.evaluations[i]) else {
                return CampaignError::Usage("an evaluation has no record".into());
            };
            let missing: Vec<String> = cal
                .rows
                .iter()
                .zip(&e.outputs)
                .filter(|(_, v)| !v.is_finite())
                .map(|(r, _)| format!("{} ({})", r.at, r.output))
                .collect();
            if missing.is_empty() {
                return InputError::new(
                    &cal.path,
                    format!(
                        "the {} point {:?} (jobs {} in {}) gives a cost that is not a finite \
                         number: a residual √w (model − value)/σ overflows (a model value far \
                         outside the targets' standard deviations)",
                        p.role.text(),
                        e.values,
                        e.job_ids.join(", "),
                        e.batch
                    ),
                )
                .into();
            }
            let why = if e.ok {
                "every job ended ok, so the study's results do not hold these outputs: check \
                 [analysis] orders, the sensors and that a run-up passes the resonance"
            } else {
                "a job did not end ok (its status and cause are in the batch's summary)"
            };
            InputError::new(
                &cal.path,
                format!(
                    "the {} point {:?} (jobs {} in {}) has no value for {}: {why}",
                    p.role.text(),
                    e.values,
                    e.job_ids.join(", "),
                    e.batch,
                    missing.join(", ")
                ),
            )
            .into()
        }
    }
}
