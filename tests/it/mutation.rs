//! Seeded mutation test of the input layer (issue 9): every shipped study, scene and the map CSV,
//! mutated hundreds of times (deleted lines and blocks, duplicated and swapped lines, wrong types,
//! extreme numbers such as 1e308, -1, 0, "nan", truncated files, garbage bytes, misspelt keys),
//! each written into a copy of `studies/` in a temp dir and given to the real binary: `plan` for
//! a study, `modes` for a scene or the map (through the reference roll that reads it), and
//! (issue 20) for a small scene also `linear` at three speeds; a scene also through an
//! `extends` chain (a child scene that builds on the mutated one); a measured CSV to `import`
//! (with an order list that may be out of range), then, when imported, `report --compare`
//! against the unmutated record's import; and `balance` of a small trial-mass study's results
//! with a bad option value or a 1× line of its results file replaced (NaN, inf, 1e308, 0, −1).
//!
//! Every case runs under a 4 GiB address-space limit (setrlimit in the child) and a 60 s timeout
//! (the slowest accepted `modes` is a mesh at the FE limit, about 15-20 s on a busy 2-core
//! machine). Asserted: no panic (exit 101 or "panicked"), no death by signal (an allocation
//! failure aborts), no hang, only exit codes 0 and 1, and every rejection names the mutated file
//! (or the option given a bad value); rejections that name neither a line nor a key are counted
//! apart (`RejectedWithoutPlace`) and listed with `--nocapture`.
//! The counts by outcome are printed (`cargo test --release --test mutation -- --nocapture`).
//!
//! The random numbers come from the library's SplitMix64 (the synthetic maps' generator) rather
//! than the `rand` crate: its `StdRng` stream may change between versions, and the cases must
//! stay the same cases.

use std::collections::BTreeMap;
use std::fs;
use std::io::Read;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rotorsweep::numerics::rng::SplitMix64;

/// Address-space limit of every case: the 4 GiB.
const MEMORY_LIMIT_BYTES: u64 = 4 << 30;
/// Per-case timeout (module doc).
const TIMEOUT: Duration = Duration::from_secs(60);
/// The default run's seed and size: 300 cases took 16 s on 2 cores (measured).
const SEED: u64 = 0x2026_1201;
const CASES: usize = 300;

/// The cases' random numbers: the library's SplitMix64 (module doc).
struct Rng(SplitMix64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(SplitMix64::new(seed))
    }

    /// Uniform in 0..n (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.0.next_u64() % n as u64) as usize
    }

    fn byte(&mut self) -> u8 {
        (self.0.next_u64() & 0xff) as u8
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Values that replace a value: wrong types, extremes, non-numbers.
const BAD_VALUES: &[&str] = &[
    "1e308",
    "-1e308",
    "-1",
    "0",
    "0.0",
    "-0.0",
    "1e-308",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "\"nan\"",
    "\"\"",
    "\"x\"",
    "[]",
    "{}",
    "[1e308, -1]",
    "true",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "1e12",
    "100000",
    "3.5",
    "1979-05-27T07:32:00Z",
];

/// Values that replace a CSV field.
const BAD_FIELDS: &[&str] = &[
    "1e308",
    "-1e308",
    "-1",
    "0",
    "nan",
    "inf",
    "",
    "x",
    "1e-308",
    "4500000",
    "360.0000001",
];

/// The shipped inputs, relative to `studies/`.
fn inputs(studies: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for sub in ["", "scenes", "maps", "measured"] {
        let dir = studies.join(sub);
        let mut names: Vec<String> = fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".toml") || n.ends_with(".csv"))
            .collect();
        names.sort();
        out.extend(names.into_iter().map(|n| {
            if sub.is_empty() {
                n
            } else {
                format!("{sub}/{n}")
            }
        }));
    }
    out
}

