//! Crash safety of a campaign: SIGKILL in the middle, then --resume finds every job exactly once.
//! In its own test binary: a child spawned while another test thread holds an HDF5 file open
//! would inherit that file's lock.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

use common::{scratch_dir, study_text, write_file};
use rotorsweep::study::Study;

#[test]
fn sigkill_then_resume_keeps_every_job_exactly_once() {
    let d = scratch_dir("kill");
    // 10 jobs of ≈ 0.1–0.3 s each on one thread: long enough to kill in the middle.
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nrange = { start = 10.0, stop = 14.5, step = 0.5 }\n",
    )
    .replace(
        "\"simulation.t_end_s\" = 0.1",
        "\"simulation.t_end_s\" = 0.6",
    );
    let study = write_file(&d, "s.toml", &text);
    let out = d.join("out.h5");
    let parts = d.join("out.h5.parts");
    let bin = env!("CARGO_BIN_EXE_rotorsweep");
    let mut child = Command::new(bin)
        .args([
            "run",
            study.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--threads",
            "1",
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait until at least three jobs are saved, then SIGKILL.
    let t0 = Instant::now();
    loop {
        let n = std::fs::read_dir(&parts)
            .map(|r| {
                r.filter_map(|e| e.ok())
                    .filter(|e| e.file_name().to_string_lossy().ends_with(".h5"))
                    .count()
            })
            .unwrap_or(0);
        if n >= 3 || t0.elapsed() > Duration::from_secs(60) {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL on Unix
    child.wait().unwrap();
    assert!(!out.exists(), "the final file appears only after assembly");
    let saved = std::fs::read_dir(&parts)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".h5"))
        .count();
    assert!(
        (3..10).contains(&saved),
        "killed in the middle: {saved} saved"
    );
    // Without --resume the campaign refuses to mix runs.
    let refuse = Command::new(bin)
        .args(["run", study.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!refuse.status.success());
    assert!(String::from_utf8_lossy(&refuse.stderr).contains("--resume"));
    let resumed = Command::new(bin)
        .args([
            "run",
            study.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--threads",
            "2",
            "--resume",
        ])
        .output()
        .unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    let err = String::from_utf8_lossy(&resumed.stderr);
    assert!(err.contains(&format!("({saved} resumed)")), "{err}");
    // Every job exactly once, the file readable, the parts gone.
    let st = Study::load(&study).unwrap();
    let f = hdf5::File::open(&out).unwrap();
    let mut names = f.group("jobs").unwrap().member_names().unwrap();
    names.sort();
    let mut want: Vec<String> = st.jobs.iter().map(|j| j.id.clone()).collect();
    want.sort();
    assert_eq!(names, want);
    assert_eq!(f.dataset("summary").unwrap().shape()[0], 10);
    assert!(!parts.exists());
}
