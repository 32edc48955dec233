//! numpy arrays ↔ asperity's shared types.
//!
//! Out: a result's storage moves into numpy without a copy (a `Vec<[f64; 3]>`
//! is flattened in place and handed over), so `Mesh.vertices`,
//! `HeightField.heights` and `PointSet.points` own the engine's buffers.
//! In: the Python layer passes C-contiguous arrays of the right dtype
//! (`numpy.ascontiguousarray`, a no-op when they already are); the Rust types
//! own their storage, so the data are copied once into them — the one copy
//! the layout forces (documented in docs/python.md).
//!
//! Python objects are read by duck typing: a mesh is anything with
//! `vertices` and `faces` (and optionally `normals`, `colors`, `uvs`,
//! `scalars`, `texture`), a height field anything with `heights`, `spacing`
//! and `origin`, a point set anything with `points`.

use asperity_engine::core::{HeightField, LengthUnit, PointSet, RgbaImage, TriMesh, Units};
use asperity_engine::io::Surface;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Rows of `N` numbers from an (n, N) float64 array named `what`.
pub fn rows<const N: usize>(a: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[f64; N]>> {
    typed_rows::<f64, N>(a, what, "float64")
}

fn typed_rows<T: numpy::Element + Copy, const N: usize>(
    a: &Bound<'_, PyAny>,
    what: &str,
    dtype: &str,
) -> PyResult<Vec<[T; N]>> {
    let arr: PyReadonlyArrayDyn<'_, T> = a.extract().map_err(|_| {
        PyTypeError::new_err(format!(
            "{what} must be a {dtype} numpy array of shape (n, {N})"
        ))
    })?;
    let shape = arr.shape();
    if shape.len() != 2 || shape[1] != N {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (n, {N}), got {shape:?}"
        )));
    }
    let flat = arr
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{what} must be C-contiguous")))?;
    Ok(flat
        .chunks_exact(N)
        .map(|c| std::array::from_fn(|k| c[k]))
        .collect())
}

fn attr_opt<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    match obj.getattr(name) {
        Ok(v) if v.is_none() => Ok(None),
        Ok(v) => Ok(Some(v)),
        Err(_) => Ok(None),
    }
}

fn attr<'py>(obj: &Bound<'py, PyAny>, name: &str, kind: &str) -> PyResult<Bound<'py, PyAny>> {
    obj.getattr(name).map_err(|_| {
        PyTypeError::new_err(format!(
            "expected {kind} (an object with `{name}`), got {}",
            obj.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })
}

fn invalid(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The `scalars` dict (name → 1-D float64 array) of a Python mesh or point set.
fn scalars_in(obj: &Bound<'_, PyAny>) -> PyResult<Vec<(String, Vec<f64>)>> {
    let Some(s) = attr_opt(obj, "scalars")? else {
        return Ok(Vec::new());
    };
    s.cast::<PyDict>()?
        .iter()
        .map(|(k, v)| {
            let values = v.extract::<numpy::PyReadonlyArray1<'_, f64>>()?.to_vec()?;
            Ok((k.extract()?, values))
        })
        .collect()
}

/// Named per-vertex values as a dict of 1-D arrays.
fn scalars_out<'py>(
    py: Python<'py>,
    attributes: &[asperity_engine::core::Attribute],
) -> PyResult<Bound<'py, PyDict>> {
    let scalars = PyDict::new(py);
    for a in attributes {
        scalars.set_item(&a.name, PyArray1::from_slice(py, &a.values))?;
    }
    Ok(scalars)
}

