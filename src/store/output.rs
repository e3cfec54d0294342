//! Output files: what a command may replace, and one writer per output.
//!
//! In: the output path a user named (`-o OUT.h5`) and whether `--overwrite` was given.
//! Out: an [`OutputLock`] held for the command's lifetime, and a verdict on the existing path.
//!
//! Rules, the same for every command that writes (`run`, `merge`, `simulate`, `report -o`):
//! - A path that does not exist may be written. An existing one is refused unless
//!   `--overwrite` is given, and even then it must be a regular file that is a rotorsweep
//!   results file (HDF5 with the root attribute `tool = "rotorsweep"`), or for a text output
//!   ([`write_text`], the HTML report) a text file that carries that output's marker. A
//!   directory, a device, a FIFO, a symbolic link, or a file from elsewhere is never replaced.
//! - The new file is written under `OUT.h5.tmp` and renamed over `OUT.h5` only when complete,
//!   so the old file stays intact until then.
//! - One writer per output: an advisory exclusive lock on `OUT.h5.lock` (`File::try_lock`,
//!   which is `flock` on Linux), taken before anything is checked or written and released by
//!   the kernel when the process ends, however it ends. A second process fails at once with
//!   the holder's PID (written into the lock file).
//!   `OUT.h5.lock`, `OUT.h5.tmp` and `OUT.h5.parts/` are rotorsweep's working names beside
//!   the output.
//!
//! Every OS error names its path.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::os::unix::fs::{FileTypeExt, MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

/// Why an output cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output exists and `--overwrite` was not given.
    #[error("{0}: exists; add --overwrite to replace it (only a file rotorsweep wrote is replaced), or choose another -o")]
    Exists(PathBuf),
    /// The output is something that is never replaced.
    #[error("{0}: {1}; refusing to replace it")]
    Refused(PathBuf, String),
    /// Another process holds the output.
    #[error("{path}: in use by another rotorsweep process ({holder}; lock {lock}); wait for it to finish or choose another -o")]
    Busy {
        /// The output.
        path: PathBuf,
        /// "PID n" or what is known of the holder.
        holder: String,
        /// The lock file.
        lock: PathBuf,
    },
    /// An OS error on a path.
    #[error("{0}: {1}")]
    Io(PathBuf, std::io::Error),
    /// Writing the output failed (the cause as the HDF5 library and the OS gave it).
    #[error("{0}: {1}")]
    Write(PathBuf, String),
}

/// An I/O error with its path.
pub fn io_at(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |e| OutputError::Io(path.to_path_buf(), e)
}

/// What kind of thing a path is, in words; `None` when nothing is there.
fn describe(path: &Path) -> Result<Option<(std::fs::Metadata, &'static str)>, OutputError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) => {
            let ft = m.file_type();
            let what = if ft.is_file() {
                "a regular file"
            } else if ft.is_dir() {
                "a directory"
            } else if ft.is_symlink() {
                "a symbolic link (name the file itself)"
            } else if ft.is_char_device() {
                "a character device"
            } else if ft.is_block_device() {
                "a block device"
            } else if ft.is_fifo() {
                "a FIFO"
            } else if ft.is_socket() {
                "a socket"
            } else {
                "not a regular file"
            };
            Ok(Some((m, what)))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(OutputError::Io(path.to_path_buf(), e)),
    }
}

/// The HDF5 file signature (its first 8 bytes).
pub const HDF5_SIGNATURE: [u8; 8] = [0x89, b'H', b'D', b'F', b'\r', b'\n', 0x1a, b'\n'];

/// Whether a regular file is a rotorsweep results file; the reason when it is not.
pub fn is_results_file(path: &Path) -> Result<(), String> {
    open_results_file(path).map(drop)
}

/// A rotorsweep results file, opened (a regular file, HDF5 signature, then `tool =
/// "rotorsweep"`); the reason when it is not one. Opening a FIFO would block (`balance`,
/// `report --compare` and `merge` read their inputs through here); no size bound, as HDF5 reads
/// only the datasets asked for.
pub fn open_results_file(path: &Path) -> Result<hdf5::File, String> {
    crate::error::regular_file(path, u64::MAX).map_err(|e| format!("cannot be read: {e}"))?;
    let mut head = [0u8; 8];
    let n = File::open(path)
        .and_then(|mut f| f.read(&mut head))
        .map_err(|e| format!("cannot be read ({e})"))?;
    if n < 8 || head != HDF5_SIGNATURE {
        return Err("is not an HDF5 file".into());
    }
    let f = hdf5::File::open(path).map_err(|e| format!("is not a readable HDF5 file ({e})"))?;
    match super::read_str(&f, "tool") {
        Ok(t) if t == "rotorsweep" => Ok(f),
        _ => Err(
            "is an HDF5 file but not a rotorsweep results file (no `tool = rotorsweep` attribute)"
                .into(),
        ),
    }
}

