//! `rotorsweep calibrate` (src/calibration/): the bad inputs of issue 24 (file, key and line),
//! a parameter that moves nothing (a warning naming its file, key and line), a calibration
//! killed and resumed (the fit of an uninterrupted run; a finished one replayed), and known
//! parameters recovered from noisy run-ups made by the model (Young's modulus, ground damping
//! and unbalance from a 1× record; ground damping, modal damping and a bending asymmetry from a
//! 2× and a 1× record).

use crate::support;
use rotorsweep::calibration::{self, Calibration, Options};
use support::{scratch, write_file};

/// The experiment: the Jeffcott rotor (studies/scenes/jeffcott.toml) at four constant speeds
/// around its first critical (44.5 Hz), 4 s to settle, the 1× over the last second; its linear
/// systems with their static sag.
fn study(dir: &std::path::Path) -> std::path::PathBuf {
    jeffcott_study(
        dir,
        "experiment.toml",
        "name = \"jeffcott-near-critical\"\n[set]\n\
         \"simulation.settle_s\" = 4.0\n\"simulation.t_end_s\" = 5.0\n\
         \"simulation.sample_rate_hz\" = 500.0\n\"damping.schedule\" = \"custom\"\n\
         \"damping.bands\" = [{ below_hz = 250.0, ratio = 0.04 }, { below_hz = 1070.0, ratio = 0.01 }]\n\
         [[axes]]\nkey = \"speed.hz\"\nvalues = [42.0, 43.5, 44.5, 45.5]\n\
         [analysis]\norders = [1.0]\n[linear]\nstatic = true\n",
    )
}

/// Calibration options for a test: `out`, two threads, no overwrite.
pub(crate) fn options(out: &std::path::Path) -> Options {
    Options {
        output: out.to_path_buf(),
        threads: 2,
        overwrite: false,
        command: "test".into(),
    }
}

/// Writes `study.toml` in `dir`: the rigid Jeffcott rotor (studies/scenes/rigid-jeffcott.toml)
/// at 5 Hz for `t_end_s` (0.1 s settling), then `tail` (more tables).
pub(crate) fn rigid_study(dir: &std::path::Path, t_end_s: f64, tail: &str) -> std::path::PathBuf {
    let scene = support::repo().join("studies/scenes/rigid-jeffcott.toml");
    write_file(
        dir,
        "study.toml",
        &format!(
            "name = \"rigid\"\nscene = {:?}\n[set]\n\"simulation.t_end_s\" = {t_end_s:?}\n\
             \"simulation.settle_s\" = 0.1\n[[axes]]\nkey = \"speed.hz\"\nvalues = [5.0]\n{tail}",
            scene.display().to_string()
        ),
    )
}

/// Writes `body` (a study without its scene) as `file` in `dir` with the Jeffcott scene
/// (studies/scenes/jeffcott.toml) as its scene.
fn jeffcott_study(dir: &std::path::Path, file: &str, body: &str) -> std::path::PathBuf {
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    write_file(
        dir,
        file,
        &format!("scene = {:?}\n{body}", scene.display().to_string()),
    )
}

/// A calibration file around the experiment for the error tests.
fn error_of(body: &str) -> (Option<String>, Option<usize>, String, String) {
    let d = scratch("calibration-errors");
    study(&d);
    let text = format!("study = \"experiment.toml\"\n{body}");
    let p = write_file(&d, "c.toml", &text);
    let e = Calibration::load(&p).unwrap_err();
    assert!(e.to_string().contains("c.toml"), "{e}");
    (e.key.clone(), e.line, e.to_string(), text)
}

fn line(text: &str, needle: &str) -> Option<usize> {
    Some(support::line_number(text, needle))
}

const PARAM: &str = "[[parameters]]\nkey = \"damping.bands[0].ratio\"\nlower = 0.01\nupper = 0.1\n";
const ROW: &str = "[[targets]]\noutput = \"critical_speed_hz:1\"\nvalue = 44.5\nstd = 0.01\n";

