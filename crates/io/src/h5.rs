//! HDF5 files (`.h5`, `.hdf5`), read as SurfaceTopography's generic HDF5
//! reader reads them: every two-dimensional numeric dataset is a channel,
//! named by its path, the first index along x and the second along y (so
//! dataset element `[i][j]` is asperity's column i of row j). HDF5 keeps no
//! sizes or units for such data: the step is 1 and the numbers unitless.
//!
//! Read with the pure-Rust `hdf5-reader` crate (no libhdf5, so the Python
//! wheels stay portable), which bounds every read it is asked for; asperity
//! asks for nothing larger than the memory estimate, which counts the
//! largest 2-D dataset the file declares before any is read. Integer and
//! floating-point datasets of any width are converted to f64; strings,
//! compounds and references are not channels. Groups are walked to a depth
//! of 32 and each object once, so links that loop end.

use std::collections::HashSet;

use asperity_core::HeightField;
use hdf5_reader::error::Error as H5Error;
use hdf5_reader::group::Group;
use hdf5_reader::{Dataset, Datatype};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};

/// HDF5's signature (at offset 0; files with a user block are not read).
pub(crate) const MAGIC: &[u8] = b"\x89HDF\r\n\x1a\n";

/// How deep groups are walked.
const MAX_DEPTH: usize = 32;

fn bad(e: impl std::fmt::Display) -> FormatError {
    FormatError::Malformed(format!("the HDF5 structure is damaged: {e}"))
}

fn open(bytes: &[u8]) -> FResult<hdf5_reader::Hdf5File> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the HDF5 signature");
    }
    hdf5_reader::Hdf5File::from_bytes(bytes).map_err(bad)
}

/// Whether a dataset's type holds numbers asperity can read.
fn numeric(t: &Datatype) -> bool {
    matches!(
        t,
        Datatype::FixedPoint {
            size: 1 | 2 | 4 | 8,
            ..
        } | Datatype::FloatingPoint { size: 4 | 8, .. }
    )
}

/// The file's two-dimensional numeric datasets, by path, in name order.
fn datasets(file: &hdf5_reader::Hdf5File) -> FResult<Vec<(String, Dataset)>> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    let mut stack: Vec<(Group, String, usize)> =
        vec![(file.root_group().map_err(bad)?, String::new(), 0)];
    while let Some((group, prefix, depth)) = stack.pop() {
        if depth > MAX_DEPTH || !seen.insert(group.address()) {
            continue;
        }
        let (groups, sets) = group.members().map_err(bad)?;
        for g in groups {
            let path = format!("{prefix}{}/", g.name());
            stack.push((g, path, depth + 1));
        }
        for d in sets {
            let shape = d.shape();
            if shape.len() == 2 && shape.iter().all(|&n| n > 0) && numeric(d.dtype()) {
                out.push((format!("{prefix}{}", d.name()), d));
            }
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    if out.is_empty() {
        return malformed("the file holds no two-dimensional numeric dataset");
    }
    Ok(out)
}

/// The datasets as channels (every one counts as heights, unitless).
fn channel_list(sets: &[(String, Dataset)]) -> Vec<ChannelInfo> {
    sets.iter()
        .enumerate()
        .map(|(index, (name, _))| ChannelInfo {
            index,
            name: name.clone(),
            height: true,
        })
        .collect()
}

/// The file's 2-D datasets as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let file = open(bytes)?;
    Ok(channel_list(&datasets(&file)?))
}

/// The elements of the largest 2-D dataset (for the memory estimate).
pub(crate) fn declared_points(bytes: &[u8]) -> FResult<u128> {
    let file = open(bytes)?;
    Ok(datasets(&file)?
        .iter()
        .map(|(_, d)| d.shape().iter().map(|&n| u128::from(n)).product::<u128>())
        .max()
        .unwrap_or(0))
}

/// Reads the dataset `choice` names (by default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    read(bytes, choice, true)
}

/// [`read_channel`] with the dataset's first index along y (element
/// `[j][i]` is column i of row j), as MATLAB 7.3 files store a matrix.
pub(crate) fn read_channel_as_stored(
    bytes: &[u8],
    choice: Option<&Channel>,
) -> FResult<HeightField> {
    read(bytes, choice, false)
}

