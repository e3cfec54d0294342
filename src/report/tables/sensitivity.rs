//! The `sensitivity` table of a Saltelli-sampled study: Sobol' indices of every output.
//!
//! In: a results file of a study with `[sample] method = "saltelli"` (its stored text names the
//! parameters), its jobs (status and label `A 12`, `B 12`, `AB_i 12`: matrix and row) and
//! their outputs ([`super::outputs`]). Out: one row per output and parameter (its first key):
//! `output`, `parameter`, `n` (design rows used: those whose every matrix ended `ok` with a
//! value), `first_order` and `total` (Saltelli 2010 and Jansen estimators,
//! [`crate::numerics::sobol_indices`]) with their 95 % bootstrap intervals (`…_low`,
//! `…_high`; 1000 resamples of the rows). For `method = "morris"` (labels `T_s 12`: step s of
//! trajectory 12) one row per output and parameter: `n` (trajectories whose step of the
//! parameter has both jobs ok with a value), `mu`, `mu_star`, `sigma` of the elementary effects
//! ([`crate::numerics::elementary_effects`]; the effect is the output's change over the step
//! divided by the step in probability, the design regenerated from the stored study text),
//! each with its 95 % bootstrap interval over the trajectories. `None` for any other study.

use hdf5::File;

use super::outputs::job_outputs;
use super::statistics::{BOOTSTRAP_SEED, RESAMPLES};
use crate::numerics::elementary_effects::elementary_effects;
use crate::numerics::sobol_indices::sobol_indices;
use crate::report::jobs::Job;
use crate::report::table::{Cell, Table};
use crate::study::sample::design::{Matrix, Method, Row};
use crate::study::sample::{design, spec_of_text, Spec};

