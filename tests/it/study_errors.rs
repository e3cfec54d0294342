//! Study inputs that would change the physics silently or exhaust the machine are input errors
//! found when the study is loaded, naming the study (or scene) file, the line and the key
//! (issue 9, items 5 and 6): keys that replace earlier ones, repeated axis values, unchecked [pruning] and
//! [reference] keys, job counts beyond the limit (counted before expanding), TOML syntax and
//! duplicate-key errors; and the references obey the study's budget.
//!
//! Every study here is a small one on the shipped reference roll (`support::study_text`: 0.1 s
//! runs); the expected line is found in the study's text, never written down by hand.

use crate::support;

use std::process::Command;
use std::time::Instant;

use rotorsweep::error::InputError;
use rotorsweep::study::Study;
use support::{repo, rotorsweep_ok, scratch, study_text, write_file};

/// 1-based line of the first line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("`{needle}` in the study"))
        + 1
}

/// Loads `text` as `dir/name`; it must fail at the line of `needle`, with `key` and `says`.
fn fails(name: &str, text: &str, needle: &str, key: &str, says: &[&str]) -> InputError {
    let d = scratch(&format!("errors-{name}"));
    let p = write_file(&d, name, text);
    let e = Study::load(&p).expect_err(name);
    let msg = e.to_string();
    assert_eq!(e.file, p, "{msg}");
    assert_eq!(e.line, Some(line_of(text, needle)), "{name}: {msg}");
    assert_eq!(e.key.as_deref(), Some(key), "{name}: {msg}");
    for s in says {
        assert!(msg.contains(s), "{name}: `{s}` missing in {msg}");
    }
    e
}

#[test]
fn a_swept_key_that_replaces_a_set_key() {
    // Issue 9: `speed.hz.x` in [set] was dropped when the axis set `speed.hz`.
    let text =
        study_text("\"speed.hz.x\" = 3.0\n[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, 12.0]\n");
    fails(
        "overlap.toml",
        &text,
        "[[axes]]",
        "axes[0]",
        &["`speed.hz` would replace `speed.hz.x` (at set.speed.hz.x)"],
    );
}

#[test]
fn an_axis_value_given_twice_in_another_spelling() {
    let text = study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [10, 10.0]\n");
    fails(
        "dup.toml",
        &text,
        "values = [10, 10.0]",
        "axes[0].values",
        &["axis `speed.hz`", "values 0 (10) and 1 (10.0)"],
    );
    // Zipped rows compare whole: [10, "bdf"] and [10.0, "bdf"] are one row.
    let text = study_text(
        "[[axes]]\nkeys = [\"speed.hz\", \"solver.integrator\"]\n\
         values = [[10, \"bdf\"], [10.0, \"bdf\"], [10.0, \"rk45\"]]\n",
    );
    fails(
        "dupzip.toml",
        &text,
        "values = [[10",
        "axes[0].values",
        &["speed.hz, solver.integrator"],
    );
    // Explicit jobs that differ only in spelling.
    let text = study_text("[[jobs]]\n\"speed.hz\" = 10\n[[jobs]]\n\"speed.hz\" = 10.0\n");
    let second = text.rfind("[[jobs]]").unwrap();
    let e = {
        let d = scratch("dupjobs");
        Study::load(&write_file(&d, "dupjobs.toml", &text)).unwrap_err()
    };
    assert_eq!(
        e.line,
        Some(text[..second].lines().count() + 1),
        "at the second job: {e}"
    );
    assert!(e.to_string().contains("jobs 0 and 1"), "{e}");
}

#[test]
fn pruning_and_reference_keys_are_checked_at_load() {
    let prune = "[[axes]]\nkey = \"reduction.prune_threshold\"\nvalues = [1e-3, 0.0]\n";
    // Issue 9: [pruning] overrides were unchecked until the pilot ran.
    let text = study_text(&format!("{prune}[pruning]\n\"solver.hmaxx\" = 1e-4\n"));
    fails(
        "pilot.toml",
        &text,
        "\"solver.hmaxx\"",
        "pruning.solver.hmaxx",
        &["pruning pilot", "unknown field `hmaxx`"],
    );
    let text = study_text(&format!("{prune}[pruning]\n\"solver.hmax\" = -1.0\n"));
    fails(
        "pilotvalue.toml",
        &text,
        "\"solver.hmax\"",
        "pruning.solver.hmax",
        &["positive"],
    );
    // The pilot runs on its jobs' model: no model keys.
    let text = study_text(&format!("{prune}[pruning]\n\"roll.shell.elements\" = 20\n"));
    fails(
        "pilotmodel.toml",
        &text,
        "\"roll.shell.elements\"",
        "pruning.roll.shell.elements",
        &["reduced model"],
    );
    // [pruning] without a pruned job would be ignored.
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n[pruning]\n\"solver.hmax\" = 1e-4\n",
    );
    fails(
        "nopilot.toml",
        &text,
        "\"solver.hmax\" = 1e-4",
        "pruning.solver.hmax",
        &["no job asks for pruning"],
    );
    // A reference value the scene refuses: at its own line.
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n[reference]\n\"solver.hmax\" = -2e-5\n",
    );
    fails(
        "refvalue.toml",
        &text,
        "\"solver.hmax\" = -2e-5",
        "reference.solver.hmax",
        &["positive"],
    );
}