#[test]
fn bad_calibrations_name_file_key_and_line() {
    // Bounds that exclude the initial value.
    let (key, at, msg, text) = error_of(&format!("{PARAM}initial = 0.2\n{ROW}"));
    assert_eq!(key.as_deref(), Some("parameters[0].initial"));
    assert_eq!(at, line(&text, "initial = 0.2"));
    assert!(msg.contains("outside the bounds"), "{msg}");
    // A target whose sensor the scene does not have (jeffcott has `disk`).
    let body = format!(
        "{PARAM}initial = 0.04\n[[resonances]]\norder = 1.0\nsensor = \"centre\"\n\
         amplitude_um = 100.0\namplitude_std_um = 5.0\n"
    );
    let (key, at, msg, text) = error_of(&body);
    assert_eq!(key.as_deref(), Some("resonances[0].sensor"));
    assert_eq!(at, line(&text, "sensor = \"centre\""));
    assert!(msg.contains("`centre`") && msg.contains("disk"), "{msg}");
    let body = format!(
        "{PARAM}initial = 0.04\n[[targets]]\noutput = \"line_amplitude_um:tending/vertical:1x\"\n\
         value = 1.0\nstd = 1.0\n"
    );
    let (key, _, msg, _) = error_of(&body);
    assert_eq!(key.as_deref(), Some("targets[0].output"));
    assert!(msg.contains("`tending`"), "{msg}");
    // A negative standard deviation and a negative weight.
    let body =
        format!("{PARAM}initial = 0.04\n[[frequencies]]\ncritical = 1\nhz = 44.5\nstd_hz = -0.1\n");
    let (key, at, msg, text) = error_of(&body);
    assert_eq!(key.as_deref(), Some("frequencies[0].std_hz"));
    assert_eq!(at, line(&text, "std_hz = -0.1"));
    assert!(msg.contains("must be positive"), "{msg}");
    let (key, at, msg, text) = error_of(&format!("{PARAM}initial = 0.04\n{ROW}weight = -2.0\n"));
    assert_eq!(key.as_deref(), Some("targets[0].weight"));
    assert_eq!(at, line(&text, "weight = -2.0"));
    assert!(msg.contains("≥ 0"), "{msg}");
    // A key the scene refuses, a log scale through zero, a job that does not exist.
    let (key, _, msg, _) = error_of(&format!(
        "[[parameters]]\nkey = \"supports[0].ground.no_such_n_per_m\"\nlower = 1.0\nupper = 2.0\ninitial = 1.5\n{ROW}"
    ));
    assert_eq!(key.as_deref(), Some("parameters[0].key"));
    assert!(msg.contains("refuses"), "{msg}");
    let (key, _, _, _) = error_of(&format!(
        "[[parameters]]\nkey = \"damping.bands[0].ratio\"\nlower = 0.0\nupper = 0.1\ninitial = 0.04\nscale = \"log\"\n{ROW}"
    ));
    assert_eq!(key.as_deref(), Some("parameters[0].lower"));
    let (key, _, msg, _) = error_of(&format!("{PARAM}initial = 0.04\n{ROW}job = 7\n"));
    assert_eq!(key.as_deref(), Some("targets[0].job"));
    assert!(msg.contains("4 job(s)"), "{msg}");
    // A value so many standard deviations from 0 that the cost would overflow (it ran, every
    // job ok, and stopped with "has no value for :" naming no row).
    let body = format!(
        "{PARAM}initial = 0.04\n[[frequencies]]\ncritical = 1\nhz = 1e308\nstd_hz = 0.01\n"
    );
    let (key, at, msg, text) = error_of(&body);
    assert_eq!(key.as_deref(), Some("frequencies[0].hz"));
    assert_eq!(at, line(&text, "hz = 1e308"));
    assert!(msg.contains("overflow"), "{msg}");
}

/// A study that sets a freed key per job (on an axis, in `[[jobs]]`, or a table holding it) and
/// a sampled study are refused at the parameter's key (or `study`), naming the study's table;
/// before, the axis case ran and failed in the evaluations' own study file.
#[test]
fn a_freed_key_the_study_sets_per_job_and_a_sampled_study_are_refused() {
    let d = scratch("calibration-freed-per-job");
    study(&d);
    let check = |cal: &str, key: &str, needles: &[&str]| {
        let text = format!("study = \"experiment.toml\"\n{cal}{ROW}");
        let p = write_file(&d, "c.toml", &text);
        let e = Calibration::load(&p).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("c.toml"), "{msg}");
        assert_eq!(e.key.as_deref(), Some(key), "{msg}");
        for n in needles {
            assert!(msg.contains(n), "{n}: {msg}");
        }
        e.line
    };
    // The experiment sweeps `speed.hz` on axes[0].
    let cal = "[[parameters]]\nkey = \"speed.hz\"\nlower = 40.0\nupper = 50.0\ninitial = 44.0\n";
    let at = check(cal, "parameters[0].key", &["`speed.hz`", "axes[0]"]);
    assert_eq!(at, Some(3));
    let cal = "[[parameters]]\nkeys = [\"damping.above_ratio\", \"speed\"]\nlower = 0.1\n\
               upper = 50.0\ninitial = 1.0\n";
    check(
        cal,
        "parameters[0].keys",
        &["`speed`", "`speed.hz`", "axes[0]"],
    );
    // Explicit jobs that set the freed key.
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    write_file(
        &d,
        "jobs.toml",
        &format!(
            "scene = {:?}\n[[jobs]]\n\"damping.above_ratio\" = 0.02\n[[jobs]]\n\"speed.hz\" = 40.0\n",
            scene.display().to_string()
        ),
    );
    let text = format!(
        "study = \"jobs.toml\"\n[[parameters]]\nkey = \"damping.above_ratio\"\nlower = 0.001\n\
         upper = 0.1\ninitial = 0.01\n{ROW}"
    );
    let p = write_file(&d, "c.toml", &text);
    let e = Calibration::load(&p).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("parameters[0].key"), "{e}");
    assert!(e.to_string().contains("its [[jobs]]"), "{e}");
    // A sampled study: its jobs are random draws, not an experiment.
    write_file(
        &d,
        "sampled.toml",
        &format!(
            "scene = {:?}\n[sample]\nmethod = \"monte-carlo\"\nn = 4\n[[sample.parameters]]\n\
             key = \"speed.hz\"\ndistribution = \"uniform\"\nlower = 40.0\nupper = 45.0\n",
            scene.display().to_string()
        ),
    );
    let text = format!("study = \"sampled.toml\"\n{PARAM}initial = 0.04\n{ROW}");
    let p = write_file(&d, "c.toml", &text);
    let e = Calibration::load(&p).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("study"), "{e}");
    assert_eq!(e.line, Some(1), "{e}");
    assert!(e.to_string().contains("[sample]"), "{e}");
}