/// Checks that `path` may be (re)written as an output: absent, or with `overwrite` a regular
/// rotorsweep results file (module doc). Its parent directory must exist.
pub fn check_replace(path: &Path, overwrite: bool) -> Result<(), OutputError> {
    check_replace_as(path, overwrite, is_results_file)
}

/// Whether the first 4 KiB of a regular file hold `marker`; the reason when not.
fn has_marker(path: &Path, marker: &str) -> Result<(), String> {
    let mut head = Vec::new();
    File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .map_err(|e| format!("cannot be read ({e})"))?;
    let text = String::from_utf8_lossy(&head);
    if text.contains(marker) {
        Ok(())
    } else {
        Err(format!(
            "is not a file rotorsweep wrote (no `{marker}` in its first 4 KiB)"
        ))
    }
}

/// [`check_replace`] for a text output that carries `marker` ([`write_text`]).
pub fn check_replace_text(path: &Path, overwrite: bool, marker: &str) -> Result<(), OutputError> {
    check_replace_as(path, overwrite, |p| has_marker(p, marker))
}

/// Writes a text output whole (the HTML report): the output's lock, then `path` checked (absent,
/// or with `overwrite` a regular file whose first 4 KiB hold `marker`, which `text` must hold
/// too), then `text` written to `path` + ".tmp" (absent, empty or ours), synced and renamed
/// over `path`. Nothing is left under either name on failure.
pub fn write_text(
    path: &Path,
    overwrite: bool,
    marker: &str,
    text: &str,
) -> Result<(), OutputError> {
    let _lock = OutputLock::acquire(path)?;
    check_replace_text(path, overwrite, marker)?;
    let tmp = super::with_suffix(path, ".tmp");
    match describe(&tmp)? {
        None => {}
        Some((m, _))
            if m.file_type().is_file() && (m.len() == 0 || has_marker(&tmp, marker).is_ok()) => {}
        Some((_, what)) => {
            return Err(OutputError::Refused(
                tmp,
                format!("is {what} rotorsweep did not write, where it keeps a working file"),
            ))
        }
    }
    let write = || -> std::io::Result<()> {
        let mut f = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o644)
            .custom_flags(libc::O_NOFOLLOW)
            .open(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()
    };
    if let Err(e) = write() {
        let _ = std::fs::remove_file(&tmp);
        return Err(OutputError::Io(tmp, e));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        OutputError::Io(path.to_path_buf(), e)
    })
}

/// [`check_replace`] with `own` judging whether an existing regular file may be replaced.
fn check_replace_as(
    path: &Path,
    overwrite: bool,
    own: impl Fn(&Path) -> Result<(), String>,
) -> Result<(), OutputError> {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match describe(parent)? {
        Some((m, _)) if m.is_dir() => {}
        Some((_, what)) => {
            return Err(OutputError::Refused(
                parent.to_path_buf(),
                format!("the output's folder is {what}"),
            ))
        }
        None => {
            return Err(OutputError::Io(
                parent.to_path_buf(),
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "the output's folder does not exist",
                ),
            ))
        }
    }
    match describe(path)? {
        None => Ok(()),
        Some((m, what)) if !m.file_type().is_file() => Err(OutputError::Refused(
            path.to_path_buf(),
            format!("is {what}"),
        )),
        Some(_) if !overwrite => Err(OutputError::Exists(path.to_path_buf())),
        Some(_) => own(path).map_err(|why| OutputError::Refused(path.to_path_buf(), why)),
    }
}

/// Whether a regular file could be a leftover of rotorsweep's own writing: empty, or starting
/// with the HDF5 signature (a killed write leaves at least that).
pub fn is_own_leftover(path: &Path) -> bool {
    let mut head = [0u8; 8];
    match File::open(path).and_then(|mut f| f.read(&mut head)) {
        Ok(0) => true,
        Ok(n) => n == 8 && head == HDF5_SIGNATURE,
        Err(_) => false,
    }
}

/// Checks that a working file of ours (`OUT.h5.tmp`, a part's `.tmp`) may be written: absent,
/// or a regular file that is empty or HDF5 (a leftover of a killed run, replaced under the
/// lock). Anything else there is a user's file and is refused.
pub fn check_working_file(path: &Path) -> Result<(), OutputError> {
    check_working_file_of(path, is_own_leftover)
}

/// [`check_working_file`] for a working file of another format, `own` saying whether a
/// regular file there is a leftover of rotorsweep's writing.
pub fn check_working_file_of(path: &Path, own: fn(&Path) -> bool) -> Result<(), OutputError> {
    match describe(path)? {
        None => Ok(()),
        Some((m, _)) if m.file_type().is_file() && own(path) => Ok(()),
        Some((m, _)) if m.file_type().is_file() => Err(OutputError::Refused(
            path.to_path_buf(),
            "is a file rotorsweep did not write, where it keeps a working file".into(),
        )),
        Some((_, what)) => Err(OutputError::Refused(
            path.to_path_buf(),
            format!("is {what}, where rotorsweep keeps a working file"),
        )),
    }
}