#[test]
fn set_errors_point_at_their_quoted_key() {
    // Issue 9: sample_rate_hz = 1e12 aborted; now the record limit names the [set] line.
    let text = study_text(
        "\"simulation.sample_rate_hz\" = 1e12\n[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n",
    );
    fails(
        "rate.toml",
        &text,
        "\"simulation.sample_rate_hz\"",
        "simulation.sample_rate_hz",
        &["samples per channel", "limit of 1e7"],
    );
    let text = study_text(
        "\"roll.shell.elements\" = 2000\n[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0]\n",
    );
    fails(
        "mesh.toml",
        &text,
        "\"roll.shell.elements\"",
        "roll.shell.elements",
        &["500 nodes"],
    );
}

#[test]
fn syntax_and_duplicate_key_errors_keep_line_and_key() {
    // The study file: a key given twice names the key.
    let text =
        study_text("\"simulation.t_end_s\" = 0.2\n[[axes]]\nkey = \"speed.hz\"\nvalues = [1.0]\n");
    let e = fails(
        "twice.toml",
        &text,
        "\"simulation.t_end_s\" = 0.2",
        "set.simulation.t_end_s",
        &["duplicate key `set.simulation.t_end_s`"],
    );
    assert!(e.reason.contains("twice"), "{e}");
    // The scene file: a syntax error keeps the scene's name and line (it lost its line before).
    let d = scratch("scene-syntax");
    let scene = std::fs::read_to_string(repo().join("studies/scenes/reference-roll.toml"))
        .unwrap()
        .replace(
            "../maps/",
            &format!("{}/", repo().join("studies/maps").display()),
        )
        .replacen("elements = 40", "elements = = 40", 1);
    let scene_path = write_file(&d, "scene.toml", &scene);
    let study = format!("scene = {scene_path:?}\n[[axes]]\nkey = \"speed.hz\"\nvalues = [1.0]\n");
    let e = Study::load(&write_file(&d, "s.toml", &study)).unwrap_err();
    assert_eq!(e.file, scene_path, "{e}");
    assert_eq!(e.line, Some(line_of(&scene, "elements = = 40")), "{e}");
}

#[test]
fn too_many_jobs_fail_fast_without_expanding() {
    // Five axes of 1000 values: 1e15 jobs (issue 9: plan aborted). The limit (MAX_JOBS) is
    // 1 000 000, passed at the third axis (1e9 jobs).
    let values: Vec<String> = (1..=1000).map(|i| format!("{i}.0")).collect();
    let values = values.join(", ");
    let keys = [
        "speed.hz",
        "solver.hmax",
        "solver.tolerance",
        "simulation.t_end_s",
        "damping.above_ratio",
    ];
    let axes: String = keys
        .iter()
        .map(|k| format!("[[axes]]\nkey = \"{k}\"\nvalues = [{values}]\n"))
        .collect();
    let text = study_text(&axes);
    let third = text.match_indices("[[axes]]").nth(2).unwrap().0;
    let d = scratch("many");
    let p = write_file(&d, "many.toml", &text);
    let t0 = Instant::now();
    let e = Study::load(&p).unwrap_err();
    assert_eq!(e.line, Some(text[..third].lines().count() + 1), "{e}");
    assert_eq!(e.key.as_deref(), Some("axes[2]"), "{e}");
    assert!(e.to_string().contains("1000000000 jobs"), "{e}");
    assert!(e.to_string().contains("limit of 1000000"), "{e}");
    // Through `plan`: exit 1 at once. Generous bound for a busy 2-core machine: expanding and
    // validating 1e9 jobs alone would take hours (about 20 µs each, measured).
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("plan")
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("many.toml"));
    assert!(t0.elapsed().as_secs_f64() < 10.0, "{:?}", t0.elapsed());
}