/// The `sensitivity` table (module doc).
pub(crate) fn sensitivity_table(
    f: &File,
    jobs: &[Job],
    study_text: &str,
) -> hdf5::Result<Option<Table>> {
    let Some(spec) = spec_of_text(study_text) else {
        return Ok(None);
    };
    if let Method::Morris(_) = spec.method {
        return morris_table(f, jobs, &spec);
    }
    if spec.method != Method::Saltelli {
        return Ok(None);
    }
    let (n, d) = (spec.n, spec.parameters.len());
    // Each job's place in the design: (matrix slot: 0 A, 1 B, 2 + i AB_i; row).
    let ok: Vec<(&Job, usize, usize)> = jobs
        .iter()
        .filter(|j| j.status == "ok")
        .filter_map(|j| {
            let (m, row) = Row::parse_label(&j.label)?;
            let slot = match m {
                Matrix::A => 0,
                Matrix::B => 1,
                Matrix::AB(i) if i < d => 2 + i,
                _ => return None,
            };
            (row < n).then_some((j, slot, row))
        })
        .collect();
    let ids: Vec<String> = ok.iter().map(|(j, _, _)| j.id.clone()).collect();
    let outputs = job_outputs(f, &ids)?;
    let columns: Vec<String> = [
        "output",
        "parameter",
        "n",
        "first_order",
        "first_order_low",
        "first_order_high",
        "total",
        "total_low",
        "total_high",
    ]
    .map(String::from)
    .to_vec();
    let mut rows = Vec::new();
    for (name, values) in &outputs {
        let mut m = vec![vec![f64::NAN; n]; d + 2];
        for ((_, slot, row), v) in ok.iter().zip(values) {
            m[*slot][*row] = *v;
        }
        let Some((indices, used)) = sobol_indices(&m[0], &m[1], &m[2..], RESAMPLES, BOOTSTRAP_SEED)
        else {
            continue;
        };
        for (p, ix) in spec.parameters.iter().zip(indices) {
            rows.push(vec![
                Cell::Text(name.clone()),
                Cell::Text(p.keys[0].clone()),
                Cell::Count(used as u64),
                Cell::Number(ix.first_order.value),
                Cell::Number(ix.first_order.low),
                Cell::Number(ix.first_order.high),
                Cell::Number(ix.total.value),
                Cell::Number(ix.total.low),
                Cell::Number(ix.total.high),
            ]);
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    Ok(Some(Table {
        name: "sensitivity".into(),
        title: "Sobol' indices of the outputs".into(),
        legend: format!(
            "Per output and sampled parameter (its first key): n design rows used (A, B and \
             every AB_i ended ok with a value), the first-order index (Saltelli 2010) and the \
             total index (Jansen 1999), both shares of the output's variance (1), each with its \
             95 % percentile-bootstrap interval over the rows (`_low`, `_high`; {RESAMPLES} \
             resamples)."
        ),
        columns,
        rows,
        markdown: None,
    }))
}

/// The Morris table (module doc).
fn morris_table(f: &File, jobs: &[Job], spec: &Spec) -> hdf5::Result<Option<Table>> {
    let (n, d) = (spec.n, spec.parameters.len());
    let points = design::rows(spec.method, n, d, spec.seed);
    // Each ok job's place: trajectory × (d + 1) + step.
    let ok: Vec<(&Job, usize)> = jobs
        .iter()
        .filter(|j| j.status == "ok")
        .filter_map(|j| match Row::parse_label(&j.label)? {
            (Matrix::Step(s), t) if s <= d && t < n => Some((j, t * (d + 1) + s)),
            _ => None,
        })
        .collect();
    let ids: Vec<String> = ok.iter().map(|(j, _)| j.id.clone()).collect();
    let outputs = job_outputs(f, &ids)?;
    let columns: Vec<String> = [
        "output",
        "parameter",
        "n",
        "mu",
        "mu_low",
        "mu_high",
        "mu_star",
        "mu_star_low",
        "mu_star_high",
        "sigma",
        "sigma_low",
        "sigma_high",
    ]
    .map(String::from)
    .to_vec();
    let mut rows = Vec::new();
    for (name, values) in &outputs {
        let mut y = vec![f64::NAN; n * (d + 1)];
        for ((_, at), v) in ok.iter().zip(values) {
            y[*at] = *v;
        }
        let effects: Vec<Vec<f64>> = (0..n)
            .map(|t| {
                let mut e = vec![f64::NAN; d];
                for s in 1..=d {
                    let (a, b) = (t * (d + 1) + s - 1, t * (d + 1) + s);
                    let (pa, pb) = (&points[a].point, &points[b].point);
                    if let Some(i) = (0..d).find(|&i| pa[i] != pb[i]) {
                        e[i] = (y[b] - y[a]) / (pb[i] - pa[i]);
                    }
                }
                e
            })
            .collect();
        let measures = elementary_effects(&effects, d, RESAMPLES, BOOTSTRAP_SEED);
        for (p, m) in spec.parameters.iter().zip(measures) {
            let Some(m) = m else { continue };
            let mut row = vec![
                Cell::Text(name.clone()),
                Cell::Text(p.keys[0].clone()),
                Cell::Count(m.n as u64),
            ];
            for e in [m.mu, m.mu_star, m.sigma] {
                row.extend([
                    Cell::Number(e.value),
                    Cell::Number(e.low),
                    Cell::Number(e.high),
                ]);
            }
            rows.push(row);
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    Ok(Some(Table {
        name: "sensitivity".into(),
        title: "Morris elementary effects of the outputs".into(),
        legend: format!(
            "Per output and sampled parameter (its first key): n trajectories used (both jobs \
             of the parameter's step ended ok with a value), the mean elementary effect mu, the \
             mean absolute effect mu_star (Campolongo 2007) and their standard deviation sigma \
             (Morris 1991), in the output's unit per unit probability of the parameter (over a \
             uniform parameter: per its range), each with its 95 % percentile-bootstrap \
             interval over the trajectories (`_low`, `_high`; {RESAMPLES} resamples)."
        ),
        columns,
        rows,
        markdown: None,
    }))
}
