//! The `statistics` table of a sampled study: per output, its distribution over the samples.
//!
//! In: a results file of a study with `[sample]` (its stored text), its jobs (status, label)
//! and their outputs ([`super::outputs`]). Out: one row per output: `output`, `n` (jobs with a
//! value), `mean`, `std`, the quantiles `q05`, `q50`, `q95`, each with its 95 % bootstrap
//! interval (`…_low`, `…_high`; 1000 resamples, [`crate::numerics::sample_statistics`]),
//! `min`, `max`, in the output's unit (its name says it). The samples are the jobs that ended
//! `ok`; of a Saltelli design only the rows of A and B (independent draws of the inputs; the
//! AB_i rows repeat A's values but one). `None` for a study without `[sample]`.

use hdf5::File;

use super::outputs::job_outputs;
use crate::numerics::sample_statistics::{summarise, Estimate};
use crate::report::jobs::Job;
use crate::report::table::{Cell, Grid, Table};
use crate::study::sample::design::{Matrix, Row};
use crate::study::sample::spec_of_text;
use crate::text::significant;

/// Bootstrap resamples of every interval.
pub(crate) const RESAMPLES: usize = 1000;

/// The bootstrap's seed (fixed: the same report every time).
pub(crate) const BOOTSTRAP_SEED: u64 = 0x5eed_b007;

/// The quantiles shown: (column, probability).
const QUANTILES: [(&str, f64); 3] = [("q05", 0.05), ("q50", 0.5), ("q95", 0.95)];

/// The `statistics` table (module doc).
pub(crate) fn statistics_table(
    f: &File,
    jobs: &[Job],
    study_text: &str,
) -> hdf5::Result<Option<Table>> {
    if spec_of_text(study_text).is_none() {
        return Ok(None);
    }
    let ids: Vec<String> = jobs
        .iter()
        .filter(|j| j.status == "ok")
        .filter(|j| !matches!(Row::parse_label(&j.label), Some((Matrix::AB(_), _))))
        .map(|j| j.id.clone())
        .collect();
    let outputs = job_outputs(f, &ids)?;
    let mut columns = vec!["output".to_string(), "n".into()];
    for c in ["mean", "std"]
        .iter()
        .chain(QUANTILES.iter().map(|(c, _)| c))
    {
        columns.extend([c.to_string(), format!("{c}_low"), format!("{c}_high")]);
    }
    columns.extend(["min".into(), "max".into()]);
    let probabilities: Vec<f64> = QUANTILES.iter().map(|(_, p)| *p).collect();
    let mut rows = Vec::new();
    let mut md = Vec::new();
    for (name, values) in &outputs {
        let Some(s) = summarise(values, &probabilities, RESAMPLES, BOOTSTRAP_SEED) else {
            continue;
        };
        let mut row = vec![Cell::Text(name.clone()), Cell::Count(s.n as u64)];
        let mut text = vec![name.clone(), s.n.to_string()];
        for e in [s.mean, s.std].iter().chain(&s.quantiles) {
            row.extend([
                Cell::Number(e.value),
                Cell::Number(e.low),
                Cell::Number(e.high),
            ]);
            text.push(with_interval(e));
        }
        row.extend([Cell::Number(s.min), Cell::Number(s.max)]);
        text.extend([significant(s.min, 4), significant(s.max, 4)]);
        rows.push(row);
        md.push(text);
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let mut md_columns = vec![
        "output".to_string(),
        "n".into(),
        "mean".into(),
        "std".into(),
    ];
    md_columns.extend(QUANTILES.iter().map(|(c, _)| c.to_string()));
    md_columns.extend(["min".into(), "max".into()]);
    Ok(Some(Table {
        name: "statistics".into(),
        title: "Statistics of the outputs over the samples".into(),
        legend: format!(
            "Per output (its unit in its name: _um µm, _hz Hz) over the jobs that ended ok \
             (of a Saltelli design the rows of A and B): n values, mean, standard deviation \
             (n − 1), the 5, 50 and 95 % quantiles (linear interpolation), min and max; each \
             statistic with its 95 % percentile-bootstrap interval (`_low`, `_high`; \
             {RESAMPLES} resamples; in markdown in brackets)."
        ),
        columns,
        rows,
        markdown: Some(Grid {
            columns: md_columns,
            rows: md,
            classes: Vec::new(),
        }),
    }))
}

/// `12.34 [12.1, 12.6]`.
fn with_interval(e: &Estimate) -> String {
    format!(
        "{} [{}, {}]",
        significant(e.value, 4),
        significant(e.low, 3),
        significant(e.high, 3)
    )
}
