//! Issue 9: campaigns that never destroy, corrupt or silently stale a user's data, through the
//! real binary: outputs that are refused, one writer per output, resumes and merges that check
//! the study's digest, faults that stop a campaign cleanly, references that count, exit codes.
//! In its own test binary: children spawned while another test holds an HDF5 file open would
//! inherit that file's lock.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use support::{scratch, study_text, write_file};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_rotorsweep")
}

fn rs(dir: &Path, args: &[&str]) -> Output {
    Command::new(bin())
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn code(o: &Output) -> i32 {
    o.status.code().expect("exited, not killed by a signal")
}

/// A 2-speed study of 0.1 s runs (2 jobs, no reference): fast.
fn tiny_study(d: &Path, name: &str) -> PathBuf {
    write_file(
        d,
        name,
        &study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0]\n"),
    )
}

fn run_ok(d: &Path, args: &[&str]) -> String {
    let o = rs(d, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stderr(&o)
}

// Exit codes (src/bin/rotorsweep/main.rs): 1 input, 2 jobs not ok, 64 usage, 74 I/O, 75 busy.
const USAGE: i32 = 64;
const IO: i32 = 74;
const BUSY: i32 = 75;

#[test]
fn outputs_that_are_not_rotorsweep_results_are_never_replaced() {
    let d = scratch("safety-outputs");
    tiny_study(&d, "s.toml");
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    let scene = scene.to_str().unwrap();
    // A directory with a file in it: `run --overwrite` used to delete it recursively.
    std::fs::create_dir(d.join("somedir")).unwrap();
    write_file(&d.join("somedir"), "keep.txt", "precious");
    // A FIFO, a text file and an HDF5 file from elsewhere (no `tool = rotorsweep`).
    assert!(Command::new("mkfifo")
        .arg(d.join("fifo"))
        .status()
        .unwrap()
        .success());
    write_file(&d, "notes.h5", "not HDF5");
    {
        let f = hdf5::File::create(d.join("other.h5")).unwrap();
        f.new_attr::<f64>()
            .shape(())
            .create("x")
            .unwrap()
            .write_scalar(&1.0)
            .unwrap();
    }
    let other = std::fs::read(d.join("other.h5")).unwrap();
    // A character device, where we may make one (root): /dev/null's numbers.
    let cdev = d.join("cdev");
    let have_cdev = Command::new("mknod")
        .arg(&cdev)
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    if !have_cdev {
        eprintln!("skipping the character-device case: mknod needs root here");
    }
    run_ok(&d, &["run", "s.toml", "-o", "mine.h5"]);
    let mut targets = vec![
        ("somedir", "is a directory"),
        ("fifo", "is a FIFO"),
        ("notes.h5", "is not an HDF5 file"),
        ("other.h5", "not a rotorsweep results file"),
    ];
    if have_cdev {
        targets.push(("cdev", "is a character device"));
    }
    for (target, why) in targets {
        let commands: [Vec<&str>; 4] = [
            vec!["run", "s.toml", "-o", target, "--overwrite"],
            vec!["simulate", scene, "-o", target, "--overwrite"],
            vec!["merge", "mine.h5", "-o", target, "--overwrite"],
            vec![
                "linear",
                scene,
                "--speed-hz",
                "10",
                "-o",
                target,
                "--overwrite",
            ],
        ];
        for args in commands {
            let o = rs(&d, &args);
            assert_eq!(code(&o), USAGE, "{args:?}: {}", stderr(&o));
            let e = stderr(&o);
            assert!(e.contains(target) && e.contains(why), "{args:?}: {e}");
        }
    }
    assert_eq!(
        std::fs::read_to_string(d.join("somedir/keep.txt")).unwrap(),
        "precious"
    );
    assert_eq!(std::fs::read(d.join("other.h5")).unwrap(), other);
    if have_cdev {
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::metadata(&cdev)
            .unwrap()
            .file_type()
            .is_char_device());
    }
    // Without --overwrite every command refuses an existing output and names the flag.
    let before = std::fs::read(d.join("mine.h5")).unwrap();
    for args in [
        vec!["run", "s.toml", "-o", "mine.h5"],
        vec!["simulate", scene, "-o", "mine.h5"],
        vec!["merge", "mine.h5", "-o", "other.h5"],
        vec!["linear", scene, "--speed-hz", "10", "-o", "mine.h5"],
    ] {
        let o = rs(&d, &args);
        assert_eq!(code(&o), USAGE, "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("--overwrite"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    assert_eq!(std::fs::read(d.join("mine.h5")).unwrap(), before);
    // A results file of ours is replaced with --overwrite, by every command.
    run_ok(&d, &["run", "s.toml", "-o", "mine.h5", "--overwrite"]);
    run_ok(&d, &["simulate", scene, "-o", "sim.h5"]);
    run_ok(&d, &["simulate", scene, "-o", "sim.h5", "--overwrite"]);
    run_ok(&d, &["merge", "mine.h5", "-o", "m.h5"]);
    run_ok(&d, &["merge", "mine.h5", "-o", "m.h5", "--overwrite"]);
    run_ok(&d, &["linear", scene, "--speed-hz", "10", "-o", "lin.h5"]);
    run_ok(
        &d,
        &[
            "linear",
            scene,
            "--speed-hz",
            "10",
            "-o",
            "lin.h5",
            "--overwrite",
        ],
    );
    // An output in a folder that does not exist names the folder.
    let o = rs(&d, &["run", "s.toml", "-o", "no/such/dir/x.h5"]);
    assert_ne!(code(&o), 0);
    assert!(stderr(&o).contains("no/such/dir"), "{}", stderr(&o));
    // No working file is left behind.
    for e in std::fs::read_dir(&d).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            !n.ends_with(".tmp") && !n.ends_with(".lock") && !n.ends_with(".parts"),
            "{n}"
        );
    }
}

