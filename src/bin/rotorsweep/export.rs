//! `rotorsweep export SCENE --model full|reduced -o DIR`: a scene's model to files, and
//! `rotorsweep export SCENE --state-space --speed-hz F -o PLANT.h5|.npz|.mat`: its linear plant.
//!
//! In: a scene (and `--set`, `--modes`). Out: the files of [`rotorsweep::export::model`] in a
//! new folder DIR (with `--model full` also `DIR/scene.toml`, a scene on the exported body), or
//! the state-space model of [`rotorsweep::export::plant`] in one new file, the format by its
//! extension; a line saying what was written and how long it took. An existing output is
//! refused (exit 64). Either output is written whole under a temporary name beside it and takes
//! its name only when complete ([`write_folder`] for the folder): a failed export leaves nothing.

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::time::Instant;

use rotorsweep::dynamics::model::Model;
use rotorsweep::export::model::{write_model, ExportError, Which, Written};
use rotorsweep::export::plant::plant;
use rotorsweep::linear::scene_system::{in_scene, scene_system};
use rotorsweep::scene::source::Source;
use rotorsweep::scene::with_overrides;

use crate::error::CliError;
use crate::speeds;

/// Arguments of `rotorsweep export`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// The model to export: `full` (the FE body, and a scene on it) or `reduced` (the selected
    /// modes).
    #[arg(long, value_parser = ["full", "reduced"], required_unless_present = "state_space", conflicts_with = "state_space")]
    model: Option<String>,
    /// Export the linear plant at `--speed-hz` as a state-space model instead.
    #[arg(long, requires = "speed_hz")]
    state_space: bool,
    /// Spin speed of the plant [Hz].
    #[arg(long)]
    speed_hz: Option<f64>,
    /// Output: a folder for `--model`, a `.h5`, `.npz` or `.mat` file for `--state-space`.
    #[arg(short, long)]
    output: PathBuf,
    /// Modes to keep, "30n+12st" or a list "0-4,7" (default: the scene's).
    #[arg(long)]
    modes: Option<String>,
    /// Override a scene value, `--set roll.shell.elements=60` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Runs `export`.
