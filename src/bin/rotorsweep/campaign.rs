//! `rotorsweep plan`, `rotorsweep run` and `rotorsweep merge`: studies from the command line.

use std::path::PathBuf;

use rotorsweep::study::merge::{merge as merge_shards, MergeOptions};
use rotorsweep::study::plan::Plan;
use rotorsweep::study::run::{run as run_study, CampaignError, ReferenceSource, RunOptions};
use rotorsweep::study::Study;

/// Arguments of `rotorsweep plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// Study file (TOML).
    study: PathBuf,
    /// Threads the cost estimate assumes.
    #[arg(long, default_value_t = 2)]
    threads: usize,
    /// List every job and every value of each varying parameter (by default a study of more
    /// than 100 jobs lists its first and last 10, and a parameter of more than 20 values its
    /// first and last 5).
    #[arg(long)]
    all_jobs: bool,
}

/// Jobs listed by `plan` without `--all-jobs`: all up to `LIST_ALL`, else `LIST_ENDS` at each end.
const LIST_ALL: usize = 100;
const LIST_ENDS: usize = 10;
/// Values of a varying parameter listed without `--all-jobs`: all up to `VALUES_ALL`, else
/// `VALUES_ENDS` at each end.
const VALUES_ALL: usize = 20;
const VALUES_ENDS: usize = 5;

/// The indices of `n` items to list: all when `all` or `n <= up_to`, else `ends` at each end
/// (the gap between them is where `None` stands).
fn listed(n: usize, all: bool, up_to: usize, ends: usize) -> Vec<Option<usize>> {
    if all || n <= up_to {
        (0..n).map(Some).collect()
    } else {
        (0..ends)
            .map(Some)
            .chain(std::iter::once(None))
            .chain((n - ends..n).map(Some))
            .collect()
    }
}

/// Arguments of `rotorsweep run`.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Study file (TOML).
    study: PathBuf,
    /// Results file (HDF5).
    #[arg(short, long)]
    output: PathBuf,
    /// Worker threads (default: all cores; at most 1024).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
    threads: Option<u16>,
    /// Finish an interrupted run: keep its saved jobs, run the rest.
    #[arg(long)]
    resume: bool,
    /// Run only shard i of n (jobs whose index modulo n is i), e.g. `--shard 0/4`.
    #[arg(long, value_name = "i/n")]
    shard: Option<String>,
    /// Accept a shard that holds no job (more shards than jobs): write its file of no jobs
    /// instead of refusing the run.
    #[arg(long, requires = "shard")]
    allow_empty: bool,
    /// Replace an existing results file (only a rotorsweep results file; it stays intact until
    /// the new one is complete) and the saved jobs of an interrupted run.
    #[arg(long, conflicts_with = "resume")]
    overwrite: bool,
    /// Run only the study's reference runs, all of them, into the output: a references file
    /// that the shards of a campaign share with --references (each reference computed once).
    #[arg(long, conflicts_with_all = ["shard", "references"])]
    references_only: bool,
    /// Copy the reference runs from this references file (written by --references-only from
    /// the same study inputs, checked) instead of computing them.
    #[arg(long, value_name = "FILE")]
    references: Option<PathBuf>,
}

/// Arguments of `rotorsweep merge`.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Shard files to join.
    inputs: Vec<PathBuf>,
    /// The joined file.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing output (only a rotorsweep results file).
    #[arg(long)]
    overwrite: bool,
    /// Merge without some shards of the split (the merged file records `partial = 1`).
    #[arg(long)]
    partial: bool,
}

