//! `rotorsweep report` of a calibration results file (issue 24, item 6): the tables
//! `calibration_parameters`, `calibration_rows`, `calibration_correlation` and
//! `calibration_evaluations` hold the numbers the calibration wrote, bit for bit (read from the
//! file, not fitted again), in the library's report, the command's CSV and JSON; a calibration
//! table asked of a study results file, and a study table asked of a calibration file, are
//! errors naming the file and saying which kind of file has the table.

use crate::support;
use rotorsweep::calibration::{self, Calibration};
use rotorsweep::report::{self, Cell, Format, Table};
use support::{scratch, write_file};

/// A small calibration: the rigid Jeffcott rotor (studies/scenes/rigid-jeffcott.toml) 0.3 s at
/// 5 Hz with its static sag, its supports' horizontal and vertical stiffness (two parameters,
/// log scale) fitted to its two critical speeds and its vertical sag at the centre (three
/// rows). Returns the folder and the fit as the library returned it.
fn small_calibration() -> (support::Scratch, calibration::Outcome) {
    let d = scratch("report-calibration");
    crate::calibration::rigid_study(&d, 0.3, "[linear]\nstatic = true\n");
    let p = write_file(
        &d,
        "cal.toml",
        "study = \"study.toml\"\n[fit]\nstep = 0.001\nmax_iterations = 8\n\
         [[parameters]]\nname = \"kx\"\n\
         keys = [\"supports[0].spring.kx_n_per_m\", \"supports[1].spring.kx_n_per_m\"]\n\
         initial = 1.0e5\nlower = 1.0e4\nupper = 1.0e6\nscale = \"log\"\n\
         [[parameters]]\nname = \"ky\"\n\
         keys = [\"supports[0].spring.ky_n_per_m\", \"supports[1].spring.ky_n_per_m\"]\n\
         initial = 1.0e5\nlower = 1.0e4\nupper = 1.0e6\nscale = \"log\"\n\
         [[targets]]\noutput = \"sag_vertical_um:centre\"\nvalue = 5376.0\nstd = 5.0\n\
         [[frequencies]]\ncritical = 1\nhz = 6.8\nstd_hz = 0.01\n\
         [[frequencies]]\ncritical = 2\nhz = 7.85\nstd_hz = 0.01\n",
    );
    let cal = Calibration::load(&p).unwrap_or_else(|e| panic!("{e}"));
    let o = calibration::calibrate(&cal, &crate::calibration::options(&d.join("cal.h5")))
        .unwrap_or_else(|e| panic!("{e}"));
    (d, o)
}

fn table<'a>(r: &'a report::Report, name: &str) -> &'a Table {
    r.tables
        .iter()
        .find(|t| t.name == name)
        .unwrap_or_else(|| panic!("no table {name}: {:?}", r.table_names()))
}

/// A cell as a key that tells every bit of a number (NaN equal to NaN).
fn key(c: &Cell) -> String {
    match c {
        Cell::Text(s) => format!("text {s}"),
        Cell::Number(x) => format!("number {:016x}", x.to_bits()),
        Cell::Count(n) => format!("count {n}"),
    }
}

/// Asserts that the rows of `t` are `want`, cell by cell, bit for bit.
fn assert_same(t: &Table, want: impl Iterator<Item = Vec<Cell>>) {
    let got: Vec<Vec<String>> = t.rows.iter().map(|r| r.iter().map(key).collect()).collect();
    let want: Vec<Vec<String>> = want.map(|r| r.iter().map(key).collect()).collect();
    assert_eq!(got, want, "{}", t.name);
}

