//! HDF5 results: one group per job, chunked and compressed datasets with `units` attributes.
//!
//! In: [`JobResult`]s and the parameters that made them. Out: an HDF5 file that h5py reads:
//!
//! ```text
//! /                      attrs: tool, tool_version, created_utc, host, command, scene_text
//! /jobs/<id>/            attrs: status, cause, modes, coordinates, integrator, the solver
//!                        statistics (steps, rejected_steps, …, cpu_time_s, wall_time_s),
//!                        lift_off_s (NaN if none), and each parameter under its dotted key
//! /jobs/<id>/time        [s]
//! /jobs/<id>/runout/<sensor>/{vertical,horizontal}   [um]
//! /jobs/<id>/journal/<node>/{x,y}  /stand/<node>/{x,y}  [um]
//! /jobs/<id>/contact/<node>/<roller>  [N]     /modal/<i>  [kg^0.5 m]
//! ```
//! Strings are variable-length UTF-8 (h5py returns `str` for attributes, `bytes` for the items
//! of a string dataset, `.asstr()` makes them `str`, and of a compound table, see [`table`]). Every dataset has a `units`
//! attribute (`""` for text). Datasets are chunked (≤ 8192 samples), shuffled and deflated
//! (level 4). The axes are HDF5 dimension scales ([`scales`]): `time` is attached to every
//! sampled channel and hard-linked into each channel group (`runout/<sensor>/time`).

pub mod linear;
pub mod output;
pub mod scales;
pub mod summary;
pub mod table;

use std::path::Path;
use std::str::FromStr;

use hdf5::types::VarLenUnicode;
use hdf5::{File, Group, Location};

use crate::dynamics::simulation::JobResult;

pub use summary::write_summary;
pub use table::{compound_table, units_of_key, Column};

/// Writes a string attribute (variable-length UTF-8).
pub fn attr_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v =
        VarLenUnicode::from_str(value).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    loc.new_attr::<VarLenUnicode>()
        .shape(())
        .create(name)?
        .write_scalar(&v)
}

