//! Wavefront OBJ: written here, read with the `tobj` crate.
//!
//! Written: `v x y z [r g b]` (the vertex-colour extension that MeshLab and
//! Blender read), `vt u v`, `vn x y z`, triangles as `f a/b/c`. A texture is
//! written as a sidecar `NAME.mtl` with `map_Kd NAME_texture.png`. OBJ has no
//! place for named scalars: they are dropped (the CLI warns).
//!
//! Read: all objects and groups merged into one mesh, polygons kept for
//! [`crate::read_poly_mesh`] or triangulated for [`crate::read_mesh`] (fanned where convex, ear-clipped where not); corners with different
//! `v/vt/vn` combinations become separate vertices (tobj's `single_index`).
//!
//! **Up axis:** OBJ's ecosystem is y-up (Blender's and MeshLab's importers
//! assume it), asperity is z-up. Written coordinates are therefore
//! (x, z, −y) — the rotation glTF uses, so faces stay front-facing — and the
//! file says so in its header (`# up: y …`). Reading a file with that line
//! turns it back, so asperity reads its own OBJ unchanged; any other OBJ is
//! taken as it is.
//!
//! **Vertex order:** tobj numbers vertices in order of first use by a face and
//! drops vertices no face uses. asperity's own OBJ files list vertices in that
//! order only when faces use them in order, so compare OBJ geometry by triangle
//! corners, not by vertex index; use PLY where vertex identity matters.

use std::io::Write;

use asperity_core::{PolyMesh, TriMesh};

use crate::UpAxis;
use crate::error::{FResult, FormatError};
use crate::up::{Y_UP_LINE, written_y_up};
use crate::format::{Access, Registration};

/// Polygon soup read from an OBJ file, with the per-vertex data tobj found.
struct ObjContents {
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
    normals: Option<Vec<[f64; 3]>>,
    colors: Option<Vec<[u8; 4]>>,
    uvs: Option<Vec<[f64; 2]>>,
}

