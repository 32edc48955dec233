//! NumPy `.npy` arrays (format versions 1.0–3.0), so `numpy.load` opens our output.
//!
//! Written by hand: the format is a short text header and raw data, and we need
//! precise errors for wrong dtypes and shapes. Spec: numpy.org/devdocs/reference/
//! generated/numpy.lib.format.html.
//!
//! - Height fields are 2-D arrays of shape `(ny, nx)`, row j = grid row j, written
//!   as `<f8` (or `<f4` on request). Read: any float or integer dtype of either
//!   byte order, C or Fortran order; a 1-D array `(n,)` is a line scan (profile).
//! - Point sets are `(N, 3)` arrays of `<f8`.

use std::io::Write;

use crate::bytes::Fields;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: &[u8] = b"\x93NUMPY";

/// A decoded array in C order, converted to `f64`.
pub(crate) struct NpyArray {
    pub shape: Vec<usize>,
    pub data: Vec<f64>,
}

fn dict_value<'a>(header: &'a str, key: &str) -> FResult<&'a str> {
    let k = format!("'{key}'");
    let at = header
        .find(&k)
        .ok_or_else(|| FormatError::Malformed(format!("header has no {k}")))?;
    let rest = header[at + k.len()..].trim_start();
    let rest = rest
        .strip_prefix(':')
        .ok_or_else(|| FormatError::Malformed(format!("header: no ':' after {k}")))?;
    Ok(rest.trim_start())
}

/// An array's element type: byte order, kind (`f`, `i`, `u`, `b`) and size.
struct Dtype {
    big: bool,
    kind: u8,
    size: usize,
}

/// Parses an `.npy` file into an f64 array.
pub(crate) fn read(bytes: &[u8]) -> FResult<NpyArray> {
    let (header, body) = split_header(bytes)?;
    let descr = dict_value(header, "descr")?;
    let descr = descr
        .get(1..)
        .and_then(|d| d.split(['\'', '"']).next())
        .unwrap_or("");
    let fortran = dict_value(header, "fortran_order")?.starts_with("True");
    let shape = shape(dict_value(header, "shape")?)?;
    let dtype = dtype(descr)?;
    let count = shape
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| FormatError::Malformed("shape too large".into()))?;
    let need = count
        .checked_mul(dtype.size)
        .ok_or_else(|| FormatError::Malformed("shape too large".into()))?;
    if body.len() < need {
        return malformed(format!(
            "shape {shape:?} of {descr} needs {need} data bytes but the file has {} (truncated)",
            body.len()
        ));
    }
    let mut data: Vec<f64> = body[..need]
        .chunks_exact(dtype.size)
        .map(|chunk| value(&dtype, chunk))
        .collect();
    if fortran && shape.len() > 1 {
        data = fortran_to_c(&data, &shape);
    }
    Ok(NpyArray { shape, data })
}

/// The header's text and the bytes after it.
fn split_header(bytes: &[u8]) -> FResult<(&str, &[u8])> {
    if !bytes.starts_with(MAGIC) || bytes.len() < 10 {
        return malformed("missing the \\x93NUMPY magic");
    }
    let f = Fields::le(bytes);
    let truncated = |_| FormatError::Malformed("truncated header".into());
    let (hlen, start) = match bytes[6] {
        1 => (usize::from(f.u16(8).map_err(truncated)?), 10),
        2 | 3 => (f.u32(8).map_err(truncated)? as usize, 12),
        v => return malformed(format!("unsupported format version {v}")),
    };
    let hbytes = f.bytes(start, hlen).map_err(truncated)?;
    let header = std::str::from_utf8(hbytes)
        .map_err(|_| FormatError::Malformed("header is not text".into()))?;
    Ok((header, &bytes[start + hlen..]))
}