#[test]
fn a_second_process_on_the_same_output_fails_at_once_naming_the_holder() {
    let d = scratch("safety-lock");
    // 8 jobs of 0.6 s simulated time on one thread: a few seconds of work.
    write_file(
        &d,
        "s.toml",
        &study_text(
            "[[axes]]\nkey = \"speed.hz\"\nrange = { start = 10.0, stop = 13.5, step = 0.5 }\n",
        )
        .replace(
            "\"simulation.t_end_s\" = 0.1",
            "\"simulation.t_end_s\" = 0.6",
        ),
    );
    let mut first = Command::new(bin())
        .current_dir(&d)
        .args(["run", "s.toml", "-o", "out.h5", "--threads", "1"])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait for the lock file, then try every writer on the same output.
    let t0 = Instant::now();
    while !d.join("out.h5.lock").exists() && t0.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(10));
    }
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    for args in [
        vec!["run", "s.toml", "-o", "out.h5", "--resume"],
        vec!["run", "s.toml", "-o", "out.h5", "--overwrite"],
        vec!["simulate", scene.to_str().unwrap(), "-o", "out.h5"],
        vec!["merge", "whatever.h5", "-o", "out.h5"],
        vec![
            "linear",
            scene.to_str().unwrap(),
            "--speed-hz",
            "10",
            "-o",
            "out.h5",
        ],
    ] {
        let o = rs(&d, &args);
        let e = stderr(&o);
        assert_eq!(code(&o), BUSY, "{args:?}: {e}");
        assert!(
            e.contains("out.h5") && e.contains(&format!("PID {}", first.id())),
            "{args:?}: {e}"
        );
    }
    assert!(first.wait().unwrap().success());
    // The first run's file is whole and readable, and the lock is released and removed.
    let f = hdf5::File::open(d.join("out.h5")).unwrap();
    assert_eq!(f.dataset("summary").unwrap().shape()[0], 8);
    for m in f.group("models").unwrap().member_names().unwrap() {
        let freq: Vec<f64> = f
            .dataset(&format!("models/{m}/freq_hz"))
            .unwrap()
            .read_raw()
            .unwrap();
        assert!(!freq.is_empty());
    }
    assert!(!d.join("out.h5.lock").exists());
}

