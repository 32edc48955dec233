//! Up axes: asperity is z-up; some formats and their programs are y-up.
//!
//! | Format | Written | Read |
//! | --- | --- | --- |
//! | OBJ | y-up, `(x, z, −y)`, marked `# up: y` in the header (Blender's and MeshLab's OBJ importers assume y-up) | y-up when the header says so (asperity's own files, back unchanged), else as it is |
//! | glTF | y-up, always (the glTF specification) | — |
//! | PLY, STL, XYZ, npy points | z-up, as they are (Blender and MeshLab import them so) | as they are |
//!
//! `--up y|z` ([`WriteOptions::up`](crate::WriteOptions::up) and [`reorient`])
//! overrides the table for OBJ, PLY, STL, XYZ and npy points: `--up y` writes
//! `(x, z, −y)` (an OBJ also gets the header line) and reads a file as y-up;
//! `--up z` writes and reads coordinates as they are. glTF stays y-up.

use std::borrow::Cow;
use std::path::Path;

use asperity_core::{PointSet, TriMesh};

use crate::{Format, IoError, Surface};

/// Which axis points up in a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// y up (OBJ and glTF by convention): asperity's `(x, y, z)` is `(x, z, −y)`.
    Y,
    /// z up, as asperity: coordinates as they are.
    Z,
}

impl std::str::FromStr for UpAxis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "y" => Ok(UpAxis::Y),
            "z" => Ok(UpAxis::Z),
            other => Err(format!("unknown up axis {other:?} (y or z)")),
        }
    }
}

/// The header line of an OBJ written y-up by asperity.
pub(crate) const Y_UP_LINE: &str = "# up: y (asperity's z-up coordinates written as x, z, -y)";

/// Whether an OBJ is one asperity wrote y-up (the header's first lines say).
pub(crate) fn written_y_up(bytes: &[u8]) -> bool {
    bytes
        .split(|&b| b == b'\n')
        .take(4)
        .any(|l| l.trim_ascii() == Y_UP_LINE.as_bytes())
}

/// asperity's z-up `(x, y, z)` in a y-up frame.
pub(crate) fn to_y_up(p: [f64; 3]) -> [f64; 3] {
    [p[0], p[2], -p[1]]
}

/// A y-up `(x, y, z)` back in asperity's z-up frame.
pub(crate) fn from_y_up(p: [f64; 3]) -> [f64; 3] {
    [p[0], -p[2], p[1]]
}

/// The up axis `format` is written with: `up` where given (glTF is y-up
/// whatever is asked), else the format's convention.
pub fn written_up(format: Format, up: Option<UpAxis>) -> UpAxis {
    match (format, up) {
        (Format::Glb, _) => UpAxis::Y,
        (_, Some(up)) => up,
        (Format::Obj, None) => UpAxis::Y,
        _ => UpAxis::Z,
    }
}

/// `mesh` in the frame of a file written with `up`.
pub(crate) fn mesh_in_file_frame(mesh: &TriMesh, up: UpAxis) -> Cow<'_, TriMesh> {
    match up {
        UpAxis::Z => Cow::Borrowed(mesh),
        UpAxis::Y => Cow::Owned(mesh.clone().map_vectors(to_y_up)),
    }
}

/// `points` in the frame of a file written with `up`.
pub(crate) fn points_in_file_frame(points: &PointSet, up: UpAxis) -> Cow<'_, PointSet> {
    match up {
        UpAxis::Z => Cow::Borrowed(points),
        UpAxis::Y => Cow::Owned(points.clone().map_vectors(to_y_up)),
    }
}

/// The up axis [`crate::read`] took `path` to have: y for an OBJ asperity
/// wrote y-up (its header says so), z for every other file.
///
/// # Errors
/// [`IoError`] when the file cannot be read.
pub fn read_up(path: &Path) -> Result<UpAxis, IoError> {
    if Format::from_path(path)? != Format::Obj {
        return Ok(UpAxis::Z);
    }
    use std::io::Read;
    let mut head = Vec::with_capacity(512);
    std::fs::File::open(path)
        .and_then(|f| f.take(512).read_to_end(&mut head))
        .map_err(|e| IoError::os(path, e))?;
    Ok(if written_y_up(&head) {
        UpAxis::Y
    } else {
        UpAxis::Z
    })
}

/// `surface`, read from `path`, as if the file had `up` as its up axis (what
/// `--up` asks on reading): meshes and points are turned from the axis the
/// reader assumed ([`read_up`]) to `up`; height fields are left alone.
///
/// # Errors
/// As [`read_up`].
pub fn reorient(surface: Surface, path: &Path, up: UpAxis) -> Result<Surface, IoError> {
    Ok(match surface {
        Surface::Mesh(m) => Surface::Mesh(reorient_mesh(m, path, up)?),
        Surface::Points(p) => Surface::Points(reorient_points(p, path, up)?),
        h @ Surface::Height(_) => h,
    })
}

/// [`reorient`] for a mesh.
///
/// # Errors
/// As [`read_up`].
pub fn reorient_mesh(m: TriMesh, path: &Path, up: UpAxis) -> Result<TriMesh, IoError> {
    Ok(match turn(path, up)? {
        Some(f) => m.map_vectors(f),
        None => m,
    })
}

/// [`reorient`] for a point set.
///
/// # Errors
/// As [`read_up`].
pub fn reorient_points(p: PointSet, path: &Path, up: UpAxis) -> Result<PointSet, IoError> {
    Ok(match turn(path, up)? {
        Some(f) => p.map_vectors(f),
        None => p,
    })
}

/// A change of frame, point by point.
type Turn = fn([f64; 3]) -> [f64; 3];

/// What turns the reader's result of `path` into the frame `up` asks for:
/// the reader turned a y-up file to z-up (assumed Y) or kept it (assumed Z).
fn turn(path: &Path, up: UpAxis) -> Result<Option<Turn>, IoError> {
    let assumed = read_up(path)?;
    Ok((assumed != up).then_some(match assumed {
        UpAxis::Y => to_y_up as Turn,
        UpAxis::Z => from_y_up,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_turns_undo_each_other_and_stand_z_up_as_y_up() {
        let p = [1.0, 2.0, 3.0];
        assert_eq!(from_y_up(to_y_up(p)), p);
        assert_eq!(to_y_up([0.0, 0.0, 1.0]), [0.0, 1.0, 0.0]);
        assert_eq!("Y".parse::<UpAxis>(), Ok(UpAxis::Y));
        assert!("x".parse::<UpAxis>().unwrap_err().contains("y or z"));
        assert_eq!(written_up(Format::Glb, Some(UpAxis::Z)), UpAxis::Y);
        assert_eq!(written_up(Format::Obj, None), UpAxis::Y);
        assert_eq!(written_up(Format::Obj, Some(UpAxis::Z)), UpAxis::Z);
        assert_eq!(written_up(Format::Ply, None), UpAxis::Z);
        assert_eq!(written_up(Format::Stl, Some(UpAxis::Y)), UpAxis::Y);
    }
}
