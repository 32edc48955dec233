//! ISO 25178-72 `.x3p` (the openGPS XML 3D surface profile), the exchange format
//! of surface metrology: measured surfaces arrive as x3p.
//!
//! An x3p file is a zip archive holding
//! - `main.xml`: `Record1` (revision, feature type `SUR`/`PRF`/`PCL`, and the
//!   axes `CX`, `CY`, `CZ`, each with `AxisType` — `I`ncremental or
//!   `A`bsolute — `DataType` — `I` int16, `L` int32, `F` float32, `D` float64 —
//!   `Increment` and `Offset`), the optional `Record2` (date, creator,
//!   instrument), `Record3` (`MatrixDimension` `SizeX`, `SizeY`, `SizeZ` and the
//!   `DataLink` to the binary data with its MD5) and `Record4` (the name of the
//!   checksum file of `main.xml`);
//! - `bindata/data.bin`: the `z` values, little-endian, `x` varying fastest;
//! - optionally `bindata/valid.bin`: one bit per point (least significant
//!   first), 0 for a point that was not measured;
//! - `md5checksum.hex`: the MD5 of `main.xml`, as `md5sum` prints it.
//!
//! x3p lengths are always metres. A point's position is `Offset + i·Increment`
//! on an incremental axis (the sample itself, not a pixel edge as in Gwyddion's
//! own formats), and its height `Offset + raw·Increment` on `CZ` (increment 1
//! and offset 0 when absent).
//!
//! **Writing**: a surface (`SUR`) with incremental `x`, `y`, float64 heights, the
//! data and `main.xml` checksums. A field with units is converted to metres; a
//! unitless field's numbers are written as metres (the format has no unitless
//! case; [`crate::lost_data`] says so). `Record2` is written only to hold the
//! parameters the surface was made with (its `Comment`, see
//! [`crate::metadata`]): its `ProbingSystem` is `Software`, and its required
//! `Date` and `CalibrationDate` state the Unix epoch, `1970-01-01T00:00:00Z` —
//! a synthetic surface was never measured, and the date of writing would make
//! the same parameters give different files.
//!
//! **Reading**: surfaces and profiles (`PRF`, read as an `n × 1` field) with
//! incremental `x` and `y` and any of the four data types, checked against the
//! stated MD5 checksums. Refused with a message: point clouds (`PCL`), absolute
//! (per-point) `x`/`y`, more than one layer, data written into `main.xml`
//! (`DataList`), and unmeasured points (a surface needs every height).
//!
//! The zip and XML come from the `zip` and `roxmltree` crates, the checksums from
//! `md-5`; the document itself is small and fixed, so it is written as text.

use std::io::{Cursor, Read, Write};

use asperity_core::{HeightField, LengthUnit, Units};
use md5::{Digest, Md5};

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Registration};

const MAIN: &str = "main.xml";
const DATA: &str = "bindata/data.bin";
const CHECKSUM: &str = "md5checksum.hex";
/// `main.xml` larger than this is refused before parsing (real ones are a few kB).
const MAX_MAIN_XML: u64 = 16 << 20;