#[test]
fn resume_refuses_an_assembled_output_of_other_inputs_and_names_what_changed() {
    let d = scratch("safety-resume");
    let text = study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0]\n");
    write_file(&d, "s.toml", &text);
    // A private copy of the scene, to edit.
    let scene_text =
        std::fs::read_to_string(support::repo().join("studies/scenes/reference-roll.toml"))
            .unwrap()
            .replace(
                "thickness_map = \"../maps/",
                &format!(
                    "thickness_map = \"{}/studies/maps/",
                    support::repo().display()
                ),
            );
    write_file(&d, "roll.toml", &scene_text);
    let own = text.replace(
        &format!(
            "{:?}",
            support::repo()
                .join("studies/scenes/reference-roll.toml")
                .display()
                .to_string()
        ),
        "\"roll.toml\"",
    );
    assert_ne!(own, text, "the study names the private scene");
    write_file(&d, "own.toml", &own);
    run_ok(&d, &["run", "own.toml", "-o", "out.h5"]);
    let before = std::fs::read(d.join("out.h5")).unwrap();
    // Unchanged: nothing to do, the file untouched.
    let e = run_ok(&d, &["run", "own.toml", "-o", "out.h5", "--resume"]);
    assert!(e.contains("(2 resumed)"), "{e}");
    // t_end changed, a speed added, the scene edited: refused, naming the changed file.
    let cases = [
        (
            own.replace(
                "\"simulation.t_end_s\" = 0.1",
                "\"simulation.t_end_s\" = 0.2",
            ),
            None,
            "study own.toml changed",
        ),
        (
            own.replace("[12.0, 14.0]", "[12.0, 14.0, 16.0]"),
            None,
            "study own.toml changed",
        ),
        (
            own.clone(),
            Some(format!("{scene_text}\n# an edit\n")),
            "scene roll.toml changed",
        ),
    ];
    for (study, scene, what) in cases {
        write_file(&d, "own.toml", &study);
        write_file(&d, "roll.toml", scene.as_deref().unwrap_or(&scene_text));
        let o = rs(&d, &["run", "own.toml", "-o", "out.h5", "--resume"]);
        let e = stderr(&o);
        assert_eq!(code(&o), USAGE, "{e}");
        assert!(e.contains(what) && e.contains("--overwrite"), "{e}");
        assert_eq!(std::fs::read(d.join("out.h5")).unwrap(), before);
    }
    // --overwrite recomputes it from the current inputs (the edited scene).
    let e = run_ok(&d, &["run", "own.toml", "-o", "out.h5", "--overwrite"]);
    assert!(e.contains("2 ok"), "{e}");
}

#[test]
fn resume_runs_again_saved_jobs_of_other_inputs() {
    let d = scratch("safety-stale-parts");
    let text = study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0]\n");
    write_file(&d, "s.toml", &text);
    run_ok(&d, &["run", "s.toml", "-o", "first.h5"]);
    // Parts saved by an interrupted run of the same jobs under another study text (same job
    // ids: only the description differs), made here by copying a finished run's job groups.
    let parts = d.join("out.h5.parts");
    std::fs::create_dir(&parts).unwrap();
    let first = hdf5::File::open(d.join("first.h5")).unwrap();
    for id in first.group("jobs").unwrap().member_names().unwrap() {
        let p = hdf5::File::create(parts.join(format!("{id}.h5"))).unwrap();
        rotorsweep::store::copy_object(&first.group("jobs").unwrap(), &id, &p, "job").unwrap();
        rotorsweep::store::attr_str(&p, "tool", "rotorsweep").unwrap();
        rotorsweep::store::attr_str(&p, "study_digest", "0123").unwrap();
    }
    drop(first);
    let e = run_ok(&d, &["run", "s.toml", "-o", "out.h5", "--resume"]);
    assert!(
        e.contains("2 saved job(s) were made from other inputs"),
        "{e}"
    );
    assert!(!e.contains("resumed"), "{e}");
    assert!(e.contains("2 ok"), "{e}");
    assert!(!parts.exists());
}