#[test]
fn a_calibration_report_reads_back_the_numbers_written() {
    let (d, o) = small_calibration();
    let file = d.join("cal.h5");
    let r = report::read(&file).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        r.table_names(),
        [
            "calibration_parameters",
            "calibration_rows",
            "calibration_correlation",
            "calibration_evaluations"
        ]
    );
    assert!(r.overview.contains(&o.stop), "{}", r.overview);
    // Parameters and rows: every cell, in the columns' order, as the fit gave it.
    let t = table(&r, "calibration_parameters");
    assert_same(
        t,
        o.parameters.iter().map(|p| {
            let mut c = vec![
                Cell::Text(p.name.clone()),
                Cell::Text(p.keys.join(",")),
                Cell::Text(p.scale.clone()),
            ];
            c.extend([p.lower, p.upper, p.initial, p.value, p.std_error].map(Cell::Number));
            c.push(Cell::Count(p.at_bound as u64));
            c
        }),
    );
    let t = table(&r, "calibration_rows");
    assert_eq!(o.rows.len(), 3);
    assert_same(
        t,
        o.rows.iter().map(|w| {
            let mut c = vec![
                Cell::Text(w.target.clone()),
                Cell::Count(w.line.unwrap() as u64),
                Cell::Text(w.output.clone()),
                Cell::Count(w.job as u64),
            ];
            c.extend(
                [w.measured, w.std, w.weight, w.initial, w.model, w.residual].map(Cell::Number),
            );
            c
        }),
    );
    // Correlation: the matrix, a row per parameter.
    let t = table(&r, "calibration_correlation");
    assert_eq!(t.columns, ["parameter", "kx", "ky"]);
    assert_same(
        t,
        o.correlation.iter().zip(&o.parameters).map(|(row, p)| {
            std::iter::once(Cell::Text(p.name.clone()))
                .chain(row.iter().copied().map(Cell::Number))
                .collect()
        }),
    );
    // Evaluations: the history, cost and values of every point.
    let t = table(&r, "calibration_evaluations");
    assert_eq!(o.evaluation_list.len(), o.evaluations);
    assert_same(
        t,
        o.evaluation_list.iter().enumerate().map(|(i, e)| {
            let mut c = vec![
                Cell::Count(i as u64),
                Cell::Text(e.role.clone()),
                Cell::Count(e.iteration as u64),
                Cell::Text(e.batch.clone()),
                Cell::Text(e.job_ids.join(",")),
                Cell::Count(e.ok as u64),
                Cell::Number(e.cost),
            ];
            c.extend(e.values.iter().copied().map(Cell::Number));
            c
        }),
    );
    // The command's CSV of one table: the title lines left out, numbers read back exactly.
    let path = file.to_str().unwrap();
    let csv = support::rotorsweep_ok(&[
        "report",
        path,
        "--table",
        "calibration_rows",
        "--format",
        "csv",
    ]);
    let csv = String::from_utf8(csv).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let model = head.iter().position(|c| *c == "model").unwrap();
    let got: Vec<f64> = lines
        .map(|l| l.split(',').nth(model).unwrap().parse().unwrap())
        .collect();
    let want: Vec<f64> = o.rows.iter().map(|r| r.model).collect();
    assert_eq!(got, want, "{csv}");
    // JSON: the evaluations' costs (serde's shortest text of each f64).
    let j = support::report_table(&file, "calibration_evaluations");
    let cost = j["columns"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c == "cost")
        .unwrap();
    let costs: Vec<f64> = j["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r[cost].as_f64().unwrap())
        .collect();
    let want: Vec<f64> = o.evaluation_list.iter().map(|e| e.cost).collect();
    for (g, w) in costs.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-15 * w.abs(), "{g} against {w}");
    }
    assert_eq!(costs.len(), want.len());
    // Markdown names every table.
    let md = r.render(Format::Markdown, None).unwrap();
    for name in r.table_names() {
        assert!(md.contains(&format!("(`{name}`)")), "{name}");
    }
}

#[test]
fn calibration_tables_of_a_study_file_and_study_tables_of_a_calibration_are_errors() {
    let (d, _) = small_calibration();
    let report_of = |file: &std::path::Path, table: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
            .args(["report", file.to_str().unwrap(), "--table", table])
            .output()
            .unwrap()
    };
    // The first evaluation's batch is a study results file.
    let study = d.join("cal.h5.evaluations/batch-000.h5");
    let out = report_of(&study, "calibration_parameters");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("batch-000.h5"), "{err}");
    assert!(
        err.contains(
            "no table `calibration_parameters` in this file (a table of a calibration results \
             file, `rotorsweep calibrate -o`; this file is not one)"
        ),
        "{err}"
    );
    let out = report_of(&d.join("cal.h5"), "solver");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cal.h5"), "{err}");
    assert!(
        err.contains("(this file is a calibration results file, `rotorsweep calibrate -o`)"),
        "{err}"
    );
    assert!(err.contains("calibration_rows"), "{err}");
}
