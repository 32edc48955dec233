//! The writers by extension: meshes (with polygons, polylines and
//! texture sidecars), point sets, height fields, `.npy` arrays, text and
//! pictures, each through [`crate::write_atomic`].

use std::path::Path;

use asperity_core::{CoreError, HeightField, PointSet, PolyMesh, RgbaImage, TriMesh};

use crate::{
    Format, IoError, NpyDtype, Surface, WriteOptions, exr_io, glb, gsf, gwy, npy, obj, ply, png_io,
    sdf, stl, text, up, write_atomic, wrong, x3p,
};

/// Writes the polygons of `poly` (quads, n-gons, kept as they are) with the
/// per-vertex data (normals, colours, scalars) of `attrs`, which must have the
/// same vertices — typically `poly.triangulate()` with attributes added. PLY and
/// OBJ hold polygons; other mesh formats get `attrs`' triangles.
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] when the vertex counts differ.
pub fn write_poly_mesh(
    path: &Path,
    poly: &PolyMesh,
    attrs: &TriMesh,
    opts: &WriteOptions,
) -> Result<(), IoError> {
    if poly.n_vertices() != attrs.n_vertices() {
        return Err(IoError::invalid(
            path,
            CoreError::LengthMismatch {
                what: "vertex attributes".into(),
                got: attrs.n_vertices(),
                expected: poly.n_vertices(),
            },
        ));
    }
    let f = Format::from_path(path)?;
    if f == Format::Ply && poly.faces().any(|face| face.len() > 255) {
        return Err(IoError::invalid(
            path,
            CoreError::InvalidParameter {
                name: "faces",
                reason: "PLY face lists hold at most 255 corners; write OBJ".into(),
            },
        ));
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    let params = opts.params_text();
    let params = params.as_deref();
    match f {
        Format::Ply if poly.n_faces() > 0 => write_atomic(path, |w| {
            ply::write_poly(
                w,
                &up::mesh_in_file_frame(attrs, up),
                poly.face_offsets(),
                poly.face_vertices(),
                opts.ply_format(),
                params,
            )
            .map_err(os)
        }),
        Format::Obj if poly.n_faces() > 0 && attrs.texture().is_none() => write_atomic(path, |w| {
            obj::write_faces(
                w,
                attrs,
                (poly.face_offsets(), poly.face_vertices()),
                (None, params),
                up,
            )
            .map_err(os)
        }),
        _ => write_mesh(path, attrs, opts),
    }
}

/// Writes a triangle mesh; the format follows the extension. A textured mesh
/// written as OBJ also gets `NAME.mtl` and `NAME_texture.png` beside it.
///
/// # Errors
/// [`IoError`]; [`IoError::WrongKind`] for formats that hold no meshes;
/// [`IoError::Invalid`] for a mesh without triangles (glTF cannot even express one).
pub fn write_mesh(path: &Path, mesh: &TriMesh, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if mesh.n_faces() == 0 {
        return Err(IoError::invalid(
            path,
            CoreError::Empty("the mesh (no triangles)"),
        ));
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    // (glTF's writer turns the mesh to y-up itself, with f32 positions)
    let in_file = || up::mesh_in_file_frame(mesh, up);
    let params = opts.params_text();
    let params = params.as_deref();
    match f {
        Format::Ply => write_atomic(path, |w| {
            ply::write_mesh(w, &in_file(), opts.ply_format(), params).map_err(os)
        }),
        Format::Stl => write_atomic(path, |w| stl::write_mesh(w, &in_file()).map_err(os)),
        Format::Glb => write_atomic(path, |w| glb::write_mesh(w, mesh, params).map_err(os)),
        Format::Obj => {
            let mtl = match mesh.texture().filter(|_| mesh.uvs().is_some()) {
                Some(tex) => Some(write_obj_sidecars(path, tex)?),
                None => None,
            };
            write_atomic(path, |w| {
                obj::write_mesh(w, mesh, mtl.as_deref(), up, params).map_err(os)
            })
        }
        Format::Xyz | Format::Npy => {
            write_points(path, &PointSet::new(mesh.positions().to_vec()), opts)
        }
        _ => Err(wrong(path, f, "a mesh")),
    }
}

fn write_obj_sidecars(path: &Path, tex: &RgbaImage) -> Result<String, IoError> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let (mtl_name, png_name) = (format!("{stem}.mtl"), format!("{stem}_texture.png"));
    let png_path = path.with_file_name(&png_name);
    let mtl_path = path.with_file_name(&mtl_name);
    write_atomic(&png_path, |w| {
        png_io::write_rgba(w, tex, None).map_err(|e| IoError::os(&png_path, e))
    })?;
    write_atomic(&mtl_path, |w| {
        obj::write_mtl(w, &png_name).map_err(|e| IoError::os(&mtl_path, e))
    })?;
    Ok(mtl_name)
}

/// Writes a point set (`.ply`, `.xyz`, `.npy`).
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] for an empty set or non-finite coordinates.
pub fn write_points(path: &Path, points: &PointSet, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if points.is_empty() {
        return Err(IoError::invalid(path, CoreError::Empty("the point set")));
    }
    points.validate().map_err(|e| IoError::invalid(path, e))?;
    let os = |e| IoError::os(path, e);
    let points = &*up::points_in_file_frame(points, up::written_up(f, opts.up));
    match f {
        Format::Ply => write_atomic(path, |w| {
            ply::write_points(w, points, opts.ply_format(), opts.params_text().as_deref())
                .map_err(os)
        }),
        Format::Xyz => write_atomic(path, |w| text::write_xyz(w, points).map_err(os)),
        Format::Npy => {
            let flat: Vec<f64> = points.positions().iter().flatten().copied().collect();
            write_atomic(path, |w| {
                npy::write(w, &[points.len(), 3], &flat, NpyDtype::Float64).map_err(os)
            })
        }
        _ => Err(wrong(path, f, "a point set")),
    }
}