/// The MD5 of `bytes` in lower-case hexadecimal.
fn md5_hex(bytes: &[u8]) -> String {
    Md5::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Writes an x3p file.
pub(crate) fn write_height(
    w: &mut dyn Write,
    h: &HeightField,
    params: Option<&str>,
) -> std::io::Result<()> {
    let units = h.units();
    let (fx, fz) = units.metre_factors();
    let data: Vec<u8> = h
        .data()
        .iter()
        .flat_map(|&z| (z * fz).to_le_bytes())
        .collect();
    let [dx, dy] = h.spacing().map(|v| v * fx);
    let [x0, y0] = h.origin().map(|v| v * fx);
    let axis = |name: &str, inc: f64, off: f64| {
        format!(
            "      <{name}>\n        <AxisType>I</AxisType>\n        <DataType>D</DataType>\n        \
             <Increment>{inc:e}</Increment>\n        <Offset>{off:e}</Offset>\n      </{name}>\n"
        )
    };
    let main = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n\
         <p:ISO5436_2 xmlns:p=\"http://www.opengps.eu/2008/ISO5436_2\" \
         xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
         xsi:schemaLocation=\"http://www.opengps.eu/2008/ISO5436_2 \
         http://www.opengps.eu/2008/ISO5436_2/ISO5436_2.xsd\">\n  \
         <Record1>\n    <Revision>ISO5436 - 2000</Revision>\n    <FeatureType>SUR</FeatureType>\n    \
         <Axes>\n{}{}      <CZ>\n        <AxisType>A</AxisType>\n        <DataType>D</DataType>\n      \
         </CZ>\n    </Axes>\n  </Record1>\n{}  <Record3>\n    <MatrixDimension>\n      \
         <SizeX>{}</SizeX>\n      <SizeY>{}</SizeY>\n      <SizeZ>1</SizeZ>\n    </MatrixDimension>\n    \
         <DataLink>\n      <PointDataLink>{DATA}</PointDataLink>\n      \
         <MD5ChecksumPointData>{}</MD5ChecksumPointData>\n    </DataLink>\n  </Record3>\n  \
         <Record4>\n    <ChecksumFile>{CHECKSUM}</ChecksumFile>\n  </Record4>\n</p:ISO5436_2>\n",
        axis("CX", dx, x0),
        axis("CY", dy, y0),
        params.map(record2).unwrap_or_default(),
        h.nx(),
        h.ny(),
        md5_hex(&data).to_uppercase(),
    );
    let zip_err = |e: zip::result::ZipError| std::io::Error::other(e.to_string());
    let deflated = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(data.len() as u64 >= u32::MAX as u64);
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    zip.start_file(MAIN, deflated).map_err(zip_err)?;
    zip.write_all(main.as_bytes())?;
    zip.start_file(DATA, deflated).map_err(zip_err)?;
    zip.write_all(&data)?;
    zip.start_file(CHECKSUM, deflated).map_err(zip_err)?;
    zip.write_all(format!("{} *{MAIN}\n", md5_hex(main.as_bytes())).as_bytes())?;
    w.write_all(&zip.finish().map_err(zip_err)?.into_inner())
}

/// `Record2` holding `params` as its `Comment` (see the module docs).
fn record2(params: &str) -> String {
    const EPOCH: &str = "1970-01-01T00:00:00Z";
    let comment = params
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    format!(
        "  <Record2>\n    <Date>{EPOCH}</Date>\n    <Creator>asperity</Creator>\n    \
         <Instrument>\n      <Manufacturer>asperity</Manufacturer>\n      \
         <Model>synthetic surface</Model>\n      <Serial>not available</Serial>\n      \
         <Version>{}</Version>\n    </Instrument>\n    \
         <CalibrationDate>{EPOCH}</CalibrationDate>\n    <ProbingSystem>\n      \
         <Type>Software</Type>\n      <Identification>asperity</Identification>\n    \
         </ProbingSystem>\n    <Comment>{comment}</Comment>\n  </Record2>\n",
        env!("CARGO_PKG_VERSION")
    )
}

/// `Record2/Comment` of `main.xml`, if it has one.
pub(crate) fn comment(bytes: &[u8]) -> FResult<Option<String>> {
    let xml = main_xml(&mut archive(bytes)?)?;
    let doc = roxmltree::Document::parse(&xml)
        .map_err(|e| FormatError::Malformed(format!("{MAIN} is not valid XML: {e}")))?;
    Ok(child(doc.root_element(), "Record2")
        .and_then(|r| text(r, "Comment"))
        .map(str::to_owned))
}

/// What `Record1` and `Record3` say about the data.
struct Layout {
    nx: usize,
    ny: usize,
    x: Axis,
    y: Axis,
    z: Axis,
    /// `CZ`'s data type: `I`, `L`, `F` or `D`.
    z_type: char,
    data_link: String,
    data_md5: Option<String>,
    valid_link: Option<String>,
}

/// An axis: value = offset + index (or raw value) × increment.
#[derive(Clone, Copy)]
struct Axis {
    increment: f64,
    offset: f64,
}

