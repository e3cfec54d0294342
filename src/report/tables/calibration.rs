//! The tables of a calibration results file (`rotorsweep calibrate -o OUT.h5`): the fitted
//! parameters, the target rows, the correlation matrix and the evaluation history.
//!
//! In: the file's `/calibration` group as `calibration::write` stores it (docs/calibration.md
//! lists every field): the compound tables `parameters`, `rows` and `evaluations`, the matrices
//! `correlation` (parameters × parameters) and `values` (evaluations × parameters), and the
//! root attributes `name`, `stop`, `iterations`, `evaluation_count`, `start_cost`, `cost`,
//! `degrees_of_freedom`, `reduced_chi_square` and `warnings`. Out: the overview line and the
//! tables, every number as stored (nothing is fitted or computed again here):
//! - `calibration_parameters`: per parameter its name, keys, scale, bounds, initial and fitted
//!   value and standard error (the keys' units; none when the parameter was held) and
//!   `at_bound` (1 when the fit ends on a bound);
//! - `calibration_rows`: per target row its key in the calibration file and line, output, job,
//!   measured value, standard deviation, weight, the model at the start and at the fit (the
//!   output's units) and the residual √w (model − measured)/σ;
//! - `calibration_correlation`: the correlation matrix, a row per parameter and a column per
//!   parameter;
//! - `calibration_evaluations`: per evaluated point its index, role (`start`, `jacobian:<k>`,
//!   `step`), iteration, batch file, study job ids, `ok`, cost ½ Σ r² and one column
//!   `value:<parameter>` per parameter (the model's outputs per row are in the file's
//!   `/calibration/outputs` and in Python's `rotorsweep.calibration`).
//!
//! Also the note `report --table NAME` adds when a calibration's table is asked of another file
//! or another table of a calibration file ([`calibration_hint`]).

use hdf5::types::VarLenUnicode;
use hdf5::File;

use crate::report::table::{text_cell, Cell, Table};
use crate::store;
use crate::text::significant;

/// The tables of a calibration file, in the report's order.
pub(crate) const CALIBRATION_TABLES: [&str; 4] = [
    "calibration_parameters",
    "calibration_rows",
    "calibration_correlation",
    "calibration_evaluations",
];

/// Whether `f` is a calibration results file (root attribute `kind = "calibration"`).
pub(crate) fn is_calibration(f: &File) -> bool {
    store::read_str(f, "kind").is_ok_and(|k| k == "calibration")
}

/// What to add to "no table `name`" of a file with `tables`: which kind of file has the table,
/// when it is a calibration's table asked of another file or the other way round; "" else.
pub(crate) fn calibration_hint(name: &str, tables: &[Table]) -> &'static str {
    let calibration = |n: &str| CALIBRATION_TABLES.contains(&n);
    let has_calibration = tables.iter().any(|t| calibration(&t.name));
    if calibration(name) && !has_calibration {
        " (a table of a calibration results file, `rotorsweep calibrate -o`; this file is not \
         one)"
    } else if !calibration(name) && has_calibration {
        " (this file is a calibration results file, `rotorsweep calibrate -o`)"
    } else {
        ""
    }
}

/// A row of `/calibration/parameters` (HDF5 converts records member by member by name).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct ParameterRow {
    name: VarLenUnicode,
    keys: VarLenUnicode,
    scale: VarLenUnicode,
    lower: f64,
    upper: f64,
    initial: f64,
    value: f64,
    std_error: f64,
    at_bound: u64,
}

/// A row of `/calibration/rows`.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct TargetRow {
    target: VarLenUnicode,
    line: u64,
    output: VarLenUnicode,
    job: u64,
    measured: f64,
    std: f64,
    weight: f64,
    initial: f64,
    model: f64,
    residual: f64,
}

/// A row of `/calibration/evaluations`.
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct EvaluationRow {
    index: u64,
    role: VarLenUnicode,
    iteration: u64,
    batch: VarLenUnicode,
    job_ids: VarLenUnicode,
    ok: u64,
    cost: f64,
}

/// A table of the calibration (no markdown grid: the rows read well as they are).
fn table(n: usize, title: &str, legend: &str, columns: Vec<String>, rows: Vec<Vec<Cell>>) -> Table {
    Table {
        name: CALIBRATION_TABLES[n].into(),
        title: title.into(),
        legend: legend.into(),
        columns,
        rows,
        markdown: None,
    }
}

/// Column names.
fn names_of(columns: &[&str]) -> Vec<String> {
    columns.iter().map(|c| c.to_string()).collect()
}

/// The records of the table `name` under `/calibration`.
fn records<T: hdf5::H5Type>(f: &File, name: &str) -> hdf5::Result<Vec<T>> {
    f.dataset(&format!("calibration/{name}"))?.read_raw()
}

/// The matrix `name` under `/calibration`, its rows of `cols` values (none when empty).
fn matrix(f: &File, name: &str, cols: usize) -> hdf5::Result<Vec<Vec<f64>>> {
    let v: Vec<f64> = f.dataset(&format!("calibration/{name}"))?.read_raw()?;
    Ok(v.chunks(cols.max(1)).map(<[f64]>::to_vec).collect())
}

