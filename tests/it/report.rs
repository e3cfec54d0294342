//! `rotorsweep report` on tiny studies run through the library (the reference roll, 0.1 s per job
//! as the `study_text` helper sets): 3 speeds × 2 integrators with a tight BDF reference per
//! speed and one explicit job that runs out of its step budget; and 3 speeds × a trial mass
//! against its baseline; and a run-up and a coast-down of the Jeffcott scene, labelled.

use crate::support;

use rotorsweep::report::{self, Cell, Format, Report};
use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;
use support::{scratch, study_text, write_file};

/// The study's axes give 3 × 2 = 6 jobs; the explicit job (`max_steps = 5`, status `budget`)
/// is the 7th.
const JOBS: usize = 7;

/// Runs the study with `body` after `study_text`'s `[set]`; returns its folder (removed when
/// dropped) and report.
fn run_study(name: &str, body: &str, ok: usize) -> (support::Scratch, Report) {
    let d = scratch(name);
    let study = Study::load(&write_file(&d, "s.toml", &study_text(body))).unwrap();
    let out = d.join("out.h5");
    let outcome = campaign::run(&study, &support::run_options(&out)).unwrap();
    assert_eq!(outcome.ok, ok);
    let r = report::read(&out).unwrap();
    (d, r)
}

/// The markdown table under the heading that ends with `(`name`)` (after its legend): its lines.
fn md_table<'a>(md: &'a str, name: &str) -> Vec<&'a str> {
    let heading = format!("(`{name}`)");
    md.lines()
        .skip_while(|l| !(l.starts_with("## ") && l.ends_with(&heading)))
        .skip(1)
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .collect()
}

/// The cells of a markdown table line.
fn md_cells(line: &str) -> Vec<&str> {
    line.trim_matches('|').split('|').map(str::trim).collect()
}