pub fn run(a: &Args) -> Result<(), CliError> {
    if a.output.exists() {
        return Err(CliError::usage(format!(
            "{}: exists; export writes a new output (remove it first)",
            a.output.display()
        )));
    }
    let ext = a.output.extension().and_then(|e| e.to_str());
    match ext {
        _ if !a.state_space => {}
        Some("h5" | "npz" | "mat") => {}
        _ => {
            return Err(CliError::usage(format!(
                "{}: the plant's file must end in .h5, .npz or .mat",
                a.output.display()
            )))
        }
    };
    let t0 = Instant::now();
    let (scene, model) = Model::load(&a.scene, &a.set, a.modes.as_deref())?;
    if a.state_space {
        let hz = speeds::hz("speed-hz", a.speed_hz.unwrap_or(0.0)).map_err(CliError::input)?;
        let sys = scene_system(&scene, &model)?;
        let p = plant(&sys, hz * std::f64::consts::TAU).map_err(in_scene(&scene))?;
        let io = |e: String| CliError::Io(format!("{}: {e}", a.output.display()).into());
        // Written whole under a temporary name beside the output (removed if the write fails,
        // e.g. a full disk), then linked to the output's name only if that is still free: a
        // failed or concurrent export never leaves a half-written file under the name given.
        let dir = parent_dir(&a.output);
        let tmp = temporary(0o666)
            .suffix(".tmp")
            .tempfile_in(&dir)
            .map_err(|e| cannot_write(&a.output, &dir, &e))?;
        match ext {
            Some("npz") => p.write_npz(tmp.path()).map_err(|e| io(e.to_string()))?,
            Some("mat") => p.write_mat(tmp.path()).map_err(|e| io(e.to_string()))?,
            _ => p.write_h5(tmp.path()).map_err(|e| io(e.to_string()))?,
        }
        tmp.persist_noclobber(&a.output)
            .map_err(|e| io(e.error.to_string()))?;
        println!(
            "{}: plant at {hz} Hz, {} states, {} inputs, {} outputs -> {} in {:.3} s",
            scene.name,
            p.a.nrows(),
            p.b.ncols(),
            p.c.nrows(),
            a.output.display(),
            t0.elapsed().as_secs_f64()
        );
        return Ok(());
    }
    let source = Source::load(&a.scene)?;
    let (table, _) = with_overrides(&source, &a.set)?;
    let which = match a.model.as_deref() {
        Some("reduced") => Which::Reduced,
        _ => Which::Full,
    };
    let w = write_folder(&a.output, |dir| {
        write_model(&scene, &model, &table, which, dir)
    })?;
    println!(
        "{}: {} model, {} DOFs -> {}/ ({}) in {:.3} s",
        scene.name,
        a.model.as_deref().unwrap_or("full"),
        w.dofs,
        a.output.display(),
        w.files.join(", "),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Runs `write` on a temporary folder beside `out` (`.rotorsweep-export-…`, in `out`'s parent,
/// the parents created here if missing) and gives it `out`'s name only when complete and only if
/// that name is still free (renameat2 with RENAME_NOREPLACE), with the permissions of a new
/// folder (0777 less the umask). A failure (a full disk, a file-size limit, a folder not
/// writable, a concurrent export to the same name) removes the temporary folder and every parent
/// created here, so no half-written folder is left under any name, and is an I/O error (exit 74)
/// naming `out` (and the file within it that failed).
fn write_folder(
    out: &Path,
    write: impl FnOnce(&Path) -> Result<Written, ExportError>,
) -> Result<Written, CliError> {
    let parent = parent_dir(out);
    let made = create_parents(&parent).map_err(|e| {
        CliError::Io(format!("{}: cannot create its folder: {e}", out.display()).into())
    })?;
    let result = (|| {
        // mkdir's mode, less the umask: a new folder's permissions, not a temporary's 0700.
        let tmp = temporary(0o777)
            .tempdir_in(&parent)
            .map_err(|e| cannot_write(out, &parent, &e))?;
        let named = |p: &Path| out.join(p.strip_prefix(tmp.path()).unwrap_or(p));
        let w = write(tmp.path()).map_err(|e| {
            let what = match &e {
                ExportError::Io(p, err) => format!("{}: {err}", named(p).display()),
                ExportError::Hdf5(p, err) => format!("{}: {err}", named(p).display()),
                other => other.to_string(),
            };
            CliError::Io(format!("{what} (nothing written: {} not created)", out.display()).into())
        })?;
        let io = |e: std::io::Error| CliError::Io(format!("{}: {e}", out.display()).into());
        rename_noreplace(tmp.path(), out).map_err(io)?;
        // The folder now has the output's name: the temporary's guard must not remove it.
        let _ = tmp.keep();
        Ok(w)
    })();
    if result.is_err() {
        for d in made.iter().rev() {
            let _ = std::fs::remove_dir(d);
        }
    }
    result
}

/// The folder an output `out` is written beside: its parent, or the working folder.
fn parent_dir(out: &Path) -> PathBuf {
    match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A temporary beside the output, under rotorsweep's working prefix, with `mode` (less the
/// umask).
fn temporary(mode: u32) -> tempfile::Builder<'static, 'static> {
    let mut b = tempfile::Builder::new();
    b.prefix(".rotorsweep-export-")
        .permissions(std::fs::Permissions::from_mode(mode));
    b
}

/// The error of a temporary that cannot be made in `dir`: the folder and the OS's reason (the
/// temporary name is not the user's business).
fn cannot_write(out: &Path, dir: &Path, e: &std::io::Error) -> CliError {
    CliError::Io(
        format!(
            "{}: cannot write in the folder {} ({})",
            out.display(),
            dir.display(),
            e.kind()
        )
        .into(),
    )
}

/// Creates the missing folders of `dir`, returning those it created (outermost first).
fn create_parents(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut missing = Vec::new();
    let mut d = Some(dir);
    while let Some(p) = d.filter(|p| !p.as_os_str().is_empty() && !p.exists()) {
        missing.push(p.to_path_buf());
        d = p.parent();
    }
    missing.reverse();
    for (i, p) in missing.iter().enumerate() {
        if let Err(e) = std::fs::create_dir(p) {
            for q in missing[..i].iter().rev() {
                let _ = std::fs::remove_dir(q);
            }
            return Err(e);
        }
    }
    Ok(missing)
}

/// Renames `from` to `to` unless `to` exists (then `AlreadyExists`), atomically.
fn rename_noreplace(from: &Path, to: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        std::ffi::CString::new(p.as_os_str().as_bytes())
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))
    };
    let (f, t) = (c(from)?, c(to)?);
    // SAFETY: two valid NUL-terminated paths, relative to the working folder.
    let r = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            f.as_ptr(),
            libc::AT_FDCWD,
            t.as_ptr(),
            libc::RENAME_NOREPLACE,
        )
    };
    if r == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}
