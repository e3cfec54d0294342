//! The figures of the HTML report, drawn by the Python package (`python -m rotorsweep.figures`,
//! the one place figures are drawn; matplotlib), never by Rust.
//!
//! In: the results file (and with `--compare` the simulated one) and the report's JSON with its
//! labels (what `report --format json --labels` prints: the error classes and number texts the
//! figures write, computed once in Rust). Out: [`Figures`]: the PNGs in the order the package
//! printed them, or, when no Python with the package and matplotlib is found, the one line that
//! says how to get them (the page is then written with its tables).
//!
//! Which Python: `$ROTORSWEEP_PYTHON` when set, else the source tree's `.venv/bin/python` (made
//! by `scripts/python-test`), else `python3`; the source tree (the one the binary was built from,
//! or the one two folders above the binary, `target/release/..`) puts its `python/` first on
//! `PYTHONPATH`, so a checkout's figures never come from another installed version; otherwise
//! the installed package (`pip install "./python[figures]"`) is used. Each candidate is asked
//! first whether it can import the package and matplotlib.
//!
//! Bounds: the figure process gets [`timeout`] (`$ROTORSWEEP_FIGURES_TIMEOUT_S`, default
//! [`DEFAULT_TIMEOUT_S`]) and is killed after it; it runs with `--until-stdin-closes`, so when
//! the report ends (or is killed) it stops and removes the report's scratch folder (its `-o`,
//! where the tables, its output and the PNGs are) itself.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use wait_timeout::ChildExt;

use super::Figure;

/// The figure process's time limit when `$ROTORSWEEP_FIGURES_TIMEOUT_S` sets none [s].
pub const DEFAULT_TIMEOUT_S: f64 = 600.0;

/// How long a Python may take to say whether it imports the package [s].
const PROBE_TIMEOUT_S: f64 = 60.0;

/// What the figure step gives the page.
#[derive(Debug)]
pub enum Figures {
    /// The PNGs, in the order the package wrote them.
    Drawn(Vec<Figure>),
    /// No Python with the package and matplotlib: the line that says how to get the figures.
    Unavailable(String),
}

/// The figure process's time limit: `$ROTORSWEEP_FIGURES_TIMEOUT_S` (a positive number of
/// seconds) or [`DEFAULT_TIMEOUT_S`].
pub fn timeout() -> Result<Duration, String> {
    match std::env::var("ROTORSWEEP_FIGURES_TIMEOUT_S") {
        Err(_) => Ok(Duration::from_secs_f64(DEFAULT_TIMEOUT_S)),
        Ok(v) => v
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|s| s.is_finite() && *s > 0.0 && *s < 1e9)
            .map(Duration::from_secs_f64)
            .ok_or_else(|| {
                format!("ROTORSWEEP_FIGURES_TIMEOUT_S={v}: not a positive number of seconds")
            }),
    }
}

/// The source trees the binary may come from: the build's, else two folders above the binary.
fn source_trees() -> Vec<PathBuf> {
    let mut v = vec![PathBuf::from(env!("CARGO_MANIFEST_DIR"))];
    if let Some(up) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent()?.parent()?.parent().map(Path::to_path_buf))
    {
        v.push(up);
    }
    v
}

/// A Python to try, with the `PYTHONPATH` that puts a source tree's package first.
struct Python {
    exe: PathBuf,
    pythonpath: Option<std::ffi::OsString>,
}

impl Python {
    fn command(&self) -> Command {
        let mut cmd = Command::new(&self.exe);
        if let Some(p) = &self.pythonpath {
            cmd.env("PYTHONPATH", p);
        }
        cmd
    }