/// The overview line: the fit's stop, steps, evaluations, cost and reduced χ², and its
/// warnings (module doc).
pub(crate) fn calibration_overview(f: &File) -> hdf5::Result<String> {
    let num = |n: &str| store::read_num(f, n);
    let mut s = format!(
        "calibration: {} after {} steps, {} evaluations; cost {} -> {}, reduced chi-square {} \
         on {} degrees of freedom",
        store::read_str(f, "stop")?,
        num("iterations")?,
        num("evaluation_count")?,
        significant(num("start_cost")?, 4),
        significant(num("cost")?, 4),
        significant(num("reduced_chi_square")?, 4),
        num("degrees_of_freedom")?,
    );
    let warnings = store::read_str(f, "warnings").unwrap_or_default();
    for w in warnings.lines().filter(|w| !w.trim().is_empty()) {
        s += &format!("; warning: {w}");
    }
    Ok(s)
}

/// The four tables of a calibration file (module doc).
pub(crate) fn calibration_tables(f: &File) -> hdf5::Result<Vec<Table>> {
    let params: Vec<ParameterRow> = records(f, "parameters")?;
    let names: Vec<String> = params.iter().map(|p| p.name.as_str().to_string()).collect();
    let n = names.len();
    let parameters = table(
        0,
        "Fitted parameters",
        "Per free parameter: the scene keys it sets, its scale (the fit moves the value, or \
         log10 of it), bounds, initial and fitted value and standard error (the keys' units; \
         none when the parameter moved no row and was held), at_bound 1 when the fit ends on a \
         bound",
        names_of(&[
            "name",
            "keys",
            "scale",
            "lower",
            "upper",
            "initial",
            "value",
            "std_error",
            "at_bound",
        ]),
        params
            .iter()
            .map(|p| {
                let mut r = vec![text_cell(&p.name), text_cell(&p.keys), text_cell(&p.scale)];
                r.extend([p.lower, p.upper, p.initial, p.value, p.std_error].map(Cell::Number));
                r.push(Cell::Count(p.at_bound));
                r
            })
            .collect(),
    );
    let targets: Vec<TargetRow> = records(f, "rows")?;
    let rows = table(
        1,
        "Target rows: measured and model",
        "Per target row: its key in the calibration file and line, the output and job it \
         compares, the measured value and its standard deviation σ, the weight w, the model at \
         the start and at the fit (the output's units: Hz, µm, N) and the residual \
         √w (model − measured)/σ [1]",
        names_of(&[
            "target", "line", "output", "job", "measured", "std", "weight", "initial", "model",
            "residual",
        ]),
        targets
            .iter()
            .map(|t| {
                let mut r = vec![
                    text_cell(&t.target),
                    Cell::Count(t.line),
                    text_cell(&t.output),
                    Cell::Count(t.job),
                ];
                r.extend(
                    [t.measured, t.std, t.weight, t.initial, t.model, t.residual].map(Cell::Number),
                );
                r
            })
            .collect(),
    );
    // A row per parameter: its name, then its row of the matrix.
    let named = |m: Vec<Vec<f64>>, names: &[String]| -> Vec<Vec<Cell>> {
        names
            .iter()
            .zip(m)
            .map(|(name, r)| {
                std::iter::once(Cell::Text(name.clone()))
                    .chain(r.into_iter().map(Cell::Number))
                    .collect()
            })
            .collect()
    };
    let correlation = table(
        2,
        "Correlation of the fitted parameters",
        "The correlation matrix of the fitted values [1]: a row and a column per parameter \
         (none for a held parameter)",
        std::iter::once("parameter".to_string())
            .chain(names.iter().cloned())
            .collect(),
        named(matrix(f, "correlation", n)?, &names),
    );
    let evals: Vec<EvaluationRow> = records(f, "evaluations")?;
    let values = matrix(f, "values", n)?;
    let evaluations = table(
        3,
        "Evaluations: cost and parameter values of every point",
        "Per evaluated point, in the order evaluated: its role (start, jacobian:<k> for the \
         finite difference of parameter k, step for a trial step), the iteration it belongs to \
         (0: the start and its Jacobian; k: the trials of step k and the Jacobian at the point \
         it accepted), its batch's results file in OUT.h5.evaluations/, the study's job ids, ok \
         1 when every job ended ok, the cost ½ Σ r² [1] and each parameter's value \
         (value:<parameter>, the keys' units)",
        names_of(&[
            "index",
            "role",
            "iteration",
            "batch",
            "job_ids",
            "ok",
            "cost",
        ])
        .into_iter()
        .chain(names.iter().map(|p| format!("value:{p}")))
        .collect(),
        evals
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let mut r = vec![
                    Cell::Count(e.index),
                    text_cell(&e.role),
                    Cell::Count(e.iteration),
                    text_cell(&e.batch),
                    text_cell(&e.job_ids),
                    Cell::Count(e.ok),
                    Cell::Number(e.cost),
                ];
                let v = values.get(i).cloned().unwrap_or_else(|| vec![f64::NAN; n]);
                r.extend(v.into_iter().map(Cell::Number));
                r
            })
            .collect(),
    );
    Ok(vec![parameters, rows, correlation, evaluations])
}