/// Refuses faces with fewer than three corners, which tobj would drop without
/// a word (a 1- or 2-corner `f` line is a broken file, not a line element), and
/// corner indices that name no earlier `v`, `vt` or `vn` (tobj turns a relative
/// index past the start into a huge number and overflows on it: found by
/// fuzzing).
fn check_face_lines(bytes: &[u8]) -> FResult<()> {
    let mut counts = [0usize; 3];
    for (n, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let mut tokens = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty());
        match tokens.next() {
            Some(b"v") => counts[0] += 1,
            Some(b"vt") => counts[1] += 1,
            Some(b"vn") => counts[2] += 1,
            Some(b"f") => {
                let corners: Vec<&[u8]> = tokens.take_while(|t| !t.starts_with(b"#")).collect();
                if corners.len() < 3 {
                    return Err(FormatError::Malformed(format!(
                        "line {}: a face needs at least 3 corners, this one has {}",
                        n + 1,
                        corners.len()
                    )));
                }
                for c in corners {
                    check_corner(c, &counts, n + 1)?;
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// One `v[/vt[/vn]]` corner: every index present is a non-zero integer naming
/// an element listed before (negative: counted back from the last one).
fn check_corner(corner: &[u8], counts: &[usize; 3], line: usize) -> FResult<()> {
    const KIND: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    for (k, part) in corner.split(|&b| b == b'/').enumerate() {
        if part.is_empty() && k > 0 {
            continue;
        }
        let text = String::from_utf8_lossy(part);
        let bad = |why: String| {
            Err(FormatError::Malformed(format!(
                "line {line}: corner {text:?}: {why}"
            )))
        };
        if k > 2 {
            return bad("a corner has at most v/vt/vn".into());
        }
        let Ok(i) = text.parse::<i64>() else {
            return bad(format!("{} index is not an integer", KIND[k]));
        };
        let n = counts[k] as i64;
        if i == 0 || i > n || i < -n {
            return bad(format!(
                "{} index {i} is out of bounds ({n} listed before this line)",
                KIND[k]
            ));
        }
    }
    Ok(())
}

fn parse(bytes: &[u8]) -> FResult<ObjContents> {
    let mut c = parse_as_written(bytes)?;
    if written_y_up(bytes) {
        c.positions
            .iter_mut()
            .for_each(|p| *p = crate::up::from_y_up(*p));
        if let Some(n) = &mut c.normals {
            n.iter_mut().for_each(|v| *v = crate::up::from_y_up(*v));
        }
    }
    Ok(c)
}

fn parse_as_written(bytes: &[u8]) -> FResult<ObjContents> {
    check_face_lines(bytes)?;
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are not needed for geometry; a missing .mtl must not fail the read.
    let (models, _materials) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &opts, |_| {
        Ok((Vec::new(), Default::default()))
    })
    .map_err(|e| FormatError::Malformed(e.to_string()))?;
    let (mut positions, mut faces) = (Vec::new(), Vec::<Vec<u32>>::new());
    let (mut normals, mut colors, mut uvs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut all_n, mut all_c, mut all_uv) = (true, true, true);
    for model in &models {
        let m = &model.mesh;
        let base = positions.len() as u32;
        let nv = m.positions.len() / 3;
        positions.extend(m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        all_n &= m.normals.len() == 3 * nv;
        all_c &= m.vertex_color.len() == 3 * nv;
        all_uv &= m.texcoords.len() == 2 * nv;
        normals.extend(m.normals.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        colors.extend(m.vertex_color.chunks_exact(3).map(|c| {
            let q = |v: f64| (v * 255.0).round().clamp(0.0, 255.0) as u8;
            [q(c[0]), q(c[1]), q(c[2]), 255]
        }));
        uvs.extend(m.texcoords.chunks_exact(2).map(|t| [t[0], t[1]]));
        let mut at = 0usize;
        let arities: Vec<u32> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.clone()
        };
        for a in arities {
            let a = a as usize;
            let Some(f) = m.indices.get(at..at + a) else {
                return Err(FormatError::Malformed("face list is inconsistent".into()));
            };
            faces.push(f.iter().map(|&i| i + base).collect());
            at += a;
        }
    }
    if faces.is_empty() {
        return Err(FormatError::Malformed("has no faces".into()));
    }
    Ok(ObjContents {
        positions,
        faces,
        normals: all_n.then_some(normals),
        colors: all_c.then_some(colors),
        uvs: all_uv.then_some(uvs),
    })
}

/// Reads a triangle mesh (polygons fanned where convex, ear-clipped where not).
pub(crate) fn read_mesh(bytes: &[u8]) -> FResult<TriMesh> {
    let c = parse(bytes)?;
    let mut m = TriMesh::from_polygons(c.positions, &c.faces)?;
    if let Some(n) = c.normals {
        m = m.with_normals(n)?;
    }
    if let Some(col) = c.colors {
        m = m.with_colors(col)?;
    }
    if let Some(uv) = c.uvs {
        m = m.with_uvs(uv)?;
    }
    Ok(m)
}

/// Reads a polygon mesh.
pub(crate) fn read_poly(bytes: &[u8]) -> FResult<PolyMesh> {
    let c = parse(bytes)?;
    Ok(PolyMesh::new(c.positions, &c.faces)?)
}

/// Writes `m` (in asperity's z-up frame) for a file whose up axis is `up`;
/// `mtl` names the material library to reference (when textured).
pub(crate) fn write_mesh(
    w: &mut dyn Write,
    m: &TriMesh,
    mtl: Option<&str>,
    up: UpAxis,
    params: Option<&str>,
) -> std::io::Result<()> {
    let flat = m.triangles().as_flattened();
    let offsets: Vec<u32> = (0..=m.n_faces() as u32).map(|f| 3 * f).collect();
    write_faces(w, m, (&offsets, flat), (mtl, params), up)
}

/// Writes polygons (CSR: `offsets` into `verts`) with the per-vertex data of
/// `m` (same vertices, in asperity's frame): positions and normals are turned
/// to the file's `up` as they are printed (no copy of the mesh), and a y-up
/// file says so in its header.
pub(crate) fn write_faces(
    w: &mut dyn Write,
    m: &TriMesh,
    (offsets, verts): (&[u32], &[u32]),
    (mtl, params): (Option<&str>, Option<&str>),
    up: UpAxis,
) -> std::io::Result<()> {
    let y_up = up == UpAxis::Y;
    let to_file = |v: [f64; 3]| if y_up { crate::up::to_y_up(v) } else { v };
    let n_faces = offsets.len().saturating_sub(1);
    writeln!(w, "# written by asperity {}", env!("CARGO_PKG_VERSION"))?;
    if let Some(p) = params {
        writeln!(w, "# {} {p}", crate::metadata::KEYWORD)?;
    }
    if y_up {
        writeln!(w, "{Y_UP_LINE}")?;
    }
    writeln!(w, "# {} vertices, {} faces", m.n_vertices(), n_faces)?;
    if let Some(lib) = mtl {
        writeln!(w, "mtllib {lib}")?;
    }
    writeln!(w, "o surface")?;
    use crate::decimal::{push_f64, push_u64, write_records};
    let floats = |text: &mut Vec<u8>, tag: &[u8], values: &[f64]| {
        text.extend_from_slice(tag);
        for &v in values {
            text.push(b' ');
            push_f64(text, v);
        }
    };
    let (positions, colors) = (m.positions(), m.colors());
    write_records(w, positions.len(), |i, text| {
        floats(text, b"v", &to_file(positions[i]));
        if let Some(c) = colors {
            // Colours keep their fixed six decimals (`{:.6}`).
            for v in &c[i][..3] {
                text.extend_from_slice(format!(" {:.6}", f64::from(*v) / 255.0).as_bytes());
            }
        }
        text.push(b'\n');
    })?;
    let uvs = m.uvs().unwrap_or(&[]);
    write_records(w, uvs.len(), |i, text| {
        floats(text, b"vt", &uvs[i]);
        text.push(b'\n');
    })?;
    let normals = m.normals().unwrap_or(&[]);
    write_records(w, normals.len(), |i, text| {
        floats(text, b"vn", &to_file(normals[i]));
        text.push(b'\n');
    })?;
    if mtl.is_some() {
        writeln!(w, "usemtl surface")?;
    }
    let (has_uv, has_n) = (m.uvs().is_some(), m.normals().is_some());
    write_records(w, n_faces, |f, text| {
        text.push(b'f');
        for &v in &verts[offsets[f] as usize..offsets[f + 1] as usize] {
            let a = u64::from(v) + 1;
            text.push(b' ');
            push_u64(text, a);
            match (has_uv, has_n) {
                (true, true) => {
                    for _ in 0..2 {
                        text.push(b'/');
                        push_u64(text, a);
                    }
                }
                (true, false) => {
                    text.push(b'/');
                    push_u64(text, a);
                }
                (false, true) => {
                    text.extend_from_slice(b"//");
                    push_u64(text, a);
                }
                (false, false) => {}
            }
        }
        text.push(b'\n');
    })?;
    Ok(())
}

/// Appends polylines as `l` elements; their points are the vertices numbered
/// from `first_vertex` (0-based) on, in order, as `write_mesh` wrote them.
pub(crate) fn write_lines(
    w: &mut dyn Write,
    lines: &[Vec<[f64; 3]>],
    first_vertex: usize,
) -> std::io::Result<()> {
    let mut next = first_vertex + 1;
    for l in lines {
        let ids: Vec<String> = (next..next + l.len()).map(|i| i.to_string()).collect();
        writeln!(w, "l {}", ids.join(" "))?;
        next += l.len();
    }
    Ok(())
}

/// The material library for a textured mesh.
pub(crate) fn write_mtl(w: &mut dyn Write, texture_file: &str) -> std::io::Result<()> {
    writeln!(w, "# written by asperity")?;
    writeln!(
        w,
        "newmtl surface\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd {texture_file}"
    )
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Wavefront OBJ",
    extensions: &["obj"],
    mesh: Access::ReadWrite,
    notes: "y-up (x, z, -y), read back unchanged; vertex colours (v x y z r g b), UVs, normals; texture as .mtl + .png; no scalars",
    read: Some(|b| read_mesh(b).map(crate::Surface::Mesh)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_groups_and_colors() {
        let src = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\ng a\nf 1 2 3 4\ng b\nf 1 3 4\n";
        let m = read_mesh(src).unwrap();
        assert_eq!(m.n_faces(), 3);
        assert_eq!(m.colors().unwrap()[1], [0, 255, 0, 255]);
        let p = read_poly(src).unwrap();
        assert_eq!(p.n_faces(), 2);
        assert!(p.faces().any(|f| f.len() == 4));
    }

    #[test]
    fn written_y_up_standing_upright_and_read_back_unchanged() {
        // a tall thin triangle along asperity's z
        let m = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.5, 3.0]],
            vec![[0, 1, 2]],
        )
        .unwrap()
        .with_computed_normals();
        let mut text = Vec::new();
        write_mesh(&mut text, &m, None, UpAxis::Y, None).unwrap();
        let s = String::from_utf8(text.clone()).unwrap();
        // in the file the height is along y, as Blender's OBJ import expects
        let ys: Vec<f64> = s
            .lines()
            .filter(|l| l.starts_with("v "))
            .map(|l| l.split_whitespace().nth(2).unwrap().parse().unwrap())
            .collect();
        assert_eq!(ys, vec![0.0, 0.0, 3.0]);
        let back = read_mesh(&text).unwrap();
        assert_eq!(back.positions(), m.positions());
        for (a, b) in back.normals().unwrap().iter().zip(m.normals().unwrap()) {
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-12));
        }
        // an OBJ asperity did not write is taken as it is (the test above reads
        // one whose z is 0 everywhere and finds it so)
        let foreign = b"v 0 0 0\nv 1 0 0\nv 0 0 3\nf 1 2 3\n";
        assert_eq!(read_mesh(foreign).unwrap().positions()[2], [0.0, 0.0, 3.0]);
    }

    #[test]
    fn bad_indices_are_errors() {
        for src in [
            &b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"[..],
            b"v 0 0 0\nf 1 x 2\n",
            b"v 0 0 0\n",
            b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        ] {
            assert!(read_mesh(src).is_err(), "{}", String::from_utf8_lossy(src));
        }
    }
}