/// A study of an axis and explicit `[[jobs]]` calibrated: every parameter point runs the axis's
/// job and each explicit job, and each target row reads its own job. The rigid Jeffcott rotor
/// (studies/scenes/rigid-jeffcott.toml) at three densities ρ, 4ρ and 2.25ρ (job 0 the axis's,
/// jobs 1 and 2 explicit), its support stiffness k fitted to the first critical speeds made
/// with k = 2e5 N/m by the closed form f = √(2k/m)/2π of the cylinder's bounce mode (Friswell
/// et al., *Dynamics of Rotating Machines*, 2010, §3.5; m = ρ π R² L; the cylinder's bending
/// moves f by less than 2e-5): f, f/2 and f/1.5. Jobs read in the wrong order would leave
/// residuals of many σ; the fit gives k within 1e-4 and every row within 1e-3 Hz.
#[test]
fn explicit_jobs_of_the_calibrated_study_run_at_every_point() {
    let d = scratch("calibration-explicit-jobs");
    rigid_study(
        &d,
        0.3,
        "[[jobs]]\n\"materials.steel.density_kg_m3\" = 31400.0\n\
         [[jobs]]\n\"materials.steel.density_kg_m3\" = 17662.5\n",
    );
    let m = 7850.0 * std::f64::consts::PI * 0.1f64.powi(2) * 0.4;
    let f = (2.0 * 2e5 / m).sqrt() / (2.0 * std::f64::consts::PI);
    let keys = "[\"supports[0].spring.kx_n_per_m\", \"supports[0].spring.ky_n_per_m\", \
                \"supports[1].spring.kx_n_per_m\", \"supports[1].spring.ky_n_per_m\"]";
    let rows: String = [(0, f), (1, f / 2.0), (2, f / 1.5)]
        .iter()
        .map(|(j, hz)| {
            format!("[[frequencies]]\njob = {j}\ncritical = 1\nhz = {hz}\nstd_hz = 0.01\n")
        })
        .collect();
    let p = write_file(
        &d,
        "cal.toml",
        &format!(
            "study = \"study.toml\"\n[fit]\nstep = 0.001\n[[parameters]]\nname = \"k\"\n\
             keys = {keys}\ninitial = 1.0e5\nlower = 1.0e4\nupper = 1.0e6\nscale = \"log\"\n{rows}"
        ),
    );
    let cal = Calibration::load(&p).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cal.study.jobs.len(), 3);
    let o = calibration::calibrate(&cal, &options(&d.join("c.h5"))).unwrap();
    let k = o.parameters[0].value;
    eprintln!(
        "k fitted {k:.3} against 2e5; rows {:?}",
        o.rows.iter().map(|r| r.model).collect::<Vec<_>>()
    );
    assert!((k / 2e5 - 1.0).abs() < 1e-4, "k = {k}");
    for (r, want) in o.rows.iter().zip([f, f / 2.0, f / 1.5]) {
        assert!(
            (r.model - want).abs() < 1e-3,
            "{} Hz against {want}",
            r.model
        );
    }
    // Every evaluation ran the three jobs.
    assert!(o
        .evaluation_list
        .iter()
        .all(|e| e.job_ids.len() == 3 && e.ok));
}

