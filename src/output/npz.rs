//! NumPy's `.npz` files (a zip archive of `.npy` arrays, NumPy's format specification
//! "NEP 1"): float64 matrices and vectors and Unicode string vectors, as `numpy.load` reads
//! them (`allow_pickle` not needed). Written uncompressed.

use nalgebra::DMatrix;
use std::io::Write as _;

/// One array of an archive.
pub enum Array<'a> {
    /// A float64 matrix (rows × columns), written in C order.
    Matrix(&'a DMatrix<f64>),
    /// A float64 vector.
    Vector(&'a [f64]),
    /// A vector of strings (NumPy dtype `<U{longest}`).
    Strings(&'a [String]),
}

/// The `.npy` bytes of `a`: magic, version 1.0, the header dictionary padded to a multiple of
/// 64 bytes, the data little-endian.
fn npy(a: &Array<'_>) -> Vec<u8> {
    let (descr, shape, data): (String, String, Vec<u8>) = match a {
        Array::Matrix(m) => {
            let mut data = Vec::with_capacity(8 * m.len());
            for r in 0..m.nrows() {
                for c in 0..m.ncols() {
                    data.extend_from_slice(&m[(r, c)].to_le_bytes());
                }
            }
            ("<f8".into(), format!("({}, {})", m.nrows(), m.ncols()), data)
        }
        Array::Vector(v) => ("<f8".into(), format!("({},)", v.len()), v.iter().flat_map(|x| x.to_le_bytes()).collect()),
        Array::Strings(v) => {
            let width = v.iter().map(|s| s.chars().count()).max().unwrap_or(0).max(1);
            let mut data = Vec::with_capacity(4 * width * v.len());
            for s in v.iter() {
                let mut k = 0;
                for ch in s.chars() {
                    data.extend_from_slice(&(ch as u32).to_le_bytes());
                    k += 1;
                }
                data.extend(std::iter::repeat_n(0u8, 4 * (width - k)));
            }
            (format!("<U{width}"), format!("({},)", v.len()), data)
        }
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    let unpadded = 10 + header.len() + 1;
    header.extend(std::iter::repeat_n(' ', unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&u16::try_from(header.len()).unwrap_or(u16::MAX).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(&data);
    out
}

/// The bytes of an `.npz` archive of the named arrays (`name.npy` each).
pub fn npz_bytes(arrays: &[(&str, Array<'_>)]) -> Result<Vec<u8>, String> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored).large_file(false);
    for (name, a) in arrays {
        zip.start_file(format!("{name}.npy"), options).map_err(|e| format!("npz: {e}"))?;
        zip.write_all(&npy(a)).map_err(|e| format!("npz: {e}"))?;
    }
    Ok(zip.finish().map_err(|e| format!("npz: {e}"))?.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Headers are padded to 64 bytes and end in a newline; data follow in C order.
    #[test]
    fn npy_layout() {
        let m = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let bytes = npy(&Array::Matrix(&m));
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + header_len) % 64, 0);
        assert_eq!(bytes[10 + header_len - 1], b'\n');
        let first = f64::from_le_bytes(bytes[10 + header_len + 8..10 + header_len + 16].try_into().unwrap());
        assert_eq!(first, 2.0);
        let s = npy(&Array::Strings(&["ab".into(), "c".into()]));
        assert!(String::from_utf8_lossy(&s).contains("'<U2'"));
    }
}
