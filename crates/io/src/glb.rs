//! glTF 2.0 binary (`.glb`) writer: positions, normals, vertex colours, UVs with an
//! embedded PNG texture, and named scalars as custom `_NAME` attributes.
//!
//! The JSON is assembled with `serde_json` rather than `gltf-json`: it is a few
//! dozen fixed fields, and the output is checked in tests by the independent
//! `gltf` crate (which validates on load) and by Python's `trimesh`.
//!
//! # Conventions
//! glTF is **y-up**, asperity is z-up: a point (x, y, z) is written as
//! (x, z, −y), a rotation that keeps faces front-facing, so Blender's importer
//! (which turns y-up back into z-up) shows the surface as asperity does.
//! glTF's texture origin is the top-left, so `v` is written as `1 − v`.
//!
//! # Colour spaces
//! glTF defines `COLOR_0` as **linear** RGB, while asperity's vertex colours
//! (like PLY's and OBJ's) are sRGB bytes: they are converted with the sRGB
//! transfer function and written as normalized 16-bit integers, so that a
//! viewer's conversion back to sRGB lands within 1/255 of the original even in
//! the darks (8-bit linear would lose them). Alpha is linear already. Texture
//! images stay sRGB, as the specification says of `baseColorTexture`.
//!
//! # Validator-clean output
//! `TEXCOORD_0` is written only with the texture it addresses (the Khronos
//! validator reports unused UVs), and a texture whose sides are not powers of
//! two is padded to the next ones (edge pixels repeated, UVs scaled to the
//! original block): mipmapped sampling needs power-of-two images in some
//! viewers, and the validator reports them otherwise.

use std::io::Write;

use asperity_core::{RgbaImage, TriMesh};
use serde_json::{Value, json};
use crate::format::{Access, Registration};

/// glTF's buffer-view targets and accessor component types (the WebGL enums).
pub const ARRAY_BUFFER: u32 = 34962;
/// See [`ARRAY_BUFFER`].
pub const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// See [`ARRAY_BUFFER`].
pub const BYTE: u32 = 5120;
/// See [`ARRAY_BUFFER`].
pub const UNSIGNED_SHORT: u32 = 5123;
/// See [`ARRAY_BUFFER`].
pub const UNSIGNED_INT: u32 = 5125;
/// See [`ARRAY_BUFFER`].
pub const FLOAT: u32 = 5126;

fn to_y_up(p: [f64; 3]) -> [f32; 3] {
    [p[0] as f32, p[2] as f32, -p[1] as f32]
}

/// An sRGB byte as a linear value in [0, 1] (the sRGB transfer function,
/// IEC 61966-2-1).
pub fn srgb_to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// An sRGB colour with linear alpha as linear 16-bit RGBA (glTF's `COLOR_0`).
pub fn linear_u16(rgba: [u8; 4]) -> [u16; 4] {
    let q = |v: f64| (v * 65535.0).round() as u16;
    [
        q(srgb_to_linear(rgba[0])),
        q(srgb_to_linear(rgba[1])),
        q(srgb_to_linear(rgba[2])),
        q(f64::from(rgba[3]) / 255.0),
    ]
}

/// `tex` padded to power-of-two sides (the original in the top-left corner,
/// its last column and row repeated into the padding) and the factors that
/// map the original's texture coordinates into the padded image.
fn power_of_two(tex: &RgbaImage) -> (RgbaImage, [f64; 2]) {
    let (w, h) = (tex.width(), tex.height());
    let (pw, ph) = (w.next_power_of_two(), h.next_power_of_two());
    if (pw, ph) == (w, h) {
        return (tex.clone(), [1.0, 1.0]);
    }
    let mut out = RgbaImage::filled(pw, ph, [0, 0, 0, 0]);
    for y in 0..ph {
        for x in 0..pw {
            out.put(x, y, tex.get(x.min(w - 1), y.min(h - 1)));
        }
    }
    let scale = [f64::from(w) / f64::from(pw), f64::from(h) / f64::from(ph)];
    (out, scale)
}