/// A calibration killed (SIGKILL) part-way, again and again (each time it saves a batch), and
/// run again, ends with the fit of an uninterrupted run: every value, standard error, row and evaluation the same (the JSON
/// output without its CPU and wall times); a run of a finished calibration replays its saved
/// evaluations and runs no job (its batch files untouched). The experiment: the rigid Jeffcott
/// rotor (studies/scenes/rigid-jeffcott.toml) 10 s at 5 Hz, the support stiffness fitted to
/// critical speeds of 8 Hz (the closed form of studies/sensitivity-jeffcott.toml).
#[test]
fn a_killed_calibration_resumes_to_the_fit_of_an_uninterrupted_one() {
    use std::process::Command;
    use std::time::{Duration, Instant};
    let d = scratch("calibration-kill");
    rigid_study(&d, 10.0, "");
    let keys = "[\"supports[0].spring.kx_n_per_m\", \"supports[0].spring.ky_n_per_m\", \
                \"supports[1].spring.kx_n_per_m\", \"supports[1].spring.ky_n_per_m\"]";
    write_file(
        &d,
        "cal.toml",
        &format!(
            "study = \"study.toml\"\n[fit]\nstep = 0.001\n[[parameters]]\nname = \"k\"\n\
             keys = {keys}\ninitial = 1.0e5\nlower = 1.0e4\nupper = 1.0e6\nscale = \"log\"\n\
             [[frequencies]]\ncritical = 1\nhz = 8.0\nstd_hz = 0.01\n\
             [[frequencies]]\ncritical = 2\nhz = 8.0\nstd_hz = 0.01\n"
        ),
    );
    let run = |out: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_rotorsweep"));
        c.current_dir(&d)
            .args([
                "calibrate",
                "cal.toml",
                "-o",
                out,
                "--json",
                "--threads",
                "1",
            ])
            .stderr(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped());
        c
    };
    // The JSON without the run's times.
    let fit = |stdout: &[u8]| -> serde_json::Value {
        let mut v: serde_json::Value = serde_json::from_slice(stdout).unwrap();
        let o = v.as_object_mut().unwrap();
        o.remove("cpu_s");
        o.remove("wall_s");
        v
    };
    let t0 = Instant::now();
    let whole = run("whole.h5").output().unwrap();
    assert!(whole.status.success());
    let whole_s = t0.elapsed().as_secs_f64();
    let batches = |out: &str| -> Vec<String> {
        let mut b: Vec<String> = std::fs::read_dir(d.join(format!("{out}.evaluations")))
            .map(|r| {
                r.filter_map(|e| e.ok())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .filter(|n| n.ends_with(".h5"))
                    .collect()
            })
            .unwrap_or_default();
        b.sort();
        b
    };
    // Each run killed as soon as a batch of its own is saved (a `batch-NNN.h5` renamed into the
    // evaluations folder; on an event, not a timer, so a loaded machine only makes it wait):
    // it is then inside the next batch, or writing the output after the last. Each run resumes
    // the saved batches and gets further; a run that finishes first ends the loop.
    let mut saved_at_kill = Vec::new();
    let deadline = Instant::now() + Duration::from_secs_f64(30.0 + 20.0 * whole_s);
    for _ in 0..6 {
        let before = batches("out.h5").len();
        let mut child = run("out.h5").spawn().unwrap();
        while batches("out.h5").len() == before && child.try_wait().unwrap().is_none() {
            assert!(
                Instant::now() < deadline,
                "a calibration run saved no batch in {:.0} s (the whole run took {whole_s:.1} s)",
                30.0 + 20.0 * whole_s
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        child.kill().unwrap();
        if child.wait().unwrap().code().is_some() {
            break; // it finished first
        }
        saved_at_kill.push(batches("out.h5").len());
    }
    eprintln!(
        "whole calibration {whole_s:.2} s, {} batches; killed when a batch was saved, batches \
         then: {saved_at_kill:?}",
        batches("whole.h5").len()
    );
    assert!(
        saved_at_kill.len() >= 2 && saved_at_kill.windows(2).all(|w| w[1] > w[0]),
        "fewer than two runs were killed part-way, each further: {saved_at_kill:?}"
    );
    let resumed = run("out.h5").output().unwrap();
    assert!(resumed.status.success());
    assert_eq!(fit(&resumed.stdout), fit(&whole.stdout));
    assert_eq!(batches("out.h5"), batches("whole.h5"));
    // Run again: the evaluations replayed, no batch file written.
    let stamps = |out: &str| -> Vec<std::time::SystemTime> {
        batches(out)
            .iter()
            .map(|b| {
                std::fs::metadata(d.join(format!("{out}.evaluations")).join(b))
                    .and_then(|m| m.modified())
                    .unwrap()
            })
            .collect()
    };
    let before = stamps("whole.h5");
    let again = run("whole.h5").output().unwrap();
    assert!(again.status.success());
    assert_eq!(fit(&again.stdout), fit(&whole.stdout));
    assert_eq!(stamps("whole.h5"), before);
}

/// A parameter that moves no target row (the run's end time does not enter the linear system
/// whose critical speeds are the targets) is a warning naming its file, key and line, and is
/// held at its start value with no standard error; the other parameter is fitted. A row that
/// no parameter moves (the horizontal sag, gravity being vertical) is a warning naming its
/// file, key and line.
#[test]
fn a_parameter_that_moves_nothing_is_a_warning() {
    let d = scratch("calibration-zero");
    study(&d);
    let text = "study = \"experiment.toml\"\n[fit]\nmax_iterations = 3\n\
                [[parameters]]\nname = \"ground\"\nkeys = [\"supports[0].ground.ky_n_per_m\", \"supports[1].ground.ky_n_per_m\"]\n\
                lower = 1e7\nupper = 2e8\ninitial = 6e7\nscale = \"log\"\n\
                [[parameters]]\nname = \"end time\"\nkey = \"simulation.t_end_s\"\n\
                lower = 4.5\nupper = 6.0\ninitial = 5.0\n\
                [[frequencies]]\ncritical = 1\nhz = 44.3\nstd_hz = 0.01\n\
                [[frequencies]]\ncritical = 2\nhz = 44.5\nstd_hz = 0.01\n\
                [[targets]]\noutput = \"sag_horizontal_um:disk\"\nvalue = 0.0\nstd = 1.0\n";
    let p = write_file(&d, "z.toml", text);
    let cal = Calibration::load(&p).unwrap_or_else(|e| panic!("{e}"));
    let o = calibration::calibrate(&cal, &options(&d.join("z.h5"))).unwrap();
    let at = support::line_number(text, "name = \"end time\"") - 1;
    let w = o
        .warnings
        .iter()
        .find(|w| w.contains("parameters[1]"))
        .unwrap_or_else(|| panic!("{:?}", o.warnings));
    assert!(w.contains(&format!("z.toml:{at}:")), "{w}");
    assert!(w.contains("moves no target row"), "{w}");
    // The horizontal sag under vertical gravity: no parameter moves it (a row warning).
    let at = support::line_number(text, "value = 0.0");
    let w = o
        .warnings
        .iter()
        .find(|w| w.contains("targets[0]"))
        .unwrap_or_else(|| panic!("{:?}", o.warnings));
    assert!(w.contains(&format!("z.toml:{at}:")), "{w}");
    assert!(
        w.contains("no parameter moves `sag_horizontal_um:disk`"),
        "{w}"
    );
    assert_eq!(o.parameters[1].value, 5.0);
    assert!(o.parameters[1].std_error.is_nan());
    assert!(o.parameters[0].value != 6e7);
}

/// The run-up of the recovery test: the Jeffcott rotor (studies/scenes/jeffcott.toml, first
/// critical speeds 44.4 Hz horizontal and 44.6 Hz vertical) held 5 s at 40 Hz, then ramped at
/// 2 Hz/s through its critical to 49 Hz and recorded from 5 s to 10 s at 1 kHz, its 1× tracked
/// (55 blocks of 8 revolutions per direction, half overlapping, 49 of them on the ramp below
/// 48.9 Hz). `set` adds `[set]` lines (the truth's values).
fn run_up(dir: &std::path::Path, name: &str, set: &str) -> std::path::PathBuf {
    jeffcott_study(
        dir,
        name,
        &format!(
            "name = \"jeffcott-runup\"\n[set]\n\"speed.profile\" = \"ramp\"\n\
             \"speed.from_hz\" = 40.0\n\"speed.to_hz\" = 49.0\n\"speed.ramp_start_s\" = 5.0\n\
             \"speed.rate_hz_per_s\" = 2.0\n\"simulation.settle_s\" = 5.0\n\
             \"simulation.t_end_s\" = 10.0\n\"simulation.sample_rate_hz\" = 1000.0\n{set}\
             [analysis]\norders = [1.0]\n"
        ),
    )
}

/// Issue 24's must-show: calibration recovers known parameters from synthetic data made by the
/// model itself plus noise. The truth (the values put in, so the one exception to "never
/// against its own output"): Young's modulus 210 GPa, the four ground dampers 5000 N s/m and the
/// unbalance 2 g. The model's run-up ([`run_up`]) at the truth, its two disk channels plus
/// seeded white noise of σ = 20 µm per sample (1.4 % of the 1.42 mm peak), written as a CSV
/// record and brought in through `rotorsweep import`'s own reader and writer
/// (`results::measured`, orders 1); the calibration fits the three from (206 GPa, 4000 N s/m,
/// 2.3 g) to the record's 1× on the ramp below 48.9 Hz (real and imaginary part of each of
/// the 98 blocks: 196 rows),
/// each part with σ = √(3/M) × 20 µm = 2.6 µm (the noise of a Hann-weighted order fit over M =
/// 8 revolutions × 1000 / 45 Hz = 178 samples; docs/runups-and-balancing.md, the noise floor).
///
/// Asserted: each fitted value within 2 % of its truth (the bound, asked for every
/// parameter; the standard errors are reported and checked to be below 2 % too, so the bound is
/// not met by luck of a wide error), the fit converged, and the reduced χ² is below 3 (1 for
/// independent blocks; the half-overlapping blocks share samples, so the residuals are
/// correlated, and at the truth itself it is 0.91). Measured 2026-12-03: E 210.0005 ± 0.0006 GPa,
/// damping 5010 ± 32 N s/m, unbalance 1.99984 ± 0.00105 g (each within 0.8 of its standard
/// error and 0.2 % of the truth), reduced χ² 0.90, 11 steps, 66 evaluations.
#[test]
fn a_noisy_run_up_gives_back_the_parameters_it_was_made_with() {
    let d = scratch("calibration-recovery");
    let truth = [210.0, 5000.0, 2.0];
    let set = set_lines(&[
        (&["materials.steel.youngs_modulus_gpa"], truth[0]),
        (&DAMPERS, truth[1]),
        (&["rotor.masses[0].mass_g"], truth[2]),
    ]);
    let (sim, ids) = run_truth(&run_up(&d, "truth.toml", &set));
    assert_eq!(ids.len(), 1);
    noisy_record(
        &sim,
        &ids[0],
        (20.0, 24),
        &[1.0],
        "disk",
        &d.join("record.h5"),
    );
    // The calibration from a start off in every parameter.
    run_up(&d, "experiment.toml", "");
    let text = format!(
        "study = \"experiment.toml\"\n[fit]\nmax_iterations = 30\nstep = 0.002\n\
         [[parameters]]\nname = \"E\"\nkey = \"materials.steel.youngs_modulus_gpa\"\n\
         lower = 150.0\nupper = 300.0\ninitial = 206.0\n\
         [[parameters]]\nname = \"ground damping\"\nkeys = [{}]\n\
         lower = 500.0\nupper = 20000.0\ninitial = 4000.0\nscale = \"log\"\n\
         [[parameters]]\nname = \"unbalance\"\nkey = \"rotor.masses[0].mass_g\"\n\
         lower = 0.5\nupper = 10.0\ninitial = 2.3\n\
         [[records]]\nfile = \"record.h5\"\namplitude_std_um = 2.6\n",
        quoted(&DAMPERS)
    );
    // The whole record holds the last 0.5 s at 49 Hz, whose blocks share a speed: an error
    // naming the file, the table and its line; so is a channel the record does not have.
    let p = write_file(&d, "dwell.toml", &text);
    let e = Calibration::load(&p).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("records[0]"), "{e}");
    assert_eq!(
        e.line,
        Some(support::line_number(&text, "[[records]]")),
        "{e}"
    );
    assert!(e.to_string().contains("both lie at"), "{e}");
    let bad = text.replace(
        "[[records]]\n",
        "[[records]]\nchannels = [\"disk/axial\"]\n",
    );
    let e = Calibration::load(&write_file(&d, "channel.toml", &bad)).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("records[0].channels"), "{e}");
    assert!(e.to_string().contains("`disk/axial`"), "{e}");
    // The ramp's blocks only (the ramp reaches 49 Hz at 9.5 s).
    let text = text + "speed_max_hz = 48.9\n";
    // A record of a sensor the scene does not have (the same ramp named `rim`): an error at
    // the record's file, naming the sensor and the scene's sensors.
    noisy_record(&sim, &ids[0], (20.0, 24), &[1.0], "rim", &d.join("rim.h5"));
    let rim = text.replace("\"record.h5\"", "\"rim.h5\"");
    let e = Calibration::load(&write_file(&d, "rim.toml", &rim)).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("records[0].file"), "{e}");
    assert_eq!(
        e.line,
        Some(support::line_number(&rim, "file = \"rim.h5\"")),
        "{e}"
    );
    let msg = e.to_string();
    assert!(msg.contains("sensor `rim` is not in the scene"), "{msg}");
    assert!(msg.contains("(its sensors: disk)"), "{msg}");
    // 2 directions × 49 ramp blocks × 2 parts.
    fit_recovers(&d, &text, 196, &truth);
}

