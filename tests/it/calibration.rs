//! `rotorsweep calibrate` (src/calibration/): the bad inputs of issue 24 (file, key and line)
//! and a parameter that moves nothing (a warning naming its file, key and line).

use crate::support;
use rotorsweep::calibration::{self, Calibration, Options};
use support::{scratch, write_file};

/// The experiment: the Jeffcott rotor (studies/scenes/jeffcott.toml) at four constant speeds
/// around its first critical (44.5 Hz), 4 s to settle, the 1× over the last second.
fn study(dir: &std::path::Path) -> std::path::PathBuf {
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    write_file(
        dir,
        "experiment.toml",
        &format!(
            "name = \"jeffcott-near-critical\"\nscene = {:?}\n[set]\n\
             \"simulation.settle_s\" = 4.0\n\"simulation.t_end_s\" = 5.0\n\
             \"simulation.sample_rate_hz\" = 500.0\n\"damping.schedule\" = \"custom\"\n\
             \"damping.bands\" = [{{ below_hz = 250.0, ratio = 0.04 }}, {{ below_hz = 1070.0, ratio = 0.01 }}]\n\
             [[axes]]\nkey = \"speed.hz\"\nvalues = [42.0, 43.5, 44.5, 45.5]\n\
             [analysis]\norders = [1.0]\n",
            scene.display().to_string()
        ),
    )
}

fn options(out: &std::path::Path) -> Options {
    Options {
        output: out.to_path_buf(),
        threads: 2,
        overwrite: false,
        command: "test".into(),
    }
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
}

/// A parameter that moves no target row (the run's end time does not enter the linear system
/// whose critical speeds are the targets) is a warning naming its file, key and line, and is
/// held at its start value with no standard error; the other parameter is fitted.
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
                [[frequencies]]\ncritical = 2\nhz = 44.5\nstd_hz = 0.01\n";
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
    assert_eq!(o.parameters[1].value, 5.0);
    assert!(o.parameters[1].std_error.is_nan());
    assert!(o.parameters[0].value != 6e7);
}
