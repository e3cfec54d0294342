//! A calibration's results file.
//!
//! In: the [`Calibration`], its [`Outcome`] and the output path. Out: `OUT.h5` (written as
//! `OUT.h5.tmp`, renamed when it reads back) with the provenance attributes of every results
//! file, `kind = "calibration"`, the calibration and study texts and the fit's summary as
//! attributes, and under `/calibration` the tables `parameters` and `rows`, the matrices
//! `correlation`, `covariance` (values' units) and `jacobian` (∂ residual/∂ fit coordinate),
//! and every evaluation: the table `evaluations` with `values` (evaluations × parameters, the
//! keys' units) and `outputs` (evaluations × rows, the outputs' units). docs/calibration.md
//! lists every field.

use std::path::Path;

use super::file::Calibration;
use super::outcome::{Options, Outcome};
use crate::store::table::{compound_table, Column};
use crate::store::{self, attr_f64, attr_str, attr_u64, dataset_2d};

fn flat(m: &[Vec<f64>]) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

/// Writes the results file (module doc).
pub(super) fn write(cal: &Calibration, o: &Outcome, opts: &Options) -> std::io::Result<()> {
    let io = |e: hdf5::Error| std::io::Error::other(e.to_string());
    let tmp = store::with_suffix(&opts.output, ".tmp");
    write_to(&tmp, cal, o, &opts.command).map_err(io)?;
    store::rename_verified(&opts.output)
}

fn write_to(path: &Path, cal: &Calibration, o: &Outcome, command: &str) -> hdf5::Result<()> {
    let f = hdf5::File::create(path)?;
    store::provenance(&f, command)?;
    attr_str(&f, "kind", "calibration")?;
    attr_str(&f, "name", &cal.name)?;
    attr_str(&f, "description", &cal.description)?;
    attr_str(&f, "calibration_text", &cal.text)?;
    attr_str(&f, "study_text", &cal.study.text)?;
    attr_str(&f, "stop", &o.stop)?;
    attr_u64(&f, "iterations", o.iterations as u64)?;
    attr_u64(&f, "evaluation_count", o.evaluations as u64)?;
    attr_f64(&f, "start_cost", o.start_cost)?;
    attr_f64(&f, "cost", o.cost)?;
    attr_f64(&f, "degrees_of_freedom", o.degrees_of_freedom as f64)?;
    attr_f64(&f, "reduced_chi_square", o.reduced_chi_square)?;
    attr_f64(&f, "cpu_s", o.cpu_s)?;
    attr_f64(&f, "wall_s", o.wall_s)?;
    attr_str(&f, "warnings", &o.warnings.join("\n"))?;
    let g = f.create_group("calibration")?;
    let ps = &o.parameters;
    let text = |v: Vec<String>, name: &str| Column::text(name, v);
    compound_table(
        &g,
        "parameters",
        &[
            text(ps.iter().map(|p| p.name.clone()).collect(), "name"),
            text(ps.iter().map(|p| p.keys.join(",")).collect(), "keys"),
            text(ps.iter().map(|p| p.scale.clone()).collect(), "scale"),
            Column::number("lower", "", ps.iter().map(|p| p.lower).collect()),
            Column::number("upper", "", ps.iter().map(|p| p.upper).collect()),
            Column::number("initial", "", ps.iter().map(|p| p.initial).collect()),
            Column::number("value", "", ps.iter().map(|p| p.value).collect()),
            Column::number("std_error", "", ps.iter().map(|p| p.std_error).collect()),
            Column::count("at_bound", ps.iter().map(|p| p.at_bound as u64).collect()),
        ],
    )?;
    let rs = &o.rows;
    compound_table(
        &g,
        "rows",
        &[
            text(rs.iter().map(|r| r.target.clone()).collect(), "target"),
            Column::count(
                "line",
                rs.iter().map(|r| r.line.unwrap_or(0) as u64).collect(),
            ),
            text(rs.iter().map(|r| r.output.clone()).collect(), "output"),
            Column::count("job", rs.iter().map(|r| r.job as u64).collect()),
            Column::number("measured", "", rs.iter().map(|r| r.measured).collect()),
            Column::number("std", "", rs.iter().map(|r| r.std).collect()),
            Column::number("weight", "1", rs.iter().map(|r| r.weight).collect()),
            Column::number("initial", "", rs.iter().map(|r| r.initial).collect()),
            Column::number("model", "", rs.iter().map(|r| r.model).collect()),
            Column::number("residual", "1", rs.iter().map(|r| r.residual).collect()),
        ],
    )?;
    let n = ps.len();
    let m = rs.len();
    dataset_2d(&g, "correlation", (n, n), &flat(&o.correlation), "1")?;
    dataset_2d(&g, "covariance", (n, n), &flat(&o.covariance), "")?;
    dataset_2d(&g, "jacobian", (m, n), &flat(&o.jacobian), "")?;
    let es = &o.evaluation_list;
    compound_table(
        &g,
        "evaluations",
        &[
            Column::count("index", (0..es.len() as u64).collect()),
            text(es.iter().map(|e| e.role.clone()).collect(), "role"),
            Column::count("iteration", es.iter().map(|e| e.iteration as u64).collect()),
            text(es.iter().map(|e| e.batch.clone()).collect(), "batch"),
            text(es.iter().map(|e| e.job_ids.join(",")).collect(), "job_ids"),
            Column::count("ok", es.iter().map(|e| e.ok as u64).collect()),
            Column::number("cost", "1", es.iter().map(|e| e.cost).collect()),
        ],
    )?;
    let values: Vec<f64> = es.iter().flat_map(|e| e.values.clone()).collect();
    dataset_2d(&g, "values", (es.len(), n), &values, "")?;
    let outputs: Vec<f64> = es.iter().flat_map(|e| e.outputs.clone()).collect();
    dataset_2d(&g, "outputs", (es.len(), m), &outputs, "")?;
    f.flush()?;
    Ok(())
}
