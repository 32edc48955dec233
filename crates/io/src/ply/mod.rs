//! PLY (Stanford polygon format), ASCII and binary, both endiannesses.
//!
//! Written by hand: the PLY crates on crates.io are unmaintained, and the format
//! is small. Reading follows Greg Turk's specification (paulbourke.net/dataformats/ply):
//! any elements and properties, all scalar types and their `int8`…`float64`
//! aliases, list properties. Unknown elements are skipped.
//!
//! # Vertex properties
//! | Meaning | Written as | Also read as |
//! | --- | --- | --- |
//! | position | `double x, y, z` | any scalar type |
//! | normal | `float nx, ny, nz` | any scalar type |
//! | colour | `uchar red, green, blue, alpha` | float colours in [0, 1]; alpha optional |
//! | texture coordinate | `float s, t` | `u, v`, `texture_u, texture_v`, `texture_s, texture_t` |
//! | named scalar | `double NAME` | any other scalar vertex property |
//! | integer label | `int NAME` for `label`, `…_label`, `…_id`, `…_index` with integer values | as above |
//!
//! Faces are `element face` with `property list uchar uint vertex_indices`
//! (`vertex_index` is also read). Polygons with more than three corners are kept
//! by [`crate::read_poly_mesh`] and triangulated by [`crate::read_mesh`] (fanned where convex, ear-clipped where not). A file without faces
//! is a point set.

use asperity_core::{CoreError, PointSet, PolyMesh, TriMesh};

use crate::error::{FResult, FormatError, malformed};

/// ASCII or binary (little-endian) output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    /// `format ascii 1.0`
    Ascii,
    /// `format binary_little_endian 1.0` (the default: smaller and faster)
    BinaryLittleEndian,
}

/// How a PLY file is written: its encoding, and whether positions and
/// named scalars are `float` rather than `double` (normals and texture
/// coordinates are always `float`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PlyFormat {
    pub(crate) encoding: PlyEncoding,
    pub(crate) float32: bool,
}

impl PlyFormat {
    fn ascii(self) -> bool {
        self.encoding == PlyEncoding::Ascii
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
enum PropKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: PropKind,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Le,
    Be,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body: usize,
}

/// A `property …` line's words as a property.
fn parse_property(w: &[&str]) -> Result<Property, &'static str> {
    let kind = if w.get(1) == Some(&"list") {
        let (Some(c), Some(i)) = (
            w.get(2).and_then(|s| Scalar::parse(s)),
            w.get(3).and_then(|s| Scalar::parse(s)),
        ) else {
            return Err("bad list property types");
        };
        if !c.is_integer() {
            return Err("list count type must be an integer type");
        }
        PropKind::List { count: c, item: i }
    } else {
        PropKind::Scalar(
            w.get(1)
                .and_then(|s| Scalar::parse(s))
                .ok_or("unknown property type")?,
        )
    };
    let name = w
        .last()
        .filter(|_| w.len() >= 3)
        .ok_or("property needs a name")?;
    Ok(Property {
        name: (*name).to_owned(),
        kind,
    })
}

/// One header line's words into the encoding or the elements.
fn header_line(
    w: &[&str],
    encoding: &mut Option<Encoding>,
    elements: &mut Vec<Element>,
) -> Result<(), &'static str> {
    match w.first().copied() {
        None | Some("comment") | Some("obj_info") => {}
        Some("format") => {
            *encoding = Some(match w.get(1).copied() {
                Some("ascii") => Encoding::Ascii,
                Some("binary_little_endian") => Encoding::Le,
                Some("binary_big_endian") => Encoding::Be,
                _ => return Err("unknown format"),
            });
        }
        Some("element") => {
            let (Some(name), Some(count)) = (w.get(1), w.get(2)) else {
                return Err("element needs a name and a count");
            };
            let count = count.parse().map_err(|_| "bad element count")?;
            elements.push(Element {
                name: (*name).to_owned(),
                count,
                props: Vec::new(),
            });
        }
        Some("property") => {
            let el = elements.last_mut().ok_or("property before any element")?;
            el.props.push(parse_property(w)?);
        }
        Some(_) => return Err("unknown header keyword"),
    }
    Ok(())
}