/// Writes a height field; mesh formats get its triangulation, point formats its samples.
///
/// Missing points (NaN heights) are carried where the format can: NaN in
/// `.npy`, `.x3p` (ISO 5436-2's invalid float), `.exr`, `.gsf` and `.csv`
/// (Gwyddion masks NaNs on import; numpy reads them), Gwyddion's mask of
/// unmeasured points in `.gwy`, holes in meshes, no point in point files.
/// PNG and SDF cannot hold them and refuse the field with the count.
///
/// # Errors
/// [`IoError`]; [`IoError::Invalid`] for infinite heights, or missing points
/// in a format that cannot hold them.
pub fn write_height(path: &Path, h: &HeightField, opts: &WriteOptions) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    h.validate_measured()
        .map_err(|e| IoError::invalid(path, e))?;
    if matches!(f, Format::Png | Format::Sdf) {
        h.validate_for(&format!(
            "{} (it has no missing-point marker)",
            f.info().name
        ))
        .map_err(|e| IoError::invalid(path, e))?;
    }
    let os = |e| IoError::os(path, e);
    let params = opts.params_text();
    let p = params.as_deref();
    let title = &opts.title;
    match f {
        Format::Npy => write_atomic(path, |w| {
            npy::write(w, &[h.ny(), h.nx()], h.data(), opts.npy_dtype).map_err(os)
        }),
        Format::Png => write_atomic(path, |w| png_io::write_height(w, h, title, p).map_err(os)),
        Format::Exr => write_atomic(path, |w| exr_io::write_height(w, h, p).map_err(os)),
        Format::Gsf => write_atomic(path, |w| gsf::write_height(w, h, title, p).map_err(os)),
        Format::Csv => write_atomic(path, |w| text::write_csv(w, h, p).map_err(os)),
        Format::Gwy => write_atomic(path, |w| gwy::write_height(w, h, title, p).map_err(os)),
        Format::X3p => write_atomic(path, |w| x3p::write_height(w, h, p).map_err(os)),
        Format::Sdf => write_atomic(path, |w| sdf::write_height(w, h, p).map_err(os)),
        Format::Ply | Format::Obj | Format::Stl | Format::Glb => {
            let mesh = h
                .to_trimesh(opts.diagonal)
                .map_err(|e| IoError::invalid(path, e))?;
            let mesh = mesh
                .with_scalar("height", h.measured_values())
                .map_err(|e| IoError::invalid(path, e))?;
            write_mesh(path, &mesh, opts)
        }
        Format::Xyz => write_points(path, &h.to_point_set(), opts),
        // The instrument formats are read-only (`FormatInfo::height`).
        _ => Err(wrong(path, f, "a height field")),
    }
}

