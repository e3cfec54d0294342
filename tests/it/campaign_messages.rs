//! Issue 20, messages that say what happened: a shard that holds no job is refused unless
//! `--allow-empty` (and its empty file then reports and merges), and a `--resume` after a scene
//! edit, with saved jobs of the earlier inputs, recomputes the changed jobs as docs/studies.md
//! says (it exited 64 calling them "not in this run"). The run log's last line after a failed
//! assembly is checked with the full disk in `campaign_safety.rs`.

use std::path::Path;
use std::process::{Command, Output};

use crate::support;
use support::{scratch, write_file};

fn rs(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn run_ok(d: &Path, args: &[&str]) -> String {
    let o = rs(d, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stderr(&o)
}

/// A study of `speeds` on a private copy of the Jeffcott scene (`roll.toml`, to edit), 0.1 s
/// runs.
fn jeffcott_study(d: &Path, speeds: &str) {
    let scene =
        std::fs::read_to_string(support::repo().join("studies/scenes/jeffcott.toml")).unwrap();
    write_file(d, "roll.toml", &scene);
    write_file(
        d,
        "s.toml",
        &format!(
            "name = \"t\"\nscene = \"roll.toml\"\n[set]\n\"simulation.t_end_s\" = 0.1\n\
             \"simulation.settle_s\" = 0.05\n[[axes]]\nkey = \"speed.hz\"\nvalues = [{speeds}]\n"
        ),
    );
}

#[test]
fn an_empty_shard_is_refused_unless_allowed_and_its_file_reports_and_merges() {
    let d = scratch("messages-empty-shard");
    jeffcott_study(&d, "12.0, 14.0");
    // Shard 2/3 of a 2-job study holds no job: it exited 0 with an empty file.
    let o = rs(&d, &["run", "s.toml", "--shard", "2/3", "-o", "s2.h5"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(64), "{e}");
    assert!(
        e.contains("--shard 2/3") && e.contains("no job") && e.contains("--allow-empty"),
        "{e}"
    );
    assert!(!d.join("s2.h5").exists());
    // Allowed: a file of no jobs, which `report` reads and `merge` joins with the others.
    let args = [
        "run",
        "s.toml",
        "--shard",
        "2/3",
        "-o",
        "s2.h5",
        "--allow-empty",
    ];
    run_ok(&d, &args);
    let o = rs(&d, &["report", "s2.h5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("0 jobs (an empty shard"), "{text}");
    run_ok(&d, &["run", "s.toml", "--shard", "0/3", "-o", "s0.h5"]);
    run_ok(&d, &["merge", "s0.h5", "s2.h5", "-o", "p.h5", "--partial"]);
    run_ok(&d, &["run", "s.toml", "--shard", "1/3", "-o", "s1.h5"]);
    run_ok(&d, &["merge", "s0.h5", "s1.h5", "s2.h5", "-o", "m.h5"]);
    let m = hdf5::File::open(d.join("m.h5")).unwrap();
    assert_eq!(m.dataset("summary").unwrap().shape()[0], 2);
    // --allow-empty only with --shard.
    let o = rs(&d, &["run", "s.toml", "-o", "x.h5", "--allow-empty"]);
    assert_eq!(o.status.code(), Some(64), "{}", stderr(&o));
}

#[test]
fn resume_after_a_scene_edit_recomputes_the_changed_jobs() {
    let d = scratch("messages-resume-edit");
    jeffcott_study(&d, "12.0, 14.0");
    run_ok(&d, &["run", "s.toml", "-o", "first.h5"]);
    // The parts an interrupted run of these inputs leaves: each job group with the run's
    // identity attributes.
    let parts = d.join("out.h5.parts");
    std::fs::create_dir(&parts).unwrap();
    let first = hdf5::File::open(d.join("first.h5")).unwrap();
    let digest = rotorsweep::store::read_str(&first, "study_digest").unwrap();
    let inputs = rotorsweep::store::read_str(&first, "study_inputs").unwrap();
    let jobs = first.group("jobs").unwrap();
    for id in jobs.member_names().unwrap() {
        let p = hdf5::File::create(parts.join(format!("{id}.h5"))).unwrap();
        rotorsweep::store::copy_object(&jobs, &id, &p, "job").unwrap();
        rotorsweep::store::attr_str(&p, "tool", "rotorsweep").unwrap();
        rotorsweep::store::attr_str(&p, "study_digest", &digest).unwrap();
        rotorsweep::store::attr_str(&p, "study_inputs", &inputs).unwrap();
    }
    drop((jobs, first));
    // The scene edited (every job's id changes): the saved jobs are of the earlier inputs, run
    // again; nothing is refused.
    let scene = std::fs::read_to_string(d.join("roll.toml")).unwrap();
    write_file(&d, "roll.toml", &format!("{scene}\n# an edit\n"));
    let e = run_ok(&d, &["run", "s.toml", "-o", "out.h5", "--resume"]);
    assert!(
        e.contains("2 saved job(s) were made from other inputs") && e.contains("2 ok"),
        "{e}"
    );
    assert!(!e.contains("resumed"), "{e}");
    assert!(!parts.exists());
    let log = std::fs::read_to_string(d.join("out.h5.log")).unwrap();
    assert!(
        log.trim_end()
            .lines()
            .last()
            .unwrap()
            .ends_with("assembled: out.h5"),
        "{log}"
    );
}

/// A journal of saved runs cut short (a crash of the machine while it was written; study::run::
/// journal checks each run's length and SHA-256) is refused by `--resume` with its cause and
/// what to do, and left where it is; moved away, the study runs whole.
#[test]
fn a_damaged_journal_is_refused_with_its_cause_and_kept() {
    let d = scratch("messages-damaged-journal");
    jeffcott_study(&d, "12.0, 14.0");
    let parts = d.join("out.h5.parts");
    std::fs::create_dir(&parts).unwrap();
    // The journal's tag, then a frame whose length runs past the end of the file.
    let mut bytes = b"rotorsweep-jrnl1".to_vec();
    bytes.extend_from_slice(&1000u64.to_le_bytes());
    bytes.extend_from_slice(&[0u8; 40]);
    let damaged = parts.join("batch-j0-2.journal");
    std::fs::write(&damaged, &bytes).unwrap();
    let o = rs(&d, &["run", "s.toml", "-o", "out.h5", "--resume"]);
    let e = stderr(&o);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains("batch-j0-2.journal")
            && e.contains("ends inside the frame at byte 16")
            && e.contains("a journal of saved runs that cannot be read; move it away"),
        "{e}"
    );
    assert_eq!(std::fs::read(&damaged).unwrap(), bytes);
    std::fs::remove_file(&damaged).unwrap();
    let e = run_ok(&d, &["run", "s.toml", "-o", "out.h5", "--resume"]);
    assert!(e.contains("2 ok"), "{e}");
}