/// One mutation of `text` (the file `name`); returns the new bytes and what was done.
fn mutate(rng: &mut Rng, name: &str, text: &str) -> (Vec<u8>, String) {
    let lines: Vec<&str> = text.lines().collect();
    let n = lines.len().max(1);
    let join = |v: &[&str]| (v.join("\n") + "\n").into_bytes();
    let csv = name.ends_with(".csv");
    match rng.below(10) {
        0 => {
            let i = rng.below(n);
            let mut v = lines.clone();
            v.remove(i.min(v.len().saturating_sub(1)));
            (join(&v), format!("delete line {}", i + 1))
        }
        1 => {
            let i = rng.below(n);
            let k = 2 + rng.below(9);
            let mut v = lines.clone();
            let end = (i + k).min(v.len());
            v.drain(i.min(end)..end);
            (join(&v), format!("delete lines {}..{}", i + 1, end))
        }
        2 => {
            let mut cut = rng.below(text.len().max(1));
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            (
                text.as_bytes()[..cut].to_vec(),
                format!("truncate at byte {cut}"),
            )
        }
        3 => {
            let mut bytes = text.as_bytes().to_vec();
            let at = rng.below(bytes.len() + 1);
            let k = 1 + rng.below(16);
            let garbage: Vec<u8> = (0..k).map(|_| rng.byte()).collect();
            bytes.splice(at..at, garbage);
            (bytes, format!("{k} garbage bytes at byte {at}"))
        }
        4 => {
            let i = rng.below(n);
            let mut v = lines.clone();
            v.insert(i, lines.get(i).copied().unwrap_or(""));
            (join(&v), format!("duplicate line {}", i + 1))
        }
        5 => {
            let (i, j) = (rng.below(n), rng.below(n));
            let mut v = lines.clone();
            if i < v.len() && j < v.len() {
                v.swap(i, j);
            }
            (join(&v), format!("swap lines {} and {}", i + 1, j + 1))
        }
        6..=8 if !csv => {
            // A key misspelt, or its value replaced: by a bad one, or a number scaled.
            let keyed: Vec<usize> = (0..lines.len())
                .filter(|&i| key_value(lines[i]).is_some())
                .collect();
            if keyed.is_empty() {
                return (text.as_bytes().to_vec(), "unchanged".into());
            }
            let i = *rng.pick(&keyed);
            let (k, v) = key_value(lines[i]).unwrap();
            let edited = match (rng.below(3), v.trim().parse::<f64>()) {
                (0, _) => format!("{k}x = {v}"),
                (1, Ok(x)) => {
                    let f = *rng.pick(&[10.0, 1000.0, 1e6, 1e-6, -1.0, 0.5]);
                    format!("{k} = {:?}", x * f)
                }
                _ => format!("{k} = {}", rng.pick(BAD_VALUES)),
            };
            let mut out = lines.clone();
            out[i] = &edited;
            (join(&out), format!("line {}: `{edited}`", i + 1))
        }
        _ => {
            // A field of a data row (CSV), or of an inline array (TOML), replaced.
            let rows: Vec<usize> = (0..lines.len())
                .filter(|&i| lines[i].contains(',') && !lines[i].trim_start().starts_with('#'))
                .collect();
            if rows.is_empty() {
                return (text.as_bytes().to_vec(), "unchanged".into());
            }
            let i = *rng.pick(&rows);
            let mut fields: Vec<String> = lines[i].split(',').map(str::to_string).collect();
            let f = rng.below(fields.len());
            let bad = if csv {
                rng.pick(BAD_FIELDS).to_string()
            } else {
                format!(" {}", rng.pick(BAD_VALUES))
            };
            fields[f] = bad;
            let edited = fields.join(",");
            let mut out = lines.clone();
            out[i] = &edited;
            (join(&out), format!("line {}: `{edited}`", i + 1))
        }
    }
}

/// `key = value` of a TOML line that is not a comment or table header.
fn key_value(line: &str) -> Option<(&str, &str)> {
    let t = line.trim_start();
    if t.starts_with('#') || t.starts_with('[') {
        return None;
    }
    line.split_once(" = ")
}

/// How one case ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Accepted,
    Rejected,
    RejectedWithoutPlace,
    RejectedWithoutTheFile,
    OtherExitCode,
    Panic,
    Signal,
    Hang,
}

impl Outcome {
    fn is_failure(self) -> bool {
        !matches!(
            self,
            Outcome::Accepted | Outcome::Rejected | Outcome::RejectedWithoutPlace
        )
    }
}