/// Writes a float attribute.
pub fn attr_f64(loc: &Location, name: &str, value: f64) -> hdf5::Result<()> {
    loc.new_attr::<f64>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

/// Writes an integer attribute.
pub fn attr_u64(loc: &Location, name: &str, value: u64) -> hdf5::Result<()> {
    loc.new_attr::<u64>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

/// Datasets of at most this many values are stored compact (in their object header, not
/// compressed): deflating a short record saves a few hundred bytes and costs more than the
/// job that made it (each compressed dataset sets up a zlib stream and a chunk index; on 0.1 s
/// Jeffcott jobs, whose datasets hold 4 to 101 values, that was a third of the saving's CPU).
pub const COMPACT_VALUES: usize = 1024;

/// Writes a 1-D float dataset (compact up to [`COMPACT_VALUES`], else chunked, shuffled and
/// deflated) with a `units` attribute, creating the intermediate groups of a path-like name.
pub fn dataset(group: &Group, name: &str, data: &[f64], units: &str) -> hdf5::Result<()> {
    let (parent, leaf) = match name.rsplit_once('/') {
        Some((p, l)) => (subgroup(group, p)?, l),
        None => (group.clone(), name),
    };
    let mut b = parent.new_dataset_builder();
    if data.len() > COMPACT_VALUES {
        b = b.chunk(data.len().min(8192)).shuffle().deflate(4);
    } else if !data.is_empty() {
        b = b.layout(hdf5::plist::dataset_create::Layout::Compact);
    }
    let ds = b.with_data(data).create(leaf)?;
    attr_str(&ds, "units", units)
}

/// Writes a 2-D float dataset `rows × cols` (row-major `data`; compact up to
/// [`COMPACT_VALUES`], else deflated) with a `units` attribute.
pub fn dataset_2d(
    group: &Group,
    name: &str,
    (rows, cols): (usize, usize),
    data: &[f64],
    units: &str,
) -> hdf5::Result<()> {
    let (parent, leaf) = match name.rsplit_once('/') {
        Some((p, l)) => (subgroup(group, p)?, l),
        None => (group.clone(), name),
    };
    let arr = ndarray::ArrayView2::from_shape((rows, cols), data)
        .map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    let mut b = parent.new_dataset_builder();
    if rows * cols > COMPACT_VALUES {
        b = b.chunk((rows, cols)).shuffle().deflate(4);
    } else if rows * cols > 0 {
        b = b.layout(hdf5::plist::dataset_create::Layout::Compact);
    }
    let ds = b.with_data(arr).create(leaf)?;
    attr_str(&ds, "units", units)
}

/// The runout channels of a job group: ("sensor/direction", samples [µm]), in file order.
pub fn runout_channels(g: &Group) -> Vec<(String, Vec<f64>)> {
    let mut out = Vec::new();
    let Ok(r) = g.group("runout") else {
        return out;
    };
    for sensor in r.member_names().unwrap_or_default() {
        let Ok(sg) = r.group(&sensor) else { continue };
        for dir in sg.member_names().unwrap_or_default() {
            if let Ok(ds) = sg.dataset(&dir) {
                if scales::is_scale(&ds) {
                    continue; // the `time` axis linked beside the channels
                }
                if let Ok(v) = ds.read_raw::<f64>() {
                    out.push((format!("{sensor}/{dir}"), v));
                }
            }
        }
    }
    out
}

/// Opens or creates a nested group `a/b/c` under `group`.
pub fn subgroup(group: &Group, path: &str) -> hdf5::Result<Group> {
    let mut g = group.clone();
    for part in path.split('/').filter(|p| !p.is_empty()) {
        g = match g.group(part) {
            Ok(x) => x,
            Err(_) => g.create_group(part)?,
        };
    }
    Ok(g)
}

/// A parameter value stored as an attribute.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Param {
    /// A number.
    Number(f64),
    /// A count (an index), stored as an unsigned integer.
    Count(u64),
    /// A string.
    Text(String),
}

impl Param {
    /// A scene value as stored: numbers (and booleans as 0/1) as numbers, strings as written,
    /// anything else as its TOML text.
    pub fn from_toml(v: &toml::Value) -> Self {
        match v {
            toml::Value::Float(x) => Param::Number(*x),
            toml::Value::Integer(i) => Param::Number(*i as f64),
            toml::Value::Boolean(b) => Param::Number(f64::from(u8::from(*b))),
            toml::Value::String(s) => Param::Text(s.clone()),
            other => Param::Text(other.to_string()),
        }
    }
}

/// As text: a number in Rust's shortest round-trip form, a string as it is.
impl std::fmt::Display for Param {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Param::Number(x) => write!(f, "{x}"),
            Param::Count(n) => write!(f, "{n}"),
            Param::Text(t) => f.write_str(t),
        }
    }
}

/// Writes one job's group: status, statistics, parameters and datasets.
pub fn write_job(
    parent: &Group,
    id: &str,
    params: &[(String, Param)],
    integrator: &str,
    r: &JobResult,
) -> hdf5::Result<()> {
    let g = parent.create_group(id)?;
    let s = &r.stats;
    attr_str(&g, "status", s.status.name())?;
    attr_str(&g, "cause", &s.cause)?;
    attr_str(&g, "modes", &r.modes)?;
    attr_str(&g, "integrator", integrator)?;
    attr_u64(&g, "coordinates", r.coordinates as u64)?;
    attr_f64(&g, "t_end_s", s.t_end_s)?;
    attr_u64(&g, "steps", s.steps)?;
    attr_u64(&g, "rejected_steps", s.rejected())?;
    attr_u64(&g, "rejected_error", s.rejected_error)?;
    attr_u64(&g, "rejected_convergence", s.rejected_convergence)?;
    attr_u64(&g, "newton_iterations", s.newton_iterations)?;
    attr_f64(&g, "iterations_per_step", s.iterations_per_step())?;
    attr_u64(&g, "jacobian_evals", s.jacobian_evals)?;
    attr_u64(&g, "factorizations", s.factorizations)?;
    attr_u64(&g, "rhs_evals", s.rhs_evals)?;
    attr_u64(&g, "events", s.events)?;
    attr_f64(&g, "cpu_time_s", s.cpu_time_s)?;
    attr_f64(&g, "wall_time_s", s.wall_time_s)?;
    attr_f64(&g, "lift_off_s", r.lift_off_s.unwrap_or(f64::NAN))?;
    for (k, v) in params {
        match v {
            Param::Number(x) => attr_f64(&g, k, *x)?,
            Param::Count(n) => attr_u64(&g, k, *n)?,
            Param::Text(t) => attr_str(&g, k, t)?,
        }
    }
    dataset(&g, "time", &r.time, "s")?;
    for c in &r.channels {
        dataset(&g, &c.name, &c.data, c.units)?;
    }
    write_fields(&g, r)?;
    scales::attach_axis(&g, "time", &[""], 0)?;
    Ok(())
}