/// Collects buffer views and accessors over one binary chunk.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.data.len().is_multiple_of(4) {
            self.data.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.data.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.data.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(&mut self, bytes: &[u8], target: u32, mut acc: Value) -> usize {
        let view = self.view(bytes, Some(target));
        acc["bufferView"] = json!(view);
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    fn floats<const N: usize>(&mut self, items: &[[f32; N]], ty: &str, bounds: bool) -> usize {
        let bytes: Vec<u8> = items
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let mut acc = json!({"componentType": FLOAT, "count": items.len(), "type": ty});
        if bounds {
            let mut lo = [f32::INFINITY; N];
            let mut hi = [f32::NEG_INFINITY; N];
            for it in items {
                for k in 0..N {
                    lo[k] = lo[k].min(it[k]);
                    hi[k] = hi[k].max(it[k]);
                }
            }
            acc["min"] = json!(lo.to_vec());
            acc["max"] = json!(hi.to_vec());
        }
        self.accessor(&bytes, ARRAY_BUFFER, acc)
    }
}

/// The positions of `m` in glTF's y-up frame.
pub fn y_up_positions(m: &TriMesh) -> Vec<[f32; 3]> {
    m.positions().iter().map(|&p| to_y_up(p)).collect()
}

/// The unit normals of `m` in glTF's y-up frame (glTF requires unit normals;
/// degenerate vertices get the up vector).
pub fn y_up_unit_normals(m: &TriMesh) -> Vec<[f32; 3]> {
    m.normals()
        .map(<[_]>::to_vec)
        .unwrap_or_else(|| m.vertex_normals())
        .into_iter()
        .map(|n| {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if l > 1e-12 {
                to_y_up(n.map(|v| v / l))
            } else {
                [0.0, 1.0, 0.0]
            }
        })
        .collect()
}

/// The texture of `m` padded to power-of-two sides and the glTF texture
/// coordinates (top-left origin) that address it, if `m` has both.
pub fn texture_and_uvs(m: &TriMesh) -> Option<(RgbaImage, Vec<[f32; 2]>)> {
    let (tex, uv) = (m.texture()?, m.uvs()?);
    let (image, scale) = power_of_two(tex);
    let t = uv
        .iter()
        .map(|t| [(t[0] * scale[0]) as f32, ((1.0 - t[1]) * scale[1]) as f32])
        .collect();
    Some((image, t))
}

/// The vertex attributes of `m` in `bin`: positions, unit normals, linear
/// colours, UVs (with the power-of-two texture they address) and scalars.
fn vertex_attributes(bin: &mut Bin, m: &TriMesh) -> (Value, Option<RgbaImage>) {
    let mut attributes = json!({"POSITION": bin.floats(&y_up_positions(m), "VEC3", true)});
    attributes["NORMAL"] = json!(bin.floats(&y_up_unit_normals(m), "VEC3", false));
    if let Some(c) = m.colors() {
        let bytes: Vec<u8> = c
            .iter()
            .flat_map(|&rgba| linear_u16(rgba))
            .flat_map(u16::to_le_bytes)
            .collect();
        let acc = json!({"componentType": UNSIGNED_SHORT, "normalized": true, "count": c.len(), "type": "VEC4"});
        attributes["COLOR_0"] = json!(bin.accessor(&bytes, ARRAY_BUFFER, acc));
    }
    let texture = texture_and_uvs(m).map(|(image, t)| {
        attributes["TEXCOORD_0"] = json!(bin.floats(&t, "VEC2", false));
        image
    });
    for a in m.scalars() {
        let vals: Vec<[f32; 1]> = a.values.iter().map(|&v| [v as f32]).collect();
        let name: String = a
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() {
                    c.to_ascii_uppercase()
                } else {
                    '_'
                }
            })
            .collect();
        attributes[format!("_{name}")] = json!(bin.floats(&vals, "SCALAR", false));
    }
    (attributes, texture)
}

/// `m` as the bytes of a `.glb` file (what [`crate::write_mesh`] writes), for
/// embedding elsewhere (the gallery's 3-D views).
///
/// # Errors
/// As the writer (a mesh too large for glTF's 32-bit sizes).
pub fn encode(m: &TriMesh) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    write_mesh(&mut out, m, None)?;
    Ok(out)
}