/// The `shape` tuple's entries.
fn shape(text: &str) -> FResult<Vec<usize>> {
    let inner = text
        .strip_prefix('(')
        .and_then(|s| s.split(')').next())
        .ok_or_else(|| FormatError::Malformed("bad shape".into()))?;
    inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse()
                .map_err(|_| FormatError::Malformed(format!("bad shape entry {s:?}")))
        })
        .collect()
}

/// The element type a `descr` names (`<f8`, `>i2`, `|u1`…), if asperity
/// reads it.
fn dtype(descr: &str) -> FResult<Dtype> {
    let b = descr.as_bytes();
    if b.len() < 3 {
        return malformed(format!("unsupported dtype {descr:?}"));
    }
    // `get`: a non-ASCII descr has no character boundary at byte 2.
    let size = descr.get(2..).and_then(|t| t.parse::<usize>().ok()).unwrap_or(0);
    let (order, kind) = (b[0], b[1]);
    let big = match order {
        b'<' | b'|' | b'=' => false,
        b'>' => true,
        _ => return malformed(format!("unsupported dtype {descr:?}")),
    };
    let supported = matches!(
        (kind, size),
        (b'f', 4 | 8) | (b'i' | b'u', 1 | 2 | 4 | 8) | (b'b', 1)
    );
    if !supported {
        return malformed(format!(
            "dtype {descr:?} is not supported; use float32 or float64 (integer and bool arrays are also read)"
        ));
    }
    Ok(Dtype { big, kind, size })
}

/// One element as f64.
fn value(dtype: &Dtype, chunk: &[u8]) -> f64 {
    let size = dtype.size;
    let mut a = [0u8; 8];
    a[..size].copy_from_slice(chunk);
    if dtype.big {
        a[..size].reverse();
    }
    match (dtype.kind, size) {
        (b'f', 4) => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        (b'f', _) => f64::from_le_bytes(a),
        (b'i', 1) => a[0] as i8 as f64,
        (b'i', 2) => i16::from_le_bytes([a[0], a[1]]) as f64,
        (b'i', 4) => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        (b'i', _) => i64::from_le_bytes(a) as f64,
        (b'u', 1) | (b'b', _) => a[0] as f64,
        (b'u', 2) => u16::from_le_bytes([a[0], a[1]]) as f64,
        (b'u', 4) => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
        _ => u64::from_le_bytes(a) as f64,
    }
}

fn fortran_to_c(data: &[f64], shape: &[usize]) -> Vec<f64> {
    let n = shape.len();
    let mut out = vec![0.0; data.len()];
    let mut idx = vec![0usize; n];
    for v in out.iter_mut() {
        // idx is the C-order multi-index of this output element.
        let mut f = 0;
        let mut stride = 1;
        for (a, &i) in idx.iter().enumerate() {
            f += i * stride;
            stride *= shape[a];
        }
        *v = data[f];
        for a in (0..n).rev() {
            idx[a] += 1;
            if idx[a] < shape[a] {
                break;
            }
            idx[a] = 0;
        }
    }
    out
}

/// Element type written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NpyDtype {
    /// `<f4`
    Float32,
    /// `<f8`
    Float64,
}

fn header(shape: &[usize], descr: &str) -> (u8, String) {
    let shape_txt = match shape {
        [n] => format!("({n},)"),
        s => format!(
            "({})",
            s.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape_txt}, }}");
    // Pad with spaces so magic + version + length + header + '\n' is a multiple of 64.
    let (version, len_bytes) = if header.len() + 11 > u16::MAX as usize {
        (2u8, 4)
    } else {
        (1u8, 2)
    };
    let unpadded = MAGIC.len() + 2 + len_bytes + header.len() + 1;
    header.extend(std::iter::repeat_n(' ', (64 - unpadded % 64) % 64));
    header.push('\n');
    (version, header)
}

