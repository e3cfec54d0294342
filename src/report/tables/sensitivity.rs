//! The `sensitivity` table of a Saltelli-sampled study: Sobol' indices of every output.
//!
//! In: a results file of a study with `[sample] method = "saltelli"` (its stored text names the
//! parameters), its jobs (status and label `A 12`, `B 12`, `AB_i 12`: matrix and row) and
//! their outputs ([`super::outputs`]). Out: one row per output and parameter (its first key):
//! `output`, `parameter`, `n` (design rows used: those whose every matrix ended `ok` with a
//! value), `first_order` and `total` (Saltelli 2010 and Jansen estimators,
//! [`crate::numerics::sobol_indices`]) with their 95 % bootstrap intervals (`…_low`,
//! `…_high`; 1000 resamples of the rows). `None` for any other study.

use hdf5::File;

use super::outputs::job_outputs;
use super::statistics::{BOOTSTRAP_SEED, RESAMPLES};
use crate::numerics::sobol_indices::sobol_indices;
use crate::report::jobs::Job;
use crate::report::table::{Cell, Table};
use crate::study::sample::design::{Matrix, Method, Row};
use crate::study::sample::spec_of_text;

/// The `sensitivity` table (module doc).
pub(crate) fn sensitivity_table(
    f: &File,
    jobs: &[Job],
    study_text: &str,
) -> hdf5::Result<Option<Table>> {
    let Some(spec) = spec_of_text(study_text).filter(|s| s.method == Method::Saltelli) else {
        return Ok(None);
    };
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