/// Writes `m` as a single-mesh, single-node `.glb`; `params` (the parameters
/// it was made with, one line of JSON) go into `asset.extras`.
pub(crate) fn write_mesh(
    w: &mut dyn Write,
    m: &TriMesh,
    params: Option<&str>,
) -> std::io::Result<()> {
    let mut bin = Bin::default();
    let (attributes, texture) = vertex_attributes(&mut bin, m);
    let idx: Vec<u8> = m
        .triangles()
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let indices = bin.accessor(
        &idx,
        ELEMENT_ARRAY_BUFFER,
        json!({"componentType": UNSIGNED_INT, "count": 3 * m.n_faces(), "type": "SCALAR"}),
    );

    let mut doc = json!({
        "asset": {"version": "2.0", "generator": format!("asperity {}", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "surface"}],
        "meshes": [{"name": "surface", "primitives": [{"attributes": attributes, "indices": indices, "material": 0, "mode": 4}]}],
    });
    if let Some(p) = params {
        let value: serde_json::Value = serde_json::from_str(p).map_err(std::io::Error::other)?;
        doc["asset"]["extras"] = json!({ "asperity_params": value });
    }
    let image = match &texture {
        Some(tex) => Some(bin.view(&texture_png(tex)?, None)),
        None => None,
    };
    set_material(&mut doc, image);
    while !bin.data.len().is_multiple_of(4) {
        bin.data.push(0);
    }
    doc["buffers"] = json!([{"byteLength": bin.data.len()}]);
    doc["bufferViews"] = json!(bin.views);
    doc["accessors"] = json!(bin.accessors);

    write_container(w, &doc, &bin.data)
}

/// The PNG bytes of a texture, as a `.glb` embeds it.
///
/// # Errors
/// The PNG encoder's.
pub fn texture_png(tex: &RgbaImage) -> std::io::Result<Vec<u8>> {
    crate::png_io::encode_rgba(tex).map_err(std::io::Error::other)
}

/// Gives `doc` its one material (matte, two-sided) and, where `image_view`
/// is the buffer view of a PNG, that image as its base colour texture.
pub fn set_material(doc: &mut Value, image_view: Option<usize>) {
    let mut pbr = json!({"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8});
    if let Some(view) = image_view {
        doc["images"] = json!([{"bufferView": view, "mimeType": "image/png"}]);
        doc["samplers"] =
            json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}]);
        doc["textures"] = json!([{"source": 0, "sampler": 0}]);
        pbr["baseColorTexture"] = json!({"index": 0, "texCoord": 0});
    }
    doc["materials"] =
        json!([{"name": "surface", "pbrMetallicRoughness": pbr, "doubleSided": true}]);
}

/// Writes a `.glb` container: the header, `doc` as the JSON chunk and `bin`
/// (padded to 4 bytes) as the binary chunk.
///
/// # Errors
/// The writer's, or a file over glTF's 4 GiB limit.
pub fn write_container(w: &mut dyn Write, doc: &Value, bin: &[u8]) -> std::io::Result<()> {
    let mut text = serde_json::to_vec(doc).map_err(std::io::Error::other)?;
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let pad = bin.len().next_multiple_of(4) - bin.len();
    let total = 12 + 8 + text.len() + 8 + bin.len() + pad;
    let total = u32::try_from(total)
        .map_err(|_| std::io::Error::other("a .glb file is limited to 4 GiB"))?;
    w.write_all(b"glTF")?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&total.to_le_bytes())?;
    w.write_all(&(text.len() as u32).to_le_bytes())?;
    w.write_all(b"JSON")?;
    w.write_all(&text)?;
    w.write_all(&((bin.len() + pad) as u32).to_le_bytes())?;
    w.write_all(b"BIN\0")?;
    w.write_all(bin)?;
    w.write_all(&[0; 3][..pad])
}

/// The parameters in `asset.extras.asperity_params` of a `.glb` file.
pub(crate) fn params(bytes: &[u8]) -> crate::error::FResult<Option<serde_json::Value>> {
    let bad = |why: &str| crate::error::FormatError::Malformed(format!("not a glTF binary: {why}"));
    if bytes.len() < 20 || &bytes[..4] != b"glTF" || &bytes[16..20] != b"JSON" {
        return Err(bad("no glTF header and JSON chunk"));
    }
    let len = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
    let text = bytes
        .get(20..20 + len)
        .ok_or_else(|| bad("the JSON chunk is cut short"))?;
    let doc: serde_json::Value =
        serde_json::from_slice(text).map_err(|e| bad(&format!("its JSON: {e}")))?;
    Ok(doc
        .pointer("/asset/extras/asperity_params")
        .filter(|v| v.is_object())
        .cloned())
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "glTF 2.0 binary",
    extensions: &["glb"],
    mesh: Access::Write,
    notes: "y-up (x, z, -y); normals, linear COLOR_0, TEXCOORD_0 + embedded PNG texture (padded to powers of two), scalars as _NAME",
    ..Registration::NONE
};