    /// Whether it imports the figures package and matplotlib (bounded by `limit`).
    fn has_figures(&self, limit: Duration) -> bool {
        let child = self
            .command()
            .args(["-c", "import rotorsweep.figures.run"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        match child {
            Ok(mut c) => match c.wait_timeout(limit) {
                Ok(Some(status)) => status.success(),
                _ => {
                    let _ = c.kill();
                    let _ = c.wait();
                    false
                }
            },
            Err(_) => false,
        }
    }
}

/// The Pythons to try, in order (module doc).
fn candidates() -> Vec<Python> {
    let trees = source_trees();
    let package = trees
        .iter()
        .map(|t| t.join("python"))
        .find(|p| p.join("rotorsweep").join("figures").is_dir());
    let pythonpath = package.and_then(|pkg| {
        let mut paths = vec![pkg];
        paths.extend(
            std::env::var_os("PYTHONPATH")
                .iter()
                .flat_map(std::env::split_paths),
        );
        std::env::join_paths(paths).ok()
    });
    let exes: Vec<PathBuf> = match std::env::var_os("ROTORSWEEP_PYTHON") {
        Some(p) => vec![PathBuf::from(p)],
        None => trees
            .iter()
            .map(|t| t.join(".venv/bin/python"))
            .filter(|p| p.is_file())
            .chain([PathBuf::from("python3")])
            .collect(),
    };
    exes.into_iter()
        .map(|exe| Python {
            exe,
            pythonpath: pythonpath.clone(),
        })
        .collect()
}

/// The figures of `file` (compared with `compare`), drawn with the report's JSON `tables`
/// (module doc). An error when the figure process fails or runs past its time limit.
pub fn draw(file: &Path, compare: Option<&Path>, tables: &str) -> Result<Figures, String> {
    let limit = timeout()?;
    let Some(python) = candidates()
        .into_iter()
        .find(|p| p.has_figures(Duration::from_secs_f64(PROBE_TIMEOUT_S)))
    else {
        return Ok(Figures::Unavailable(
            "Figures: none drawn, no Python with the rotorsweep package and matplotlib was found \
             (pip install \"./python[figures]\" in rotorsweep's source tree, or set \
             ROTORSWEEP_PYTHON to a Python that has them)."
                .to_string(),
        ));
    };
    // A fresh folder of our own, removed with what the figures wrote when `dir` drops.
    let dir = tempfile::Builder::new()
        .prefix("rotorsweep-report-")
        .tempdir()
        .map_err(|e| format!("cannot make a scratch folder for the figures: {e}"))?;
    let io = |e: std::io::Error| format!("the figures' scratch folder: {e}");
    let tables_path = dir.path().join("tables.json");
    std::fs::write(&tables_path, tables).map_err(io)?;
    let stdout_path = dir.path().join("stdout");
    let stderr_path = dir.path().join("stderr");
    let mut child = python
        .command()
        .args(["-m", "rotorsweep.figures"])
        .arg(file)
        .args(compare.iter().flat_map(|c| [Path::new("--compare"), c]))
        .arg("--tables")
        .arg(&tables_path)
        .arg("-o")
        .arg(dir.path())
        .arg("--until-stdin-closes")
        .stdin(Stdio::piped())
        .stdout(File::create(&stdout_path).map_err(io)?)
        .stderr(File::create(&stderr_path).map_err(io)?)
        .spawn()
        .map_err(|e| format!("cannot run {} for the figures ({e})", python.exe.display()))?;
    // Our end of its standard input stays open until it has ended (`--until-stdin-closes`).
    let stdin = child.stdin.take();
    let status = match child.wait_timeout(limit) {
        Ok(Some(status)) => status,
        Ok(None) | Err(_) => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "the figures took longer than {} s and were stopped \
                 (ROTORSWEEP_FIGURES_TIMEOUT_S sets the limit; --no-figures leaves them out)",
                limit.as_secs_f64()
            ));
        }
    };
    drop(stdin);
    if !status.success() {
        let err = std::fs::read_to_string(&stderr_path).unwrap_or_default();
        return Err(format!(
            "the figures (`{} -m rotorsweep.figures`) failed ({status}):\n{}\n\
             (ROTORSWEEP_PYTHON picks the Python; --no-figures leaves the figures out)",
            python.exe.display(),
            err.trim_end()
        ));
    }
    let printed = std::fs::read_to_string(&stdout_path).map_err(io)?;
    printed
        .lines()
        .filter(|l| l.ends_with(".png"))
        .map(|l| {
            let p = PathBuf::from(l);
            let png = std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))?;
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            Ok(Figure { name, png })
        })
        .collect::<Result<Vec<_>, String>>()
        .map(Figures::Drawn)
}