fn archive(bytes: &[u8]) -> FResult<zip::ZipArchive<Cursor<&[u8]>>> {
    zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| FormatError::Malformed(format!("not a zip archive (an x3p file is one): {e}")))
}

/// Reads a member of the archive, refusing more than `limit` bytes.
fn member(zip: &mut zip::ZipArchive<Cursor<&[u8]>>, name: &str, limit: u64) -> FResult<Vec<u8>> {
    let file = zip.by_name(name).map_err(|e| match e {
        zip::result::ZipError::FileNotFound => {
            FormatError::Malformed(format!("the archive has no {name}"))
        }
        e => FormatError::Malformed(format!("cannot read {name} from the archive: {e}")),
    })?;
    let mut out = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| FormatError::Malformed(format!("cannot decompress {name}: {e}")))?;
    if out.len() as u64 > limit {
        return malformed(format!("{name} is larger than the {limit} bytes expected"));
    }
    Ok(out)
}

/// `main.xml`, checked against `md5checksum.hex` when that file names it.
fn main_xml(zip: &mut zip::ZipArchive<Cursor<&[u8]>>) -> FResult<String> {
    let main = member(zip, MAIN, MAX_MAIN_XML)?;
    if let Ok(sum) = member(zip, CHECKSUM, 4096) {
        let sum = String::from_utf8_lossy(&sum);
        let mut words = sum.split_whitespace();
        let digest = words.next().unwrap_or("");
        let names_main = words
            .next()
            .is_none_or(|n| n.trim_start_matches('*') == MAIN);
        if names_main && digest.len() == 32 && !digest.eq_ignore_ascii_case(&md5_hex(&main)) {
            return malformed(format!(
                "{MAIN} does not match the checksum in {CHECKSUM} (the file is damaged or was edited)"
            ));
        }
    }
    String::from_utf8(main).map_err(|_| FormatError::Malformed(format!("{MAIN} is not UTF-8")))
}

/// The number of samples an x3p file declares (for the memory estimate), from
/// `main.xml` alone.
pub(crate) fn header_pixels(bytes: &[u8]) -> FResult<u128> {
    let mut zip = archive(bytes)?;
    let layout = layout(&main_xml(&mut zip)?)?;
    Ok(layout.nx as u128 * layout.ny as u128)
}

/// Reads an x3p file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let mut zip = archive(bytes)?;
    let l = layout(&main_xml(&mut zip)?)?;
    let size: usize = match l.z_type {
        'I' => 2,
        'L' | 'F' => 4,
        _ => 8,
    };
    // SizeX and SizeY are free text: their product can overflow where the
    // memory budget was set high enough to let the header through.
    let too_big =
        || FormatError::Malformed(format!("{}×{} values do not fit in memory", l.nx, l.ny));
    let n = l.nx.checked_mul(l.ny).ok_or_else(too_big)?;
    let need = n.checked_mul(size).ok_or_else(too_big)? as u64;
    let raw = member(&mut zip, &l.data_link, need)?;
    if raw.len() as u64 != need {
        return malformed(format!(
            "{} holds {} bytes but {}×{} values of type {} need {need}",
            l.data_link,
            raw.len(),
            l.nx,
            l.ny,
            l.z_type
        ));
    }
    if let Some(sum) = &l.data_md5
        && sum.len() == 32
        && !sum.eq_ignore_ascii_case(&md5_hex(&raw))
    {
        return malformed(format!(
            "{} does not match its MD5 checksum in {MAIN} (the file is damaged)",
            l.data_link
        ));
    }
    let value: fn(&[u8]) -> f64 = match l.z_type {
        'I' => |c| i16::from_le_bytes([c[0], c[1]]) as f64,
        'L' => |c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64,
        'F' => |c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64,
        _ => |c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]),
    };
    let data: Vec<f64> = raw
        .chunks_exact(size)
        .map(|c| l.z.offset + value(c) * l.z.increment)
        .collect();
    // Invalid points (NaN in float data, or cleared in the valid-points
    // bitmap) are missing points (NaN).
    let mut data = data;
    data.iter_mut()
        .filter(|z| !z.is_finite())
        .for_each(|z| *z = f64::NAN);
    if let Some(link) = &l.valid_link {
        let bits = member(&mut zip, link, n.div_ceil(8) as u64)?;
        if bits.len() != n.div_ceil(8) {
            return malformed(format!(
                "{link} holds {} bytes, {n} points need {}",
                bits.len(),
                n.div_ceil(8)
            ));
        }
        for (i, z) in data.iter_mut().enumerate() {
            if bits[i / 8] >> (i % 8) & 1 == 0 {
                *z = f64::NAN;
            }
        }
    }
    Ok(HeightField::from_vec([l.nx, l.ny], data)?
        .with_spacing([l.x.increment, l.y.increment])?
        .with_origin([l.x.offset, l.y.offset])?
        .with_units(Units::same(LengthUnit::M)))
}