#[test]
fn report_tables_in_markdown_csv_and_json() {
    let (_dir, r) = run_study(
        "report",
        "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0, 16.0]\n\
         [[axes]]\nkey = \"solver.integrator\"\nvalues = [\"bdf\", \"gen-alpha\"]\n\
         [[jobs]]\n\"speed.hz\" = 12.0\n\"solver.integrator\" = \"bdf\"\n\"solver.max_steps\" = 5\n\
         [reference]\n\"solver.integrator\" = \"bdf\"\n\"solver.tolerance\" = 1e-10\n\"solver.hmax\" = 2e-5\n",
        JOBS - 1,
    );
    assert_eq!(
        r.table_names(),
        vec!["solver", "resonances", "stability", "linear"],
        "no trial_mass: the study has no [analysis] baseline"
    );

    // Markdown: 7 jobs ≤ 8, so the solver table is transposed: a heading column plus one
    // column per job; rows CPU time, relative, iterations/step, max and RMS error, status, and
    // cause (one job did not end ok).
    let md = r.render(Format::Markdown, None).unwrap();
    let solver = md_table(&md, "solver");
    assert_eq!(md_cells(solver[0]).len(), 1 + JOBS, "{md}");
    let headings: Vec<&str> = solver[2..].iter().map(|l| md_cells(l)[0]).collect();
    assert_eq!(
        headings,
        vec![
            "CPU time [s]",
            "relative",
            "iterations/step",
            "max error [µm]",
            "RMS error [µm]",
            "peak amplitude error [µm]",
            "status",
            "cause"
        ]
    );
    let statuses = md_cells(solver[8]);
    assert_eq!(statuses.iter().filter(|s| **s == "ok").count(), JOBS - 1);
    assert_eq!(statuses.iter().filter(|s| **s == "budget").count(), 1);
    // The stability matrix: one row per integrator, one column per setting without the
    // integrator: the 3 speeds, and the budget job's own (its max_steps varies too).
    let stability = md_table(&md, "stability");
    assert_eq!(
        stability.len(),
        2 + 2,
        "header, rule, bdf, gen-alpha:\n{md}"
    );
    assert_eq!(
        md_cells(stability[0]),
        vec![
            "integrator",
            "speed.hz=12",
            "speed.hz=14",
            "speed.hz=16",
            "speed.hz=12, solver.max_steps=5"
        ]
    );
    let bdf = md_cells(stability[2]);
    assert!(
        bdf[1].starts_with("ok ") && bdf[4].starts_with("budget "),
        "{md}"
    );
    assert_eq!(
        md_cells(stability[3])[4],
        "",
        "no gen-alpha job with max_steps"
    );

    // CSV of one table: a header and one line per job, no title line, so pandas reads it; the
    // job's id and one column per varying key (the file's `varying_keys`), no joined setting.
    let csv = r.render(Format::Csv, Some("solver")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + JOBS, "{csv}");
    assert_eq!(
        lines[0],
        "job_id,speed.hz,solver.integrator,solver.max_steps,status,cpu_time_s,relative,\
         iterations_per_step,steps,rejected_steps,error_max_um,error_rms_um,error_peak_um,cause"
    );
    // The first job: speed 12, bdf, no max_steps of its own (empty); the explicit job has 5.
    let first: Vec<&str> = lines[1].split(',').collect();
    assert!(first[0].starts_with('j'), "{csv}");
    assert_eq!(&first[1..4], ["12", "bdf", ""], "{csv}");
    assert!(
        lines.iter().any(|l| l.split(',').nth(3) == Some("5")),
        "{csv}"
    );
    // All tables: each after a `# title` and a `# legend` line, tables apart by one blank line.
    let all = r.render(Format::Csv, None).unwrap();
    assert_eq!(all.lines().filter(|l| l.starts_with("# ")).count(), 2 * 4);
    assert_eq!(all.lines().filter(|l| l.is_empty()).count(), 3);
    // Short headings: a title of a few words, the units in the legend.
    assert!(
        r.tables.iter().all(|t| t.title.split(' ').count() <= 5),
        "{:?}",
        r.table_names()
    );
    assert!(r.tables.iter().all(|t| t.legend.contains('[')));

    // JSON: the study and its tables, numbers as numbers.
    let json: serde_json::Value =
        serde_json::from_str(&r.render(Format::Json, None).unwrap()).unwrap();
    assert_eq!(json["study"], "t", "the name `study_text` gives");
    let tables = json["tables"].as_array().unwrap();
    let names: Vec<&str> = tables.iter().map(|t| t["name"].as_str().unwrap()).collect();
    assert_eq!(names, r.table_names());
    let solver = &tables[0];
    let col = |name: &str| {
        solver["columns"]
            .as_array()
            .unwrap()
            .iter()
            .position(|c| c == name)
            .unwrap()
    };
    let rows = solver["rows"].as_array().unwrap();
    assert_eq!(rows.len(), JOBS);
    // relative = CPU time / the least CPU time of the ok jobs: exactly 1 for that job (x / x),
    // and no ok job below it.
    let relative: Vec<f64> = rows
        .iter()
        .filter(|row| row[col("status")] == "ok")
        .map(|row| row[col("relative")].as_f64().unwrap())
        .collect();
    assert_eq!(relative.iter().copied().fold(f64::INFINITY, f64::min), 1.0);
    // The budget job stopped after max_steps = 5 steps, and has no error against the reference
    // (NaN in the file, null here); its cause is given.
    let budget = rows
        .iter()
        .find(|row| row[col("status")] == "budget")
        .unwrap();
    assert_eq!(budget[col("steps")], 5);
    assert!(budget[col("error_max_um")].is_null());
    assert!(!budget[col("cause")].as_str().unwrap().is_empty());
    // The ok jobs have finite errors against their speed's reference.
    assert!(rows
        .iter()
        .filter(|row| row[col("status")] == "ok")
        .all(|row| row[col("error_max_um")]
            .as_f64()
            .is_some_and(f64::is_finite)));

    // Resonances: 2 sweeps (one per integrator: bdf's 3 ok speeds, gen-alpha's 3) × 2 directions
    // × the integer orders ≥ 2 of the default orders 1, 2, 3, 4.
    let res = &tables[1];
    assert_eq!(res["rows"].as_array().unwrap().len(), 2 * 2 * 3, "{res}");
    assert_eq!(
        res["columns"],
        serde_json::json!([
            "sweep",
            "direction",
            "order",
            "expected_hz",
            "speed_hz",
            "step_hz",
            "note",
            "centre_um",
            "drive_um",
            "tending_um"
        ])
    );
    // Three speeds 12, 14, 16 Hz: a 2 Hz step around any peak (14 Hz, the only interior
    // sample), 14 % of the speed: every resonance found is flagged coarse.
    for row in res["rows"].as_array().unwrap() {
        if row[4].is_f64() {
            assert_eq!(row[5], 2.0, "{row}");
            assert!(row[6].as_str().unwrap().contains("coarse"), "{row}");
        }
    }
    // Long form of the stability table: one row per job.
    assert_eq!(tables[2]["rows"].as_array().unwrap().len(), JOBS);

    // The linear table of the study's one linearised system (one model, one set of supports):
    // its stored Campbell data, 201 speeds 0–100 Hz × the lateral modes with their damping
    // (the layout of `rotorsweep linear -o`), then its critical speeds and its threshold: none,
    // the reference roll is stable over 0–100 Hz (docs/linear.md, "The reference roll").
    let linear = &tables[3];
    let lrows = linear["rows"].as_array().unwrap();
    let quantity = |q: &'static str| lrows.iter().filter(move |row| row[1] == q);
    let modes: Vec<&serde_json::Value> = quantity("mode").collect();
    let per_speed = modes.iter().filter(|row| row[2] == 0.0).count();
    assert!(per_speed >= 4, "{per_speed} lateral modes");
    assert_eq!(modes.len(), 201 * per_speed);
    assert!(modes.iter().all(|row| {
        row[5].as_f64().is_some_and(|f| f > 0.0) && row[7].as_f64().is_some_and(|d| d > 0.0)
    }));
    // The first bending pair of the reference roll on its stands (docs/linear.md, "The reference roll": 30.52 / 32.35 Hz).
    let f1 = modes[0][5].as_f64().unwrap();
    assert!((f1 - 30.5).abs() < 0.5, "{f1}");
    let crit: Vec<f64> = quantity("critical_speed")
        .map(|row| row[2].as_f64().unwrap())
        .collect();
    assert!(crit.iter().any(|c| (c - f1).abs() < 0.1), "{crit:?}");
    // One threshold row, empty: stable over the range.
    let threshold: Vec<&serde_json::Value> = quantity("stability_threshold").collect();
    assert_eq!(threshold.len(), 1);
    assert!(threshold[0][2].is_null(), "{:?}", threshold[0]);
}

