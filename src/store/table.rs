//! Typed, lossless tables: `/summary` and the `/analysis` tables as HDF5 compound datasets.
//!
//! In: named [`Column`]s of equal length, each float64 numbers, unsigned 64-bit counts or
//! text, with its units. Out: one compound dataset (one record per row) that numpy reads as a
//! structured array and `pandas.DataFrame(f[name][()])` takes directly, with an attribute
//! `units:<column>` per column (`""` for text, `"1"` for counts and other pure numbers).
//!
//! Text is variable-length UTF-8: nothing is cut and no character is dropped. h5py returns
//! variable-length strings inside a compound dataset as `bytes`; decode them with
//! `df[c] = df[c].str.decode("utf-8")` (the Python package `rotorsweep` in `python/` does it
//! for every text column).
//! A NUL character, which C strings cannot hold, is stored as U+2400 (␀).

use std::ffi::CString;

use hdf5::types::{CompoundField, CompoundType, FloatSize, IntSize, TypeDescriptor};
use hdf5::Group;

/// The values of one column.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// float64 values (NaN where a row has none).
    Number(Vec<f64>),
    /// Counts, stored as unsigned 64-bit integers.
    Count(Vec<u64>),
    /// Variable-length UTF-8 text.
    Text(Vec<String>),
}

/// One column of a table: its name, units and values.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Column (field) name.
    pub name: String,
    /// Units of the values (`""` for text).
    pub units: String,
    /// The values, one per row.
    pub values: Values,
}

impl Column {
    /// A float64 column in `units`.
    pub fn number(name: &str, units: &str, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            units: units.into(),
            values: Values::Number(values),
        }
    }

    /// A count column (units "1").
    pub fn count(name: &str, values: Vec<u64>) -> Self {
        Self {
            name: name.into(),
            units: "1".into(),
            values: Values::Count(values),
        }
    }

    /// A text column.
    pub fn text(name: &str, values: Vec<String>) -> Self {
        Self {
            name: name.into(),
            units: String::new(),
            values: Values::Text(values),
        }
    }

    fn len(&self) -> usize {
        match &self.values {
            Values::Number(v) => v.len(),
            Values::Count(v) => v.len(),
            Values::Text(v) => v.len(),
        }
    }
}

/// The units a dotted scene key's name states (`speed.hz` → Hz, `…_mm` → mm), or that the
/// solver keys are documented in (`solver.hmax` [s], `solver.tolerance` [m]); "1" otherwise.
pub fn units_of_key(key: &str) -> &'static str {
    let leaf = key.rsplit('.').next().unwrap_or(key);
    match leaf {
        "hmax" | "hmin" | "h0" => return "s",
        "tolerance" => return "m",
        _ => {}
    }
    const SUFFIXES: [(&str, &str); 16] = [
        ("n_per_m", "N/m"),
        ("ns_per_m", "N s/m"),
        ("n_s_per_m", "N s/m"),
        ("m_s2", "m/s^2"),
        ("hz_per_s", "Hz/s"),
        ("kg_m2", "kg m^2"),
        ("hz", "Hz"),
        ("mm", "mm"),
        ("um", "um"),
        ("deg", "deg"),
        ("rad", "rad"),
        ("kg", "kg"),
        ("g", "g"),
        ("m", "m"),
        ("s", "s"),
        ("n", "N"),
    ];
    SUFFIXES
        .iter()
        .find(|(s, _)| leaf == *s || leaf.ends_with(&format!("_{s}")))
        .map_or("1", |(_, u)| u)
}

/// Writes `columns` as the compound dataset `name` under `group` (module doc). Every column
/// must have the same number of rows.
pub fn compound_table(group: &Group, name: &str, columns: &[Column]) -> hdf5::Result<()> {
    let rows = columns.first().map_or(0, Column::len);
    if let Some(c) = columns.iter().find(|c| c.len() != rows) {
        return Err(hdf5::Error::from(
            format!(
                "table {name}: column {} has {} rows, not {rows}",
                c.name,
                c.len()
            )
            .as_str(),
        ));
    }
    const PTR: usize = std::mem::size_of::<*const std::ffi::c_char>();
    let mut fields = Vec::new();
    let mut offset = 0;
    for (index, c) in columns.iter().enumerate() {
        let (ty, size) = match c.values {
            Values::Number(_) => (TypeDescriptor::Float(FloatSize::U8), 8),
            Values::Count(_) => (TypeDescriptor::Unsigned(IntSize::U8), 8),
            Values::Text(_) => (TypeDescriptor::VarLenUnicode, PTR),
        };
        fields.push(CompoundField {
            name: c.name.clone(),
            ty,
            offset,
            index,
        });
        offset += size;
    }
    let size = offset;
    let desc = TypeDescriptor::Compound(CompoundType { fields, size });
    // The C strings the records point to; they live until the write is done.
    let mut strings: Vec<CString> = Vec::new();
    let mut buf = vec![0u8; size * rows];
    let mut off = 0;
    for c in columns {
        match &c.values {
            Values::Number(v) => {
                for (r, x) in v.iter().enumerate() {
                    buf[r * size + off..r * size + off + 8].copy_from_slice(&x.to_ne_bytes());
                }
                off += 8;
            }
            Values::Count(v) => {
                for (r, x) in v.iter().enumerate() {
                    buf[r * size + off..r * size + off + 8].copy_from_slice(&x.to_ne_bytes());
                }
                off += 8;
            }
            Values::Text(v) => {
                for (r, s) in v.iter().enumerate() {
                    let cs = CString::new(s.replace('\0', "\u{2400}"))
                        .expect("NUL characters were replaced");
                    let p = cs.as_ptr() as usize;
                    strings.push(cs);
                    buf[r * size + off..r * size + off + PTR].copy_from_slice(&p.to_ne_bytes());
                }
                off += PTR;
            }
        }
    }
    let dtype = hdf5::Datatype::from_descriptor(&desc)?;
    let ds = group
        .new_dataset_builder()
        .empty_as(dtype.clone())
        .shape(rows)
        .create(name)?;
    for c in columns {
        super::attr_str(&ds, &format!("units:{}", c.name), &c.units)?;
    }
    if rows == 0 {
        return Ok(());
    }
    let written = hdf5::sync::sync(|| {
        // SAFETY: the buffer holds `rows` packed records laid out exactly as `dtype` describes
        // (offsets computed above; text fields hold pointers to NUL-terminated UTF-8 strings
        // owned by `strings`, alive until after this call), and the dataset has `rows`
        // elements of that type. `h5check` takes the error stack while the lock is held.
        hdf5::h5check(unsafe {
            hdf5_sys::h5d::H5Dwrite(
                ds.id(),
                dtype.id(),
                hdf5_sys::h5s::H5S_ALL,
                hdf5_sys::h5s::H5S_ALL,
                hdf5_sys::h5p::H5P_DEFAULT,
                buf.as_ptr().cast(),
            )
        })
    });
    drop(strings);
    written?;
    Ok(())
}