/// The first child element of `node` named `name` (namespaces ignored: the
/// records are unqualified).
fn child<'a>(node: roxmltree::Node<'a, 'a>, name: &str) -> Option<roxmltree::Node<'a, 'a>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == name)
}

fn text<'a>(node: roxmltree::Node<'a, 'a>, name: &str) -> Option<&'a str> {
    child(node, name).and_then(|c| c.text()).map(str::trim)
}

fn required<'a>(node: roxmltree::Node<'a, 'a>, path: &str) -> FResult<roxmltree::Node<'a, 'a>> {
    path.split('/').try_fold(node, |n, name| {
        child(n, name).ok_or_else(|| FormatError::Malformed(format!("{MAIN} has no {path}")))
    })
}

fn number(node: roxmltree::Node, name: &str, default: Option<f64>) -> FResult<f64> {
    match text(node, name) {
        Some(t) => t
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| {
                FormatError::Malformed(format!(
                    "{}/{name} = {t:?} is not a number",
                    node.tag_name().name()
                ))
            }),
        None => default.ok_or_else(|| {
            FormatError::Malformed(format!("{} has no {name}", node.tag_name().name()))
        }),
    }
}

fn size(node: roxmltree::Node, name: &str) -> FResult<usize> {
    let t = text(node, name).unwrap_or("");
    t.parse().ok().filter(|&n| n > 0).ok_or_else(|| {
        FormatError::Malformed(format!(
            "MatrixDimension/{name} = {t:?} is not a positive integer"
        ))
    })
}

/// An incremental `x` or `y` axis.
fn lateral_axis(axes: roxmltree::Node, name: &str) -> FResult<Axis> {
    let a = required(axes, name)?;
    if text(a, "AxisType") != Some("I") {
        return malformed(format!(
            "{name} is not incremental (AxisType {:?}): x and y given per point (an irregular grid) \
             are not supported",
            text(a, "AxisType").unwrap_or("")
        ));
    }
    let increment = number(a, "Increment", None)?;
    if increment <= 0.0 {
        return malformed(format!(
            "{name}/Increment = {increment} is not a positive length"
        ));
    }
    Ok(Axis {
        increment,
        offset: number(a, "Offset", Some(0.0))?,
    })
}