#[test]
fn references_obey_the_study_budget_unless_they_set_their_own() {
    let d = scratch("budget");
    let body = "[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, 12.0]\n\
                [reference]\n\"solver.hmax\" = 2e-5\n[budget]\ncpu_s = 30.0\nsteps = 1000000\n";
    let st = Study::load(&write_file(&d, "a.toml", &study_text(body))).unwrap();
    assert_eq!(st.references.len(), 2);
    for r in &st.references {
        let scene = st.scene_of(&r.overrides).unwrap();
        assert_eq!(scene.solver.cpu_budget, Some(30.0));
        assert_eq!(scene.solver.max_steps, 1_000_000);
    }
    let own = body.replace(
        "\"solver.hmax\" = 2e-5\n",
        "\"solver.hmax\" = 2e-5\n\"solver.cpu_budget_s\" = 60.0\n",
    );
    let st = Study::load(&write_file(&d, "b.toml", &study_text(&own))).unwrap();
    for r in &st.references {
        let scene = st.scene_of(&r.overrides).unwrap();
        assert_eq!(scene.solver.cpu_budget, Some(60.0));
        assert_eq!(scene.solver.max_steps, 1_000_000);
    }
    for j in &st.jobs {
        assert_eq!(
            st.scene_of(&j.overrides).unwrap().solver.cpu_budget,
            Some(30.0)
        );
    }
}

#[test]
fn plan_prints_memory_and_disk_estimates() {
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("plan")
        .arg(repo().join("studies/smoke.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    // smoke: 12 jobs and 4 references of 0.5 s recorded at 1 kHz (501 samples) × (3 sensors × 2
    // runout directions + time) × 8 B = 28 056 B each, 16 × 28 056 B = 0.45 MB.
    assert!(stdout.contains("disk estimate: 0.4 MB"), "{stdout}");
    assert!(stdout.contains("memory estimate: "), "{stdout}");
}

#[test]
fn a_study_given_as_a_scene_and_a_scene_given_as_a_study_say_so() {
    let smoke = repo().join("studies/smoke.toml");
    let e = rotorsweep::scene::Scene::load(&smoke, &[]).unwrap_err();
    assert_eq!(e.file, smoke);
    assert!(e.reason.contains("this is a study file"), "{e}");
    assert!(e.reason.contains("rotorsweep run"), "{e}");
    let roll = repo().join("studies/scenes/reference-roll.toml");
    let e = Study::load(&roll).unwrap_err();
    assert_eq!(e.file, roll);
    assert!(e.reason.contains("this is a scene file"), "{e}");
    assert!(e.reason.contains("rotorsweep modes"), "{e}");
}

#[test]
fn plan_lists_numeric_values_in_numeric_order() {
    let d = scratch("plan-order");
    let p = write_file(
        &d,
        "s.toml",
        &study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, 5.0, 6.0, 12.5]\n"),
    );
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(["plan", p.to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("speed.hz: 5.0, 6.0, 10.0, 12.5"),
        "as text 10.0 sorted before 5.0:\n{text}"
    );
}

#[test]
fn plan_of_a_long_study_lists_its_ends_and_all_jobs_lists_every_one() {
    let d = scratch("plan-long");
    // 150 jobs: more than the 100 that `plan` lists whole, and 150 values of one parameter.
    let p = write_file(
        &d,
        "s.toml",
        &study_text(
            "[[axes]]\nkey = \"speed.hz\"\nrange = { start = 5.0, stop = 6.495, step = 0.01 }\n",
        ),
    );
    let plan = |extra: &[&str]| {
        let args: Vec<&str> = ["plan", p.to_str().unwrap()]
            .into_iter()
            .chain(extra.iter().copied())
            .collect();
        String::from_utf8(rotorsweep_ok(&args)).unwrap()
    };
    let job_lines = |text: &str| {
        text.lines()
            .filter(|l| l.contains("speed.hz=") && l.trim_start().starts_with(char::is_numeric))
            .count()
    };
    let short = plan(&[]);
    assert!(short.starts_with("study "), "{short}");
    assert!(short.contains("150 jobs"), "{short}");
    assert!(
        short.contains(
            "speed.hz: 5.0, 5.01, 5.02, 5.03, 5.04, …, 6.45, 6.46, 6.47, 6.48, 6.49 (150 values)"
        ),
        "{short}"
    );
    assert_eq!(job_lines(&short), 20, "{short}");
    assert!(
        short.contains("130 jobs not listed (--all-jobs lists every one)"),
        "{short}"
    );
    let all = plan(&["--all-jobs"]);
    assert_eq!(job_lines(&all), 150, "{all}");
    assert!(!all.contains('…'), "{all}");
}
