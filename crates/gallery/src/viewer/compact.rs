//! The 3-D view's copy of a mesh: a `.glb` that is quantized
//! (`KHR_mesh_quantization`), compressed (`EXT_meshopt_compression`) and
//! simplified above a triangle budget, so that a card's view costs a few
//! hundred kilobytes where the full-precision `.glb` costs megabytes.
//!
//! This copy is for looking only. The files a user downloads (`.glb`, `.ply`,
//! `.obj`) stay full-precision and uncompressed: Blender's importer and most
//! tools cannot read meshopt streams.
//!
//! What is stored, vertex by vertex (glTF's y-up frame, as [`glb`] writes it):
//! - `POSITION`: unsigned 16-bit integers over the mesh's bounding box, the
//!   same step on every axis (a uniform node scale keeps normals true); the
//!   node's translation and scale turn them back into metres;
//! - `NORMAL`: signed 8-bit normalized;
//! - `COLOR_0`: linear RGBA as normalized 16-bit (8-bit linear would band the
//!   darks, see [`glb`]);
//! - `TEXCOORD_0`: normalized 16-bit, with the texture as PNG.
//!
//! Vertices equal after quantization are merged first (a cell-coloured mesh
//! repeats each corner once per cell); a mesh still above the budget is
//! simplified with meshoptimizer's edge collapse, which keeps colour seams and
//! leaves open borders where they are (a cell mesh's base triangles meet at
//! unmatched borders, which would crack), and then ordered for the vertex
//! cache and fetch. A mesh that is all seams and borders (a cell mesh of a
//! colour per cell) stays above the budget. Streams are encoded with
//! meshoptimizer's vertex codec version 0 and index codec, the only versions
//! `EXT_meshopt_compression` allows. The encoder is the
//! `meshopt` crate (bindings to meshoptimizer, the format's reference
//! implementation); the page decodes with the decoder bundled in
//! `<model-viewer>` (see [`super`]).
//!
//! [`glb`]: asperity_engine::io::glb

use asperity_engine::core::{RgbaImage, TriMesh};
use asperity_engine::io::glb::{
    self, ARRAY_BUFFER, BYTE, ELEMENT_ARRAY_BUFFER, UNSIGNED_INT, UNSIGNED_SHORT,
};
use meshopt::{SimplifyOptions, VertexDataAdapter};
use serde_json::{Value, json};

/// Meshes with more triangles are simplified to about this many for the view
/// (a 400-pixel card shows no more; zoomed in, the downloads have them all).
pub const TRIANGLE_BUDGET: usize = 150_000;

/// How far simplification may move the surface, relative to the mesh's size:
/// the first that meets the budget (a mesh of many colour seams needs more).
const SIMPLIFY_ERRORS: [f32; 3] = [0.005, 0.02, 0.1];

/// One vertex as the view stores it; padded to whole 4-byte words, as glTF
/// requires of vertex strides.
#[derive(Clone, Copy, Default, PartialEq)]
#[repr(C)]
struct Vertex {
    position: [u16; 4],
    normal: [i8; 4],
    color: [u16; 4],
    uv: [u16; 2],
}

/// What the view copy is made of: the quantized vertices and triangles, the
/// node's dequantization and the texture, if any.
struct Quantized {
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    offset: [f32; 3],
    step: f32,
    texture: Option<RgbaImage>,
}

fn quantize(m: &TriMesh) -> Quantized {
    let positions = glb::y_up_positions(m);
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in &positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f32, f32::max);
    let step = if extent > 0.0 { extent / 65535.0 } else { 1.0 };
    let normals = glb::y_up_unit_normals(m);
    let colors = m.colors();
    let textured = glb::texture_and_uvs(m);
    let unit16 = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
    let vertices = (0..positions.len())
        .map(|i| {
            let p = positions[i];
            let q = |k: usize| ((p[k] - lo[k]) / step).round().clamp(0.0, 65535.0) as u16;
            let n = normals[i].map(|v| (v.clamp(-1.0, 1.0) * 127.0).round() as i8);
            Vertex {
                position: [q(0), q(1), q(2), 0],
                normal: [n[0], n[1], n[2], 0],
                color: colors.map_or([0; 4], |c| glb::linear_u16(c[i])),
                uv: textured
                    .as_ref()
                    .map_or([0; 2], |(_, t)| [unit16(t[i][0]), unit16(t[i][1])]),
            }
        })
        .collect();
    Quantized {
        vertices,
        indices: m.triangles().iter().flatten().copied().collect(),
        offset: lo,
        step,
        texture: textured.map(|(image, _)| image),
    }
}

