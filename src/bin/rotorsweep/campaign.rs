//! `rotorsweep plan`, `rotorsweep run` and `rotorsweep merge`: studies from the command line.

use std::collections::BTreeSet;
use std::path::PathBuf;

use rotorsweep::study::campaign::{self, CampaignError, ReferenceSource, RunOptions};
use rotorsweep::study::Study;

/// Arguments of `rotorsweep plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// Study file (TOML).
    study: PathBuf,
    /// Threads the cost estimate assumes.
    #[arg(long, default_value_t = 2)]
    threads: usize,
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

/// Rough CPU seconds of one job: steps × (1.5 µs + 1.5 ns × n²), from the timing case
/// (45 coordinates, 100 000 steps, 0.46 s); explicit rk45 at its stability limit 3/ω_max.
fn estimate(job: &rotorsweep::scene::Scene, coords: usize, f_max_hz: f64) -> f64 {
    let s = &job.solver;
    let t = job.simulation.t_end;
    let steps = match s.integrator {
        rotorsweep::integrators::IntegratorKind::Rk45 => {
            (t / s.hmax).max(t * 2.0 * std::f64::consts::PI * f_max_hz / 3.0)
        }
        _ => t / s.hmax,
    };
    steps * (1.5e-6 + 1.5e-9 * (coords * coords) as f64)
}

/// Runs `plan`.
pub fn plan(a: &PlanArgs) -> Result<(), crate::error::CliError> {
    let st = Study::load(&a.study)?;
    println!("study {}: {} jobs", st.name, st.jobs.len());
    if !st.description.is_empty() {
        println!("  {}", st.description);
    }
    println!("varying parameters:");
    for k in &st.varying {
        let vals: BTreeSet<String> = st.jobs.iter().filter_map(|j| st.value_text(j, k)).collect();
        let mut vals: Vec<String> = vals.into_iter().collect();
        // Numbers in numeric order (10 after 9, not after 1), text as text.
        vals.sort_by(|a, b| match (a.parse::<f64>(), b.parse::<f64>()) {
            (Ok(x), Ok(y)) => x.total_cmp(&y),
            _ => a.cmp(b),
        });
        println!("  {k}: {}", vals.join(", "));
    }
    let models: BTreeSet<&str> = st.jobs.iter().map(|j| j.model_id.as_str()).collect();
    let pruned = st.jobs.iter().filter(|j| j.prune.is_some()).count();
    println!(
        "distinct reduced models: {} (pruning pilots: {})",
        models.len(),
        st.jobs
            .iter()
            .filter(|j| j.prune.is_some())
            .map(|j| j.model_id.as_str())
            .collect::<BTreeSet<_>>()
            .len()
    );
    if pruned > 0 {
        println!("jobs on pruned mode sets: {pruned}");
    }
    println!(
        "reference runs: {}",
        if st.has_reference {
            st.references.len().to_string()
        } else {
            "none (no [reference] section)".into()
        }
    );
    // Mode counts per model from the scenes (cheap: no model is built).
    let coordinates =
        |sc: &rotorsweep::scene::Scene| sc.modal_coordinates() + 2 * sc.supports.len();
    let mut total = 0.0;
    for j in &st.jobs {
        total += estimate(&j.scene, coordinates(&j.scene), 6000.0);
    }
    if st.has_reference {
        for r in &st.references {
            total += estimate(&r.scene, coordinates(&r.scene), 6000.0);
        }
    }
    println!(
        "cost estimate: {:.0} s CPU, about {:.0} s on {} threads",
        total,
        total / a.threads.max(1) as f64,
        a.threads
    );
    // Memory and disk: a run's record is samples × (channels + time) × 8 bytes; a model build
    // peaks near 90 bytes per DOF² (dense FE matrices and eigen-solutions: 0.74 GB measured at
    // 2958 DOFs); the loaded study holds about 60 KB per job (measured: 274 MB for 4901 jobs).
    let record = |sc: &rotorsweep::scene::Scene| sc.samples() * (sc.channels() + 1) as f64 * 8.0;
    let scenes: Vec<&rotorsweep::scene::Scene> = st
        .jobs
        .iter()
        .map(|j| &j.scene)
        .chain(
            st.references
                .iter()
                .filter(|_| st.has_reference)
                .map(|r| &r.scene),
        )
        .collect();
    let disk: f64 = scenes.iter().map(|sc| record(sc)).sum();
    let per_thread = scenes
        .iter()
        .map(|sc| {
            let dofs = 6.0 * sc.max_nodes() as f64;
            record(sc).max(90.0 * dofs * dofs)
        })
        .fold(0.0, f64::max);
    let memory = per_thread * a.threads.max(1) as f64 + 60e3 * st.jobs.len() as f64;
    let size = |b: f64| {
        if b < 1e9 {
            format!("{:.1} MB", b / 1e6)
        } else {
            format!("{:.2} GB", b / 1e9)
        }
    };
    println!(
        "memory estimate: {} on {} threads (per thread the largest record, samples × channels × \
         8 B, or model build, about 90 B per DOF²; plus about 60 KB per job)",
        size(memory),
        a.threads
    );
    println!(
        "disk estimate: {} of samples (every job's and reference's record, samples × channels × \
         8 B, before compression)",
        size(disk)
    );
    println!("\n  job  id                 overrides");
    for j in &st.jobs {
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
    let out = campaign::run(&st, &opts)?;
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
    let opts = campaign::MergeOptions {
        overwrite: a.overwrite,
        partial: a.partial,
    };
    let out = campaign::merge(&a.inputs, &a.output, &opts)?;
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