#[test]
fn merge_refuses_incomplete_mixed_duplicate_and_foreign_shards() {
    let d = scratch("safety-merge");
    let text = study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 13.0, 14.0]\n");
    write_file(&d, "s.toml", &text);
    for (i, n) in [(0, 2), (1, 2), (1, 3)] {
        run_ok(
            &d,
            &[
                "run",
                "s.toml",
                "-o",
                &format!("s{i}of{n}.h5"),
                "--shard",
                &format!("{i}/{n}"),
            ],
        );
    }
    // The same study, another description: another digest.
    write_file(
        &d,
        "s.toml",
        &text.replace("name = \"t\"", "name = \"t\"\ndescription = \"edited\""),
    );
    run_ok(&d, &["run", "s.toml", "-o", "e1of2.h5", "--shard", "1/2"]);
    // Wrong input files are input errors (1); a wrong set of them on the command line, usage
    // errors (64).
    let refuse_as = |want: i32, args: &[&str], what: &[&str]| {
        let o = rs(&d, args);
        let e = stderr(&o);
        assert_eq!(code(&o), want, "{args:?}: {e}");
        for w in what {
            assert!(e.contains(w), "{args:?}: {e}");
        }
        assert!(!d.join("m.h5").exists());
    };
    let refuse = |args: &[&str], what: &[&str]| refuse_as(USAGE, args, what);
    refuse(
        &["merge", "s0of2.h5", "-o", "m.h5"],
        &["shards missing: 1/2", "--partial"],
    );
    refuse_as(
        1,
        &["merge", "s0of2.h5", "s1of3.h5", "-o", "m.h5"],
        &[
            "different splits",
            "s0of2.h5 is shard 0/2",
            "s1of3.h5 is shard 1/3",
        ],
    );
    refuse(
        &["merge", "s0of2.h5", "s0of2.h5", "-o", "m.h5"],
        &["s0of2.h5 is given twice"],
    );
    refuse(
        &["merge", "s0of2.h5", "./s0of2.h5", "-o", "m.h5"],
        &["given twice"],
    );
    refuse_as(
        1,
        &["merge", "s0of2.h5", "e1of2.h5", "-o", "m.h5"],
        &["e1of2.h5: comes from other inputs", "study s.toml differs"],
    );
    // A file that is not a study's results (a simulate file) says so, as an input error.
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    run_ok(&d, &["simulate", scene.to_str().unwrap(), "-o", "sim.h5"]);
    refuse_as(
        1,
        &["merge", "s0of2.h5", "sim.h5", "-o", "m.h5"],
        &["sim.h5: has no study digest", "simulate"],
    );
    refuse(
        &["merge", "s0of2.h5", "-o", "s0of2.h5", "--overwrite"],
        &["the output too"],
    );
    // --partial merges and records it; the complete set merges without it.
    let e = run_ok(&d, &["merge", "s0of2.h5", "-o", "p.h5", "--partial"]);
    assert!(e.contains("shards 1/2 are missing"), "{e}");
    let p = hdf5::File::open(d.join("p.h5")).unwrap();
    assert_eq!(rotorsweep::store::read_num(&p, "partial").unwrap(), 1.0);
    assert_eq!(rotorsweep::store::read_str(&p, "shard").unwrap(), "0/2");
    run_ok(&d, &["merge", "s0of2.h5", "s1of2.h5", "-o", "m.h5"]);
    let m = hdf5::File::open(d.join("m.h5")).unwrap();
    assert_eq!(rotorsweep::store::read_num(&m, "partial").unwrap(), 0.0);
    assert_eq!(rotorsweep::store::read_str(&m, "shard").unwrap(), "0/2,1/2");
    assert_eq!(m.dataset("summary").unwrap().shape()[0], 3);
}

/// `run s.toml -o OUT --threads 1` under a file-size limit of `kib` KiB (`ulimit -f`).
fn run_limited(d: &Path, kib: u32, out: &str) -> Output {
    Command::new("sh")
        .current_dir(d)
        .args([
            "-c",
            &format!(
                "ulimit -f {kib} && exec {} run s.toml -o {out} --threads 1",
                bin()
            ),
        ])
        .output()
        .unwrap()
}

