//! A MATLAB Level 5 MAT-file writer: real double matrices and cell arrays of strings, as the
//! linear plant needs them (MATLAB `load`, `scipy.io.loadmat`).
//!
//! In: named variables ([`Var`]: a real matrix [any units, the caller's], or a column cell array
//! of strings). Out: the bytes of a MAT-file (little-endian, uncompressed).
//! Method: the documented Level 5 format (MathWorks, "MAT-File Format", version 7 and earlier,
//! matfile_format.pdf: "Level 5 MAT-File Format"): a 128-byte header (116 bytes of descriptive
//! text, 8 bytes of subsystem offset, zero; version 0x0100; the endian indicator "IM"), then one
//! data element per variable: an 8-byte tag (data type, byte count) and its data padded to a
//! multiple of 8 bytes. A variable is an miMATRIX (14) element holding the array flags
//! (miUINT32: the class, mxDOUBLE_CLASS 6, mxCHAR_CLASS 4 or mxCELL_CLASS 1), the dimensions
//! (miINT32), the name (miINT8) and the data: miDOUBLE (9) values in column-major order; for a
//! character array its UTF-16 code units as miUINT16 (4), as MATLAB writes them; for a cell
//! array each cell an miMATRIX element with an empty name, column-major. No maintained Rust
//! crate writes this format (the `matfile` crate reads only), hence this file.

/// A variable of a MAT-file.
pub enum Var<'a> {
    /// A real matrix: rows, columns, values in column-major order.
    Matrix(usize, usize, &'a [f64]),
    /// A column cell array (n × 1) of character row vectors.
    Strings(&'a [String]),
}

const MI_INT8: u32 = 1;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_DOUBLE: u32 = 9;
const MI_MATRIX: u32 = 14;
const MX_CELL: u32 = 1;
const MX_CHAR: u32 = 4;
const MX_DOUBLE: u32 = 6;

/// An element: tag, data, padding to 8 bytes.
fn element(out: &mut Vec<u8>, kind: u32, data: &[u8]) {
    out.extend_from_slice(&kind.to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    out.resize(out.len() + (8 - data.len() % 8) % 8, 0);
}

/// An miMATRIX element of class `class`, dimensions `dims`, name `name`, then `body` (the
/// data's elements, already encoded).
fn matrix(out: &mut Vec<u8>, class: u32, dims: [usize; 2], name: &str, body: &[u8]) {
    let mut m = Vec::new();
    let mut flags = class.to_le_bytes().to_vec();
    flags.extend_from_slice(&[0; 4]);
    element(&mut m, MI_UINT32, &flags);
    let d: Vec<u8> = dims
        .iter()
        .flat_map(|&x| (x as i32).to_le_bytes())
        .collect();
    element(&mut m, MI_INT32, &d);
    element(&mut m, MI_INT8, name.as_bytes());
    m.extend_from_slice(body);
    element(out, MI_MATRIX, &m);
}

fn string(out: &mut Vec<u8>, s: &str) {
    let units: Vec<u16> = s.encode_utf16().collect();
    let data: Vec<u8> = units.iter().flat_map(|u| u.to_le_bytes()).collect();
    let mut body = Vec::new();
    element(&mut body, MI_UINT16, &data);
    matrix(out, MX_CHAR, [1, units.len()], "", &body);
}

/// The MAT-file of `vars` (name, variable), `text` the header's description (cut to 116
/// bytes).
pub fn mat_file(text: &str, vars: &[(&str, Var)]) -> Vec<u8> {
    let mut out = text.as_bytes()[..text.len().min(116)].to_vec();
    out.resize(116, b' ');
    out.extend_from_slice(&[0; 8]);
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for (name, v) in vars {
        match v {
            Var::Matrix(r, c, values) => {
                assert_eq!(r * c, values.len(), "matrix size");
                let data: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
                let mut body = Vec::new();
                element(&mut body, MI_DOUBLE, &data);
                matrix(&mut out, MX_DOUBLE, [*r, *c], name, &body);
            }
            Var::Strings(items) => {
                let mut body = Vec::new();
                for s in items.iter() {
                    string(&mut body, s);
                }
                matrix(&mut out, MX_CELL, [items.len(), 1], name, &body);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bytes of a 1 × 1 double `x = 2.5` by the format's layout (header, then tag 14 with
    /// 56 bytes: flags 16, dims 16, name "x" 16, data 16 bytes).
    #[test]
    fn a_scalar_has_the_documented_layout() {
        let b = mat_file("MATLAB 5.0 MAT-file", &[("x", Var::Matrix(1, 1, &[2.5]))]);
        assert_eq!(b.len(), 128 + 8 + 64);
        assert_eq!(&b[124..128], &[0x00, 0x01, b'I', b'M']);
        let u32_at = |i: usize| u32::from_le_bytes(b[i..i + 4].try_into().unwrap());
        assert_eq!((u32_at(128), u32_at(132)), (14, 64));
        assert_eq!((u32_at(136), u32_at(140), u32_at(144)), (6, 8, 6));
        assert_eq!(
            (u32_at(152), u32_at(156), u32_at(160), u32_at(164)),
            (5, 8, 1, 1)
        );
        assert_eq!((u32_at(168), u32_at(172), b[176]), (1, 1, b'x'));
        assert_eq!((u32_at(184), u32_at(188)), (9, 8));
        assert_eq!(f64::from_le_bytes(b[192..200].try_into().unwrap()), 2.5);
    }
}