/// Copies `from` (a directory of files and subdirectories) to `to`.
fn copy_tree(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for e in fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let p = e.path();
        if p.is_dir() {
            copy_tree(&p, &to.join(e.file_name()));
        } else {
            fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// Runs `rotorsweep ARGS` in `dir` under the memory limit and the timeout.
fn run_limited(dir: &Path, args: &[&str]) -> (Option<std::process::ExitStatus>, String) {
    if let ["--write-child", path, text] = args {
        fs::write(dir.join(path), text).unwrap();
        return (Some(std::process::ExitStatus::from_raw(0)), String::new());
    }
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rotorsweep"));
    cmd.args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    // SAFETY: setrlimit is async-signal-safe; nothing else runs between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            let lim = libc::rlimit {
                rlim_cur: MEMORY_LIMIT_BYTES,
                rlim_max: MEMORY_LIMIT_BYTES,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &lim) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let mut child = cmd.spawn().expect("spawn rotorsweep");
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = stderr.read_to_end(&mut s);
        String::from_utf8_lossy(&s).into_owned()
    });
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if t0.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status, reader.join().unwrap())
}

/// Whether an error message names a place: a line (`FILE:LINE:` or `line N`), a key, a
/// dataset, a column or an option.
fn names_place(stderr: &str) -> bool {
    let line = stderr
        .split(':')
        .skip(1)
        .any(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
    let line_word = stderr
        .match_indices("line ")
        .any(|(i, w)| stderr[i + w.len()..].starts_with(|c: char| c.is_ascii_digit()));
    line || line_word
        || ["key `", "dataset `", "column `", "--", "/analysis/"]
            .iter()
            .any(|k| stderr.contains(k))
}

fn classify(status: Option<std::process::ExitStatus>, stderr: &str, names: &[String]) -> Outcome {
    let Some(status) = status else {
        return Outcome::Hang;
    };
    if stderr.contains("panicked") || status.code() == Some(101) {
        return Outcome::Panic;
    }
    if status.signal().is_some() {
        return Outcome::Signal;
    }
    let named = names.iter().any(|n| stderr.contains(n.as_str()));
    match status.code() {
        Some(0) => Outcome::Accepted,
        // clap's own refusal of an option's value (`--holes=x`) names the option; the binary
        // exits 64 for it (usage), as for its other option errors.
        Some(64) if named && stderr.contains("--") => Outcome::Rejected,
        Some(1) if named && names_place(stderr) => Outcome::Rejected,
        Some(1) if named => Outcome::RejectedWithoutPlace,
        Some(1) => Outcome::RejectedWithoutTheFile,
        _ => Outcome::OtherExitCode,
    }
}

/// Runs `cases` seeded mutations on two threads; panics listing every failure.
fn campaign(seed: u64, cases: usize) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let studies = root.join("studies");
    let files = inputs(&studies);
    assert!(files.len() >= 10, "{files:?}");
    let base = crate::support::scratch(&format!("mutation-{seed:x}"));
    // The cases, drawn up front so that they do not depend on the threads.
    let mut rng = Rng::new(seed);
    let plan: Vec<(String, Vec<u8>, String)> = (0..cases)
        .map(|_| {
            if rng.below(12) == 0 {
                let (bytes, what) = balance_mutation(&mut rng);
                return (BALANCE.to_string(), bytes, what);
            }
            let name = rng.pick(&files).clone();
            let text = fs::read_to_string(studies.join(&name)).unwrap();
            let (bytes, what) = mutate(&mut rng, &name, &text);
            (name, bytes, what)
        })
        .collect();
    let fixtures = Fixtures::new(&base, &studies);
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(usize, Outcome, String)>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some((name, bytes, _)) = plan.get(i) else {
                    break;
                };
                let dir = base.join(format!("case-{i:04}"));
                copy_tree(&studies, &dir.join("studies"));
                let (status, stderr, names) = if name == BALANCE {
                    balance_case(&dir, &fixtures.balance, bytes)
                } else {
                    fs::write(dir.join("studies").join(name), bytes).unwrap();
                    let file = Path::new(name).file_name().unwrap().to_string_lossy();
                    let mut names = vec![file.into_owned()];
                    let steps = commands(name, i, &fixtures.reference_import, &mut names);
                    let mut last = (None, String::new());
                    for step in &steps {
                        let args: Vec<&str> = step.iter().map(String::as_str).collect();
                        last = run_limited(&dir, &args);
                        if last.0.is_none_or(|s| s.code() != Some(0)) {
                            break;
                        }
                    }
                    (last.0, last.1, names)
                };
                let outcome = classify(status, &stderr, &names);
                if !outcome.is_failure() {
                    let _ = fs::remove_dir_all(&dir);
                }
                results.lock().unwrap().push((i, outcome, stderr));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|r| r.0);
    let mut counts: BTreeMap<Outcome, usize> = BTreeMap::new();
    let mut by_file: BTreeMap<&str, (usize, usize)> = BTreeMap::new();
    for (i, o, _) in &results {
        *counts.entry(*o).or_default() += 1;
        let e = by_file.entry(plan[*i].0.as_str()).or_default();
        if *o == Outcome::Accepted {
            e.0 += 1;
        } else {
            e.1 += 1;
        }
    }
    println!("mutation test, seed {seed:#x}, {cases} cases: {counts:?}");
    for (i, _, e) in results
        .iter()
        .filter(|r| r.1 == Outcome::RejectedWithoutPlace)
    {
        println!(
            "  no line or key: case {i} ({}: {}): {}",
            plan[*i].0,
            plan[*i].2,
            e.trim()
        );
    }
    for (f, (a, r)) in &by_file {
        println!("  {f}: {a} accepted, {r} not");
    }
    let failures: Vec<String> = results
        .iter()
        .filter(|(_, o, _)| o.is_failure())
        .map(|(i, o, e)| {
            let dir = base.join(format!("case-{i:04}"));
            format!(
                "case {i} ({}: {}) -> {o:?} in {}: {}",
                plan[*i].0,
                plan[*i].2,
                dir.display(),
                e.trim()
            )
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert_eq!(results.len(), cases);
}

/// The plan's name of a `balance` case (no file of `studies/` is mutated).
const BALANCE: &str = "<balance>";

/// Order lists given to `import`: the default, fractional, and out of range.
const ORDERS: &[&str] = &[
    "1,2,3", "0.92,1", "1e308", "1e-320", "0", "-1", "nan", "1,1",
];

/// Results files the cases share, made once per campaign.
struct Fixtures {
    /// The unmutated synthetic run-up's import (`report --compare` of an imported case).
    reference_import: String,
    /// A trial-mass study's results (`balance` cases).
    balance: std::path::PathBuf,
}

impl Fixtures {
    fn new(base: &Path, studies: &Path) -> Self {
        fs::create_dir_all(base).unwrap();
        let reference_import = base.join("reference-import.h5");
        crate::support::rotorsweep_ok(&[
            "import",
            studies
                .join("measured/jeffcott-runup-synthetic.csv")
                .to_str()
                .unwrap(),
            "-o",
            reference_import.to_str().unwrap(),
        ]);
        Self {
            reference_import: reference_import.to_string_lossy().into_owned(),
            balance: balance_results(base),
        }
    }
}

/// The commands of a file case, run in order while they succeed; `names` gets what else a
/// rejection may name (an option given a bad value).
fn commands(name: &str, case: usize, reference: &str, names: &mut Vec<String>) -> Vec<Vec<String>> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<String>>();
    let target = format!("studies/{name}");
    if name.starts_with("measured/") {
        let orders = ORDERS[case % ORDERS.len()];
        names.push("--orders".into());
        return vec![
            s(&["import", &target, "-o", "imported.h5", "--orders", orders]),
            s(&[
                "report",
                "imported.h5",
                "--compare",
                reference,
                "--format",
                "json",
            ]),
        ];
    }
    if name.ends_with(".csv") {
        return vec![s(&["modes", "studies/scenes/reference-roll.toml"])];
    }
    if !name.starts_with("scenes/") {
        return vec![s(&["plan", &target])];
    }
    let small = name.ends_with("jeffcott.toml") || name.ends_with("linear-unbalance.toml");
    match case % 3 {
        // An `extends` chain: a child scene that builds on the mutated one.
        0 => {
            let base = Path::new(name).file_name().unwrap().to_string_lossy();
            let child = format!("studies/scenes/child-of-{base}");
            let text = format!("extends = \"{base}\"\nname = \"child\"\n");
            vec![s(&["--write-child", &child, &text]), s(&["modes", &child])]
        }
        1 if small => vec![s(&["linear", &target, "--speeds", "0:40:3", "--json"])],
        _ => vec![s(&["modes", &target])],
    }
}