/// Writes text (HTML, JSON, SVG…) atomically.
///
/// # Errors
/// [`IoError::Os`].
pub fn write_text(path: &Path, text: &str) -> Result<(), IoError> {
    write_atomic(path, |w| {
        std::io::Write::write_all(w, text.as_bytes()).map_err(|e| IoError::os(path, e))
    })
}

/// Writes an 8-bit RGBA picture (a render, a colour map, a texture) as PNG.
///
/// # Errors
/// [`IoError::Os`].
pub fn write_png(path: &Path, img: &RgbaImage) -> Result<(), IoError> {
    write_png_with(path, img, &WriteOptions::default())
}

/// [`write_png`] recording `opts.params` (see [`crate::metadata`]).
///
/// # Errors
/// [`IoError::Os`].
pub fn write_png_with(path: &Path, img: &RgbaImage, opts: &WriteOptions) -> Result<(), IoError> {
    let params = opts.params_text();
    write_atomic(path, |w| {
        png_io::write_rgba(w, img, params.as_deref()).map_err(|e| IoError::os(path, e))
    })
}

/// `Ok` when `len` values fill `shape` exactly.
fn check_shape(path: &Path, shape: &[usize], len: usize) -> Result<(), IoError> {
    let n: usize = shape.iter().product();
    if n != len {
        let source = CoreError::GridSize {
            dims: shape.to_vec(),
            expected: n,
            got: len,
        };
        return Err(IoError::invalid(path, source));
    }
    Ok(())
}

/// Writes a `uint8` array of `shape` (C order) as `.npy`, e.g. a CA evolution
/// `(T+1, ny, nx)`.
///
/// # Errors
/// [`IoError::Os`]; [`IoError::Invalid`] if `data` does not fill `shape`.
pub fn write_npy_u8(path: &Path, shape: &[usize], data: &[u8]) -> Result<(), IoError> {
    check_shape(path, shape, data.len())?;
    write_atomic(path, |w| {
        npy::write_u8(w, shape, data).map_err(|e| IoError::os(path, e))
    })
}

/// Writes a C-order float64 `.npy` array of any `shape` (e.g. a 1-D profile),
/// atomically.
///
/// # Errors
/// [`IoError::Invalid`] when `shape` does not match the data; I/O errors.
pub fn write_npy_f64(path: &Path, shape: &[usize], data: &[f64]) -> Result<(), IoError> {
    check_shape(path, shape, data.len())?;
    write_atomic(path, |w| {
        npy::write(w, shape, data, npy::NpyDtype::Float64).map_err(|e| IoError::os(path, e))
    })
}

