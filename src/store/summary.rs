//! The `/summary` table of a results file: one row per job, from the job groups' attributes.
//!
//! In: an open results file whose `/jobs/<id>` groups carry the attributes of
//! [`write_job`](super::write_job) (and, in a study's file, the error attributes against the
//! reference runs), and the study's varying keys. Out: the compound dataset `/summary`
//! ([`table`](super::table)), replaced if present: text columns, `job_index` as a count, a column
//! per varying key, then the solver statistics and the runout errors with their units (s, um,
//! `1` for counts).

use super::{units_of_key, Column, Param};

/// The statistics every summary row carries, in order: (name, units, is a count).
const STAT_COLUMNS: [(&str, &str, bool); 14] = [
    ("cpu_time_s", "s", false),
    ("wall_time_s", "s", false),
    ("steps", "1", true),
    ("rejected_steps", "1", true),
    ("newton_iterations", "1", true),
    ("iterations_per_step", "1", false),
    ("jacobian_evals", "1", true),
    ("rhs_evals", "1", true),
    ("factorizations", "1", true),
    ("events", "1", true),
    ("t_end_s", "s", false),
    ("error_max_um", "um", false),
    ("error_rms_um", "um", false),
    ("error_peak_um", "um", false),
];

/// (Re)writes `/summary` from the job groups' attributes, ordered by job index: text columns
/// (job_id, status, cause, error_cause, integrator, modes, label), job_index as a count, every
/// varying key as its own column (numbers where every value is a number, else each value's
/// full text; table-valued parameters as their canonical TOML), then the statistics (counts
/// as integers), each with its units (`store::table`).
pub fn write_summary(f: &hdf5::File, varying: &[String]) -> hdf5::Result<()> {
    if let Ok(old) = f.dataset("summary") {
        drop(old);
        f.unlink("summary")?;
    }
    let jobs = f.group("jobs")?;
    let mut rows: Vec<(f64, hdf5::Group, String)> = Vec::new();
    for name in jobs.member_names()? {
        let g = jobs.group(&name)?;
        let idx = super::read_num(&g, "job_index").unwrap_or(f64::NAN);
        rows.push((idx, g, name));
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let text = |name: &str| {
        Column::text(
            name,
            rows.iter()
                .map(|r| super::read_str(&r.1, name).unwrap_or_default())
                .collect(),
        )
    };
    let mut cols = vec![
        Column::text("job_id", rows.iter().map(|r| r.2.clone()).collect()),
        Column::count(
            "job_index",
            rows.iter()
                .map(|r| {
                    if r.0.is_finite() {
                        r.0 as u64
                    } else {
                        u64::MAX
                    }
                })
                .collect(),
        ),
        text("status"),
        text("cause"),
        text("error_cause"),
        text("integrator"),
        text("modes"),
        text("label"),
    ];
    for key in varying {
        if key == "solver.integrator" {
            continue;
        }
        let vals: Vec<Option<Param>> = rows
            .iter()
            .map(|r| super::read_param(&r.1, key).ok())
            .collect();
        if vals.iter().flatten().all(|v| matches!(v, Param::Number(_))) {
            cols.push(Column::number(
                key,
                units_of_key(key),
                vals.iter()
                    .map(|v| match v {
                        Some(Param::Number(x)) => *x,
                        _ => f64::NAN,
                    })
                    .collect(),
            ));
        } else {
            cols.push(Column::text(
                key,
                vals.iter()
                    .map(|v| v.as_ref().map(Param::to_string).unwrap_or_default())
                    .collect(),
            ));
        }
    }
    for (key, units, count) in STAT_COLUMNS {
        let v = rows
            .iter()
            .map(|r| super::read_num(&r.1, key).unwrap_or(f64::NAN));
        cols.push(if count {
            Column::count(key, v.map(|x| x as u64).collect())
        } else {
            Column::number(key, units, v.collect())
        });
    }
    super::compound_table(f, "summary", &cols)
}