/// The last line of `OUT.log` says `out` was not assembled, and how to finish.
fn assert_not_assembled(d: &Path, out: &str) {
    let log = std::fs::read_to_string(d.join(format!("{out}.log"))).unwrap();
    let last = log.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.contains("not assembled: ") && last.contains("--resume"),
        "{out}: {log}"
    );
}

#[test]
fn a_full_disk_stops_the_campaign_and_resume_completes_it_to_the_same_results() {
    let d = scratch("safety-full");
    // 6 jobs and 6 references; a part file is about 40-60 kB here.
    write_file(
        &d,
        "s.toml",
        &study_text(
            "[[axes]]\nkey = \"speed.hz\"\nvalues = [11.0, 12.0, 13.0, 14.0, 15.0, 16.0]\n\
             [reference]\n\"solver.hmax\" = 5e-5\n",
        ),
    );
    run_ok(&d, &["run", "s.toml", "-o", "whole.h5", "--threads", "1"]);
    // A file-size limit (`ulimit -f`, 1 KiB blocks) makes every write past 20 KiB fail with
    // EFBIG, as a full disk fails with ENOSPC.
    let limited = run_limited(&d, 20, "out.h5");
    let e = stderr(&limited);
    assert_eq!(code(&limited), IO, "{e}");
    assert!(
        e.contains("out.h5.parts/") && e.contains("File too large (errno 27)"),
        "{e}"
    );
    assert!(
        e.contains("the campaign stopped") && e.contains("--resume"),
        "{e}"
    );
    // Nothing unsaved is reported ok: runs are saved in batches (of up to a second of runs, and
    // these 12 take less), so every run of the failed batch is reported NOT SAVED and none ok.
    let progress: Vec<&str> = e.lines().filter(|l| l.starts_with('[')).collect();
    assert!((1..=12).contains(&progress.len()), "{e}");
    assert!(progress.iter().all(|l| l.contains("NOT SAVED")), "{e}");
    assert!(e.contains("0 of 12 runs are saved"), "{e}");
    assert!(!d.join("out.h5").exists());
    assert_not_assembled(&d, "out.h5");
    // Space freed: --resume completes it, with the results of the uninterrupted run.
    let e = run_ok(&d, &["run", "s.toml", "-o", "out.h5", "--resume"]);
    assert!(e.contains("6 ok"), "{e}");
    assert_eq!(
        support::results_content(&d.join("out.h5")),
        support::results_content(&d.join("whole.h5"))
    );
    // Assembly itself failing (the parts fit, the results file does not) names the file and
    // the OS error, and leaves no half file.
    let limited = run_limited(&d, 70, "big.h5");
    let e = stderr(&limited);
    assert_eq!(code(&limited), IO, "{e}");
    assert!(e.contains("File too large (errno 27)"), "{e}");
    assert!(!d.join("big.h5").exists() && !d.join("big.h5.tmp").exists());
    // The run log's last line is the assembly's outcome (it ended "12 of 12 finished, 0 not
    // ok").
    assert_not_assembled(&d, "big.h5");
    // A limit just below the whole file's size: the write fails at the very end (the final
    // flush; review finding: the broken file was renamed into place and the parts removed).
    // Refused with the cause; the parts stay, and --resume completes.
    let kib = std::fs::metadata(d.join("whole.h5")).unwrap().len() / 1024;
    let limited = run_limited(&d, (kib - 2) as u32, "late.h5");
    let e = stderr(&limited);
    assert_eq!(code(&limited), IO, "{e}");
    assert!(e.contains("late.h5.tmp"), "{e}");
    assert!(!d.join("late.h5").exists() && d.join("late.h5.parts").exists());
    run_ok(&d, &["run", "s.toml", "-o", "late.h5", "--resume"]);
    assert_eq!(
        support::results_content(&d.join("late.h5")),
        support::results_content(&d.join("whole.h5"))
    );
}