#[test]
fn trial_mass_table_per_job_against_the_baseline() {
    let (_dir, r) = run_study(
        "report-trial",
        "[[axes]]\nkey = \"roll.masses\"\n\
         values = [[], [{ z_mm = 2250.0, radius_mm = 160.0, angle_deg = 0.0, mass_g = 100.0 }]]\n\
         labels = [\"none\", \"100 g 0°\"]\n\
         [[axes]]\nkey = \"speed.hz\"\nvalues = [16.0, 12.0, 14.0]\n\
         [analysis]\nbaseline = \"none\"\n",
        6,
    );
    let t = r.tables.iter().find(|t| t.name == "trial_mass").unwrap();
    let mut columns = vec![
        "job_id".to_string(),
        "label".to_string(),
        "speed_hz".to_string(),
    ];
    for s in ["centre", "drive", "tending"] {
        columns.push(format!("{s}_amplitude_change_um"));
        columns.push(format!("{s}_vector_change_um"));
    }
    assert_eq!(t.columns, columns);
    // One row per trial-mass job (3 speeds), sorted by speed; the label as the study wrote it
    // (the file's table keeps ASCII only: "100 g 0").
    let speeds: Vec<Cell> = t.rows.iter().map(|row| row[2].clone()).collect();
    assert_eq!(speeds, [12.0, 14.0, 16.0].map(Cell::Number));
    assert!(t
        .rows
        .iter()
        .all(|row| row[1] == Cell::Text("100 g 0°".into())));
    assert!(t
        .rows
        .iter()
        .all(|row| matches!(&row[0], Cell::Text(id) if id.starts_with('j'))));
    // A 100 g mass at the centre changes the 1× response there.
    assert!(t
        .rows
        .iter()
        .all(|row| matches!(row[4], Cell::Number(v) if v > 0.0)));
}

