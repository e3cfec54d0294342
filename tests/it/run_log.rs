//! The campaign log `OUT.h5.log`: written beside the results, appended by every run (never
//! truncated), refused when a user's file, a folder or a link holds its name; and the plain
//! progress lines on a stderr that is not a terminal.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::support;
use support::scratch;

/// A four-job study of the Jeffcott rotor (0.2 s each), with labels.
fn study(dir: &Path) -> PathBuf {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/scenes/jeffcott.toml");
    let p = dir.join("s.toml");
    fs::write(
        &p,
        format!(
            "scene = {:?}\n[set]\n\"simulation.t_end_s\" = 0.2\n[[axes]]\nkey = \"speed.hz\"\n\
             values = [5.0, 10.0, 15.0, 20.0]\nlabels = [\"slow\", \"mid\", \"fast\", \"top\"]\n",
            scene.to_str().unwrap()
        ),
    )
    .unwrap();
    p
}

fn run(dir: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .current_dir(dir)
        .args(["run", "s.toml", "-o", "out.h5", "--threads", "2"])
        .args(extra)
        .output()
        .expect("run rotorsweep")
}

#[test]
fn every_run_appends_its_section_and_the_lines_name_each_job() {
    let dir = scratch("log");
    study(&dir);
    let o = run(&dir, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    // stderr is a pipe here: one plain line per job, with elapsed time, ETA, label and status.
    for label in ["slow", "mid", "fast", "top"] {
        assert_eq!(
            err.lines()
                .filter(|l| l.starts_with('[') && l.contains(&format!("({label}) ok cpu")))
                .count(),
            1,
            "{err}"
        );
    }
    // Lines are printed as their batch is saved (up to a second after the run ended), so the
    // elapsed time depends on the machine's load; the last line's ETA is 0:00.
    assert!(
        err.lines()
            .any(|l| l.starts_with("[4/4 ") && l.contains(" elapsed, ETA 0:00] j")),
        "{err}"
    );
    let log = fs::read_to_string(dir.join("out.h5.log")).unwrap();
    assert!(log.starts_with("# rotorsweep log\n"), "{log}");
    assert!(
        log.contains("start: ") && log.contains("4 runs to do, 0 saved before"),
        "{log}"
    );
    assert!(log.contains("end: 4 of 4 runs finished"), "{log}");
    assert_eq!(
        log.lines().filter(|l| l.contains(") ok cpu ")).count(),
        4,
        "{log}"
    );
    // Each line carries its UTC time.
    assert!(
        log.lines()
            .skip(1)
            .all(|l| l.len() > 21 && &l[10..11] == "T" && &l[19..20] == "Z"),
        "{log}"
    );
    // A second run (--overwrite) appends its own section; the first stays.
    let o = run(&dir, &["--overwrite"]);
    assert!(o.status.success());
    let again = fs::read_to_string(dir.join("out.h5.log")).unwrap();
    assert!(again.starts_with(&log), "the first section was changed");
    assert_eq!(again.matches("# rotorsweep log\n").count(), 2);
    assert_eq!(again.matches("end: 4 of 4 runs finished").count(), 2);
}

#[test]
fn a_users_file_folder_or_link_at_the_logs_name_is_refused_untouched() {
    let dir = scratch("refuse");
    study(&dir);
    let log = dir.join("out.h5.log");
    // After a run killed with its parts saved, an --overwrite run that is refused removes
    // nothing either.
    fs::create_dir(dir.join("out.h5.parts")).unwrap();
    fs::write(&log, "my notes\n").unwrap();
    let o = run(&dir, &["--overwrite"]);
    assert_eq!(
        o.status.code(),
        Some(64),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("out.h5.log") && err.contains("not a rotorsweep log"),
        "{err}"
    );
    assert_eq!(fs::read_to_string(&log).unwrap(), "my notes\n");
    assert!(!dir.join("out.h5").exists() && dir.join("out.h5.parts").is_dir());
    fs::remove_dir(dir.join("out.h5.parts")).unwrap();
    fs::remove_file(&log).unwrap();
    fs::create_dir(&log).unwrap();
    assert_eq!(run(&dir, &[]).status.code(), Some(64));
    fs::remove_dir(&log).unwrap();
    let target = dir.join("elsewhere.log");
    fs::write(&target, "# rotorsweep log\n").unwrap();
    std::os::unix::fs::symlink(&target, &log).unwrap();
    assert_eq!(run(&dir, &[]).status.code(), Some(64));
    assert_eq!(fs::read_to_string(&target).unwrap(), "# rotorsweep log\n");
}
