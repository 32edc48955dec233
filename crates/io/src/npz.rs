//! NumPy archives (`.npz`, as `numpy.savez` and `numpy.savez_compressed`
//! write them), read: a zip of `.npy` members, every two-dimensional array a
//! channel named by its member (without `.npy`), in the archive's order (as
//! SurfaceTopography and Gwyddion's `npyfile.c` list them).
//!
//! Each array is read as asperity reads an `.npy` ([`crate::npy`]): shape
//! (ny, nx), grid row j the array's row j — so `numpy.load(f)["name"]` is the
//! same array `asperity convert` writes to `.npy`. SurfaceTopography takes
//! the first index along x instead: its heights are this field transposed.
//! No sizes or units are stored: the step is 1 and the numbers unitless.
//!
//! Every member is inflated to at most the size the archive's directory
//! declares for it, and the memory estimate counts those
//! sizes before anything is inflated.

use asperity_core::HeightField;

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::npy;
use crate::zipped::{self, Archive};
use crate::format::{Access, Codec, Registration};

fn bad(e: String) -> FormatError {
    FormatError::Malformed(format!("not a readable NumPy archive: {e}"))
}

fn open(bytes: &[u8]) -> FResult<Archive<'_>> {
    zipped::open(bytes, bad)
}

/// Member `k`, inflated to at most its declared size.
fn member(zip: &mut Archive<'_>, k: usize) -> FResult<(String, Vec<u8>)> {
    zipped::by_index(zip, k, bad)
}

/// The archive's two-dimensional arrays: member index and channel name.
fn arrays(zip: &mut Archive<'_>) -> FResult<Vec<(usize, String)>> {
    let mut out = Vec::new();
    for k in 0..zip.len() {
        let (name, bytes) = member(zip, k)?;
        let Some(stem) = name.strip_suffix(".npy") else {
            continue;
        };
        // Members that are no readable array are not channels, as in ST.
        if npy::read(&bytes).is_ok_and(|a| a.shape.len() == 2) {
            out.push((k, stem.to_owned()));
        }
    }
    if out.is_empty() {
        return malformed("the archive holds no two-dimensional .npy array");
    }
    Ok(out)
}

/// The archive's 2-D arrays as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let mut zip = open(bytes)?;
    Ok(arrays(&mut zip)?
        .into_iter()
        .enumerate()
        .map(|(index, (_, name))| ChannelInfo {
            index,
            name,
            height: true,
        })
        .collect())
}

/// Reads the array `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let mut zip = open(bytes)?;
    let list = arrays(&mut zip)?;
    let infos: Vec<ChannelInfo> = list
        .iter()
        .enumerate()
        .map(|(index, (_, name))| ChannelInfo {
            index,
            name: name.clone(),
            height: true,
        })
        .collect();
    let (k, _) = &list[pick(&infos, choice)?];
    let (_, data) = member(&mut zip, *k)?;
    let a = npy::read(&data)?;
    let [ny, nx] = a.shape[..] else {
        return malformed(format!("shape {:?} is not two-dimensional", a.shape));
    };
    Ok(HeightField::from_vec([nx, ny], a.data)?)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NumPy archive (.npz)",
    extensions: &["npz"],
    height: Access::Read,
    notes: "numpy.savez / savez_compressed: every two-dimensional array a channel by name, each read as an .npy (shape (ny, nx); SurfaceTopography takes the first index along x); no sizes or units: step 1, unitless",
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .declared(crate::zipped::declared_twice)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Cursor;
    use std::io::Write;

    use super::*;

    fn npy_bytes(shape: &str, data: &[f64]) -> Vec<u8> {
        let mut h = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
        h.push_str(&" ".repeat(63 - (10 + h.len()) % 64));
        h.push('\n');
        let mut b = b"\x93NUMPY\x01\x00".to_vec();
        b.extend((h.len() as u16).to_le_bytes());
        b.extend(h.as_bytes());
        b.extend(data.iter().flat_map(|v| v.to_le_bytes()));
        b
    }

    fn archive(members: &[(&str, Vec<u8>)], deflate: bool) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let method = if deflate {
            zip::CompressionMethod::Deflated
        } else {
            zip::CompressionMethod::Stored
        };
        let opts = zip::write::SimpleFileOptions::default().compression_method(method);
        for (name, data) in members {
            zip.start_file(*name, opts).unwrap();
            zip.write_all(data).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    #[test]
    fn two_dimensional_arrays_are_channels_in_the_archive_order() {
        for deflate in [false, true] {
            let f = archive(
                &[
                    (
                        "b.npy",
                        npy_bytes("(2, 3)", &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
                    ),
                    ("line.npy", npy_bytes("(4,)", &[0.0; 4])),
                    ("notes.txt", b"not an array".to_vec()),
                    ("a.npy", npy_bytes("(1, 2)", &[7.0, 8.0])),
                ],
                deflate,
            );
            let names: Vec<String> = channels(&f).unwrap().into_iter().map(|c| c.name).collect();
            assert_eq!(names, ["b", "a"]);
            let h = read_channel(&f, None).unwrap();
            assert_eq!((h.dims(), h.row(1)), ([3, 2], &[4.0, 5.0, 6.0][..]));
            let a = read_channel(&f, Some(&Channel::parse("a"))).unwrap();
            assert_eq!(a.data(), &[7.0, 8.0]);
            assert!(crate::zipped::declared_bytes(&f).unwrap() > 48);
        }
    }

    #[test]
    fn truncated_archives_and_archives_without_arrays_are_refused() {
        let f = archive(&[("z.npy", npy_bytes("(2, 2)", &[1.0; 4]))], true);
        for cut in [0, 10, f.len() / 2, f.len() - 1] {
            assert!(read_channel(&f[..cut], None).is_err(), "cut at {cut}");
        }
        let none = archive(&[("v.npy", npy_bytes("(3,)", &[1.0; 3]))], false);
        let e = format!("{:?}", read_channel(&none, None).unwrap_err());
        assert!(e.contains("no two-dimensional"), "{e}");
    }
}
