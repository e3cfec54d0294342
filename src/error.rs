//! Input errors: every problem with a user's file names the file, the line, the key and the reason.
//!
//! In: a path, an optional 1-based line, an optional dotted key, and a reason.
//! Out: an error whose `Display` reads `FILE:LINE: key `KEY`: REASON`, ready for the CLI.

use std::fmt::{self, Write as _};
use std::path::{Path, PathBuf};

/// A problem with an input file (scene, study, thickness map): where it is and why.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file the problem is in (or `<command line>` for `--set` values).
    pub file: PathBuf,
    /// 1-based line number, when the problem can be pinned to a line.
    pub line: Option<usize>,
    /// Dotted key of the offending value (`roll.shell.wall_thickness_mm`), when there is one.
    pub key: Option<String>,
    /// What is wrong, in words a user can act on.
    pub reason: String,
}

impl InputError {
    /// An error in `file` with a reason and no location yet.
    pub fn new(file: &Path, reason: impl Into<String>) -> Self {
        Self {
            file: file.to_path_buf(),
            line: None,
            key: None,
            reason: reason.into(),
        }
    }

    /// The same error pinned to a 1-based line.
    pub fn at_line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    /// The same error attributed to a dotted key.
    pub fn with_key(mut self, key: impl Into<String>) -> Self {
        self.key = Some(key.into());
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ":")?;
        if let Some(key) = &self.key {
            write!(f, " key `")?;
            shown(f, key)?;
            write!(f, "`:")?;
        }
        write!(f, " ")?;
        shown(f, &self.reason)
    }
}

/// Writes `text` (a key or reason, which may quote what a user wrote) with its control
/// characters escaped (`\u{7f}`), so an invisible one is seen; line breaks and tabs are kept.
fn shown(f: &mut fmt::Formatter<'_>, text: &str) -> fmt::Result {
    for c in text.chars() {
        if c.is_control() && c != '\n' && c != '\t' {
            write!(f, "{}", c.escape_default())?;
        } else {
            f.write_char(c)?;
        }
    }
    Ok(())
}

impl std::error::Error for InputError {}

/// 1-based line number of a byte offset in `text`.
pub fn line_of_offset(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// What a TOML text is, for the hint when a file is given to the wrong command: `"study"` when
/// it names a `scene` and has none of a scene's own tables, `"scene"` when it has a `roll`,
/// `rotor`, `supports` or `extends` and no `scene`; `None` otherwise (or when it is not TOML).
pub fn toml_kind(text: &str) -> Option<&'static str> {
    let t: toml::Table = toml::from_str(text).ok()?;
    let has = |k: &str| t.contains_key(k);
    let scene_like = has("roll") || has("rotor") || has("supports") || has("extends");
    match (has("scene"), scene_like) {
        (true, false) => Some("study"),
        (false, true) => Some("scene"),
        _ => None,
    }
}

/// Longest name that becomes an HDF5 group (a sensor's), in characters.
pub const MAX_NAME_CHARS: usize = 64;

/// Checks a name that becomes an HDF5 group (a sensor's, under `runout/`): 1 to
/// [`MAX_NAME_CHARS`] letters, digits, `_`, `-` and `.`, starting with a letter, digit or `_`.
/// So never empty, `.` or `..` (HDF5 paths), nor with a `/` (a deeper group), a space or a
/// control character.
pub fn safe_name(name: &str) -> Result<(), String> {
    let ok_char = |c: char| c.is_alphanumeric() || matches!(c, '_' | '-' | '.');
    let first_ok = name
        .chars()
        .next()
        .is_some_and(|c| c.is_alphanumeric() || c == '_');
    if first_ok && name.chars().all(ok_char) && name.chars().count() <= MAX_NAME_CHARS {
        return Ok(());
    }
    Err(format!(
        "the name {name:?} is not a safe identifier (it names an HDF5 group): 1 to \
         {MAX_NAME_CHARS} letters, digits, `_`, `-` or `.`, starting with a letter, digit or `_`"
    ))
}

/// The largest input file read (scenes, studies, maps): 64 MiB, far above any real one.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Reads an input file as text, like `std::fs::read_to_string`, but only a regular file of at
/// most [`MAX_INPUT_BYTES`]: a FIFO would block, and `/dev/zero` would fill the memory.
/// Text that is not UTF-8 is refused naming the line (1-based) of the first byte that is not.
pub fn read_text(path: &Path) -> std::io::Result<String> {
    read_text_up_to(path, MAX_INPUT_BYTES)
}

/// [`read_text`] with another size limit (large FE matrix files).
pub fn read_text_up_to(path: &Path, max_bytes: u64) -> std::io::Result<String> {
    regular_file(path, max_bytes)?;
    String::from_utf8(std::fs::read(path)?).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let line = bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("line {line}: not UTF-8 text (byte {} of the file)", at + 1),
        )
    })
}

/// Checks, before anything opens it, that `path` is a regular file of at most `max_bytes`
/// (opening a FIFO blocks until a writer comes; a directory or device is no input file).
pub fn regular_file(path: &Path, max_bytes: u64) -> std::io::Result<()> {
    let m = std::fs::metadata(path)?;
    if !m.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file (a directory, device or FIFO)",
        ));
    }
    if m.len() > max_bytes {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{} bytes: larger than the {} MiB an input file may have",
                m.len(),
                max_bytes >> 20
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A control character a user wrote (here DEL, U+007F, in a study's string value) is shown
    /// escaped, so `bd\u{7f}f` is not printed as an apparent `bdf`; line breaks stay.
    #[test]
    fn control_characters_of_a_message_are_shown_escaped() {
        let e = InputError::new(Path::new("s.toml"), "`bd\u{7f}f`: expected bdf\nsee docs")
            .with_key("solver.integr\u{1b}ator");
        assert_eq!(
            e.to_string(),
            "s.toml: key `solver.integr\\u{1b}ator`: `bd\\u{7f}f`: expected bdf\nsee docs"
        );
    }
}