/// A `balance` case: bytes are `OPTION VALUE` (an option given a bad value) or `line ROW FIELD
/// VALUE` (a 1× line of the results file replaced).
fn balance_mutation(rng: &mut Rng) -> (Vec<u8>, String) {
    const OPTIONS: &[&str] = &["--angles-deg", "--holes", "--max-mass-g"];
    const VALUES: &[&str] = &[
        "1e308", "-1e308", "0", "-1", "nan", "inf", "0,0", "0,360", "10,-350", "361", "1e-320",
        "100000", "x",
    ];
    let what = if rng.below(2) == 0 {
        format!("{} {}", rng.pick(OPTIONS), rng.pick(VALUES))
    } else {
        let field = rng.pick(&["amplitude_um", "phase_deg"]);
        let value = rng.pick(&["nan", "inf", "-inf", "1e308", "0", "-1"]);
        format!("line {} {field} {value}", rng.below(64))
    };
    (what.clone().into_bytes(), what)
}

/// A row of `/analysis/lines` (as `study::balancing` reads it).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct LineRow {
    job_id: hdf5::types::VarLenUnicode,
    channel: hdf5::types::VarLenUnicode,
    order: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

/// Runs the small trial-mass study of tests/it/balancing.rs into `base`; its results file.
fn balance_results(base: &Path) -> std::path::PathBuf {
    let dir = base.join("balance");
    fs::create_dir_all(&dir).unwrap();
    let study = crate::support::trial_mass_study(&dir, "balance-mutation", &[100.0]);
    let out = dir.join("bal.h5");
    crate::support::rotorsweep_ok(&["run", study.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    out
}

/// Runs one `balance` case (module doc) in `dir`: (status, stderr, what a rejection must name).
fn balance_case(
    dir: &Path,
    results: &Path,
    bytes: &[u8],
) -> (Option<std::process::ExitStatus>, String, Vec<String>) {
    let what = String::from_utf8_lossy(bytes).into_owned();
    let file = dir.join("bal.h5");
    fs::copy(results, &file).unwrap();
    let words: Vec<&str> = what.split(' ').collect();
    if let ["line", row, field, value] = words[..] {
        let f = hdf5::File::open_rw(&file).unwrap();
        let ds = f.dataset("analysis/lines").unwrap();
        let mut rows: Vec<LineRow> = ds.read_raw().unwrap();
        let n = rows.len();
        let r = &mut rows[row.parse::<usize>().unwrap() % n];
        let v: f64 = value.parse().unwrap();
        if field == "phase_deg" {
            r.phase_deg = v;
        } else {
            r.amplitude_um = v;
        }
        ds.write(&rows).unwrap();
        drop(f);
        let (status, stderr) = run_limited(dir, &["balance", "bal.h5"]);
        return (status, stderr, vec!["bal.h5".into()]);
    }
    // As `--holes=-1`: given apart, a value starting with `-` is read as another option.
    let option = format!("{}={}", words[0], words[1]);
    let (status, stderr) = run_limited(dir, &["balance", "bal.h5", &option]);
    (status, stderr, vec![words[0].to_string()])
}

#[test]
fn mutated_inputs_never_panic_abort_or_hang() {
    campaign(SEED, CASES);
}

/// The same with 3000 cases and another seed (163 s on 2 cores, measured).
#[test]
#[ignore]
fn mutated_inputs_never_panic_abort_or_hang_many() {
    campaign(SEED ^ 0xdead_beef, 3000);
}

/// The mutations themselves: each kind changes the text, and the generator is the reference
/// SplitMix64 (first output for seed 0 from the published algorithm).
#[test]
fn mutations_change_the_text_and_the_generator_is_splitmix64() {
    assert_eq!(SplitMix64::new(0).next_u64(), 0xe220_a839_7b1d_cdaf);
    let text = "a = 1\nb = \"x\"\n[t]\nc = [1, 2]\n";
    let mut rng = Rng::new(SEED);
    let changed = (0..200)
        .filter(|_| mutate(&mut rng, "f.toml", text).0 != text.as_bytes())
        .count();
    assert!(
        changed > 150,
        "only {changed} of 200 mutations changed the text"
    );
}
