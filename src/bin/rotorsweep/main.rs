//! The `rotorsweep` command line.
//!
//! Exit codes (the same for every subcommand; docs/cli.md "Exit codes"):
//! 0 done, every job ok; 1 input error (a scene, study, map or results file given as input is
//! wrong: the message names the file, line and key); 2 done, but some job or reference run did
//! not end ok; 64 usage error (options, or an output that may not be written); 74 I/O error
//! while writing (disk full, read-only folder: the message names the path and the OS error);
//! 75 the output is in use by another rotorsweep process (try again later).
//!
//! Each subcommand's file parses its options, calls the library and prints; its `run` returns
//! `Ok(true)` (exit 0), `Ok(false)` (some job not ok: exit 2) or a [`CliError`], whose variant
//! is the exit code ([`error`]); `main` maps them in one `match`.

mod balance;
mod barring;
mod calibrate;
mod campaign;
mod check;
mod error;
mod export;
mod import;
mod keys;
mod linear;
mod modes;
mod reduce;
mod report;
mod simulate;
mod speeds;

use std::process::ExitCode;

/// mimalloc instead of the system allocator (Cargo.toml says why).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use clap::{Parser, Subcommand};
use error::CliError;

#[derive(Parser)]
#[command(
    name = "rotorsweep",
    version,
    about = "Parameter studies of flexible-rotor dynamics",
    after_help = "Examples:
  rotorsweep modes studies/scenes/reference-roll.toml         the model, its modes and critical speeds
  rotorsweep simulate studies/scenes/timing-case.toml -o run.h5
  rotorsweep plan studies/smoke.toml                          jobs, models, cost, memory and disk
  rotorsweep run studies/smoke.toml -o smoke.h5 --threads 2   (--resume after a crash, --overwrite to redo)
  rotorsweep run S.toml -o s0.h5 --shard 0/2; ... ; rotorsweep merge s0.h5 s1.h5 -o all.h5
  rotorsweep report smoke.h5 --format csv --table solver
  rotorsweep check studies/scenes/timing-case.toml --set roll.shell.elements=60   effective scene
                                                              (after extends, --set), derived values
  rotorsweep keys > scene-keys.md                             every scene key (docs/scene-keys.md)
  rotorsweep export S.toml --model full -o body/; rotorsweep modes body/scene.toml   round trip
  rotorsweep export S.toml --state-space --speed-hz 10 -o plant.npz   A, B, C, D for control

Exit codes: 0 done, every job ok; 1 input error (the message names the file, line and key);
2 done, some job or reference run not ok; 64 usage error (options, or an output that may not
be replaced); 74 I/O error while writing (path and OS error named); 75 the output is in use by
another rotorsweep process."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The reduced model of a scene: mass, modes, supported frequencies, critical speeds.
    Modes(modes::Args),
    /// Linear rotordynamics of a scene: damped modes vs speed, critical speeds, stability,
    /// unbalance response, Floquet, statics.
    Linear(linear::Args),
    /// Barring stability map of a machine's viscoelastic nip over speed x nip load: growth
    /// rate, polygon order, onset speed (JSON keys and HDF5 layout: docs/machines.md).
    Barring(barring::Args),
    /// One time simulation of a scene: statistics, and results to HDF5 with -o.
    Simulate(simulate::Args),
    /// The jobs of a study, without running them: count, parameters, models, cost.
    Plan(campaign::PlanArgs),
    /// Run a study into one HDF5 file.
    Run(campaign::RunArgs),
    /// Join shard files of one study into one file.
    Merge(campaign::MergeArgs),
    /// Tables of a study results file: solver cost and error, resonances, trial masses, stability.
    Report(report::Args),
    /// The effective scene of a scene or study file (after `extends` and --set, with units) and
    /// what is derived from it: positions, wall, mass, balancing masses, first frequencies.
    Check(check::Args),
    /// Every key a scene file accepts (type, units, default, range, meaning), as Markdown.
    Keys(keys::Args),
    /// Influence-coefficient balancing from a study's trial-mass runs: corrections, predicted
    /// residual, and with --check a run of the corrected roll.
    Balance(balance::Args),
    /// Scene parameters fitted to measured targets (a resonance table, natural frequencies,
    /// any output) by weighted least squares, every evaluation a study run.
    Calibrate(calibrate::Args),
    /// A measured record (CSV) into a results file, analysed like a simulated job.
    Import(import::Args),
    /// A scene's model to Matrix Market, CSV and HDF5 with a scene on the exported body
    /// (--model full|reduced), or its linear plant at a speed as a state-space model
    /// (--state-space --speed-hz F, .h5, .npz or .mat).
    Export(export::Args),
    /// The sparse Craig–Bampton reduction of a large [fe] body at its named nodes (no dense
    /// n × n matrix): reduced matrices and frequencies to a folder.
    Reduce(reduce::Args),
}

fn main() -> ExitCode {
    // The two dispositions go through libc: std has no stable setting for them, and the crates
    // that wrap signals (nix's `signal`/`sigaction`, signal-hook's `register`) are unsafe too.
    // Behave like other Unix tools when the reader of our output goes away (`| head`).
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // A file-size limit (`ulimit -f`) should fail the write with EFBIG and a message, not kill
    // the process with SIGXFSZ.
    // SAFETY: setting a signal's disposition to ignore, before any thread starts.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { EXIT_USAGE } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Modes(a) => modes::run(&a).map(|()| true),
        Command::Linear(a) => linear::run(&a).map(|()| true),
        Command::Barring(a) => barring::run(&a).map(|()| true),
        Command::Simulate(a) => simulate::run(&a),
        Command::Plan(a) => campaign::plan(&a).map(|()| true),
        Command::Run(a) => campaign::run(&a),
        Command::Merge(a) => campaign::merge(&a).map(|()| true),
        Command::Report(a) => report::run(&a).map(|()| true),
        Command::Check(a) => check::run(&a).map(|()| true),
        Command::Keys(a) => keys::run(&a).map(|()| true),
        Command::Balance(a) => balance::run(&a).map(|()| true),
        Command::Calibrate(a) => calibrate::run(&a).map(|()| true),
        Command::Import(a) => import::run(&a).map(|()| true),
        Command::Export(a) => export::run(&a).map(|()| true),
        Command::Reduce(a) => reduce::run(&a).map(|()| true),
    };
    if let Err(e) = &result {
        eprintln!("error: {e}");
    }
    ExitCode::from(match result {
        Ok(true) => 0,
        Ok(false) => EXIT_NOT_OK,
        Err(CliError::Input(_)) => EXIT_INPUT,
        Err(CliError::Usage(_)) => EXIT_USAGE,
        Err(CliError::Io(_)) => EXIT_IO,
        Err(CliError::Busy(_)) => EXIT_BUSY,
    })
}

/// Some job or reference run did not end ok.
const EXIT_NOT_OK: u8 = 2;
/// An input file is wrong.
const EXIT_INPUT: u8 = 1;
/// Bad options, or an output that may not be written (sysexits EX_USAGE).
const EXIT_USAGE: u8 = 64;
/// Writing failed (sysexits EX_IOERR).
const EXIT_IO: u8 = 74;
/// The output is held by another process (sysexits EX_TEMPFAIL).
const EXIT_BUSY: u8 = 75;
