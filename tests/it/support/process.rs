//! Process helpers: the rotorsweep binary run (or spawned, to be killed) and its JSON tables
//! read, campaign options for a test, and the deterministic content of a results file.

/// Runs the rotorsweep binary with `args` and returns its standard output; panics with its
/// standard error when it fails.
pub fn rotorsweep_ok(args: &[&str]) -> Vec<u8> {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rotorsweep {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// `rotorsweep run STUDY -o OUT --threads 1 [--resume]` in `dir`, its standard error
/// discarded: a command to spawn and kill (the crash-safety tests).
pub fn run_command(
    dir: &std::path::Path,
    study: &str,
    out: &str,
    resume: bool,
) -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"));
    c.current_dir(dir)
        .args(["run", study, "-o", out, "--threads", "1"])
        .stderr(std::process::Stdio::null());
    if resume {
        c.arg("--resume");
    }
    c
}

/// `rotorsweep report FILE --table NAME --format json`: the one table of that name.
pub fn report_table(file: &std::path::Path, name: &str) -> serde_json::Value {
    let out = rotorsweep_ok(&[
        "report",
        file.to_str().unwrap(),
        "--table",
        name,
        "--format",
        "json",
    ]);
    let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
    doc["tables"][0].clone()
}

/// Campaign options for a test: `out`, two threads, no resume, overwrite, shard or shared
/// references.
pub fn run_options(out: &std::path::Path) -> rotorsweep::study::run::RunOptions {
    rotorsweep::study::run::RunOptions {
        output: out.to_path_buf(),
        threads: 2,
        resume: false,
        overwrite: false,
        shard: None,
        command: "test".into(),
        references: Default::default(),
    }
}

/// The deterministic content of a results file: every dataset of every run (bit patterns) and
/// the runs' attributes other than timings, by path.
pub fn results_content(path: &std::path::Path) -> Vec<(String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap();
    let mut out = Vec::new();
    for group in ["jobs", "references"] {
        let Ok(g) = f.group(group) else { continue };
        let mut ids = g.member_names().unwrap();
        ids.sort();
        for id in ids {
            let run = g.group(&id).unwrap();
            fn walk(g: &hdf5::Group, prefix: &str, out: &mut Vec<(String, Vec<u64>)>) {
                let mut names = g.member_names().unwrap();
                names.sort();
                for n in names {
                    let p = format!("{prefix}/{n}");
                    if let Ok(ds) = g.dataset(&n) {
                        let v: Vec<f64> = ds.read_raw().unwrap();
                        out.push((p, v.iter().map(|x| x.to_bits()).collect()));
                    } else if let Ok(sub) = g.group(&n) {
                        walk(&sub, &p, out);
                    }
                }
            }
            walk(&run, &format!("{group}/{id}"), &mut out);
            let mut attrs = run.attr_names().unwrap();
            attrs.sort();
            for a in attrs {
                if a.starts_with("cpu_time_s") || a.starts_with("wall_time_s") {
                    continue;
                }
                let v = match rotorsweep::store::read_param(&run, &a).unwrap() {
                    rotorsweep::store::Param::Number(x) => vec![x.to_bits()],
                    rotorsweep::store::Param::Count(n) => vec![n],
                    rotorsweep::store::Param::Text(t) => t.bytes().map(u64::from).collect(),
                };
                out.push((format!("{group}/{id}@{a}"), v));
            }
        }
    }
    out
}

/// How many batches of saved runs a study run on `out` in `dir` holds now: its journals
/// (`OUT.h5.parts/batch-….journal`, study::run::parts).
pub fn saved_batches(dir: &std::path::Path, out: &str) -> usize {
    std::fs::read_dir(dir.join(format!("{out}.parts")))
        .map(|r| {
            r.filter_map(|e| e.ok())
                .filter(|e| e.file_name().to_string_lossy().ends_with(".journal"))
                .count()
        })
        .unwrap_or(0)
}

/// The [`results_content`] of `st` run into `dir` at one thread, at two, and as two shards
/// merged, in that order (the determinism checks compare the three).
pub fn contents_at_one_two_threads_and_shards(
    st: &rotorsweep::study::Study,
    dir: &std::path::Path,
) -> [Vec<(String, Vec<u64>)>; 3] {
    use rotorsweep::study::merge;
    let run = |name: &str, threads: usize, shard: Option<(usize, usize)>| {
        let out = dir.join(name);
        let opts = rotorsweep::study::run::RunOptions {
            threads,
            shard,
            ..run_options(&out)
        };
        rotorsweep::study::run::run(st, &opts).unwrap();
        out
    };
    let one = results_content(&run("one.h5", 1, None));
    let two = results_content(&run("two.h5", 2, None));
    let (s0, s1) = (run("s0.h5", 2, Some((0, 2))), run("s1.h5", 2, Some((1, 2))));
    let merged = dir.join("merged.h5");
    merge::merge(&[s0, s1], &merged, &merge::MergeOptions::default()).unwrap();
    [one, two, results_content(&merged)]
}