fn parse_header(bytes: &[u8]) -> FResult<Header> {
    if !bytes.starts_with(b"ply") {
        return malformed("does not start with the `ply` magic line");
    }
    let end = find(bytes, b"end_header")
        .ok_or_else(|| FormatError::Malformed("no `end_header` line".into()))?;
    // The body starts after the newline that ends `end_header` (\n or \r\n).
    let mut body = end + b"end_header".len();
    if bytes.get(body) == Some(&b'\r') {
        body += 1;
    }
    if bytes.get(body) == Some(&b'\n') {
        body += 1;
    }
    let text = std::str::from_utf8(&bytes[..end])
        .map_err(|_| FormatError::Malformed("header is not text".into()))?;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in text.lines().enumerate().skip(1) {
        let w: Vec<&str> = line.split_whitespace().collect();
        header_line(&w, &mut encoding, &mut elements).map_err(|what| {
            FormatError::Malformed(format!("header line {}: {what}: {line:?}", n + 1))
        })?;
    }
    let encoding =
        encoding.ok_or_else(|| FormatError::Malformed("header has no `format` line".into()))?;
    Ok(Header {
        encoding,
        elements,
        body,
    })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Sequential value source over the body, ASCII or binary.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    encoding: Encoding,
}

impl Body<'_> {
    fn scalar(&mut self, s: Scalar) -> FResult<f64> {
        match self.encoding {
            Encoding::Ascii => {
                let b = self.bytes;
                while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
                    self.pos += 1;
                }
                let start = self.pos;
                while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
                    self.pos += 1;
                }
                if start == self.pos {
                    return malformed("file ends early (truncated)");
                }
                let tok = std::str::from_utf8(&b[start..self.pos]).unwrap_or("?");
                tok.parse::<f64>()
                    .map_err(|_| FormatError::Malformed(format!("{tok:?} is not a number")))
            }
            enc => {
                let n = s.size();
                let Some(raw) = self.bytes.get(self.pos..self.pos + n) else {
                    return malformed("file ends early (truncated)");
                };
                self.pos += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(raw);
                if enc == Encoding::Be {
                    a[..n].reverse();
                }
                Ok(match s {
                    Scalar::I8 => a[0] as i8 as f64,
                    Scalar::U8 => a[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(a),
                })
            }
        }
    }

    fn count(&mut self, s: Scalar) -> FResult<usize> {
        let v = self.scalar(s)?;
        if v < 0.0 || v.fract() != 0.0 {
            return malformed(format!("list length {v} is not a non-negative integer"));
        }
        Ok(v as usize)
    }
}

/// Everything read from a PLY file, before deciding what it is.
pub(crate) struct Contents {
    pub positions: Vec<[f64; 3]>,
    pub normals: Option<Vec<[f64; 3]>>,
    pub colors: Option<Vec<[u8; 4]>>,
    pub uvs: Option<Vec<[f64; 2]>>,
    pub scalars: Vec<(String, Vec<f64>)>,
    pub faces: Vec<Vec<u32>>,
    pub has_face_element: bool,
}

const UV_NAMES: [(&str, &str); 4] = [
    ("s", "t"),
    ("u", "v"),
    ("texture_u", "texture_v"),
    ("texture_s", "texture_t"),
];

/// A vertex property column read: name, type, values.
type ReadColumn = (String, Scalar, Vec<f64>);

/// The values of every element: vertex columns and faces.
struct Values {
    columns: Vec<ReadColumn>,
    faces: Vec<Vec<u32>>,
    has_face_element: bool,
}

/// One face's vertex indices (a list of `n` values of type `it`).
fn read_face(body: &mut Body, n: usize, it: Scalar, item: usize) -> FResult<Vec<u32>> {
    let mut f = Vec::with_capacity(n.min(64));
    for _ in 0..n {
        let v = body.scalar(it)?;
        if v < 0.0 || v.fract() != 0.0 || v > u32::MAX as f64 {
            return malformed(format!("face {item} has vertex index {v}"));
        }
        f.push(v as u32);
    }
    Ok(f)
}