/// A `TriMesh` from a Python mesh.
pub fn mesh_in(obj: &Bound<'_, PyAny>) -> PyResult<TriMesh> {
    let vertices = rows::<3>(&attr(obj, "vertices", "a mesh")?, "mesh.vertices")?;
    let faces = typed_rows::<u32, 3>(&attr(obj, "faces", "a mesh")?, "mesh.faces", "uint32")?;
    let mut m = TriMesh::new(vertices, faces).map_err(invalid)?;
    if let Some(n) = attr_opt(obj, "normals")? {
        m = m
            .with_normals(rows::<3>(&n, "mesh.normals")?)
            .map_err(invalid)?;
    }
    if let Some(c) = attr_opt(obj, "colors")? {
        m = m
            .with_colors(typed_rows::<u8, 4>(&c, "mesh.colors", "uint8")?)
            .map_err(invalid)?;
    }
    if let Some(uv) = attr_opt(obj, "uvs")? {
        m = m.with_uvs(rows::<2>(&uv, "mesh.uvs")?).map_err(invalid)?;
    }
    for (name, values) in scalars_in(obj)? {
        m = m.with_scalar(&name, values).map_err(invalid)?;
    }
    if let Some(t) = attr_opt(obj, "texture")? {
        m = m.with_texture(image_in(&t, "mesh.texture")?);
    }
    Ok(m)
}

/// An `RgbaImage` from an (H, W, 4) uint8 array.
pub fn image_in(a: &Bound<'_, PyAny>, what: &str) -> PyResult<RgbaImage> {
    let arr: PyReadonlyArrayDyn<'_, u8> = a
        .extract()
        .map_err(|_| PyTypeError::new_err(format!("{what} must be a uint8 array (H, W, 4)")))?;
    let shape = arr.shape().to_vec();
    if shape.len() != 3 || shape[2] != 4 {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (H, W, 4), got {shape:?}"
        )));
    }
    let pixels = arr.as_slice().map_err(invalid)?.to_vec();
    RgbaImage::from_pixels(shape[1] as u32, shape[0] as u32, pixels).map_err(invalid)
}

/// A `HeightField` from a Python height field.
pub fn height_in(obj: &Bound<'_, PyAny>) -> PyResult<HeightField> {
    let h = attr(obj, "heights", "a height field")?;
    let arr: PyReadonlyArrayDyn<'_, f64> = h.extract().map_err(|_| {
        PyTypeError::new_err("heights must be a float64 numpy array of shape (ny, nx)")
    })?;
    let shape = arr.shape().to_vec();
    if shape.len() != 2 {
        return Err(PyValueError::new_err(format!(
            "heights must have shape (ny, nx), got {shape:?}"
        )));
    }
    let data = arr.as_slice().map_err(invalid)?.to_vec();
    let spacing: [f64; 2] = attr(obj, "spacing", "a height field")?.extract()?;
    let origin: [f64; 2] = attr(obj, "origin", "a height field")?.extract()?;
    let units = match attr_opt(obj, "units")? {
        None => Units::default(),
        Some(u) => {
            let (xy, z): (String, String) = u.extract().map_err(|_| {
                PyTypeError::new_err(
                    "units must be a pair of unit names (xy, z), e.g. (\"µm\", \"nm\")",
                )
            })?;
            Units {
                xy: LengthUnit::parse(&xy).map_err(invalid)?,
                z: LengthUnit::parse(&z).map_err(invalid)?,
            }
        }
    };
    HeightField::from_vec([shape[1], shape[0]], data)
        .and_then(|g| g.with_spacing(spacing))
        .and_then(|g| g.with_origin(origin))
        .map(|g| g.with_units(units))
        .map_err(invalid)
}

/// A `PointSet` from a Python point set.
pub fn points_in(obj: &Bound<'_, PyAny>) -> PyResult<PointSet> {
    let p = attr(obj, "points", "a point set")?;
    let mut ps = PointSet::new(rows::<3>(&p, "points")?);
    if let Some(n) = attr_opt(obj, "normals")? {
        ps.set_normals(rows::<3>(&n, "normals")?).map_err(invalid)?;
    }
    if let Some(c) = attr_opt(obj, "colors")? {
        ps.set_colors(typed_rows::<u8, 4>(&c, "colors", "uint8")?)
            .map_err(invalid)?;
    }
    for (name, values) in scalars_in(obj)? {
        ps.add_attribute(&name, values).map_err(invalid)?;
    }
    Ok(ps)
}

