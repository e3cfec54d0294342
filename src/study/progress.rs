//! A campaign's progress: on the terminal as it runs, and in a log file beside the results.
//!
//! In: the number of runs to do, each finished run's id, name (labels or varying values),
//! status and CPU time, and the log opened beside the output.
//! Out: on stderr, a progress bar when stderr is a terminal (elapsed time, ETA from the mean
//! time per run, runs per second, runs not ok), with each finished run's line printed above it;
//! otherwise one plain line per run, `[done/total m:ss elapsed, ETA m:ss] ID (NAME) STATUS cpu
//! S s[: CAUSE]`. The log `OUT.h5.log` gets the same lines, each with its UTC time, between a
//! start line and an end line, then the line that says whether the results file was assembled
//! (`assembled: OUT.h5` or `not assembled: CAUSE`), so that the last line is the run's outcome;
//! it is appended to (a resumed or repeated run adds its own
//! section), never truncated or removed, and a file of that name that is not a rotorsweep log
//! is refused before anything runs.

use std::fs::File;
use std::io::{IsTerminal, Read, Write};
use std::path::{Path, PathBuf};

use crate::integrators::Stats;
use crate::store;
use crate::store::output::OutputError;

/// The first line of every log section: how a log file is told from a user's file.
const LOG_MARK: &str = "# rotorsweep log";

/// Seconds as `m:ss` (or `h:mm:ss`).
fn clock(s: f64) -> String {
    let s = s.round() as u64;
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

/// The campaign log beside a results file (module doc).
pub struct RunLog {
    path: PathBuf,
    file: Option<File>,
}

impl RunLog {
    /// The log's path for results file `output`: `OUT.h5.log`.
    pub fn path_of(output: &Path) -> PathBuf {
        store::with_suffix(output, ".log")
    }

    /// Whether the log of `output` may be appended to: absent, or a regular file that begins
    /// as a rotorsweep log (a symbolic link, a folder, a FIFO or a user's file of that name is
    /// refused). Checked before anything is written or removed.
    pub fn check(output: &Path) -> Result<(), OutputError> {
        let path = Self::path_of(output);
        let Ok(m) = std::fs::symlink_metadata(&path) else {
            return Ok(());
        };
        let mut head = vec![0u8; LOG_MARK.len()];
        let own = m.file_type().is_file()
            && (m.len() == 0
                || File::open(&path)
                    .and_then(|mut f| f.read_exact(&mut head))
                    .is_ok_and(|()| head == LOG_MARK.as_bytes()));
        if own {
            Ok(())
        } else {
            Err(OutputError::Refused(
                path,
                "exists and is not a rotorsweep log, where rotorsweep appends the run's log \
                 (move it away, or choose another -o)"
                    .into(),
            ))
        }
    }

    /// Opens the log of `output` for appending, after [`RunLog::check`].
    pub fn open(output: &Path) -> Result<RunLog, OutputError> {
        Self::check(output)?;
        let path = Self::path_of(output);
        let file = std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(&path)
            .map_err(|e| OutputError::Io(path.clone(), e))?;
        Ok(RunLog {
            path,
            file: Some(file),
        })
    }

    /// Appends a line with its UTC time; the first failure is reported once and ends logging
    /// (the run goes on: its results do not depend on the log).
    fn line(&mut self, text: &str) {
        let Some(f) = &mut self.file else { return };
        let now = humantime::format_rfc3339_seconds(std::time::SystemTime::now());
        if let Err(e) = writeln!(f, "{now} {text}") {
            eprintln!(
                "warning: {}: cannot write the log ({e}); the run goes on without it",
                self.path.display()
            );
            self.file = None;
        }
    }
}

/// Progress of one campaign (module doc).
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    log: std::cell::RefCell<RunLog>,
    start: std::time::Instant,
    total: u64,
    done: std::cell::Cell<u64>,
    failed: std::cell::Cell<u64>,
}

impl Progress {
    /// Starts the progress of `total` runs; `what` (the command, shard, threads) opens the
    /// log's section.
    pub fn new(total: u64, mut log: RunLog, what: &str) -> Self {
        if let Some(f) = &mut log.file {
            // The mark starts the section's first line, so that a log is told from other files.
            if let Err(e) = writeln!(f, "{LOG_MARK}") {
                eprintln!("warning: {}: cannot write the log: {e}", log.path.display());
                log.file = None;
            }
        }
        log.line(&format!("start: {what}"));
        let bar = std::io::stderr().is_terminal().then(|| {
            let b = indicatif::ProgressBar::new(total);
            let style = indicatif::ProgressStyle::with_template(
                "{bar:30} {pos}/{len} runs, {rate}, {elapsed} elapsed, ETA {eta}, {msg} not ok",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .with_key(
                "rate",
                |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(w, "{:.2} runs/s", s.per_sec());
                },
            );
            b.set_style(style);
            b.set_message("0");
            b
        });
        Self {
            bar,
            log: log.into(),
            start: std::time::Instant::now(),
            total,
            done: 0.into(),
            failed: 0.into(),
        }
    }

    /// Reports a finished run `id` (`name`: its labels or varying values): its status, or that
    /// it could not be saved (then it is not ok, whatever the integrator said).
    pub fn job_done(
        &self,
        id: &str,
        name: &str,
        stats: &Stats,
        not_saved: Option<&dyn std::fmt::Display>,
    ) {
        self.done.set(self.done.get() + 1);
        if !stats.status.completed() || not_saved.is_some() {
            self.failed.set(self.failed.get() + 1);
        }
        let (done, total) = (self.done.get(), self.total);
        let elapsed = self.start.elapsed().as_secs_f64();
        let eta = elapsed / done as f64 * total.saturating_sub(done) as f64;
        let head = format!(
            "[{done}/{total} {} elapsed, ETA {}] {id} ({name})",
            clock(elapsed),
            clock(eta),
        );
        let line = match not_saved {
            Some(e) => format!("{head} NOT SAVED ({} in memory): {e}", stats.status.name()),
            None => format!(
                "{head} {} cpu {:.3} s{}",
                stats.status.name(),
                stats.cpu_time_s,
                if stats.cause.is_empty() {
                    String::new()
                } else {
                    format!(": {}", stats.cause)
                }
            ),
        };
        self.log.borrow_mut().line(&line);
        match &self.bar {
            Some(b) => {
                b.println(&line);
                b.inc(1);
                b.set_message(self.failed.get().to_string());
            }
            None => eprintln!("{line}"),
        }
    }

    /// Ends the bar and the log's section.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish();
        }
        let elapsed = self.start.elapsed().as_secs_f64();
        self.log.borrow_mut().line(&format!(
            "end: {} of {} runs finished in {}, {} not ok",
            self.done.get(),
            self.total,
            clock(elapsed),
            self.failed.get()
        ));
    }

    /// The log's last line: the results file `output` assembled, or why not (`failure`), and
    /// that the saved runs are kept for `--resume`.
    pub fn assembled(&self, output: &Path, failure: Option<&dyn std::fmt::Display>) {
        let line = match failure {
            None => format!("assembled: {}", output.display()),
            Some(e) => {
                format!("not assembled: {e} (the saved runs are kept: finish with --resume)")
            }
        };
        self.log.borrow_mut().line(&line);
    }
}