/// The four ground dampers of the Jeffcott scene (both supports, both directions).
const DAMPERS: [&str; 4] = [
    "supports[0].ground.cx_ns_per_m",
    "supports[0].ground.cy_ns_per_m",
    "supports[1].ground.cx_ns_per_m",
    "supports[1].ground.cy_ns_per_m",
];

/// `[set]` lines: every key of each group at the group's value.
fn set_lines(groups: &[(&[&str], f64)]) -> String {
    let mut set = String::new();
    for (keys, v) in groups {
        for k in *keys {
            set += &format!("\"{k}\" = {v:?}\n");
        }
    }
    set
}

/// The keys as a TOML array's items: `"a", "b"`.
fn quoted(keys: &[&str]) -> String {
    let q: Vec<String> = keys.iter().map(|k| format!("{k:?}")).collect();
    q.join(", ")
}

/// Runs the truth's study (next to it, as `truth.h5`): the results file and the job ids in the
/// study's order.
fn run_truth(study: &std::path::Path) -> (std::path::PathBuf, Vec<String>) {
    let truth = rotorsweep::study::Study::load(study).unwrap();
    let sim = study.with_file_name("truth.h5");
    rotorsweep::study::run::run(&truth, &support::run_options(&sim)).unwrap();
    (sim, truth.jobs.iter().map(|j| j.id.clone()).collect())
}

