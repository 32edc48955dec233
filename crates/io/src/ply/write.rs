//! The PLY writer: vertices with their normals, colours, texture coordinates
//! and named scalars (as `float`, or `int` for labels), faces as triangles or
//! polygons, optional edges; ASCII or binary little-endian.

use std::io::Write;

use asperity_core::{PointSet, TriMesh};

use super::PlyFormat;

/// A property name safe for a PLY header.
fn sanitize(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "scalar".into() } else { s }
}

enum Column<'a> {
    F64(&'static str, &'a [[f64; 3]], usize),
    F32(&'static str, &'a [[f64; 3]], usize),
    Uv(&'static str, &'a [[f64; 2]], usize),
    U8(&'static str, &'a [[u8; 4]], usize),
    Scalar(String, &'a [f64]),
    Scalar32(String, &'a [f64]),
    Int(String, &'a [f64]),
}

/// Whether a named scalar is written as PLY `int`: names `label`, `…_label`,
/// `…_id` or `…_index` whose values are all integers that fit in 32 bits.
fn is_integer_column(name: &str, data: &[f64]) -> bool {
    (name == "label"
        || name.ends_with("_label")
        || name.ends_with("_id")
        || name.ends_with("_index"))
        && data
            .iter()
            .all(|&v| v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64)
}

impl Column<'_> {
    fn header(&self) -> String {
        match self {
            Column::F64(n, ..) => format!("property double {n}"),
            Column::F32(n, ..) | Column::Uv(n, ..) => format!("property float {n}"),
            Column::Scalar32(n, _) => format!("property float {n}"),
            Column::U8(n, ..) => format!("property uchar {n}"),
            Column::Scalar(n, _) => format!("property double {n}"),
            Column::Int(n, _) => format!("property int {n}"),
        }
    }
    fn write(&self, i: usize, ascii: bool, out: &mut Vec<u8>) {
        match self {
            Column::F64(_, d, k) => put_f64(d[i][*k], ascii, out),
            Column::F32(_, d, k) => put_f32(d[i][*k] as f32, ascii, out),
            Column::Uv(_, d, k) => put_f32(d[i][*k] as f32, ascii, out),
            Column::U8(_, d, k) => {
                if ascii {
                    let _ = write!(out, "{} ", d[i][*k]);
                } else {
                    out.push(d[i][*k]);
                }
            }
            Column::Scalar(_, d) => put_f64(d[i], ascii, out),
            Column::Scalar32(_, d) => put_f32(d[i] as f32, ascii, out),
            Column::Int(_, d) => {
                let v = d[i] as i32;
                if ascii {
                    let _ = write!(out, "{v} ");
                } else {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
}

fn put_f64(v: f64, ascii: bool, out: &mut Vec<u8>) {
    if ascii {
        let _ = write!(out, "{v} ");
    } else {
        out.extend_from_slice(&v.to_le_bytes());
    }
}
fn put_f32(v: f32, ascii: bool, out: &mut Vec<u8>) {
    if ascii {
        let _ = write!(out, "{v} ");
    } else {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

struct VertexData<'a> {
    positions: &'a [[f64; 3]],
    normals: Option<&'a [[f64; 3]]>,
    colors: Option<&'a [[u8; 4]]>,
    uvs: Option<&'a [[f64; 2]]>,
    scalars: Vec<(&'a str, &'a [f64])>,
}

/// Faces to write: triangles, or polygons in CSR layout.
#[derive(Clone, Copy)]
pub(crate) enum Faces<'a> {
    /// Triangles.
    Tri(&'a [[u32; 3]]),
    /// Polygons: face f is `verts[offsets[f]..offsets[f + 1]]`.
    Poly(&'a [u32], &'a [u32]),
}

impl Faces<'_> {
    fn len(&self) -> usize {
        match self {
            Faces::Tri(t) => t.len(),
            Faces::Poly(o, _) => o.len().saturating_sub(1),
        }
    }
    fn get(&self, f: usize) -> &[u32] {
        match self {
            Faces::Tri(t) => &t[f],
            Faces::Poly(o, v) => &v[o[f] as usize..o[f + 1] as usize],
        }
    }
}

/// The columns of the vertex element: position, then normals, colours, UVs
/// and the named scalars (renamed where they clash with a standard name);
/// positions and scalars as `double`, or `float` with `float32`.
fn vertex_columns<'a>(v: &VertexData<'a>, float32: bool) -> Vec<Column<'a>> {
    let position = |name, k| match float32 {
        true => Column::F32(name, v.positions, k),
        false => Column::F64(name, v.positions, k),
    };
    let mut cols = vec![position("x", 0), position("y", 1), position("z", 2)];
    if let Some(n) = v.normals {
        cols.extend([
            Column::F32("nx", n, 0),
            Column::F32("ny", n, 1),
            Column::F32("nz", n, 2),
        ]);
    }
    if let Some(c) = v.colors {
        cols.extend([
            Column::U8("red", c, 0),
            Column::U8("green", c, 1),
            Column::U8("blue", c, 2),
            Column::U8("alpha", c, 3),
        ]);
    }
    if let Some(uv) = v.uvs {
        cols.extend([Column::Uv("s", uv, 0), Column::Uv("t", uv, 1)]);
    }
    let reserved = [
        "x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha", "s", "t", "u", "v",
    ];
    for (name, data) in &v.scalars {
        let mut n = sanitize(name);
        if reserved.contains(&n.as_str()) {
            n = format!("{n}_scalar");
        }
        if is_integer_column(&n, data) {
            cols.push(Column::Int(n, data));
        } else if float32 {
            cols.push(Column::Scalar32(n, data));
        } else {
            cols.push(Column::Scalar(n, data));
        }
    }
    cols
}

/// The header for `vertices` vertices with `cols`, optional faces and edges.
fn header(
    ascii: bool,
    vertices: usize,
    cols: &[Column],
    faces: Option<usize>,
    edges: usize,
    params: Option<&str>,
) -> String {
    let mut h = String::from("ply\n");
    h += if ascii {
        "format ascii 1.0\n"
    } else {
        "format binary_little_endian 1.0\n"
    };
    h += &format!(
        "comment written by asperity {}\n",
        env!("CARGO_PKG_VERSION")
    );
    if let Some(p) = params {
        h += &format!("comment {} {p}\n", crate::metadata::KEYWORD);
    }
    h += &format!("element vertex {vertices}\n");
    for c in cols {
        h += &c.header();
        h.push('\n');
    }
    if let Some(f) = faces {
        h += &format!("element face {f}\nproperty list uchar uint vertex_indices\n");
    }
    if edges > 0 {
        h += &format!("element edge {edges}\nproperty int vertex1\nproperty int vertex2\n");
    }
    h += "end_header\n";
    h
}

/// Rows formatted by `row` (each appended to the buffer it is given),
/// written in order. Blocks of rows are formatted in parallel and written one
/// after the other, a bounded number at a time: a 12 M-triangle mesh is tens
/// of millions of rows.
fn write_rows(
    w: &mut dyn Write,
    n: usize,
    row: impl Fn(usize, &mut Vec<u8>) + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    const BLOCK: usize = 1 << 14;
    const BLOCKS_AT_ONCE: usize = 32;
    // The buffers are kept from batch to batch and sized after their first
    // row (binary rows have one size): fresh or growing buffers fault pages
    // in again and again once freed memory goes back to the system.
    let mut blocks: Vec<Vec<u8>> = vec![Vec::new(); BLOCKS_AT_ONCE];
    let mut start = 0;
    while start < n {
        let end = (start + BLOCK * BLOCKS_AT_ONCE).min(n);
        let used = (end - start).div_ceil(BLOCK);
        blocks[..used]
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, buf)| {
                buf.clear();
                let first = start + k * BLOCK;
                let last = (first + BLOCK).min(end);
                for i in first..last {
                    row(i, buf);
                    if i == first {
                        buf.reserve(buf.len() * (last - first - 1));
                    }
                }
            });
        for b in &blocks[..used] {
            w.write_all(b)?;
        }
        start = end;
    }
    Ok(())
}

/// The face element: a count byte, then the indices.
fn write_faces(w: &mut dyn Write, faces: Faces<'_>, ascii: bool) -> std::io::Result<()> {
    write_rows(w, faces.len(), |f, out| {
        let t = faces.get(f);
        if ascii {
            let idx: Vec<String> = t.iter().map(u32::to_string).collect();
            let _ = writeln!(out, "{} {}", t.len(), idx.join(" "));
        } else {
            out.push(t.len() as u8);
            for k in t {
                out.extend_from_slice(&k.to_le_bytes());
            }
        }
    })
}

fn write_ply(
    w: &mut dyn Write,
    v: &VertexData,
    faces: Option<Faces<'_>>,
    edges: &[[u32; 2]],
    format: PlyFormat,
    params: Option<&str>,
) -> std::io::Result<()> {
    let ascii = format.ascii();
    let cols = vertex_columns(v, format.float32);
    let h = header(
        ascii,
        v.positions.len(),
        &cols,
        faces.map(|f| f.len()),
        edges.len(),
        params,
    );
    w.write_all(h.as_bytes())?;
    write_rows(w, v.positions.len(), |i, out| {
        for c in &cols {
            c.write(i, ascii, out);
        }
        if ascii {
            out.pop();
            out.push(b'\n');
        }
    })?;
    if let Some(faces) = faces {
        write_faces(w, faces, ascii)?;
    }
    for e in edges {
        if ascii {
            writeln!(w, "{} {}", e[0], e[1])?;
        } else {
            w.write_all(&(e[0] as i32).to_le_bytes())?;
            w.write_all(&(e[1] as i32).to_le_bytes())?;
        }
    }
    Ok(())
}

/// Every per-vertex column of a triangle mesh.
fn mesh_vertex_data(m: &TriMesh) -> VertexData<'_> {
    VertexData {
        positions: m.positions(),
        normals: m.normals(),
        colors: m.colors(),
        uvs: m.uvs(),
        scalars: m
            .scalars()
            .iter()
            .map(|a| (a.name.as_str(), a.values.as_slice()))
            .collect(),
    }
}