/// Reads back a file just written before it is renamed into place: every group's attributes,
/// members and every dataset header must read (a write that failed late, at the final flush,
/// leaves a file whose heaps do not). Listing a group's attributes decodes each attribute's
/// message (from the object header, or from the fractal heap where a group has many), which
/// is what opening each would read again: opening them cost half of this check's time. The
/// data themselves are not read again: a failed data write already fails the flush. The error
/// says what could not be read.
pub fn verify_written(path: &Path) -> Result<(), String> {
    fn walk(g: &hdf5::Group) -> hdf5::Result<()> {
        g.attr_names()?;
        for name in g.member_names()? {
            if let Ok(sub) = g.group(&name) {
                walk(&sub)?;
            } else {
                g.dataset(&name)?.dtype()?;
            }
        }
        Ok(())
    }
    let f = hdf5::File::open(path).map_err(|e| format!("cannot be read back ({e})"))?;
    if super::read_str(&f, "tool").ok().as_deref() != Some("rotorsweep") {
        return Err("reads back without its `tool` attribute".into());
    }
    walk(&f).map_err(|e| format!("cannot be read back ({e})"))
}

/// Claims a single-file output for a command that writes it whole (`simulate`, `linear`):
/// takes its lock, then checks that it may be replaced and that its working file `OUT.h5.tmp`
/// may be written. Called before any work, so a refused or busy output costs nothing.
pub fn claim(path: &Path, overwrite: bool) -> Result<OutputLock, OutputError> {
    let lock = OutputLock::acquire(path)?;
    check_replace(path, overwrite)?;
    check_working_file(&super::with_suffix(path, ".tmp"))?;
    Ok(lock)
}

/// The lock file of an output.
pub fn lock_path(output: &Path) -> PathBuf {
    super::with_suffix(output, ".lock")
}

/// An exclusive advisory lock on an output, held until dropped (or the process ends).
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
}

impl OutputLock {
    /// Takes the lock of `output` (module doc), or fails at once naming the holder.
    pub fn acquire(output: &Path) -> Result<Self, OutputError> {
        let path = lock_path(output);
        loop {
            if let Some((m, what)) = describe(&path)? {
                if !m.file_type().is_file() {
                    return Err(OutputError::Refused(
                        path.clone(),
                        format!("is {what}, where rotorsweep keeps the output's lock file"),
                    ));
                }
                // A lock file holds a PID or nothing: anything else is a user's file.
                let text = std::fs::read(&path).map_err(io_at(&path))?;
                let ours = text.len() <= 24
                    && std::str::from_utf8(&text)
                        .is_ok_and(|t| t.trim().is_empty() || t.trim().parse::<u32>().is_ok());
                if !ours {
                    return Err(OutputError::Refused(
                        path.clone(),
                        "is a file rotorsweep did not write, where it keeps the output's lock file"
                            .into(),
                    ));
                }
            }
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .mode(0o644)
                .custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC)
                .open(&path)
                .map_err(io_at(&path))?;
            // Non-blocking exclusive lock (flock on Unix): WouldBlock when another process holds it.
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    let mut text = String::new();
                    let _ = file.read_to_string(&mut text);
                    let holder = match text.trim().parse::<u32>() {
                        Ok(pid) => format!("PID {pid}"),
                        Err(_) => "PID unknown".to_string(),
                    };
                    return Err(OutputError::Busy {
                        path: output.to_path_buf(),
                        holder,
                        lock: path,
                    });
                }
                Err(std::fs::TryLockError::Error(e)) => return Err(OutputError::Io(path, e)),
            }
            // The file we locked must still be the one under the name: a holder that was just
            // finishing may have removed it between our open and our lock.
            let ours = file.metadata().map_err(io_at(&path))?;
            match std::fs::symlink_metadata(&path) {
                Ok(now) if now.dev() == ours.dev() && now.ino() == ours.ino() => {}
                _ => continue,
            }
            file.set_len(0).map_err(io_at(&path))?;
            file.rewind().map_err(io_at(&path))?;
            writeln!(file, "{}", std::process::id()).map_err(io_at(&path))?;
            return Ok(Self { file, path });
        }
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Remove the name while still holding the lock; a process that opened it meanwhile
        // sees the name gone (or another file) after locking and starts again.
        let _ = std::fs::remove_file(&self.path);
        // Closing the file (when `self.file` drops) would release the lock anyway.
        let _ = self.file.unlock();
    }
}