/// Merges vertices equal after quantization, simplifies above `budget`
/// triangles and orders what is left for the vertex cache and fetch.
fn optimise(q: &mut Quantized, budget: usize) {
    let (count, remap) = meshopt::generate_vertex_remap(&q.vertices, Some(&q.indices));
    q.indices = meshopt::remap_index_buffer(Some(&q.indices), count, &remap);
    q.vertices = meshopt::remap_vertex_buffer(&q.vertices, count, &remap);
    drop_degenerate(&mut q.indices);
    if q.indices.len() / 3 > budget {
        // positions as meshoptimizer reads them: three native-order f32s
        let bytes: Vec<u8> = q
            .vertices
            .iter()
            .flat_map(|v| v.position[..3].iter().map(|&c| f32::from(c)))
            .flat_map(f32::to_ne_bytes)
            .collect();
        if let Ok(adapter) = VertexDataAdapter::new(&bytes, 12, 0) {
            // the least error that meets the budget, in three steps
            for error in SIMPLIFY_ERRORS {
                q.indices = meshopt::simplify(
                    &q.indices,
                    &adapter,
                    budget * 3,
                    error,
                    // unmatched borders stay (see crate::downloads)
                    SimplifyOptions::LockBorder,
                    None,
                );
                if q.indices.len() / 3 <= budget {
                    break;
                }
            }
        }
    }
    drop_degenerate(&mut q.indices);
    meshopt::optimize_vertex_cache_in_place(&mut q.indices, q.vertices.len());
    q.vertices = meshopt::optimize_vertex_fetch(&mut q.indices, &q.vertices);
}

/// Removes the triangles that use a vertex twice: merging vertices closer than
/// the quantization step turns the tiniest triangles into lines.
fn drop_degenerate(indices: &mut Vec<u32>) {
    let kept: Vec<u32> = indices
        .chunks_exact(3)
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .flatten()
        .copied()
        .collect();
    *indices = kept;
}

/// The binary chunk and the two buffers' views: each stream is stored
/// compressed in buffer 0 and declared, decoded, in the fallback buffer 1.
#[derive(Default)]
struct Streams {
    bin: Vec<u8>,
    decoded_len: usize,
    views: Vec<Value>,
}

impl Streams {
    fn pad(&mut self) {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
    }

    /// A meshopt-compressed view of `count` elements of `stride` bytes.
    fn compressed(&mut self, encoded: &[u8], count: usize, stride: usize, mode: &str) -> usize {
        self.pad();
        let mut ext = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": encoded.len(),
            "byteStride": stride, "mode": mode, "count": count});
        self.bin.extend_from_slice(encoded);
        let len = count * stride;
        let mut view = json!({"buffer": 1, "byteOffset": self.decoded_len, "byteLength": len});
        if mode == "ATTRIBUTES" {
            view["byteStride"] = json!(stride);
            view["target"] = json!(ARRAY_BUFFER);
        } else {
            view["target"] = json!(ELEMENT_ARRAY_BUFFER);
            ext["byteStride"] = json!(stride);
        }
        view["extensions"] = json!({"EXT_meshopt_compression": ext});
        self.decoded_len = (self.decoded_len + len).next_multiple_of(4);
        self.views.push(view);
        self.views.len() - 1
    }

    /// A plain view in buffer 0 (the texture's PNG).
    fn plain(&mut self, bytes: &[u8]) -> usize {
        self.pad();
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }
}

/// One vertex attribute of `v` (each field read by `field`) as a compressed
/// stream of `N`-byte elements.
fn attribute<const N: usize>(
    s: &mut Streams,
    v: &[Vertex],
    field: impl Fn(&Vertex) -> [u8; N],
) -> std::io::Result<usize> {
    let items: Vec<[u8; N]> = v.iter().map(field).collect();
    let encoded = meshopt::encode_vertex_buffer_level(&items, 2, Some(0))
        .map_err(|e| std::io::Error::other(format!("meshopt: {e:?}")))?;
    Ok(s.compressed(&encoded, items.len(), N, "ATTRIBUTES"))
}

fn le16<const N: usize, const B: usize>(v: [u16; N]) -> [u8; B] {
    let mut out = [0; B];
    for (k, x) in v.iter().enumerate() {
        out[2 * k..2 * k + 2].copy_from_slice(&x.to_le_bytes());
    }
    out
}

