//! HDF5 dimension scales: the axes (`time` [s], `freq_hz` [Hz], `speed_hz` [Hz], …) attached to
//! the datasets sampled along them, so that netCDF readers label the arrays without rotorsweep's
//! Python package (`xarray.open_dataset(path, group="jobs/<id>/runout/centre",
//! engine="h5netcdf")` gives `vertical` and `horizontal` over a `time` coordinate).
//!
//! In: a group holding a 1-D axis dataset and, below it, datasets whose dimension `dim` runs
//! along that axis. Out: the axis marked as a dimension scale named after itself (HDF5's
//! high-level H5DS library: `CLASS = "DIMENSION_SCALE"`, `NAME`, `REFERENCE_LIST`), attached
//! to dimension `dim` of every dataset below whose length there equals the axis's
//! (`DIMENSION_LIST`), and hard-linked under its own name into every group holding such a
//! dataset: a netCDF group sees only its own variables, so `runout/centre/time` is the same
//! dataset as `time` (a second name, not a copy). A dataset of another length is left without
//! that axis: never a wrong one.
//!
//! H5Ocopy does not translate object references nested in variable-length or compound
//! attributes (`DIMENSION_LIST`, `REFERENCE_LIST`), so a copy into another file points into
//! the source. [`reattach_copy`] rebuilds the copy's attachments from the source's.

use std::ffi::{c_char, c_int, c_uint, c_void, CString};

use hdf5::{Dataset, Group, Location};
use hdf5_sys::h5::{herr_t, htri_t};
use hdf5_sys::h5i::hid_t;

// The HDF5 high-level library (hdf5-sys feature "hl"); hdf5-sys declares only the core API.
extern "C" {
    fn H5DSset_scale(dsid: hid_t, dimname: *const c_char) -> herr_t;
    fn H5DSattach_scale(did: hid_t, dsid: hid_t, idx: c_uint) -> herr_t;
    fn H5DSis_scale(did: hid_t) -> htri_t;
    fn H5DSget_scale_name(did: hid_t, name: *mut c_char, size: usize) -> isize;
    fn H5DSiterate_scales(
        did: hid_t,
        dim: c_uint,
        idx: *mut c_int,
        visitor: extern "C" fn(hid_t, c_uint, hid_t, *mut c_void) -> herr_t,
        visitor_data: *mut c_void,
    ) -> herr_t;
}

fn err(msg: String) -> hdf5::Error {
    hdf5::Error::from(msg.as_str())
}

/// Whether `ds` is a dimension scale (an axis, possibly hard-linked next to its data).
pub fn is_scale(ds: &Dataset) -> bool {
    // SAFETY: `ds` is an open dataset id; the library lock is held by `sync`.
    hdf5::sync::sync(|| unsafe { H5DSis_scale(ds.id()) }) > 0
}

fn set_scale(ds: &Dataset, name: &str) -> hdf5::Result<()> {
    if is_scale(ds) {
        return Ok(());
    }
    let c = CString::new(name).map_err(|e| err(e.to_string()))?;
    // SAFETY: an open dataset id and a NUL-terminated name; the lock is held by `sync`, and
    // `h5check` takes the error stack under it.
    hdf5::sync::sync(|| hdf5::h5check(unsafe { H5DSset_scale(ds.id(), c.as_ptr()) })).map(|_| ())
}

fn attach(ds: &Dataset, scale: &Dataset, dim: usize) -> hdf5::Result<()> {
    let dim = c_uint::try_from(dim).map_err(|e| err(e.to_string()))?;
    // SAFETY: two open dataset ids of one file; the lock is held by `sync`.
    hdf5::sync::sync(|| hdf5::h5check(unsafe { H5DSattach_scale(ds.id(), scale.id(), dim) }))
        .map(|_| ())
}