#[test]
fn failed_references_count_in_the_exit_code_and_the_summary_says_why() {
    let d = scratch("safety-references");
    write_file(
        &d,
        "s.toml",
        &study_text(
            "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0]\n[reference]\n\"solver.max_steps\" = 5\n",
        ),
    );
    let o = rs(&d, &["run", "s.toml", "-o", "out.h5"]);
    let e = stderr(&o);
    assert_eq!(code(&o), 2, "{e}");
    assert!(
        e.contains("1 ok") && e.contains("1 reference run(s) did not end ok"),
        "{e}"
    );
    let f = hdf5::File::open(d.join("out.h5")).unwrap();
    let g = f.group("jobs").unwrap();
    let id = &g.member_names().unwrap()[0];
    let cause = rotorsweep::store::read_str(&g.group(id).unwrap(), "error_cause").unwrap();
    assert!(cause.starts_with("reference budget"), "{cause}");
}

#[test]
fn shared_references_keep_their_failures_and_a_finished_shard_reruns_as_a_no_op() {
    let d = scratch("safety-shared-references");
    let body = "[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 14.0]\n[reference]\n\"solver.max_steps\" = 5\n";
    write_file(&d, "s.toml", &study_text(body));
    // The references step: both reference runs (one per speed) over their 5-step budget; the
    // file is complete and the exit code says 2, as a run computing them itself would.
    let o = rs(&d, &["run", "s.toml", "--references-only", "-o", "refs.h5"]);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(
        stderr(&o).contains("2 reference runs, 2 not ok"),
        "{}",
        stderr(&o)
    );
    // A shard that copies them: its job says why it has no error columns, exit 2.
    let shard = [
        "run",
        "s.toml",
        "--shard",
        "0/2",
        "--references",
        "refs.h5",
        "-o",
        "s0.h5",
    ];
    let o = rs(&d, &shard);
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    let f = hdf5::File::open(d.join("s0.h5")).unwrap();
    let g = f.group("jobs").unwrap();
    let id = &g.member_names().unwrap()[0];
    let cause = rotorsweep::store::read_str(&g.group(id).unwrap(), "error_cause").unwrap();
    assert!(cause.starts_with("reference budget"), "{cause}");
    drop(f);
    // Run again as a requeued or resubmitted Slurm task does: nothing runs, the file stays as it
    // was, the exit code is the first run's.
    let before = std::fs::read(d.join("s0.h5")).unwrap();
    let o = rs(&d, &[&shard[..], &["--resume"]].concat());
    assert_eq!(code(&o), 2, "{}", stderr(&o));
    assert!(stderr(&o).contains("(1 resumed)"), "{}", stderr(&o));
    assert_eq!(before, std::fs::read(d.join("s0.h5")).unwrap());
    // References of other inputs are an input error naming the file; nothing is started.
    write_file(&d, "t.toml", &study_text(&body.replace("14.0", "16.0")));
    let o = rs(
        &d,
        &[
            "run",
            "t.toml",
            "--shard",
            "0/2",
            "--references",
            "refs.h5",
            "-o",
            "t0.h5",
        ],
    );
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("refs.h5: holds the reference runs of other inputs"));
    assert!(!d.join("t0.h5").exists() && !d.join("t0.h5.parts").exists());
    // A study without [reference] has none to share: a usage error.
    tiny_study(&d, "p.toml");
    let o = rs(&d, &["run", "p.toml", "--references-only", "-o", "p.h5"]);
    assert_eq!(code(&o), USAGE, "{}", stderr(&o));
}

#[test]
fn usage_errors_have_their_own_exit_code() {
    let d = scratch("safety-usage");
    tiny_study(&d, "s.toml");
    for args in [
        vec!["run", "s.toml"],
        vec!["run", "s.toml", "-o", "x.h5", "--shard", "2/2"],
        vec!["run", "s.toml", "-o", "x.h5", "--resume", "--overwrite"],
        vec!["no-such-command"],
    ] {
        let o = rs(&d, &args);
        assert_eq!(code(&o), USAGE, "{args:?}: {}", stderr(&o));
    }
    // An input error is 1 and names the file.
    let o = rs(&d, &["run", "missing.toml", "-o", "x.h5"]);
    assert_eq!(code(&o), 1, "{}", stderr(&o));
    assert!(stderr(&o).contains("missing.toml"));
    // --help is not an error.
    assert_eq!(code(&rs(&d, &["run", "--help"])), 0);
}