fn read(bytes: &[u8], choice: Option<&Channel>, x_first: bool) -> FResult<HeightField> {
    let file = open(bytes)?;
    let sets = datasets(&file)?;
    let (name, d) = &sets[pick(&channel_list(&sets), choice)?];
    let (a, b) = (
        usize::try_from(d.shape()[0]).map_err(bad)?,
        usize::try_from(d.shape()[1]).map_err(bad)?,
    );
    let (nx, ny) = if x_first { (a, b) } else { (b, a) };
    let values = read_f64(d).map_err(|e| FormatError::Malformed(format!("dataset {name}: {e}")))?;
    if values.len() != nx * ny {
        return malformed(format!(
            "dataset {name}: {} values for {nx} × {ny}",
            values.len()
        ));
    }
    if !x_first {
        return Ok(HeightField::from_vec([nx, ny], values)?);
    }
    // Element [i][j] (x = i) is stored at i·ny + j; asperity's rows are y.
    let mut data = vec![0.0; nx * ny];
    for (k, v) in values.into_iter().enumerate() {
        let (i, j) = (k / ny, k % ny);
        data[j * nx + i] = v;
    }
    Ok(HeightField::from_vec([nx, ny], data)?)
}

/// A dataset's numbers as f64, whatever their type.
pub(crate) fn read_f64(d: &Dataset) -> Result<Vec<f64>, H5Error> {
    fn all<T: hdf5_reader::H5Type + Copy>(
        d: &Dataset,
        f: impl Fn(T) -> f64,
    ) -> Result<Vec<f64>, H5Error> {
        Ok(d.read_array::<T>()?.iter().map(|&v| f(v)).collect())
    }
    match d.dtype() {
        Datatype::FloatingPoint { size: 8, .. } => all::<f64>(d, |v| v),
        Datatype::FloatingPoint { .. } => all::<f32>(d, f64::from),
        Datatype::FixedPoint {
            size: 1,
            signed: true,
            ..
        } => all::<i8>(d, f64::from),
        Datatype::FixedPoint { size: 1, .. } => all::<u8>(d, f64::from),
        Datatype::FixedPoint {
            size: 2,
            signed: true,
            ..
        } => all::<i16>(d, f64::from),
        Datatype::FixedPoint { size: 2, .. } => all::<u16>(d, f64::from),
        Datatype::FixedPoint {
            size: 4,
            signed: true,
            ..
        } => all::<i32>(d, f64::from),
        Datatype::FixedPoint { size: 4, .. } => all::<u32>(d, f64::from),
        Datatype::FixedPoint { signed: true, .. } => all::<i64>(d, |v| v as f64),
        _ => all::<u64>(d, |v| v as f64),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Written by h5py: `scan/height` (3 × 2 int16), `amplitude` (4 × 3
    /// float32), a string dataset and a 1-D one (neither a channel).
    const SMALL: &[u8] = include_bytes!("../tests/data/small.h5");

    #[test]
    fn two_dimensional_numeric_datasets_are_channels_x_first() {
        let names: Vec<String> = channels(SMALL)
            .unwrap()
            .into_iter()
            .map(|c| c.name)
            .collect();
        assert_eq!(names, ["amplitude", "scan/height"]);
        let h = read_channel(SMALL, Some(&Channel::parse("scan/height"))).unwrap();
        // Element [i][j] is x = i, y = j: [[1, 2], [3, 4], [5, -6]].
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!((*h.get(0, 0), *h.get(1, 0), *h.get(2, 1)), (1.0, 3.0, -6.0));
        let a = read_channel(SMALL, None).unwrap();
        assert_eq!((a.dims(), *a.get(3, 2)), ([4, 3], 11.0));
        assert_eq!(declared_points(SMALL).unwrap(), 12);
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        for cut in (0..SMALL.len()).step_by(97) {
            let read = read_channel(&SMALL[..cut], None);
            assert!(read.is_err(), "cut at {cut}");
        }
        let e = read_channel(b"\x89PNG\r\n\x1a\n", None).unwrap_err();
        assert!(format!("{e:?}").contains("HDF5 signature"));
    }
}