/// Any of the three, by what the object carries.
pub fn surface_in(obj: &Bound<'_, PyAny>) -> PyResult<Surface> {
    if obj.hasattr("faces")? {
        Ok(Surface::Mesh(mesh_in(obj)?))
    } else if obj.hasattr("heights")? {
        Ok(Surface::Height(height_in(obj)?))
    } else if obj.hasattr("points")? {
        Ok(Surface::Points(points_in(obj)?))
    } else {
        Err(PyTypeError::new_err(
            "expected an asperity Mesh, HeightField or PointSet",
        ))
    }
}

/// `rows` as an (n, N) array, moved without a copy.
pub fn rows_out<'py, T: numpy::Element, const N: usize>(
    py: Python<'py>,
    rows: Vec<[T; N]>,
) -> PyResult<Bound<'py, PyAny>> {
    let n = rows.len();
    let flat: Vec<T> = rows.into_flattened();
    Ok(PyArray1::from_vec(py, flat).reshape([n, N])?.into_any())
}

/// A mesh as the dict `asperity.Mesh` is built from.
pub fn mesh_out<'py>(py: Python<'py>, m: &TriMesh) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("vertices", rows_out(py, m.positions().to_vec())?)?;
    d.set_item("faces", rows_out(py, m.triangles().to_vec())?)?;
    if let Some(n) = m.normals() {
        d.set_item("normals", rows_out(py, n.to_vec())?)?;
    }
    if let Some(c) = m.colors() {
        d.set_item("colors", rows_out(py, c.to_vec())?)?;
    }
    if let Some(uv) = m.uvs() {
        d.set_item("uvs", rows_out(py, uv.to_vec())?)?;
    }
    d.set_item("scalars", scalars_out(py, m.scalars())?)?;
    if let Some(t) = m.texture() {
        d.set_item("texture", image_out(py, t)?)?;
    }
    Ok(d)
}

/// A height field as the dict `asperity.HeightField` is built from; the
/// heights are (ny, nx), row j at y = origin_y + j·dy.
pub fn height_out<'py>(py: Python<'py>, h: HeightField) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let [nx, ny] = h.dims();
    d.set_item("spacing", h.spacing())?;
    d.set_item("origin", h.origin())?;
    let u = h.units();
    d.set_item("units", (u.xy.to_string(), u.z.to_string()))?;
    let heights = PyArray1::from_vec(py, h.into_data()).reshape([ny, nx])?;
    d.set_item("heights", heights)?;
    Ok(d)
}

/// A point set as the dict `asperity.PointSet` is built from.
pub fn points_out<'py>(py: Python<'py>, p: &PointSet) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("points", rows_out(py, p.positions().to_vec())?)?;
    if let Some(n) = p.normals() {
        d.set_item("normals", rows_out(py, n.to_vec())?)?;
    }
    if let Some(c) = p.colors() {
        d.set_item("colors", rows_out(py, c.to_vec())?)?;
    }
    d.set_item("scalars", scalars_out(py, p.attributes())?)?;
    Ok(d)
}

/// Any surface as a dict with its `kind`.
pub fn surface_out<'py>(py: Python<'py>, s: Surface) -> PyResult<Bound<'py, PyDict>> {
    let (kind, d) = match s {
        Surface::Mesh(m) => ("mesh", mesh_out(py, &m)?),
        Surface::Height(h) => ("height", height_out(py, h)?),
        Surface::Points(p) => ("points", points_out(py, &p)?),
    };
    d.set_item("kind", kind)?;
    Ok(d)
}

/// An image as an (H, W, 4) uint8 array.
pub fn image_out<'py>(py: Python<'py>, img: &RgbaImage) -> PyResult<Bound<'py, PyAny>> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    Ok(PyArray1::from_slice(py, img.pixels())
        .reshape([h, w, 4])?
        .into_any())
}

/// Measurements as the JSON text of the CLI's report (the Python layer parses it).
pub fn json(v: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(v).map_err(invalid)
}