/// Parses `main.xml` into what reading the data needs; refuses what asperity
/// cannot represent.
fn layout(xml: &str) -> FResult<Layout> {
    let doc = roxmltree::Document::parse(xml)
        .map_err(|e| FormatError::Malformed(format!("{MAIN} is not valid XML: {e}")))?;
    let root = doc.root_element();
    let record1 = required(root, "Record1")?;
    match text(record1, "FeatureType").unwrap_or("") {
        "SUR" | "PRF" => {}
        "PCL" => {
            return malformed(
                "a point cloud (FeatureType PCL); asperity reads x3p surfaces and profiles",
            );
        }
        other => return malformed(format!("unknown FeatureType {other:?} (SUR, PRF or PCL)")),
    }
    let axes = required(record1, "Axes")?;
    let (x, y) = (lateral_axis(axes, "CX")?, lateral_axis(axes, "CY")?);
    let cz = required(axes, "CZ")?;
    let z_type = match text(cz, "DataType") {
        Some(t @ ("I" | "L" | "F" | "D")) => t.chars().next().unwrap_or('D'),
        other => {
            return malformed(format!(
                "CZ/DataType {:?} is not I, L, F or D",
                other.unwrap_or("")
            ));
        }
    };
    let z = Axis {
        increment: number(cz, "Increment", Some(1.0))?,
        offset: number(cz, "Offset", Some(0.0))?,
    };
    let record3 = required(root, "Record3")?;
    let dims = required(record3, "MatrixDimension")?;
    let (nx, ny) = (size(dims, "SizeX")?, size(dims, "SizeY")?);
    if text(dims, "SizeZ").unwrap_or("1") != "1" {
        return malformed(format!(
            "{} layers (SizeZ); asperity reads a single-layer surface",
            text(dims, "SizeZ").unwrap_or("")
        ));
    }
    let Some(link) = child(record3, "DataLink") else {
        return malformed(if child(record3, "DataList").is_some() {
            "the heights are written into main.xml (DataList), which is not supported; \
             only binary data (DataLink) is"
        } else {
            "Record3 has no DataLink"
        });
    };
    Ok(Layout {
        nx,
        ny,
        x,
        y,
        z,
        z_type,
        data_link: text(link, "PointDataLink")
            .filter(|t| !t.is_empty())
            .ok_or_else(|| FormatError::Malformed("DataLink has no PointDataLink".into()))?
            .to_owned(),
        data_md5: text(link, "MD5ChecksumPointData").map(str::to_owned),
        valid_link: text(link, "ValidPointsLink")
            .filter(|t| !t.is_empty())
            .map(str::to_owned),
    })
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "ISO 25178-72 x3p",
    extensions: &["x3p"],
    height: Access::ReadWrite,
    notes: "zip of main.xml + f64 data with MD5 checksums; always metres; surfaces and profiles read (int16/32, f32, f64), not point clouds; missing points NaN (read: NaN or valid.bin)",
    codec: Some(Codec::new(|b, _| read_height(b))
        .declared(|b| header_pixels(b).map(crate::pixel_bytes))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn field() -> HeightField {
        HeightField::from_vec([3, 2], vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.5])
            .unwrap()
            .with_spacing([0.5, 0.25])
            .unwrap()
            .with_origin([1.0, -2.0])
            .unwrap()
            .with_units(Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Nm,
            })
    }

    fn written(h: &HeightField) -> Vec<u8> {
        let mut out = Vec::new();
        write_height(&mut out, h, None).unwrap();
        out
    }

    #[test]
    fn round_trip_in_metres() {
        let back = read_height(&written(&field())).unwrap();
        assert_eq!(
            back.units(),
            Units {
                xy: LengthUnit::M,
                z: LengthUnit::M
            }
        );
        assert_eq!((back.nx(), back.ny()), (3, 2));
        let expected = field().in_units(back.units());
        assert_eq!(back.data(), expected.data());
        for k in 0..2 {
            assert!((back.spacing()[k] - expected.spacing()[k]).abs() <= 1e-20);
            assert!((back.origin()[k] - expected.origin()[k]).abs() <= 1e-20);
        }
        assert_eq!(header_pixels(&written(&field())).unwrap(), 6);
    }

    #[test]
    fn written_twice_is_identical() {
        assert_eq!(written(&field()), written(&field()));
    }

    /// Rewrites `main.xml` of an archive made by [`write_height`] (and its
    /// checksum file, so only the edit is tested).
    fn with_main(edit: impl Fn(String) -> String, extra: &[(&str, &[u8])]) -> Vec<u8> {
        let bytes = written(&field());
        let mut zip = archive(&bytes).unwrap();
        let main = edit(main_xml(&mut zip).unwrap());
        let data = member(&mut zip, DATA, 1 << 20).unwrap();
        let opts = zip::write::SimpleFileOptions::default();
        let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
        out.start_file(MAIN, opts).unwrap();
        out.write_all(main.as_bytes()).unwrap();
        out.start_file(DATA, opts).unwrap();
        out.write_all(&data).unwrap();
        for (name, content) in extra {
            out.start_file(*name, opts).unwrap();
            out.write_all(content).unwrap();
        }
        out.finish().unwrap().into_inner()
    }

    fn error(bytes: &[u8]) -> String {
        match read_height(bytes) {
            Err(FormatError::Malformed(m)) => m,
            other => panic!("expected a malformed-file error, got {other:?}"),
        }
    }

    #[test]
    fn unsupported_layouts_are_refused_by_name() {
        let cases = [
            ("<FeatureType>SUR", "<FeatureType>PCL", "point cloud"),
            (
                "<AxisType>I</AxisType>",
                "<AxisType>A</AxisType>",
                "irregular grid",
            ),
            ("<SizeZ>1", "<SizeZ>3", "3 layers"),
            (
                "<DataType>D</DataType>\n      </CZ>",
                "<DataType>X</DataType>\n      </CZ>",
                "not I, L, F or D",
            ),
            ("<SizeX>3", "<SizeX>4", "need 64"),
        ];
        for (from, to, expect) in cases {
            let m = error(&with_main(|s| s.replacen(from, to, 1), &[]));
            assert!(m.contains(expect), "{to}: {m}");
        }
        assert!(error(b"PK\x03\x04 not really").contains("not a zip archive"));
        // Sizes whose product overflows (the memory check lets them through
        // only under a budget set that high): an error, not a panic.
        let huge = with_main(
            |s| {
                s.replacen("<SizeX>3", "<SizeX>4611686018427387904", 1)
                    .replacen("<SizeY>2", "<SizeY>8", 1)
            },
            &[],
        );
        assert!(
            error(&huge).contains("do not fit in memory"),
            "{}",
            error(&huge)
        );
    }

    #[test]
    fn damage_is_detected_by_the_checksums() {
        let m = error(&with_main(
            |s| s.replace("<Offset>1e-6", "<Offset>2e-6"),
            &[(CHECKSUM, b"0123456789abcdef0123456789abcdef *main.xml\n")],
        ));
        assert!(m.contains("does not match the checksum"), "{m}");
        let m = error(&with_main(
            |s| {
                let at = s.find("<MD5ChecksumPointData>").unwrap() + 22;
                format!("{}0{}", &s[..at], &s[at + 1..])
            },
            &[],
        ));
        assert!(m.contains("does not match its MD5"), "{m}");
    }

    #[test]
    fn integer_heights_use_the_z_increment_and_offset() {
        // int16 raw values 1..6 with z = 0.5 + raw × 0.25
        let raw: Vec<u8> = (1i16..=6).flat_map(|v| v.to_le_bytes()).collect();
        let bytes = written(&field());
        let mut zip = archive(&bytes).unwrap();
        let main = main_xml(&mut zip)
            .unwrap()
            .replace(
                "<DataType>D</DataType>\n      </CZ>",
                "<DataType>I</DataType>\n        <Increment>0.25</Increment>\n        <Offset>0.5</Offset>\n      </CZ>",
            );
        let start = main.find("<MD5ChecksumPointData>").unwrap();
        let end = main.find("</MD5ChecksumPointData>").unwrap() + 23;
        let main = format!("{}{}", &main[..start], &main[end..]);
        let opts = zip::write::SimpleFileOptions::default();
        let mut out = zip::ZipWriter::new(Cursor::new(Vec::new()));
        out.start_file(MAIN, opts).unwrap();
        out.write_all(main.as_bytes()).unwrap();
        out.start_file(DATA, opts).unwrap();
        out.write_all(&raw).unwrap();
        let back = read_height(&out.finish().unwrap().into_inner()).unwrap();
        assert_eq!(back.data(), &[0.75, 1.0, 1.25, 1.5, 1.75, 2.0]);
    }

    #[test]
    fn unmeasured_points_are_missing() {
        let valid = [0b0011_1011u8]; // point 2 not measured
        let h = read_height(&with_main(
            |s| {
                s.replace(
                    "</PointDataLink>",
                    "</PointDataLink>\n      <ValidPointsLink>bindata/valid.bin</ValidPointsLink>",
                )
            },
            &[("bindata/valid.bin", &valid)],
        ))
        .unwrap();
        assert_eq!(h.missing_count(), 1);
        assert!(h.data()[2].is_nan());
    }
}