/// Writes a mesh with polylines drawn on it: OBJ `l` elements or a PLY `edge`
/// element (MeshLab and Blender read both). The polyline points are appended
/// to the vertices (with zero/default attributes) and referenced by the lines.
///
/// # Errors
/// [`IoError::WrongKind`] for formats other than OBJ and PLY; as [`write_mesh`].
pub fn write_mesh_with_polylines(
    path: &Path,
    mesh: &TriMesh,
    lines: &[Vec<[f64; 3]>],
    opts: &WriteOptions,
) -> Result<(), IoError> {
    let f = Format::from_path(path)?;
    if !matches!(f, Format::Obj | Format::Ply) {
        return Err(wrong(path, f, "polylines (use .obj or .ply)"));
    }
    let invalid = |e| IoError::invalid(path, e);
    let extra: usize = lines.iter().map(Vec::len).sum();
    let mut positions = mesh.positions().to_vec();
    let mut edges = Vec::new();
    for l in lines {
        let start = positions.len() as u32;
        positions.extend_from_slice(l);
        edges.extend((1..l.len() as u32).map(|k| [start + k - 1, start + k]));
    }
    let mut m = TriMesh::new(positions, mesh.triangles().to_vec()).map_err(invalid)?;
    if let Some(n) = mesh.normals() {
        m = m
            .with_normals(
                n.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0.0, 0.0, 1.0], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    if let Some(c) = mesh.colors() {
        m = m
            .with_colors(
                c.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0, 0, 0, 255], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    if let Some(uv) = mesh.uvs() {
        m = m
            .with_uvs(
                uv.iter()
                    .copied()
                    .chain(std::iter::repeat_n([0.0, 0.0], extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    for a in mesh.scalars() {
        m = m
            .with_scalar(
                &a.name,
                a.values
                    .iter()
                    .copied()
                    .chain(std::iter::repeat_n(0.0, extra))
                    .collect(),
            )
            .map_err(invalid)?;
    }
    let os = |e| IoError::os(path, e);
    let up = up::written_up(f, opts.up);
    let params = opts.params_text();
    let params = params.as_deref();
    match f {
        Format::Ply => write_atomic(path, |w| {
            let m = up::mesh_in_file_frame(&m, up);
            ply::write_mesh_edges(w, &m, &edges, opts.ply_format(), params).map_err(os)
        }),
        _ => write_atomic(path, |w| {
            obj::write_mesh(w, &m, None, up, params)
                .and_then(|()| obj::write_lines(w, lines, mesh.n_vertices()))
                .map_err(os)
        }),
    }
}

/// Writes any [`Surface`].
///
/// # Errors
/// As the specific writers.
pub fn write(path: &Path, s: &Surface, opts: &WriteOptions) -> Result<(), IoError> {
    match s {
        Surface::Mesh(m) => write_mesh(path, m, opts),
        Surface::Points(p) => write_points(path, p, opts),
        Surface::Height(h) => write_height(path, h, opts),
    }
}

/// What writing `s` to `format` loses (attributes the format has no place for).
pub fn lost_data(s: &Surface, format: Format) -> Vec<String> {
    let mut lost = Vec::new();
    if let Surface::Mesh(m) = s {
        let no_scalars = matches!(format, Format::Obj | Format::Stl);
        if no_scalars {
            lost.extend(m.scalars().iter().map(|a| format!("scalar '{}'", a.name)));
        }
        if format == Format::Stl {
            if m.colors().is_some() {
                lost.push("vertex colours".into());
            }
            if m.uvs().is_some() {
                lost.push("UVs".into());
            }
        }
        if m.texture().is_some() && matches!(format, Format::Ply | Format::Stl) {
            lost.push("texture image".into());
        }
        if matches!(format, Format::Xyz | Format::Npy) {
            lost.push("faces".into());
        }
    }
    if let Surface::Height(h) = s {
        if h.has_missing() {
            let n = h.missing_count();
            match format {
                Format::Ply | Format::Obj | Format::Stl | Format::Glb => {
                    lost.push(format!("{n} missing points (holes in the mesh)"));
                }
                Format::Xyz => lost.push(format!("{n} missing points (no point written)")),
                _ => {}
            }
        }
        if !h.units().is_none() && format == Format::Npy {
            lost.push("units (npy has no metadata)".into());
        }
        if matches!(format, Format::Exr | Format::Gsf) {
            lost.push("f64 precision (stored as f32)".into());
        }
        if format == Format::Png {
            lost.push("precision below (max−min)/65535 (16-bit quantisation)".into());
        }
        if format == Format::Npy {
            lost.push("spacing and origin (npy has no metadata)".into());
        }
        if matches!(format, Format::X3p | Format::Sdf) && h.units().is_none() {
            lost.push(format!(
                "unitlessness ({} lengths are metres: the numbers are written as metres)",
                if format == Format::X3p { "x3p" } else { "SDF" }
            ));
        }
    }
    lost
}