/// A job's fields ([rows × time], a nip's segment forces): each with its row axis beside it,
/// attached as dimension 0, and the job's `time` as dimension 1.
fn write_fields(g: &Group, r: &JobResult) -> hdf5::Result<()> {
    for f in &r.fields {
        let rows = f.axis_values.len();
        dataset_2d(g, &f.name, (rows, r.time.len()), &f.data, f.units)?;
        let parent = f.name.rsplit_once('/').map_or("", |(p, _)| p);
        let pg = if parent.is_empty() {
            g.clone()
        } else {
            g.group(parent)?
        };
        if !pg.link_exists(f.axis) {
            dataset(&pg, f.axis, &f.axis_values, f.axis_units)?;
        }
        scales::attach_axis(&pg, f.axis, &[""], 0)?;
    }
    if let Some(f) = r.fields.first() {
        let top = f.name.split_once('/').map_or("", |(t, _)| t);
        scales::attach_axis(g, "time", &[top], 1)?;
    }
    Ok(())
}

/// The provenance attributes of every results file: tool, tool_version, created_utc, host and
/// the command line.
pub fn provenance(f: &File, command: &str) -> hdf5::Result<()> {
    attr_str(f, "tool", "rotorsweep")?;
    attr_str(f, "tool_version", env!("CARGO_PKG_VERSION"))?;
    attr_str(f, "created_utc", &utc_now())?;
    attr_str(f, "host", &hostname())?;
    attr_str(f, "command", command)
}

/// Creates a results file with its provenance attributes and an empty `jobs` group. The file is
/// written to `path` + ".tmp" and renamed by [`finish_file`], so a crash leaves no half file
/// under the final name. The caller holds the output's lock and has checked that `path` may be
/// replaced ([`output`]).
pub fn create_file(path: &Path, command: &str, scene_text: &str) -> hdf5::Result<(File, Group)> {
    let part = with_suffix(path, ".tmp");
    let f = File::create(&part)?;
    provenance(&f, command)?;
    attr_str(&f, "scene_text", scene_text)?;
    let jobs = f.create_group("jobs")?;
    Ok((f, jobs))
}

/// Creates the HDF5 file `path`, fills it with `body` and closes it, reporting a write that
/// fails only at the final flush or close (a full disk, a file-size limit): HDF5 defers those
/// writes, and a file merely dropped would hide their errors. `body`'s handles are dropped
/// before the flush, so the close is real.
pub fn write_closed(path: &Path, body: impl FnOnce(&File) -> hdf5::Result<()>) -> hdf5::Result<()> {
    let f = File::create(path)?;
    body(&f)?;
    f.flush()?;
    f.close()
}

/// Closes the file and moves it to its final name ([`rename_verified`]).
pub fn finish_file(path: &Path, file: File, jobs: Group) -> std::io::Result<()> {
    drop(jobs);
    file.flush()
        .map_err(|e| std::io::Error::other(e.to_string()))?;
    file.close()
        .map_err(|e| std::io::Error::other(e.to_string()))?;
    rename_verified(path)
}

/// Moves the closed working file `path` + ".tmp" to `path`, once it reads back
/// (`output::verify_written`): a write that failed at the end (disk full) is an error, not a
/// renamed broken file.
pub fn rename_verified(path: &Path) -> std::io::Result<()> {
    let tmp = with_suffix(path, ".tmp");
    output::verify_written(&tmp).map_err(|why| {
        std::io::Error::other(format!(
            "{}: {why}: the write failed (disk full or a file-size limit?)",
            tmp.display()
        ))
    })?;
    std::fs::rename(tmp, path)
}