/// Makes `group/axis` a dimension scale and attaches it as dimension `dim` of every dataset
/// under `group/u` for each `u` of `under` (`""` is `group` itself, a dataset is that dataset;
/// a missing one is skipped) whose length along `dim` is the axis's (module doc). Returns how
/// many datasets it labels.
pub fn attach_axis(group: &Group, axis: &str, under: &[&str], dim: usize) -> hdf5::Result<usize> {
    let scale = group.dataset(axis)?;
    let n = scale.shape().first().copied().unwrap_or(0);
    set_scale(&scale, axis)?;
    fn walk(
        g: &Group,
        top: bool,
        axis: &str,
        scale: &Dataset,
        n: usize,
        dim: usize,
    ) -> hdf5::Result<usize> {
        let mut here = 0;
        let mut below = 0;
        for name in g.member_names()? {
            if let Ok(sub) = g.group(&name) {
                below += walk(&sub, false, axis, scale, n, dim)?;
            } else if let Ok(ds) = g.dataset(&name) {
                if is_scale(&ds) || ds.shape().get(dim) != Some(&n) {
                    continue;
                }
                attach(&ds, scale, dim)?;
                here += 1;
            }
        }
        if here > 0 && !top && !g.link_exists(axis) {
            g.link_hard(&scale.name(), axis)?;
        }
        Ok(here + below)
    }
    let mut labelled = 0;
    for u in under {
        let target = if u.is_empty() {
            group.clone()
        } else if let Ok(g) = group.group(u) {
            g
        } else if let Ok(ds) = group.dataset(u) {
            // A dataset beside the axis (a sweep's job_ids along speed_hz).
            if ds.shape().get(dim) == Some(&n) {
                attach(&ds, &scale, dim)?;
                labelled += 1;
            }
            continue;
        } else {
            continue;
        };
        labelled += walk(&target, u.is_empty(), axis, &scale, n, dim)?;
    }
    Ok(labelled)
}

/// The names of the scales attached to each dimension of `ds` (one per dimension; `None` where
/// none is attached).
fn scale_names(ds: &Dataset) -> hdf5::Result<Vec<Option<String>>> {
    extern "C" fn visit(_did: hid_t, _dim: c_uint, scale: hid_t, data: *mut c_void) -> herr_t {
        let mut buf = [0 as c_char; 256];
        // SAFETY: `scale` is the open scale id HDF5 passes in; `buf` holds 256 bytes and the
        // library writes at most that many, NUL-terminated. `data` is the `Option<String>` the
        // caller below passed.
        let len = unsafe { H5DSget_scale_name(scale, buf.as_mut_ptr(), buf.len()) };
        if len > 0 {
            let name = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) };
            let out = unsafe { &mut *data.cast::<Option<String>>() };
            *out = Some(name.to_string_lossy().into_owned());
        }
        1 // stop at the first scale: rotorsweep attaches one per dimension
    }
    let mut out = Vec::new();
    for dim in 0..ds.ndim() {
        let mut name: Option<String> = None;
        let d = c_uint::try_from(dim).map_err(|e| err(e.to_string()))?;
        hdf5::sync::sync(|| {
            // SAFETY: an open dataset id, the visitor above and a pointer to `name`, which
            // outlives the call; the lock is held by `sync`.
            hdf5::h5check(unsafe {
                H5DSiterate_scales(
                    ds.id(),
                    d,
                    std::ptr::null_mut(),
                    visit,
                    (&mut name as *mut Option<String>).cast(),
                )
            })
        })?;
        out.push(name);
    }
    Ok(out)
}