#[test]
fn errors_name_the_file() {
    let d = scratch("report-errors");
    let missing = d.join("missing.h5");
    let e = report::read(&missing).unwrap_err().to_string();
    assert!(e.starts_with(&missing.display().to_string()), "{e}");
    // An HDF5 file that is not a study's results.
    let other = d.join("other.h5");
    hdf5::File::create(&other).unwrap();
    let e = report::read(&other).unwrap_err().to_string();
    assert!(e.starts_with(&other.display().to_string()), "{e}");
    assert!(e.contains("not a study results file"), "{e}");
    // A text file.
    let text = write_file(&d, "study.toml", "name = \"x\"\n");
    let e = report::read(&text).unwrap_err().to_string();
    assert!(e.contains("not an HDF5 file"), "{e}");
}

#[test]
fn ramp_tables_name_jobs_by_their_labels_and_small_numbers_are_scientific() {
    // A run-up and a coast-down of the Jeffcott scene (2 s ramps at 15 Hz/s, 8-revolution
    // blocks: about 0.3 s CPU), labelled on their axis. The order tables name each job by its
    // label (markdown and HTML, column `job`) and carry job_id, label and the varying keys in
    // the long form, as the solver table does (their job ids are hashes a reader cannot place).
    let d = scratch("report-ramp-labels");
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    let text = format!(
        "name = \"ramps\"\nscene = {:?}\n[set]\n\"speed.profile\" = \"ramp\"\n\
         \"speed.ramp_start_s\" = 0.5\n\"simulation.settle_s\" = 0.5\n\
         \"simulation.sample_rate_hz\" = 1000.0\n\"speed.rate_hz_per_s\" = 15.0\n\
         \"simulation.t_end_s\" = 3.0\n[[axes]]\nkeys = [\"speed.from_hz\", \"speed.to_hz\"]\n\
         values = [[30.0, 60.0], [60.0, 30.0]]\nlabels = [\"run-up\", \"coast-down\"]\n\
         [analysis]\norders = [1.0, 2.0]\norder_revolutions = 8.0\n",
        scene.display().to_string()
    );
    let study = Study::load(&write_file(&d, "s.toml", &text)).unwrap();
    let out = d.join("out.h5");
    assert_eq!(
        campaign::run(&study, &support::run_options(&out))
            .unwrap()
            .ok,
        2
    );
    let r = report::read(&out).unwrap();
    let md = r.render(Format::Markdown, None).unwrap();
    for name in ["orders", "order_resonances"] {
        let t = md_table(&md, name);
        assert_eq!(md_cells(t[0])[..2], ["job", "order"], "{name}:\n{md}");
        let jobs: std::collections::BTreeSet<&str> =
            t[2..].iter().map(|l| md_cells(l)[0]).collect();
        assert_eq!(
            jobs.into_iter().collect::<Vec<_>>(),
            ["coast-down", "run-up"],
            "{name}"
        );
        let csv = r.render(Format::Csv, Some(name)).unwrap();
        let header = csv.lines().next().unwrap();
        assert!(
            header.starts_with("job_id,label,speed.from_hz,speed.to_hz,order,"),
            "{header}"
        );
        let second = csv.lines().nth(1).unwrap();
        let label = second.split(',').nth(1).unwrap();
        assert!(label == "run-up" || label == "coast-down", "{second}");
    }
    // Numbers below 1e-3 (the Jeffcott's first mode at 60 Hz has a damping ratio of 9.7e-4 in
    // the `linear` table) are scientific in every text form: no "0.000…" in markdown or CSV.
    let csv = r.render(Format::Csv, None).unwrap();
    let fixed_small = |text: &str| {
        text.split([',', '|', ' ', '\n'])
            .map(str::trim)
            .find(|f| f.trim_start_matches('-').starts_with("0.000"))
            .map(str::to_string)
    };
    assert!(
        csv.contains("e-"),
        "some value below 1e-3 is there to write"
    );
    assert_eq!(fixed_small(&csv), None);
    assert_eq!(fixed_small(&md), None);
}