fn write_header(w: &mut dyn Write, shape: &[usize], descr: &str) -> std::io::Result<()> {
    let (version, header) = header(shape, descr);
    w.write_all(MAGIC)?;
    w.write_all(&[version, 0])?;
    if version == 1 {
        w.write_all(&(header.len() as u16).to_le_bytes())?;
    } else {
        w.write_all(&(header.len() as u32).to_le_bytes())?;
    }
    w.write_all(header.as_bytes())
}

/// Writes a C-order `uint8` array.
pub(crate) fn write_u8(w: &mut dyn Write, shape: &[usize], data: &[u8]) -> std::io::Result<()> {
    write_header(w, shape, "|u1")?;
    w.write_all(data)
}

/// Writes a C-order array of `shape` from `values`.
pub(crate) fn write(
    w: &mut dyn Write,
    shape: &[usize],
    values: &[f64],
    dtype: NpyDtype,
) -> std::io::Result<()> {
    let descr = match dtype {
        NpyDtype::Float32 => "<f4",
        NpyDtype::Float64 => "<f8",
    };
    write_header(w, shape, descr)?;
    let mut buf = Vec::with_capacity(1 << 16);
    for chunk in values.chunks(8192) {
        buf.clear();
        for &v in chunk {
            match dtype {
                NpyDtype::Float32 => buf.extend_from_slice(&(v as f32).to_le_bytes()),
                NpyDtype::Float64 => buf.extend_from_slice(&v.to_le_bytes()),
            }
        }
        w.write_all(&buf)?;
    }
    Ok(())
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NumPy .npy",
    extensions: &["npy"],
    points: Access::ReadWrite,
    height: Access::ReadWrite,
    notes: "height (ny, nx) <f8 (or <f4), missing points NaN; points (N, 3) <f8; reads any float/int dtype",
    magic: Magic::Starts(&[b"\x93NUMPY"]),
    codec: Some(Codec::new(|b, _| crate::npy_height(read(b)?))),
    read: Some(crate::npy_surface),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn file(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let h = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}\n",
            if fortran { "True" } else { "False" }
        );
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&[1, 0]);
        out.extend_from_slice(&(h.len() as u16).to_le_bytes());
        out.extend_from_slice(h.as_bytes());
        out.extend_from_slice(data);
        out
    }

    #[test]
    fn dtypes_orders_and_errors() {
        let a = read(&file(">i2", false, "(2, 2)", &[0, 1, 0, 2, 255, 255, 0, 4])).unwrap();
        assert_eq!(a.data, vec![1.0, 2.0, -1.0, 4.0]);
        // Fortran order: column-major [[1, 2], [3, 4]] is stored 1 3 2 4.
        let a = read(&file("|u1", true, "(2, 2)", &[1, 3, 2, 4])).unwrap();
        assert_eq!(a.data, vec![1.0, 2.0, 3.0, 4.0]);
        let FormatError::Malformed(m) = read(&file("<c16", false, "(1,)", &[0; 16])).err().unwrap()
        else {
            panic!()
        };
        assert!(m.contains("\"<c16\" is not supported"), "{m}");
        let FormatError::Malformed(m) = read(&file("<U3", false, "(1,)", &[0; 12])).err().unwrap()
        else {
            panic!()
        };
        assert!(m.contains("not supported"), "{m}");
        let FormatError::Malformed(m) =
            read(&file("<f8", false, "(3, 2)", &[0; 40])).err().unwrap()
        else {
            panic!()
        };
        assert!(m.contains("needs 48 data bytes"), "{m}");
        assert!(read(b"\x93NUMPY").is_err());
    }

    #[test]
    fn header_is_aligned_and_roundtrips() {
        let mut out = Vec::new();
        write(
            &mut out,
            &[2, 3],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5],
            NpyDtype::Float64,
        )
        .unwrap();
        assert_eq!((out.len() - 48) % 64, 0);
        let a = read(&out).unwrap();
        assert_eq!(a.shape, vec![2, 3]);
        assert_eq!(a.data[5], 6.5);
    }
}