/// The view copy of `m` as `.glb` bytes, simplified to about `budget`
/// triangles when it has more.
///
/// # Errors
/// The encoder's (none expected), or a mesh over glTF's sizes.
pub fn encode(m: &TriMesh, budget: usize) -> std::io::Result<Vec<u8>> {
    let mut q = quantize(m);
    optimise(&mut q, budget);
    let v = &q.vertices;
    let mut s = Streams::default();
    let mut attributes = json!({
        "POSITION": attribute(&mut s, v, |x| le16::<4, 8>(x.position))?,
        "NORMAL": attribute(&mut s, v, |x| x.normal.map(|c| c as u8))?,
    });
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": UNSIGNED_SHORT, "count": v.len(), "type": "VEC3",
            "min": quantized_bound(v, u16::min, u16::MAX), "max": quantized_bound(v, u16::max, 0)}),
        json!({"bufferView": 1, "componentType": BYTE, "normalized": true, "count": v.len(), "type": "VEC3"}),
    ];
    if m.colors().is_some() {
        let view = attribute(&mut s, v, |x| le16::<4, 8>(x.color))?;
        attributes["COLOR_0"] = json!(accessors.len());
        accessors.push(json!({"bufferView": view, "componentType": UNSIGNED_SHORT, "normalized": true, "count": v.len(), "type": "VEC4"}));
    }
    if q.texture.is_some() {
        let view = attribute(&mut s, v, |x| le16::<2, 4>(x.uv))?;
        attributes["TEXCOORD_0"] = json!(accessors.len());
        accessors.push(json!({"bufferView": view, "componentType": UNSIGNED_SHORT, "normalized": true, "count": v.len(), "type": "VEC2"}));
    }
    let encoded = meshopt::encode_index_buffer(&q.indices, v.len())
        .map_err(|e| std::io::Error::other(format!("meshopt: {e:?}")))?;
    let (stride, component) = if v.len() <= usize::from(u16::MAX) {
        (2, UNSIGNED_SHORT)
    } else {
        (4, UNSIGNED_INT)
    };
    let view = s.compressed(&encoded, q.indices.len(), stride, "TRIANGLES");
    let indices = accessors.len();
    accessors.push(json!({"bufferView": view, "componentType": component, "count": q.indices.len(), "type": "SCALAR"}));

    let scale = [q.step; 3];
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": format!("asperity {} (view copy)", env!("CARGO_PKG_VERSION"))},
        "extensionsUsed": ["EXT_meshopt_compression", "KHR_mesh_quantization"],
        "extensionsRequired": ["EXT_meshopt_compression", "KHR_mesh_quantization"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "surface", "translation": q.offset, "scale": scale}],
        "meshes": [{"name": "surface", "primitives": [{"attributes": attributes, "indices": indices, "material": 0, "mode": 4}]}],
    });
    let image = match &q.texture {
        Some(tex) => Some(s.plain(&glb::texture_png(tex)?)),
        None => None,
    };
    glb::set_material(&mut doc, image);
    s.pad();
    doc["buffers"] = json!([
        {"byteLength": s.bin.len()},
        {"byteLength": s.decoded_len, "extensions": {"EXT_meshopt_compression": {"fallback": true}}},
    ]);
    doc["bufferViews"] = json!(s.views);
    doc["accessors"] = json!(accessors);
    let mut out = Vec::new();
    glb::write_container(&mut out, &doc, &s.bin)?;
    Ok(out)
}

/// The component-wise bound (`pick` = min or max, from `start`) of the
/// quantized positions, as glTF requires of `POSITION`.
fn quantized_bound(v: &[Vertex], pick: fn(u16, u16) -> u16, start: u16) -> [u16; 3] {
    v.iter().fold([start; 3], |b, x| {
        [
            pick(b[0], x.position[0]),
            pick(b[1], x.position[1]),
            pick(b[2], x.position[2]),
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `w`×`w` grid of squares over the unit square, heights a gentle wave.
    fn grid(w: u32) -> TriMesh {
        let mut p = Vec::new();
        for j in 0..=w {
            for i in 0..=w {
                let (x, y) = (f64::from(i) / f64::from(w), f64::from(j) / f64::from(w));
                p.push([x, y, 0.05 * (6.0 * x).sin() * (4.0 * y).cos()]);
            }
        }
        let mut t = Vec::new();
        for j in 0..w {
            for i in 0..w {
                let a = j * (w + 1) + i;
                t.push([a, a + 1, a + w + 2]);
                t.push([a, a + w + 2, a + w + 1]);
            }
        }
        TriMesh::new(p, t).unwrap()
    }

    #[test]
    fn small_meshes_keep_every_triangle_and_large_ones_meet_the_budget() {
        let m = grid(40);
        let q = {
            let mut q = quantize(&m);
            optimise(&mut q, TRIANGLE_BUDGET);
            q
        };
        assert_eq!(q.indices.len(), 3 * m.n_faces());
        assert_eq!(q.vertices.len(), m.n_vertices());
        let mut q = quantize(&m);
        optimise(&mut q, 400);
        let kept = q.indices.len() / 3;
        assert!((200..=400).contains(&kept), "{kept} triangles");
        assert!(q.vertices.len() < m.n_vertices() / 2);
    }

    #[test]
    fn positions_come_back_within_half_a_step() {
        let m = grid(30);
        let q = quantize(&m);
        let ys = glb::y_up_positions(&m);
        for (v, p) in q.vertices.iter().zip(&ys) {
            for ((&offset, &code), &want) in q.offset.iter().zip(&v.position).zip(p) {
                let back = offset + q.step * f32::from(code);
                assert!(
                    (back - want).abs() <= 0.5 * q.step + 1e-6,
                    "{back} vs {want}"
                );
            }
        }
    }
}