/// Writes polygons (CSR) with the per-vertex data of `m` (same vertices).
pub(crate) fn write_poly(
    w: &mut dyn Write,
    m: &TriMesh,
    offsets: &[u32],
    verts: &[u32],
    format: PlyFormat,
    params: Option<&str>,
) -> std::io::Result<()> {
    let v = mesh_vertex_data(m);
    write_ply(
        w,
        &v,
        Some(Faces::Poly(offsets, verts)),
        &[],
        format,
        params,
    )
}

/// Writes a triangle mesh with all its per-vertex data.
pub(crate) fn write_mesh(
    w: &mut dyn Write,
    m: &TriMesh,
    format: PlyFormat,
    params: Option<&str>,
) -> std::io::Result<()> {
    write_mesh_edges(w, m, &[], format, params)
}

/// Writes a triangle mesh plus an `edge` element (polylines drawn on it).
pub(crate) fn write_mesh_edges(
    w: &mut dyn Write,
    m: &TriMesh,
    edges: &[[u32; 2]],
    format: PlyFormat,
    params: Option<&str>,
) -> std::io::Result<()> {
    let v = mesh_vertex_data(m);
    write_ply(
        w,
        &v,
        Some(Faces::Tri(m.triangles())),
        edges,
        format,
        params,
    )
}

/// Writes a point set (vertices only).
pub(crate) fn write_points(
    w: &mut dyn Write,
    p: &PointSet,
    format: PlyFormat,
    params: Option<&str>,
) -> std::io::Result<()> {
    let v = VertexData {
        positions: p.positions(),
        normals: p.normals(),
        colors: p.colors(),
        uvs: None,
        scalars: p
            .attributes()
            .iter()
            .map(|a| (a.name.as_str(), a.values.as_slice()))
            .collect(),
    };
    write_ply(w, &v, None, &[], format, params)
}