/// Rebuilds the dimension-scale attachments of `dst_name` under `dst`, a copy (H5Ocopy) of
/// `src_name` under `src`: each dataset of the copy gets, on each dimension, the scale of the
/// source's name hard-linked in its own group (module doc), and the copied reference attributes
/// that point into the source are removed first.
pub fn reattach_copy(
    src: &Location,
    src_name: &str,
    dst: &Location,
    dst_name: &str,
) -> hdf5::Result<()> {
    // (group path relative to the copied object, dataset name, scale name per dimension)
    type Found = (String, String, Vec<Option<String>>);
    fn collect(g: &Group, rel: &str, out: &mut Vec<Found>) -> hdf5::Result<()> {
        for name in g.member_names()? {
            if let Ok(sub) = g.group(&name) {
                collect(&sub, &format!("{rel}{name}/"), out)?;
            } else if let Ok(ds) = g.dataset(&name) {
                if is_scale(&ds) {
                    continue;
                }
                let names = scale_names(&ds)?;
                if names.iter().any(Option::is_some) {
                    out.push((rel.to_string(), name, names));
                }
            }
        }
        Ok(())
    }
    let open = |loc: &Location, name: &str| -> hdf5::Result<Option<Group>> {
        let path = format!("{}/{name}", loc.name().trim_end_matches('/'));
        let file = loc.file()?;
        Ok(file.group(&path).ok())
    };
    let (Some(sg), Some(dg)) = (open(src, src_name)?, open(dst, dst_name)?) else {
        return Ok(()); // a dataset or a group without scales below
    };
    let mut found = Vec::new();
    collect(&sg, "", &mut found)?;
    let scale_of = |rel: &str, name: &str| -> hdf5::Result<Dataset> {
        dg.dataset(&format!("{rel}{name}")).map_err(|e| {
            err(format!(
                "{}/{rel}: the copy has no axis {name} beside its data ({e})",
                dg.name()
            ))
        })
    };
    for (rel, name, scales) in &found {
        let ds = dg.dataset(&format!("{rel}{name}"))?;
        if ds.attr_names()?.iter().any(|a| a == "DIMENSION_LIST") {
            ds.delete_attr("DIMENSION_LIST")?;
        }
        for s in scales.iter().flatten() {
            let sc = scale_of(rel, s)?;
            if sc.attr_names()?.iter().any(|a| a == "REFERENCE_LIST") {
                sc.delete_attr("REFERENCE_LIST")?;
            }
        }
    }
    for (rel, name, scales) in &found {
        let ds = dg.dataset(&format!("{rel}{name}"))?;
        for (dim, s) in scales.iter().enumerate() {
            if let Some(s) = s {
                attach(&ds, &scale_of(rel, s)?, dim)?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> std::path::PathBuf {
        let d =
            std::env::temp_dir().join(format!("rotorsweep-scales-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A job-like group: `time` [4], two channels of 4 samples in `runout/a`, one of 3 (no axis).
    fn job(g: &Group) {
        crate::store::dataset(g, "time", &[0.0, 0.1, 0.2, 0.3], "s").unwrap();
        crate::store::dataset(g, "runout/a/vertical", &[1.0, 2.0, 3.0, 4.0], "um").unwrap();
        crate::store::dataset(g, "runout/a/horizontal", &[5.0, 6.0, 7.0, 8.0], "um").unwrap();
        crate::store::dataset(g, "runout/a/short", &[1.0, 2.0, 3.0], "um").unwrap();
    }

    /// The two 4-sample channels of `runout/a` carry the axis `time`; the 3-sample one none.
    fn attached(a: &Group) {
        for name in ["vertical", "horizontal"] {
            let names = scale_names(&a.dataset(name).unwrap()).unwrap();
            assert_eq!(names, vec![Some("time".into())], "{name}");
        }
        assert_eq!(
            scale_names(&a.dataset("short").unwrap()).unwrap(),
            vec![None]
        );
    }

    #[test]
    fn attached_linked_and_kept_through_a_copy_into_another_file() {
        let d = dir("copy");
        let src = hdf5::File::create(d.join("a.h5")).unwrap();
        let g = src.create_group("job").unwrap();
        job(&g);
        // Two of the three channels have the axis's length; the third gets none.
        assert_eq!(attach_axis(&g, "time", &[""], 0).unwrap(), 2);
        let a = g.group("runout/a").unwrap();
        assert!(
            is_scale(&a.dataset("time").unwrap()),
            "time is linked beside its data"
        );
        attached(&a);
        // Into another file: H5Ocopy alone would leave references into a.h5 (unreadable there).
        let dst = hdf5::File::create(d.join("b.h5")).unwrap();
        let jobs = dst.create_group("jobs").unwrap();
        crate::store::copy_object(&src, "job", &jobs, "j1").unwrap();
        drop((a, g, src));
        let b = jobs.group("j1/runout/a").unwrap();
        attached(&b);
        // The linked time is the copy's own time (one object): 4 samples, 0.3 s last.
        let t: Vec<f64> = b.dataset("time").unwrap().read_raw().unwrap();
        assert_eq!(t, vec![0.0, 0.1, 0.2, 0.3]);
        drop((b, jobs, dst));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
