//! Scratch folders for tests: each a fresh temporary folder (the `tempfile` crate) that is
//! removed when the test lets go of it, also when the test fails.

use std::ops::Deref;
use std::path::Path;

/// A fresh, empty folder under the system temp dir, removed on drop; derefs to its path.
pub struct Scratch(tempfile::TempDir);

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A fresh scratch folder whose name starts with `rotorsweep-{name}-`.
pub fn scratch(name: &str) -> Scratch {
    Scratch(
        tempfile::Builder::new()
            .prefix(&format!("rotorsweep-{name}-"))
            .tempdir()
            .expect("create a scratch folder"),
    )
}