/// Writes the calibration `text` as `recover.toml` in `dir`, checks its row count, calibrates it
/// into `recover.h5` and asserts the recovery (the bound): the fit converged, its
/// reduced χ² below 3, each fitted value within 2 % of its truth and each standard error below
/// 2 % of it (so the bound is not met by a wide error). Prints the fit.
fn fit_recovers(dir: &std::path::Path, text: &str, rows: usize, truth: &[f64]) {
    let cal =
        Calibration::load(&write_file(dir, "recover.toml", text)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cal.rows.len(), rows);
    let o = calibration::calibrate(&cal, &options(&dir.join("recover.h5"))).unwrap();
    let report: Vec<String> = o
        .parameters
        .iter()
        .map(|p| format!("{} {} ± {}", p.name, p.value, p.std_error))
        .collect();
    let summary = format!(
        "{report:?}, {} rows, stop {}, {} steps, {} evaluations, reduced χ² {}, cpu {} s, \
         correlation {:?}",
        cal.rows.len(),
        o.stop,
        o.iterations,
        o.evaluations,
        o.reduced_chi_square,
        o.cpu_s,
        o.correlation
    );
    println!("{summary}");
    assert_eq!(o.stop, "converged", "{summary}");
    assert!(o.reduced_chi_square < 3.0, "{summary}");
    assert_eq!(o.parameters.len(), truth.len());
    for (p, &t) in o.parameters.iter().zip(truth) {
        assert!(
            (p.value / t - 1.0).abs() < 0.02,
            "{} {} against {t}: {summary}",
            p.name,
            p.value
        );
        assert!(p.std_error < 0.02 * t, "{}: {summary}", p.name);
    }
}