/// Item `item` of element `el`: vertex scalars into the columns, the face list
/// (property `face_prop`) into the faces, everything else read and dropped.
fn read_item(
    el: &Element,
    item: usize,
    face_prop: Option<usize>,
    body: &mut Body,
    v: &mut Values,
) -> FResult<()> {
    let (is_vertex, is_face) = (el.name == "vertex", el.name == "face");
    let mut col = 0;
    for (k, p) in el.props.iter().enumerate() {
        match p.kind {
            PropKind::Scalar(s) => {
                let x = body.scalar(s)?;
                if is_vertex {
                    v.columns[col].2.push(x);
                    col += 1;
                }
            }
            PropKind::List { count, item: it } => {
                let n = body.count(count)?;
                if is_face && Some(k) == face_prop {
                    v.faces.push(read_face(body, n, it, item)?);
                } else {
                    for _ in 0..n {
                        body.scalar(it)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Reads every element of the body.
fn read_values(header: &Header, bytes: &[u8]) -> FResult<Values> {
    let mut body = Body {
        bytes: &bytes[header.body..],
        pos: 0,
        encoding: header.encoding,
    };
    let mut v = Values {
        columns: Vec::new(),
        faces: Vec::new(),
        has_face_element: false,
    };
    // Each value needs at least one byte, so the file length bounds any allocation.
    let cap = |n: usize| n.min(bytes.len());
    for el in &header.elements {
        let is_face = el.name == "face";
        v.has_face_element |= is_face;
        if el.name == "vertex" {
            v.columns = el
                .props
                .iter()
                .filter_map(|p| match p.kind {
                    PropKind::Scalar(s) => {
                        Some((p.name.clone(), s, Vec::with_capacity(cap(el.count))))
                    }
                    PropKind::List { .. } => None,
                })
                .collect();
        }
        if is_face {
            v.faces.reserve(cap(el.count));
        }
        let face_prop = el
            .props
            .iter()
            .position(|p| p.name == "vertex_indices" || p.name == "vertex_index");
        if is_face && face_prop.is_none() {
            return malformed("face element has no vertex_indices list");
        }
        for item in 0..el.count {
            read_item(el, item, face_prop, &mut body, &mut v).map_err(|e| match e {
                FormatError::Malformed(m) => {
                    FormatError::Malformed(format!("{} {item} of {}: {m}", el.name, el.count))
                }
                other => other,
            })?;
        }
    }
    Ok(v)
}

/// The column called `name`, removed from `columns`.
fn take(name: &str, columns: &mut Vec<ReadColumn>) -> Option<ReadColumn> {
    columns
        .iter()
        .position(|c| c.0 == name)
        .map(|i| columns.remove(i))
}

/// Colours from red, green, blue (and alpha) columns: integer types as they
/// are, floats scaled from [0, 1].
fn colors(columns: &mut Vec<ReadColumn>, n: usize) -> Option<Vec<[u8; 4]>> {
    let (Some(r), Some(g), Some(b)) = (
        take("red", columns),
        take("green", columns),
        take("blue", columns),
    ) else {
        return None;
    };
    let a = take("alpha", columns);
    let to_u8 = |c: &ReadColumn, i: usize| {
        let v = c.2[i];
        let v = if c.1.is_integer() { v } else { v * 255.0 };
        v.round().clamp(0.0, 255.0) as u8
    };
    Some(
        (0..n)
            .map(|i| {
                [
                    to_u8(&r, i),
                    to_u8(&g, i),
                    to_u8(&b, i),
                    a.as_ref().map_or(255, |a| to_u8(a, i)),
                ]
            })
            .collect(),
    )
}

pub(crate) fn parse(bytes: &[u8]) -> FResult<Contents> {
    let header = parse_header(bytes)?;
    let Values {
        mut columns,
        faces,
        has_face_element,
    } = read_values(&header, bytes)?;
    let (Some(x), Some(y), Some(z)) = (
        take("x", &mut columns),
        take("y", &mut columns),
        take("z", &mut columns),
    ) else {
        return malformed("vertex element needs x, y and z properties");
    };
    let n = x.2.len();
    let positions = (0..n).map(|i| [x.2[i], y.2[i], z.2[i]]).collect();
    let normals = match (
        take("nx", &mut columns),
        take("ny", &mut columns),
        take("nz", &mut columns),
    ) {
        (Some(a), Some(b), Some(c)) => Some((0..n).map(|i| [a.2[i], b.2[i], c.2[i]]).collect()),
        _ => None,
    };
    let colors = colors(&mut columns, n);
    let mut uvs = None;
    for (un, vn) in UV_NAMES {
        if let (Some(u), Some(v)) = (take(un, &mut columns), take(vn, &mut columns)) {
            uvs = Some((0..n).map(|i| [u.2[i], v.2[i]]).collect());
            break;
        }
    }
    let scalars = columns.into_iter().map(|(name, _, v)| (name, v)).collect();
    Ok(Contents {
        positions,
        normals,
        colors,
        uvs,
        scalars,
        faces,
        has_face_element,
    })
}

fn apply_vertex_data(mut mesh: TriMesh, c: Contents) -> Result<TriMesh, CoreError> {
    if let Some(n) = c.normals {
        mesh = mesh.with_normals(n)?;
    }
    if let Some(col) = c.colors {
        mesh = mesh.with_colors(col)?;
    }
    if let Some(uv) = c.uvs {
        mesh = mesh.with_uvs(uv)?;
    }
    for (name, v) in c.scalars {
        mesh = mesh.with_scalar(&name, v)?;
    }
    Ok(mesh)
}

/// Reads a triangle mesh; polygons are triangulated (fanned where convex, ear-clipped where not).
pub(crate) fn read_mesh(bytes: &[u8]) -> FResult<TriMesh> {
    let mut c = parse(bytes)?;
    if c.faces.is_empty() {
        return malformed("has no faces (it is a point set; read it as points)");
    }
    let faces = std::mem::take(&mut c.faces);
    let mesh = TriMesh::from_polygons(std::mem::take(&mut c.positions), &faces)?;
    Ok(apply_vertex_data(mesh, c)?)
}

/// Reads a polygon mesh (faces kept as they are).
pub(crate) fn read_poly(bytes: &[u8]) -> FResult<PolyMesh> {
    let c = parse(bytes)?;
    Ok(PolyMesh::new(c.positions, &c.faces)?)
}

/// Reads the vertices as a point set (faces ignored).
pub(crate) fn read_points(bytes: &[u8]) -> FResult<PointSet> {
    let c = parse(bytes)?;
    let mut p = PointSet::new(c.positions);
    if let Some(n) = c.normals {
        p.set_normals(n)?;
    }
    if let Some(col) = c.colors {
        p.set_colors(col)?;
    }
    for (name, v) in c.scalars {
        p.add_attribute(&name, v)?;
    }
    p.validate()?;
    Ok(p)
}

mod write;

pub(crate) use write::{write_mesh, write_mesh_edges, write_points, write_poly};
use crate::format::{Access, Magic, Registration};


/// A PLY file: a mesh where it has faces, else a point set.
fn read_surface(bytes: &[u8]) -> FResult<crate::Surface> {
    let c = parse(bytes)?;
    Ok(if c.has_face_element && !c.faces.is_empty() {
        crate::Surface::Mesh(read_mesh(bytes)?)
    } else {
        crate::Surface::Points(read_points(bytes)?)
    })
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "PLY (binary little-endian or ASCII)",
    extensions: &["ply"],
    mesh: Access::ReadWrite,
    points: Access::ReadWrite,
    notes: "f64 positions; normals, RGBA colours, UVs (s, t) and named scalars",
    magic: Magic::Starts(&[b"ply\n", b"ply\r\n"]),
    read: Some(read_surface),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_big_endian_and_skips_unknown_elements() {
        let mut f = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement material 1\nproperty list uchar int junk\nelement face 1\nproperty uchar flags\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.5] {
            f.extend_from_slice(&v.to_be_bytes());
        }
        f.extend_from_slice(&[2, 0, 0, 0, 9, 0, 0, 0, 9]);
        f.extend_from_slice(&[7, 3]);
        for i in [0i32, 1, 2] {
            f.extend_from_slice(&i.to_be_bytes());
        }
        let m = read_mesh(&f).unwrap();
        assert_eq!(m.triangles(), &[[0, 1, 2]]);
        assert_eq!(m.positions()[2], [0.0, 1.0, 0.5]);
    }

    #[test]
    fn ascii_quads_and_float_colors() {
        let f = b"ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty float red\nproperty float green\nproperty float blue\nproperty float quality\nelement face 1\nproperty list uchar int vertex_index\nend_header\n0 0 0 1 0 0 0.5\n1 0 0 0 1 0 1\n1 1 0 0 0 1 2\n0 1 0 1 1 1 3\n4 0 1 2 3\n";
        let m = read_mesh(f).unwrap();
        assert_eq!(m.n_faces(), 2);
        assert_eq!(m.colors().unwrap()[0], [255, 0, 0, 255]);
        assert_eq!(m.scalar("quality").unwrap(), &[0.5, 1.0, 2.0, 3.0]);
        let p = read_poly(f).unwrap();
        assert_eq!(p.face(0), &[0, 1, 2, 3]);
    }

    #[test]
    fn malformed_files_are_explained() {
        let good = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        assert!(read_mesh(good).is_ok());
        let msg = |b: &[u8]| match read_mesh(b) {
            Err(FormatError::Malformed(m)) => m,
            Err(FormatError::Invalid(e)) => e.to_string(),
            other => panic!(
                "expected an error, got {:?}",
                other.map(|m| m.n_faces()).map_err(|_| ())
            ),
        };
        assert!(
            msg(&good[..good.len() - 4]).contains("face 0 of 1"),
            "{}",
            msg(&good[..good.len() - 4])
        );
        assert!(msg(b"plx\n").contains("magic"));
        assert!(msg(b"ply\nformat ascii 1.0\nelement vertex 1\n").contains("end_header"));
        let bad_index = String::from_utf8_lossy(good).replace("3 0 1 2", "3 0 1 7");
        assert!(msg(bad_index.as_bytes()).contains("vertex 7"));
        let nan = String::from_utf8_lossy(good).replace("1 0 0\n", "nan 0 0\n");
        assert!(msg(nan.as_bytes()).contains("not finite"));
        let bad_type = String::from_utf8_lossy(good).replace("float x", "quad x");
        assert!(msg(bad_type.as_bytes()).contains("unknown property type"));
    }
}