/// Runs `plan`.
pub fn plan(a: &PlanArgs) -> Result<(), crate::error::CliError> {
    let st = Study::load(&a.study)?;
    let plan = Plan::of(&st, a.threads);
    println!("study {}: {} jobs", st.name, st.jobs.len());
    if !st.description.is_empty() {
        println!("  {}", st.description);
    }
    println!("varying parameters:");
    for (k, vals) in &plan.varying {
        let shown: Vec<&str> = listed(vals.len(), a.all_jobs, VALUES_ALL, VALUES_ENDS)
            .into_iter()
            .map(|i| i.map_or("…", |i| vals[i].as_str()))
            .collect();
        let count = if shown.len() < vals.len() {
            format!(" ({} values)", vals.len())
        } else {
            String::new()
        };
        println!("  {k}: {}{count}", shown.join(", "));
    }
    println!(
        "distinct reduced models: {} (pruning pilots: {})",
        plan.models, plan.pilots
    );
    if plan.pruned > 0 {
        println!("jobs on pruned mode sets: {}", plan.pruned);
    }
    println!(
        "reference runs: {}",
        if st.has_reference {
            st.references.len().to_string()
        } else {
            "none (no [reference] section)".into()
        }
    );
    println!(
        "cost estimate: {:.0} s CPU, about {:.0} s on {} threads",
        plan.cpu_s,
        plan.cpu_s / a.threads.max(1) as f64,
        a.threads
    );
    let size = |b: f64| {
        if b < 1e9 {
            format!("{:.1} MB", b / 1e6)
        } else {
            format!("{:.2} GB", b / 1e9)
        }
    };
    println!(
        "memory estimate: {} on {} threads (per thread the largest record, samples × channels × \
         8 B, or model build, about 90 B per DOF²; plus about 1.2 KB per job)",
        size(plan.memory_bytes),
        a.threads
    );
    println!(
        "disk estimate: {} of samples (every job's and reference's record, samples × channels × \
         8 B, before compression)",
        size(plan.disk_bytes)
    );
    println!("\n  job  id                 overrides");
    for i in listed(st.jobs.len(), a.all_jobs, LIST_ALL, LIST_ENDS) {
        let Some(i) = i else {
            println!(
                "  …  {} jobs not listed (--all-jobs lists every one)",
                st.jobs.len() - 2 * LIST_ENDS
            );
            continue;
        };
        let j = &st.jobs[i];
        let over: Vec<String> = st
            .varying
            .iter()
            .map(|k| format!("{k}={}", st.value_text(j, k).unwrap_or_default()))
            .collect();
        let labels: Vec<&str> = j.labels.iter().map(|(_, l)| l.as_str()).collect();
        let labels = if labels.is_empty() {
            String::new()
        } else {
            format!("[{}]  ", labels.join(", "))
        };
        println!("  {:>3}  {}  {labels}{}", j.index, j.id, over.join(" "));
    }
    Ok(())
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (i, n) = s.split_once('/').ok_or("--shard takes i/n, e.g. 0/4")?;
    let (i, n): (usize, usize) = (
        i.trim()
            .parse()
            .map_err(|_| "--shard: i must be a number")?,
        n.trim()
            .parse()
            .map_err(|_| "--shard: n must be a number")?,
    );
    if n == 0 || i >= n {
        return Err(format!("--shard {s}: need 0 <= i < n"));
    }
    Ok((i, n))
}

/// Runs `run`; Ok(true) when every job ended ok.
pub fn run(a: &RunArgs) -> Result<bool, crate::error::CliError> {
    let st = Study::load(&a.study)?;
    let threads = a.threads.map(usize::from).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let opts = RunOptions {
        output: a.output.clone(),
        threads,
        resume: a.resume,
        overwrite: a.overwrite,
        shard: a
            .shard
            .as_deref()
            .map(parse_shard)
            .transpose()
            .map_err(CampaignError::Usage)?,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        references: match (&a.references, a.references_only) {
            (Some(p), _) => ReferenceSource::File(p.clone()),
            (None, true) => ReferenceSource::Only,
            (None, false) => ReferenceSource::Run,
        },
    };
    if let Some((i, n)) = opts.shard {
        if st.shard(i, n).is_empty() && !a.allow_empty {
            return Err(CampaignError::Usage(format!(
                "--shard {i}/{n}: holds no job ({} has {} jobs, and shard i runs the jobs whose \
                 index modulo {n} is i); split into at most {} shards, or add --allow-empty to \
                 write a file of no jobs",
                a.study.display(),
                st.jobs.len(),
                st.jobs.len()
            ))
            .into());
        }
    }
    let t0 = std::time::Instant::now();
    let out = run_study(&st, &opts)?;
    if a.references_only {
        eprintln!(
            "{}: {} reference runs, {} not ok, in {:.1} s -> {}",
            st.name,
            st.references.len(),
            out.references_failed,
            t0.elapsed().as_secs_f64(),
            a.output.display()
        );
        return Ok(out.references_failed == 0);
    }
    eprintln!(
        "{}: {} jobs, {} ok, {}{} failed{}{} in {:.1} s -> {}",
        st.name,
        out.jobs,
        out.ok,
        if out.untrusted > 0 {
            format!(
                "{} untrusted (status and cause in the summary), ",
                out.untrusted
            )
        } else {
            String::new()
        },
        out.failed,
        if out.resumed > 0 {
            format!(" ({} resumed)", out.resumed)
        } else {
            String::new()
        },
        if out.stale > 0 {
            format!(" ({} saved runs of other inputs run again)", out.stale)
        } else {
            String::new()
        },
        t0.elapsed().as_secs_f64(),
        a.output.display()
    );
    if out.references_failed > 0 {
        eprintln!(
            "{}: {} reference run(s) did not end ok: their jobs have no error against the \
             reference (summary column error_cause says why)",
            st.name, out.references_failed
        );
    }
    Ok(out.failed == 0 && out.references_failed == 0)
}

/// Runs `merge`.
pub fn merge(a: &MergeArgs) -> Result<(), crate::error::CliError> {
    let opts = MergeOptions {
        overwrite: a.overwrite,
        partial: a.partial,
    };
    let out = merge_shards(&a.inputs, &a.output, &opts)?;
    eprintln!(
        "merged {} files (shards {}), {} jobs -> {}",
        a.inputs.len(),
        out.shards.join(", "),
        out.jobs,
        a.output.display()
    );
    if !out.missing.is_empty() {
        eprintln!(
            "partial merge: shards {} are missing (recorded as partial = 1)",
            out.missing.join(", ")
        );
    }
    Ok(())
}
