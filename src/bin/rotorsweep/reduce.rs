//! `rotorsweep reduce SCENE --normal N -o DIR`: the sparse Craig–Bampton reduction of a large
//! `[fe]` body, with no dense n × n matrix.
//!
//! In: a scene whose `[fe]` body is a Matrix Market model (any size; nodes anywhere), its named
//! nodes (`fe.named`) the interface, and the number of fixed-interface normal modes. Out, in a
//! new folder DIR: `stiffness.mtx` and `mass.mtx` (the Craig–Bampton matrices K̂, M̂, SI,
//! symmetric), `interface.csv` (`coordinate,node,dof`: the interface DOFs, the first
//! coordinates) and `frequencies.csv` (`set,index,hz`: the fixed-interface normal modes and the
//! reduced body's modes, free at its interface); a line per step with its time. Method:
//! [`rotorsweep::rotor::import::sparse_body`] and [`rotorsweep::rotor::sparse_reduction`].
//! An existing output is refused (exit 64); a bad body is an input error naming its file and
//! line (exit 65).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use rotorsweep::error::InputError;
use rotorsweep::rotor::import::matrix_market::{format, Symmetry};
use rotorsweep::rotor::import::sparse_body;
use rotorsweep::rotor::import::tables::DOF_NAMES;
use rotorsweep::rotor::sparse_reduction::craig_bampton;
use rotorsweep::scene::fe_body_files;

use crate::error::CliError;

/// Arguments of `rotorsweep reduce`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML) with an `[fe]` body in Matrix Market files.
    scene: PathBuf,
    /// Fixed-interface normal modes to keep (1–1000).
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=1000))]
    normal: u32,
    /// Output folder (new).
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs `reduce`.
pub fn run(a: &Args) -> Result<(), CliError> {
    if a.output.exists() {
        return Err(CliError::usage(format!(
            "{}: exists; reduce writes a new folder (remove it first)",
            a.output.display()
        )));
    }
    let t0 = Instant::now();
    let (files, named) = fe_body_files(&a.scene)?;
    if let Some(s) = &files.stress {
        return Err(InputError::new(
            &s.stiffness,
            "`reduce` does not reduce a stress stiffness (fe.stress_stiffness): remove the key, \
             or attach the body in a scene (the dense path) to use it",
        )
        .into());
    }
    let body = sparse_body::load(&files)?;
    let n = body.dofs.len();
    println!(
        "read {} DOFs, {} + {} stored entries (M, K) in {:.2} s",
        n,
        body.mass.nnz(),
        body.stiffness.nnz(),
        t0.elapsed().as_secs_f64()
    );
    if named.is_empty() {
        return Err(InputError::new(
            &a.scene,
            "fe.named is empty: the named nodes are the reduction's interface",
        )
        .with_key("fe.named")
        .into());
    }
    let ids: Vec<i64> = named.values().copied().collect();
    let boundary: Vec<usize> = (0..n)
        .filter(|&r| ids.contains(&body.dofs[r].node))
        .collect();
    for (name, id) in &named {
        if !body.dofs.iter().any(|d| d.node == *id) {
            return Err(InputError::new(
                &a.scene,
                format!(
                    "node {id} has no row in the DOF table {}",
                    files.dofs.as_deref().unwrap_or(&files.mass).display()
                ),
            )
            .with_key(format!("fe.named.{name}"))
            .into());
        }
    }
    let r = craig_bampton(&body.stiffness, &body.mass, &boundary, a.normal as usize)
        .map_err(|e| CliError::input(format!("{}: {e}", a.scene.display())))?;
    let steps = [
        "blocks",
        "factorisation",
        "constraint modes",
        "normal modes",
        "projection",
        "reduced eigenproblem",
    ];
    for (s, t) in steps.iter().zip(r.seconds) {
        println!("  {s}: {t:.2} s");
    }
    std::fs::create_dir(&a.output)?;
    let write = |name: &str, text: String| -> Result<(), CliError> {
        let p = a.output.join(name);
        std::fs::write(&p, text).map_err(|e| CliError::Io(format!("{}: {e}", p.display()).into()))
    };
    let comment = format!(
        "Craig-Bampton reduction of {}: {} interface DOFs, then {} normal modes",
        a.scene.display(),
        boundary.len(),
        a.normal
    );
    write(
        "stiffness.mtx",
        format(&r.k, Symmetry::Symmetric, "SI", &comment),
    )?;
    write(
        "mass.mtx",
        format(&r.m, Symmetry::Symmetric, "SI", &comment),
    )?;
    let mut t = String::from("coordinate,node,dof\n");
    for (c, &row) in boundary.iter().enumerate() {
        let d = body.dofs[row];
        let _ = writeln!(t, "{},{},{}", c + 1, d.node, DOF_NAMES[d.dof]);
    }
    write("interface.csv", t)?;
    let mut f = String::from("set,index,hz\n");
    for (i, hz) in r.fixed_hz.iter().enumerate() {
        let _ = writeln!(f, "fixed-interface,{},{hz:e}", i + 1);
    }
    for (i, hz) in r.free_hz.iter().enumerate() {
        let _ = writeln!(f, "reduced,{},{hz:e}", i + 1);
    }
    write("frequencies.csv", f)?;
    let first: Vec<String> = r
        .free_hz
        .iter()
        .take(12)
        .map(|f| format!("{f:.3}"))
        .collect();
    println!(
        "{} DOFs -> {} coordinates ({} interface + {} normal) -> {}/ in {:.2} s; fixed-interface {:.3}–{:.3} Hz; reduced body's first modes (free, rigid ones near 0) [Hz]: {}",
        n,
        r.k.nrows(),
        boundary.len(),
        a.normal,
        a.output.display(),
        t0.elapsed().as_secs_f64(),
        r.fixed_hz.first().copied().unwrap_or(0.0),
        r.fixed_hz.last().copied().unwrap_or(0.0),
        first.join(", ")
    );
    Ok(())
}
