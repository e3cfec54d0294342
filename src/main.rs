//! The `rotorsweep` command line.

mod campaign_cli;
mod modes;
mod report_cli;
mod simulate;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "rotorsweep",
    version,
    about = "Parameter studies of flexible-rotor dynamics"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The reduced model of a scene: mass, modes, supported frequencies, critical speeds.
    Modes(modes::Args),
    /// One time simulation of a scene: statistics, and results to HDF5 with -o.
    Simulate(simulate::Args),
    /// The jobs of a study, without running them: count, parameters, models, cost.
    Plan(campaign_cli::PlanArgs),
    /// Run a study into one HDF5 file.
    Run(campaign_cli::RunArgs),
    /// Join shard files of one study into one file.
    Merge(campaign_cli::MergeArgs),
    /// Tables of a study results file: solver cost and error, resonances, trial masses, stability.
    Report(report_cli::Args),
}

fn main() -> ExitCode {
    // Behave like other Unix tools when the reader of our output goes away (`| head`).
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Modes(a) => modes::run(&a).map(|()| true),
        Command::Simulate(a) => simulate::run(&a),
        Command::Plan(a) => campaign_cli::plan(&a).map(|()| true),
        Command::Run(a) => campaign_cli::run(&a),
        Command::Merge(a) => campaign_cli::merge(&a).map(|()| true),
        Command::Report(a) => report_cli::run(&a).map(|()| true),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