/// A measured record made from the model: the time, roll angle and both disk channels of job
/// `id` of the results file `sim`, each channel plus seeded white noise of `sigma` µm per
/// sample, written as a CSV record (its channels named by the sensor `as_sensor`) and brought
/// in with `rotorsweep import`'s own reader and writer (`results::measured`, the given orders)
/// as `out`.
fn noisy_record(
    sim: &std::path::Path,
    id: &str,
    (sigma, seed): (f64, u64),
    orders: &[f64],
    as_sensor: &str,
    out: &std::path::Path,
) {
    use rotorsweep::numerics::rng::SplitMix64;
    use rotorsweep::results::measured;
    let (time, angle, channels) = {
        let f = hdf5::File::open(sim).unwrap();
        let g = f.group(&format!("jobs/{id}")).unwrap();
        let read = |n: &str| -> Vec<f64> { g.dataset(n).unwrap().read_raw().unwrap() };
        let chans: Vec<Vec<f64>> = ["vertical", "horizontal"]
            .iter()
            .map(|dir| read(&format!("runout/disk/{dir}")))
            .collect();
        (read("time"), read("speed/roll_angle"), chans)
    };
    let mut rng = SplitMix64::new(seed);
    let mut csv = format!(
        "time_s,roll_angle_rad,runout/{as_sensor}/vertical,runout/{as_sensor}/horizontal\n"
    );
    for i in 0..time.len() {
        let v = channels[0][i] + sigma * rng.normal();
        let h = channels[1][i] + sigma * rng.normal();
        csv += &format!("{:?},{:?},{v:?},{h:?}\n", time[i], angle[i]);
    }
    let csv_path = out.with_extension("csv");
    std::fs::write(&csv_path, csv).unwrap();
    let record = measured::read(&csv_path).unwrap();
    measured::write(out, "record", &record, orders, "test").unwrap();
}

/// The experiment of the damping and asymmetry recovery: the Jeffcott rotor
/// (studies/scenes/jeffcott.toml, critical speeds 44.4 Hz horizontal and 44.6 Hz vertical) with
/// custom modal damping (0.5 % below 250 Hz, 1 % below 1070 Hz) as two run-ups, recorded at
/// 1 kHz from the ramp's start at 0.5 s to its end: job 0 through the half-critical, 21 → 23.5
/// Hz at 0.5 Hz/s (its 2×, from gravity on the asymmetric shaft, passes 44.4–44.6 Hz), job 1
/// through the critical, 42 → 47 Hz at 2 Hz/s (its 1×, from the 2 g unbalance). Orders 1 and 2
/// tracked. `set` adds `[set]` lines (the truth's values).
fn two_run_ups(dir: &std::path::Path, name: &str, set: &str) -> std::path::PathBuf {
    jeffcott_study(
        dir,
        name,
        &format!(
            "name = \"jeffcott-two-runups\"\n[set]\n\"speed.profile\" = \"ramp\"\n\
             \"speed.ramp_start_s\" = 0.5\n\"simulation.settle_s\" = 0.5\n\
             \"simulation.sample_rate_hz\" = 1000.0\n\"damping.schedule\" = \"custom\"\n\
             \"damping.bands\" = [{{ below_hz = 250.0, ratio = 0.005 }}, {{ below_hz = 1070.0, ratio = 0.01 }}]\n\
             {set}[[axes]]\n\
             keys = [\"speed.from_hz\", \"speed.to_hz\", \"speed.rate_hz_per_s\", \"simulation.t_end_s\"]\n\
             values = [[21.0, 23.5, 0.5, 5.5], [42.0, 47.0, 2.0, 3.0]]\n\
             labels = [\"half-critical\", \"critical\"]\n[analysis]\norders = [1.0, 2.0]\n"
        ),
    )
}

