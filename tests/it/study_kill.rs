//! Crash safety of a campaign: SIGKILL at random moments, each followed by `--resume`, ends with
//! every job exactly once and the same results as an uninterrupted run.
//! In its own test binary: a child spawned while another test thread holds an HDF5 file open
//! would inherit that file's lock.

use crate::support;

use std::process::Command;
use std::time::{Duration, Instant};

use rotorsweep::study::Study;
use support::{results_content, scratch, study_text, write_file};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_rotorsweep")
}

/// A seeded pseudo-random sequence in [0, 1) (64-bit LCG of Knuth's MMIX, top 53 bits): the
/// kill moments are the same on every run of the test.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn sigkill_at_random_moments_then_resume_gives_every_job_once_and_the_same_results() {
    // ROTORSWEEP_KILLS sets the number of kills (the 20 for the closing note).
    let kills: usize = std::env::var("ROTORSWEEP_KILLS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let d = scratch("kill");
    // 20 jobs of ≈ 0.1 s each on one thread, with 20 references: long enough to kill often.
    let text = study_text(
        "[[axes]]\nkey = \"speed.hz\"\nrange = { start = 10.0, stop = 19.5, step = 0.5 }\n\
         [reference]\n\"solver.hmax\" = 5e-5\n",
    )
    .replace(
        "\"simulation.t_end_s\" = 0.1",
        "\"simulation.t_end_s\" = 0.3",
    );
    let study = write_file(&d, "s.toml", &text);
    let run = |out: &str, resume: bool| support::run_command(&d, "s.toml", out, resume);
    let t0 = Instant::now();
    assert!(run("whole.h5", false).status().unwrap().success());
    let whole_s = t0.elapsed().as_secs_f64();
    // Kill moments uniform in [0, whole/10): each run gets a small share of the work done
    // first, so that the kills fall in model building, jobs and assembly alike.
    let mut rng = Lcg(0x5eed_0009);
    let mut killed = 0;
    let mut saved_before_resume = Vec::new();
    for _ in 0..kills {
        if d.join("out.h5").exists() {
            break;
        }
        let mut child = run("out.h5", true).spawn().unwrap();
        std::thread::sleep(Duration::from_secs_f64(rng.next() * whole_s / 10.0));
        child.kill().unwrap(); // SIGKILL on Unix
        let status = child.wait().unwrap();
        if status.code().is_none() {
            killed += 1;
        }
        saved_before_resume.push(support::saved_batches(&d, "out.h5"));
    }
    eprintln!("{killed} of {kills} runs killed; part files after each: {saved_before_resume:?}");
    assert!(killed >= kills.min(3), "the runs were killed: {killed}");
    // A run that was killed left no results file under the final name.
    if !d.join("out.h5").exists() {
        // Without --resume the campaign refuses to mix runs.
        let refuse = Command::new(bin())
            .current_dir(&d)
            .args(["run", "s.toml", "-o", "out.h5"])
            .output()
            .unwrap();
        assert!(!refuse.status.success());
        assert!(String::from_utf8_lossy(&refuse.stderr).contains("--resume"));
    }
    let resumed = Command::new(bin())
        .current_dir(&d)
        .args([
            "run",
            "s.toml",
            "-o",
            "out.h5",
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
    // Every job exactly once, the file readable, the parts gone, the same results.
    let st = Study::load(&study).unwrap();
    let f = hdf5::File::open(d.join("out.h5")).unwrap();
    let mut names = f.group("jobs").unwrap().member_names().unwrap();
    names.sort();
    let mut want: Vec<String> = st.jobs.iter().map(|j| j.id.clone()).collect();
    want.sort();
    assert_eq!(names, want);
    assert_eq!(f.dataset("summary").unwrap().shape()[0], 20);
    drop(f);
    assert!(!d.join("out.h5.parts").exists());
    assert!(!d.join("out.h5.tmp").exists());
    assert_eq!(
        results_content(&d.join("out.h5")),
        results_content(&d.join("whole.h5"))
    );
}
