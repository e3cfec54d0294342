//! `rotorsweep reduce SCENE --normal N -o DIR`: the sparse Craig–Bampton reduction of a large
//! `[fe]` body, with no dense n × n matrix.
//!
//! In: a scene whose `[fe]` body is a model in Matrix Market, Abaqus, Nastran DMIG or OP4 files
//! (any size; nodes anywhere), its named nodes (`fe.named`) and ring attachments (`fe.rings`,
//! RBE3-like) whose nodes are the interface, the number of fixed-interface normal modes, and
//! optionally a number of the whole body's own free modes (`--free`). Out, in a new folder DIR:
//! `stiffness.mtx` and `mass.mtx`
//! (the Craig–Bampton matrices K̂, M̂, SI, symmetric; with a stress stiffness
//! `fe.stress_stiffness`, `stress_stiffness.mtx`: K̂_σ per (rad/s)² on the same basis, so
//! K̂(Ω) = K̂ + Ω² K̂_σ), `interface.csv` (`coordinate,node,dof`:
//! the interface DOFs, the first coordinates), `attachments.csv` (`row,name,dof,x,y,z`: each
//! named node's DOFs and each ring's reference point's six, position [m]) with
//! `attachments.mtx` (array: the attachments' motion from the reduced coordinates, m or rad
//! per coordinate: a ring's row is its interpolation, [`rotorsweep::rotor::import::rings`]),
//! `frequencies.csv` (`set,index,hz`: the fixed-interface normal modes, the reduced body's
//! modes free at its interface, with `--free` the whole body's free modes `free-body` and
//! with `--supported` the whole body's modes on the scene's supports at standstill
//! `supported-body`, [`rotorsweep::linear::solid_supported`])
//! and, with `--free`, `free_modes.mtx` (array, DOFs × modes in the DOF table's order,
//! M-normalised, m per unit modal coordinate); a line per step with its time. Method:
//! [`rotorsweep::rotor::import::sparse_body`] and [`rotorsweep::rotor::sparse_reduction`].
//! An existing output is refused (exit 64); a bad body is an input error naming its file and
//! line (exit 65).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use rotorsweep::error::InputError;
use rotorsweep::linear::solid_supported::{solid_of, supported_modes, Failure};
use rotorsweep::rotor::import::matrix_market::{format, format_array, Symmetry};
use rotorsweep::rotor::import::solid::{self, SolidBody};
use rotorsweep::rotor::import::sparse_body;
use rotorsweep::rotor::import::tables::DOF_NAMES;
use rotorsweep::rotor::sparse_reduction::{body_modes, craig_bampton};
use rotorsweep::scene::source::Source;
use rotorsweep::scene::{fe_body_files, fe_body_rings, Scene};

use crate::error::CliError;

