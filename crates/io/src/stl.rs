//! STL: binary written; binary and ASCII read.
//!
//! Written by hand (the format is 50 bytes a triangle). STL stores each triangle's
//! three corners separately, in `f32`; reading welds corners with bit-identical
//! coordinates back into shared vertices, so a mesh written and read again has its
//! connectivity back. Colours, UVs and scalars have no place in STL.

use std::collections::HashMap;
use std::io::Write;

use asperity_core::TriMesh;

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Registration};

/// Writes binary STL: 80-byte header, count, then normal + 3 corners + 0u16 per triangle.
pub(crate) fn write_mesh(w: &mut dyn Write, m: &TriMesh) -> std::io::Result<()> {
    let mut header = [b' '; 80];
    let text = format!(
        "binary STL written by asperity {}",
        env!("CARGO_PKG_VERSION")
    );
    header[..text.len()].copy_from_slice(text.as_bytes());
    w.write_all(&header)?;
    let n = u32::try_from(m.n_faces())
        .map_err(|_| std::io::Error::other("more than 2^32 triangles"))?;
    w.write_all(&n.to_le_bytes())?;
    let mut rec = [0u8; 50];
    for (t, normal) in m.triangles().iter().zip(m.face_normals()) {
        let vals = normal
            .iter()
            .chain(t.iter().flat_map(|&v| m.positions()[v as usize].iter()));
        for (k, v) in vals.enumerate() {
            rec[4 * k..4 * k + 4].copy_from_slice(&(*v as f32).to_le_bytes());
        }
        w.write_all(&rec)?;
    }
    Ok(())
}

fn weld(corners: Vec<[f32; 3]>) -> FResult<TriMesh> {
    let mut index: HashMap<[u32; 3], u32> = HashMap::with_capacity(corners.len() / 2);
    let mut positions = Vec::with_capacity(corners.len() / 2);
    let mut ids = Vec::with_capacity(corners.len());
    for c in corners {
        // +0.0 and -0.0 weld together.
        let key = c.map(|v| if v == 0.0 { 0 } else { v.to_bits() });
        let id = *index.entry(key).or_insert_with(|| {
            positions.push(c.map(f64::from));
            (positions.len() - 1) as u32
        });
        ids.push(id);
    }
    let tris = ids.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    Ok(TriMesh::new(positions, tris)?)
}

/// Reads binary or ASCII STL.
pub(crate) fn read_mesh(bytes: &[u8]) -> FResult<TriMesh> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() as u128 == 84 + 50 * n as u128 {
            return read_binary(bytes, n);
        }
    }
    if bytes.trim_ascii_start().starts_with(b"solid") {
        return read_ascii(bytes);
    }
    if bytes.len() < 84 {
        return malformed(format!(
            "{} bytes is too short for binary STL (84-byte header)",
            bytes.len()
        ));
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u128;
    malformed(format!(
        "header declares {n} triangles ({} bytes) but the file has {} bytes (truncated?)",
        84 + 50 * n,
        bytes.len()
    ))
}

fn read_binary(bytes: &[u8], n: usize) -> FResult<TriMesh> {
    let mut corners = Vec::with_capacity(3 * n);
    for rec in bytes[84..].chunks_exact(50) {
        for c in 0..3 {
            let o = 12 + 12 * c;
            let f = |k: usize| {
                f32::from_le_bytes([
                    rec[o + 4 * k],
                    rec[o + 4 * k + 1],
                    rec[o + 4 * k + 2],
                    rec[o + 4 * k + 3],
                ])
            };
            corners.push([f(0), f(1), f(2)]);
        }
    }
    weld(corners)
}

fn read_ascii(bytes: &[u8]) -> FResult<TriMesh> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| FormatError::Malformed("ASCII STL is not text".into()))?;
    let mut corners = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let mut w = line.split_whitespace();
        if w.next() == Some("vertex") {
            let mut c = [0f32; 3];
            for v in &mut c {
                let tok = w.next().unwrap_or("");
                *v = tok.parse().map_err(|_| {
                    FormatError::Malformed(format!("line {}: bad vertex {line:?}", n + 1))
                })?;
            }
            corners.push(c);
        }
    }
    if corners.len() % 3 != 0 {
        return malformed(format!(
            "{} vertex lines is not a whole number of triangles",
            corners.len()
        ));
    }
    weld(corners)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "STL (binary; ASCII also read)",
    extensions: &["stl"],
    mesh: Access::ReadWrite,
    notes: "f32 corners, welded on read; geometry only",
    read: Some(|b| read_mesh(b).map(crate::Surface::Mesh)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_and_truncated() {
        let src = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let m = read_mesh(src).unwrap();
        assert_eq!((m.n_vertices(), m.n_faces()), (3, 1));
        let mut bin = vec![0u8; 80];
        bin.extend_from_slice(&2u32.to_le_bytes());
        bin.extend_from_slice(&[0u8; 60]);
        let FormatError::Malformed(msg) = read_mesh(&bin).unwrap_err() else {
            panic!()
        };
        assert!(msg.contains("declares 2 triangles"), "{msg}");
    }
}