/// `path` with `suffix` appended to its file name (`out.h5` → `out.h5.part`).
pub fn with_suffix(path: &Path, suffix: &str) -> std::path::PathBuf {
    let mut p = path.as_os_str().to_owned();
    p.push(suffix);
    p.into()
}

/// The host name (from /proc or the environment), or "unknown".
pub fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|s| s.trim().to_string())
        .ok()
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// Current UTC time as ISO 8601 (from the system clock, no time-zone database needed).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let (days, rem) = (secs / 86_400, secs % 86_400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        (rem % 3600) / 60,
        rem % 60
    )
}

/// Reads a string attribute (variable-length UTF-8).
pub fn read_str(loc: &Location, name: &str) -> hdf5::Result<String> {
    Ok(loc.attr(name)?.read_scalar::<VarLenUnicode>()?.to_string())
}

/// Reads a numeric attribute as f64 (floats and integers).
pub fn read_num(loc: &Location, name: &str) -> hdf5::Result<f64> {
    use hdf5::types::TypeDescriptor as T;
    let a = loc.attr(name)?;
    Ok(match a.dtype()?.to_descriptor()? {
        T::Unsigned(_) => a.read_scalar::<u64>()? as f64,
        T::Integer(_) => a.read_scalar::<i64>()? as f64,
        _ => a.read_scalar::<f64>()?,
    })
}

/// The file's varying keys (its `varying_keys` attribute, one per line); none when absent.
pub fn varying_keys(f: &File) -> Vec<String> {
    read_str(f, "varying_keys")
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.is_empty())
        .map(str::to_string)
        .collect()
}

/// A parameter attribute as it was written: number or text.
pub fn read_param(loc: &Location, name: &str) -> hdf5::Result<Param> {
    use hdf5::types::TypeDescriptor as T;
    let a = loc.attr(name)?;
    Ok(match a.dtype()?.to_descriptor()? {
        T::VarLenUnicode | T::VarLenAscii | T::FixedAscii(_) | T::FixedUnicode(_) => {
            Param::Text(read_str(loc, name)?)
        }
        T::Unsigned(_) | T::Integer(_) => Param::Count(read_num(loc, name)? as u64),
        _ => Param::Number(read_num(loc, name)?),
    })
}

/// Writes a 1-D dataset of strings (variable-length UTF-8) with the `units` attribute `""`.
pub fn string_dataset(group: &Group, name: &str, items: &[String]) -> hdf5::Result<()> {
    let v: Vec<VarLenUnicode> = items
        .iter()
        .map(|s| VarLenUnicode::from_str(s).unwrap_or_default())
        .collect();
    let ds = group.new_dataset_builder().with_data(&v).create(name)?;
    attr_str(&ds, "units", "")
}

/// Deep-copies the object `src_name` under `src` to `dst_name` under `dst` (HDF5's H5Ocopy):
/// datasets keep their chunking, filters and bytes, and their dimension scales
/// ([`scales::reattach_copy`]: H5Ocopy alone leaves them pointing into the source file).
pub fn copy_object(
    src: &Location,
    src_name: &str,
    dst: &Location,
    dst_name: &str,
) -> hdf5::Result<()> {
    let (a, b) = (
        std::ffi::CString::new(src_name).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?,
        std::ffi::CString::new(dst_name).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?,
    );
    hdf5::sync::sync(|| {
        // SAFETY: both ids are open HDF5 locations owned by the callers; the names are valid
        // NUL-terminated strings; the library lock is held by `sync`. `h5check` takes the
        // library's error stack (with the OS error of a failed write) while the lock is held.
        hdf5::h5check(unsafe {
            hdf5_sys::h5o::H5Ocopy(
                src.id(),
                a.as_ptr(),
                dst.id(),
                b.as_ptr(),
                hdf5_sys::h5p::H5P_DEFAULT,
                hdf5_sys::h5p::H5P_DEFAULT,
            )
        })
    })?;
    scales::reattach_copy(src, src_name, dst, dst_name)
}