/// Arguments of `rotorsweep reduce`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML) with an `[fe]` body (Matrix Market, Abaqus, Nastran DMIG or OP4 files).
    scene: PathBuf,
    /// Fixed-interface normal modes to keep (1–1000).
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=1000))]
    normal: u32,
    /// Also the lowest N modes of the whole body, free (0–1000; 0: none): frequencies.csv's
    /// `free-body` set and free_modes.mtx.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=1000))]
    free: u32,
    /// Also the lowest N modes of the whole body on the scene's linear supports and drive at
    /// standstill (0–1000; 0: none): frequencies.csv's `supported-body` set. The scene must be
    /// a complete scene (supports, drive) on a solid body.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=1000))]
    supported: u32,
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
    // With --supported the scene is read whole (its supports and drive), and its solid body
    // (read once, by the scene) is the one reduced.
    let scene = if a.supported > 0 {
        Some(Scene::load(&a.scene, &[])?)
    } else {
        None
    };
    let failed = |f: Failure| -> CliError {
        match f {
            // In the file that writes the key (a scene may extend another), at its line.
            Failure::Key(key, reason) => match Source::load(&a.scene) {
                Ok(source) => source.err(&key, reason).into(),
                Err(e) => e.into(),
            },
            Failure::Solver(e) => CliError::input(format!("{}: {e}", a.scene.display())),
        }
    };
    let scene_solid = scene
        .as_ref()
        .map(|s| solid_of(s).map_err(failed))
        .transpose()?;
    let read: SolidBody;
    let solid: &SolidBody = match scene_solid {
        Some(s) => s,
        None => {
            let body = sparse_body::load(&files)?;
            let rings = fe_body_rings(&a.scene, &body.nodes, files.units)?;
            if named.is_empty() && rings.is_empty() {
                return Err(InputError::new(
                    &a.scene,
                    "fe.named and fe.rings are empty: the named nodes and the rings are the \
                     reduction's interface",
                )
                .with_key("fe.named")
                .into());
            }
            read = solid::attach(body, &named, &rings, &files.dofs_file())
                .map_err(|(key, reason)| InputError::new(&a.scene, reason).with_key(key))?;
            &read
        }
    };
    let n = solid.body.dofs.len();
    println!(
        "read {} DOFs, {} + {} stored entries (M, K) in {:.2} s",
        n,
        solid.body.mass.nnz(),
        solid.body.stiffness.nnz(),
        t0.elapsed().as_secs_f64()
    );
    let body = &solid.body;
    let boundary = &solid.interface;
    let r = craig_bampton(
        &body.stiffness,
        &body.mass,
        body.stress.as_ref(),
        boundary,
        a.normal as usize,
        false,
    )
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
    let free = (a.free > 0)
        .then(|| {
            timed("free modes of the whole body", || {
                body_modes(&body.stiffness, &body.mass, a.free as usize)
                    .map_err(|e| CliError::input(format!("{}: {e}", a.scene.display())))
            })
        })
        .transpose()?;
    let supported = scene
        .as_ref()
        .map(|sc| {
            timed("modes of the whole body on its supports", || {
                supported_modes(sc, a.supported as usize).map_err(failed)
            })
        })
        .transpose()?;
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
    if let Some(ks) = &r.ks {
        write(
            "stress_stiffness.mtx",
            format(
                ks,
                Symmetry::Symmetric,
                "SI",
                &format!(
                    "{comment}; stress stiffening per (rad/s)^2, K(Omega) = K + Omega^2 Ks \
                     (dK at Omega_ref = 1 rad/s)"
                ),
            ),
        )?;
    }
    let mut t = String::from("coordinate,node,dof\n");
    for (c, &row) in boundary.iter().enumerate() {
        let d = body.dofs[row];
        let _ = writeln!(t, "{},{},{}", c + 1, d.node, DOF_NAMES[d.dof]);
    }
    write("interface.csv", t)?;
    let mut f = String::from("set,index,hz\n");
    hz_rows(&mut f, "fixed-interface", r.fixed_hz.iter().copied());
    hz_rows(&mut f, "reduced", r.free_hz.iter().copied());
    if let Some(fm) = &free {
        hz_rows(&mut f, "free-body", fm.values.iter().map(|&l| hz(l)));
        write(
            "free_modes.mtx",
            format_array(
                n,
                fm.values.len(),
                |i, j| fm.vectors[(i, j)],
                "SI",
                &format!(
                    "free modes of the whole body {}: DOFs in the DOF table's order x modes, \
                     M-normalised",
                    a.scene.display()
                ),
            ),
        )?;
    }
    if let Some(sm) = &supported {
        hz_rows(&mut f, "supported-body", sm.values.iter().map(|&l| hz(l)));
    }
    write("frequencies.csv", f)?;
    let (table, rows) = attachments(solid);
    write("attachments.csv", table)?;
    write(
        "attachments.mtx",
        format_array(
            rows.len(),
            r.k.nrows(),
            |i, j| rows[i].get(&j).copied().unwrap_or(0.0),
            "SI",
            "attachment motion [m, rad] per reduced coordinate: attachments.csv's rows x the \
             reduced coordinates (interface.csv's, then the normal modes)",
        ),
    )?;
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

/// `work` run, its time printed after `what`.
fn timed<T>(what: &str, work: impl FnOnce() -> Result<T, CliError>) -> Result<T, CliError> {
    let t = Instant::now();
    let out = work()?;
    println!("  {what}: {:.2} s", t.elapsed().as_secs_f64());
    Ok(out)
}

/// The frequency [Hz] of an eigenvalue λ [(rad/s)²] (a negative one's as 0).
fn hz(lambda: f64) -> f64 {
    lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// frequencies.csv's rows `set,index,hz` of one set, numbered from 1.
fn hz_rows(out: &mut String, set: &str, hz: impl Iterator<Item = f64>) {
    for (i, x) in hz.enumerate() {
        let _ = writeln!(out, "{set},{},{x:e}", i + 1);
    }
}

/// One row of an attachment matrix: reduced coordinate → coefficient.
type Row = HashMap<usize, f64>;

/// attachments.csv's text and attachments.mtx's rows: each attachment's rows
/// ([`solid::Attachment`]: a named node's own DOFs, a ring's six reference DOFs) over the
/// reduced coordinates (the interface coordinate of each body DOF row it names).
fn attachments(solid: &SolidBody) -> (String, Vec<Row>) {
    let coordinate: HashMap<usize, usize> = solid
        .interface
        .iter()
        .enumerate()
        .map(|(c, &r)| (r, c))
        .collect();
    let mut text = String::from("row,name,dof,x,y,z\n");
    let mut rows = Vec::new();
    for at in &solid.attachments {
        for (dof, dof_name) in DOF_NAMES.iter().enumerate() {
            if !at.ring && at.rows[dof].is_empty() {
                continue;
            }
            rows.push(
                at.rows[dof]
                    .iter()
                    .map(|&(r, x)| (coordinate[&r], x))
                    .collect(),
            );
            let c = at.centre;
            let _ = writeln!(
                text,
                "{},{},{dof_name},{:e},{:e},{:e}",
                rows.len(),
                at.name,
                c[0],
                c[1],
                c[2]
            );
        }
    }
    (text, rows)
}