#[test]
fn files_rotorsweep_did_not_write_are_never_removed_or_replaced() {
    // Review findings: a user's files under rotorsweep's working names (a part-like name in the
    // parts folder, OUT.h5.tmp, OUT.h5.lock) were deleted by --overwrite, --resume or a run.
    let d = scratch("safety-working-names");
    tiny_study(&d, "s.toml");
    let parts = d.join("w.h5.parts");
    std::fs::create_dir(&parts).unwrap();
    let notes = write_file(&parts, "j0123456789abcdef.h5", "my notes");
    for args in [
        vec!["run", "s.toml", "-o", "w.h5", "--overwrite"],
        vec!["run", "s.toml", "-o", "w.h5", "--resume"],
    ] {
        let o = rs(&d, &args);
        assert_ne!(code(&o), 0, "{args:?}");
        assert!(
            stderr(&o).contains("j0123456789abcdef.h5"),
            "{}",
            stderr(&o)
        );
        assert_eq!(std::fs::read_to_string(&notes).unwrap(), "my notes");
    }
    for name in ["b.h5.tmp", "b.h5.lock"] {
        let f = write_file(&d, name, "precious");
        let o = rs(&d, &["run", "s.toml", "-o", "b.h5"]);
        assert_eq!(code(&o), USAGE, "{}", stderr(&o));
        assert!(stderr(&o).contains(name), "{}", stderr(&o));
        assert_eq!(std::fs::read_to_string(&f).unwrap(), "precious");
        std::fs::remove_file(f).unwrap();
    }
    // Another shard's saved jobs on the same output are not discarded by a resume.
    let text = study_text("[[axes]]\nkey = \"speed.hz\"\nvalues = [12.0, 13.0, 14.0, 15.0]\n");
    write_file(&d, "four.toml", &text);
    let sharded = d.join("sh.h5.parts");
    std::fs::create_dir(&sharded).unwrap();
    run_ok(&d, &["run", "four.toml", "-o", "s0.h5", "--shard", "0/2"]);
    let s0 = hdf5::File::open(d.join("s0.h5")).unwrap();
    let jobs = s0.group("jobs").unwrap();
    let id = jobs.member_names().unwrap()[0].clone();
    {
        let p = hdf5::File::create(sharded.join(format!("{id}.h5"))).unwrap();
        rotorsweep::store::copy_object(&jobs, &id, &p, "job").unwrap();
        rotorsweep::store::attr_str(&p, "tool", "rotorsweep").unwrap();
    }
    drop((jobs, s0));
    let o = rs(
        &d,
        &[
            "run",
            "four.toml",
            "-o",
            "sh.h5",
            "--shard",
            "1/2",
            "--resume",
        ],
    );
    assert_eq!(code(&o), USAGE, "{}", stderr(&o));
    assert!(stderr(&o).contains("not in this run"), "{}", stderr(&o));
    assert!(sharded.join(format!("{id}.h5")).exists());
}

#[test]
fn inputs_that_would_block_or_exhaust_the_machine_are_refused() {
    let d = scratch("safety-blocking-inputs");
    // A scene that is a FIFO (reading it would block) or a device (/dev/zero would fill the
    // memory): input errors at once.
    assert!(Command::new("mkfifo")
        .arg(d.join("fifo.toml"))
        .status()
        .unwrap()
        .success());
    for scene in ["fifo.toml", "/dev/zero"] {
        write_file(&d, "s.toml", &format!("name = \"x\"\nscene = {scene:?}\n"));
        let t0 = Instant::now();
        let o = rs(&d, &["plan", "s.toml"]);
        assert_eq!(code(&o), 1, "{scene}: {}", stderr(&o));
        assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
        assert!(t0.elapsed() < Duration::from_secs(10));
    }
    // A thread count beyond 1024 is a usage error, not minutes of silent thread starts.
    tiny_study(&d, "t.toml");
    let o = rs(&d, &["run", "t.toml", "-o", "x.h5", "--threads", "100000"]);
    assert_eq!(code(&o), USAGE, "{}", stderr(&o));
}