/// Issue 24's must-show in the issue's own words: stand damping, modal damping and an asymmetry
/// amplitude recovered from a noisy run-up made by the model itself, each within 2 % or its
/// reported standard error. The truth (the values put in): the four ground dampers 5000 N s/m,
/// modal damping 0.5 % below 250 Hz and the shaft's bending asymmetry
/// (`rotor.segments[].bending_asymmetry`, (I_x − I_y)/(I_x + I_y)) 0.01; the unbalance stays
/// the scene's 2 g, known. The experiment ([`two_run_ups`]) at the truth, plus seeded white
/// noise per sample of σ = 5 µm on the half-critical job's channels and 20 µm on the critical
/// job's, brought in through `rotorsweep import`'s reader and writer; the calibration fits the
/// three from (4000 N s/m, 0.8 %, 0.013) to the half-critical run-up's 2× and the critical
/// run-up's 1× (real and imaginary part of every block of both channels). The σ of a part is
/// √(3/M) × the sample noise (docs/runups-and-balancing.md, the noise floor), M = 8 revolutions
/// × 1000 Hz / speed: 5 µm × √(3/360) = 0.46 µm at 22.25 Hz and 20 µm × √(3/178) = 2.6 µm at
/// 44.5 Hz.
///
/// Why two run-ups: modal damping acts in the rotating frame, which a synchronous forward whirl
/// (the 1×) does not move, so the 1× through the critical sees the ground dampers alone; the
/// 2× through the half-critical whirls at 2Ω, once Ω in the rotating frame, and sees both.
/// Measured (docs/calibration.md): the 2× alone also separates them (correlation −0.56), with
/// twice the ground dampers' standard error (93 against 42 N s/m).
///
/// Asserted ([`fit_recovers`]): the fit converged, its reduced χ² below 3, each fitted value
/// within 2 % of its truth and each standard error below 2 % of it (the issue asks 2 % or the
/// standard error; with the error below 2 % the first is the bound). Measured 2026-12-03: ground dampers 4973 ± 42 N s/m (0.55 %,
/// 0.65 σ), modal damping 0.49869 % ± 0.00274 % (0.26 %, 0.5 σ), asymmetry 0.0099869 ±
/// 0.0000093 (0.13 %, 1.4 σ); 208 rows, converged after 4 steps, 25 evaluations (50 run-ups),
/// reduced χ² 0.85, CPU 17 s.
#[test]
fn a_noisy_run_up_gives_back_stand_damping_modal_damping_and_asymmetry() {
    let d = scratch("calibration-damping-asymmetry");
    let asymmetry = [
        "rotor.segments[0].bending_asymmetry",
        "rotor.segments[1].bending_asymmetry",
    ];
    let truth = [5000.0, 0.005, 0.01];
    let set = set_lines(&[
        (&DAMPERS, truth[0]),
        (&["damping.bands[0].ratio"], truth[1]),
        (&asymmetry, truth[2]),
    ]);
    let (sim, ids) = run_truth(&two_run_ups(&d, "truth.toml", &set));
    assert_eq!(ids.len(), 2);
    let orders = [1.0, 2.0];
    noisy_record(
        &sim,
        &ids[0],
        (5.0, 241),
        &orders,
        "disk",
        &d.join("half.h5"),
    );
    noisy_record(
        &sim,
        &ids[1],
        (20.0, 242),
        &orders,
        "disk",
        &d.join("critical.h5"),
    );
    two_run_ups(&d, "experiment.toml", "");
    let text = format!(
        "study = \"experiment.toml\"\n[fit]\nmax_iterations = 30\nstep = 0.002\n\
         [[parameters]]\nname = \"ground damping\"\nkeys = [{}]\n\
         lower = 500.0\nupper = 20000.0\ninitial = 4000.0\nscale = \"log\"\n\
         [[parameters]]\nname = \"modal damping\"\nkey = \"damping.bands[0].ratio\"\n\
         lower = 0.001\nupper = 0.05\ninitial = 0.008\nscale = \"log\"\n\
         [[parameters]]\nname = \"asymmetry\"\nkeys = [{}]\n\
         lower = 0.001\nupper = 0.1\ninitial = 0.013\n\
         [[records]]\nfile = \"half.h5\"\njob = 0\norders = [2.0]\namplitude_std_um = 0.46\n\
         [[records]]\nfile = \"critical.h5\"\njob = 1\norders = [1.0]\namplitude_std_um = 2.6\n",
        quoted(&DAMPERS),
        quoted(&asymmetry)
    );
    // 2 records × 2 directions × 26 blocks × 2 parts.
    fit_recovers(&d, &text, 208, &truth);
}

/// The shipped files of issue 24 load: studies/calibrate-table51.toml (three free parameters,
/// the twelve rows of the source's Table 5.1: speed and three amplitudes of each of 2×, 3×, 4×)
/// and studies/monte-carlo-wall.toml (a Saltelli design of n = 256 over d = 3 parameters:
/// n (d + 2) = 1280 jobs).
#[test]
fn the_shipped_calibration_and_monte_carlo_study_load() {
    let cal = Calibration::load(&support::repo().join("studies/calibrate-table51.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cal.parameters.len(), 3);
    assert_eq!(cal.rows.len(), 12);
    let exc = Calibration::load(&support::repo().join("studies/calibrate-table51-excitation.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(exc.parameters.len(), 4);
    // The same rows as the first calibration (docs/calibration.md compares the two).
    let rows = |c: &Calibration| -> Vec<(String, usize, f64, f64)> {
        c.rows
            .iter()
            .map(|r| (r.output.clone(), r.job, r.value, r.std))
            .collect()
    };
    assert_eq!(rows(&exc), rows(&cal));
    let st = rotorsweep::study::Study::load(&support::repo().join("studies/monte-carlo-wall.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    // The wall's seed, stand ky and stand cy: the 1280 jobs docs/statistics.md reports.
    assert_eq!(st.jobs.len(), 256 * 5);
}
