//! A linear analysis of one scene as a results file: what `rotorsweep linear -o OUT.h5` writes.
//!
//! In: the output path (claimed by the caller, `store::output::claim`), the [`Scene`], its
//! [`Results`] and the command line. Out: `OUT.h5` in a study's layout with one group,
//! `/linear/<scene name>`: [`Results::write`] with the wall times (the layout of a study's
//! `/linear/<id>` plus what `rotorsweep report` and the figures draw); root attributes as every
//! results file has them (`store::create_file`, the scene's text as `scene_text`). Written
//! under `OUT.h5.tmp` and renamed when complete; on failure the temporary file is removed and
//! the error is [`OutputError::Write`] with the cause as the HDF5 library and the OS gave it.

use std::path::Path;

use crate::linear::request::Results;
use crate::scene::Scene;
use crate::store::{self, output::OutputError};

/// Writes `r`, the linear analysis of `scene`, to `path` (module doc).
pub fn write(path: &Path, scene: &Scene, r: &Results, command: &str) -> Result<(), OutputError> {
    let text = std::fs::read_to_string(&scene.source).unwrap_or_default();
    let write = || -> Result<(), String> {
        let (file, jobs) = store::create_file(path, command, &text).map_err(|e| e.to_string())?;
        let g =
            store::subgroup(&file, &format!("linear/{}", scene.name)).map_err(|e| e.to_string())?;
        r.write(&g, true).map_err(|e| e.to_string())?;
        store::finish_file(path, file, jobs).map_err(|e| e.to_string())
    };
    write().map_err(|e| {
        let _ = std::fs::remove_file(store::with_suffix(path, ".tmp"));
        OutputError::Write(path.to_path_buf(), e)
    })
}
