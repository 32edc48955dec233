//! Sensofar `.plux` (SensoSCAN 6 and later), read.
//!
//! A zip archive: `index.xml` describes the measurement — `GENERAL` with
//! `IMAGE_SIZE_X`, `IMAGE_SIZE_Y`, the pixel size `FOV_X`, `FOV_Y` (µm,
//! despite its name) and `DATE`; one `LAYER_n` element per layer whose
//! `FILENAME_Z` names the member holding its heights; `INFO` with `ITEM_n`
//! name/value pairs (the device among them) — and each layer's member holds
//! f32 heights in µm, x fastest, row by row (file rows are asperity's grid
//! rows), NaN where nothing was measured (missing points). Each layer is a
//! channel (`Layer 0`, `Layer 1`…, as SurfaceTopography names them). Layout
//! from SurfaceTopography's `PLUX.py`; checked against it on a file built to
//! that layout (no instrument file is public).
//!
//! Members are inflated to at most the size the archive's directory
//! declares, which the memory estimate counts before anything is inflated.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::zipped::{self, Archive};
use crate::format::{Access, Codec, Registration};

fn bad(e: String) -> FormatError {
    FormatError::Malformed(format!("not a readable PLUX archive: {e}"))
}

fn member(zip: &mut Archive<'_>, name: &str) -> FResult<Vec<u8>> {
    zipped::required(zip, name, u64::MAX, bad)
}

/// What `index.xml` says: grid, pixel size, the layers' members, the
/// date and the `INFO` items.
struct Index {
    nx: usize,
    ny: usize,
    pixel: [f64; 2],
    layers: Vec<String>,
    meta: Metadata,
}

fn child<'a, 'i>(node: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    node.children().find(|c| c.has_tag_name(tag))
}

fn text_of(node: roxmltree::Node<'_, '_>, tag: &str) -> Option<String> {
    child(node, tag)
        .and_then(|c| c.text())
        .map(|t| t.trim().to_owned())
}

fn index(zip: &mut Archive<'_>) -> FResult<Index> {
    let xml = member(zip, "index.xml")?;
    let text = String::from_utf8_lossy(&xml);
    let doc = roxmltree::Document::parse(&text)
        .map_err(|e| FormatError::Malformed(format!("index.xml is not XML: {e}")))?;
    let root = doc.root_element();
    let general = child(root, "GENERAL")
        .ok_or_else(|| FormatError::Malformed("index.xml has no GENERAL section".into()))?;
    let number = |tag: &str| -> FResult<f64> {
        let t = text_of(general, tag)
            .ok_or_else(|| FormatError::Malformed(format!("index.xml gives no {tag}")))?;
        t.parse()
            .map_err(|_| FormatError::Malformed(format!("index.xml: {tag} {t:?} is not a number")))
    };
    let (nx, ny) = (number("IMAGE_SIZE_X")?, number("IMAGE_SIZE_Y")?);
    let pixel = [number("FOV_X")?, number("FOV_Y")?];
    let count = |v: f64| (v >= 1.0 && v.fract() == 0.0 && v < 1e9).then_some(v as usize);
    let (Some(nx), Some(ny)) = (count(nx), count(ny)) else {
        return malformed(format!("an image of {nx} × {ny} points"));
    };
    if !pixel.iter().all(|p| p.is_finite() && *p > 0.0) {
        return malformed(format!("pixels of {pixel:?} µm"));
    }
    let layers: Vec<String> = root
        .children()
        .filter(|c| c.tag_name().name().starts_with("LAYER_"))
        .filter_map(|l| text_of(l, "FILENAME_Z"))
        .collect();
    if layers.is_empty() {
        return malformed("index.xml names no layer (LAYER_n with FILENAME_Z)");
    }
    let mut meta = Vec::new();
    if let Some(date) = text_of(general, "DATE") {
        meta.push(("Date".to_owned(), date));
    }
    if let Some(info) = child(root, "INFO") {
        for item in info
            .children()
            .filter(|c| c.tag_name().name().starts_with("ITEM_"))
        {
            if let (Some(k), Some(v)) = (text_of(item, "NAME"), text_of(item, "VALUE")) {
                meta.push((k, v));
            }
        }
    }
    Ok(Index {
        nx,
        ny,
        pixel,
        layers,
        meta,
    })
}

fn open(bytes: &[u8]) -> FResult<(Archive<'_>, Index)> {
    let mut zip = zipped::open(bytes, bad)?;
    let index = index(&mut zip)?;
    Ok((zip, index))
}

fn infos(index: &Index) -> Vec<ChannelInfo> {
    (0..index.layers.len())
        .map(|k| ChannelInfo {
            index: k,
            name: format!("Layer {k}"),
            height: true,
        })
        .collect()
}

/// The layers as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(infos(&open(bytes)?.1))
}

/// Reads the layer `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let (mut zip, index) = open(bytes)?;
    let k = pick(&infos(&index), choice)?;
    let name = &index.layers[k];
    let data = member(&mut zip, name)?;
    let n = index.nx * index.ny;
    if data.len() < 4 * n {
        return malformed(format!(
            "layer {k} ({name:?}): {} × {} f32 heights need {} bytes, the member has {} (truncated?)",
            index.nx,
            index.ny,
            4 * n,
            data.len()
        ));
    }
    let heights = data[..4 * n]
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
        .collect();
    let um = Units::same(LengthUnit::Um);
    Ok(HeightField::from_vec([index.nx, index.ny], heights)?
        .with_spacing(index.pixel)?
        .with_units(um))
}

/// The date and the `INFO` items (device, objective…).
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    Ok(open(bytes)?.1.meta)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Sensofar PLUX (.plux)",
    extensions: &["plux"],
    height: Access::Read,
    notes: "the zip's layers as channels: f32 heights in µm, pixel size from index.xml, NaN read as missing; the date and the INFO items (device…) kept as metadata",
    codec: Some(Codec::new(read_channel)
        .channels(channels)
        .metadata(metadata)
        .declared(crate::zipped::declared_twice)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Cursor;
    use std::io::Write;

    use super::*;

    fn plux(layers: &[&[f32]], truncate_layer: bool) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default();
        let mut xml = String::from(
            "<xml><GENERAL><IMAGE_SIZE_X>3</IMAGE_SIZE_X><IMAGE_SIZE_Y>2</IMAGE_SIZE_Y>\
             <FOV_X>0.5</FOV_X><FOV_Y>0.25</FOV_Y><DATE>28/11/2026 19:50:00</DATE></GENERAL>",
        );
        for k in 0..layers.len() {
            xml += &format!("<LAYER_{k}><FILENAME_Z>LAYER_{k}.raw</FILENAME_Z></LAYER_{k}>");
        }
        xml += "<INFO><ITEM_0><NAME>Device</NAME><VALUE>S neox</VALUE></ITEM_0></INFO></xml>";
        zip.start_file("index.xml", opts).unwrap();
        zip.write_all(xml.as_bytes()).unwrap();
        for (k, z) in layers.iter().enumerate() {
            zip.start_file(format!("LAYER_{k}.raw"), opts).unwrap();
            let mut raw: Vec<u8> = z.iter().flat_map(|v| v.to_le_bytes()).collect();
            if truncate_layer {
                raw.pop();
            }
            zip.write_all(&raw).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    #[test]
    fn layers_are_channels_in_micrometres_with_nan_missing() {
        let f = plux(&[&[1.0, 2.0, 3.0, f32::NAN, 5.0, 6.0], &[0.0; 6]], false);
        let names: Vec<String> = channels(&f).unwrap().into_iter().map(|c| c.name).collect();
        assert_eq!(names, ["Layer 0", "Layer 1"]);
        let h = read_channel(&f, None).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [0.5, 0.25]));
        assert_eq!(h.row(0), &[1.0, 2.0, 3.0]);
        assert!(h.row(1)[0].is_nan());
        let m = metadata(&f).unwrap();
        assert_eq!(m[1], ("Device".to_owned(), "S neox".to_owned()));
    }

    #[test]
    fn truncated_layers_and_archives_without_an_index_are_refused() {
        let f = plux(&[&[0.0; 6]], true);
        let e = format!("{:?}", read_channel(&f, None).unwrap_err());
        assert!(e.contains("truncated"), "{e}");
        let whole = plux(&[&[0.0; 6]], false);
        assert!(read_channel(&whole[..whole.len() / 2], None).is_err());
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        zip.start_file("other.txt", zip::write::SimpleFileOptions::default())
            .unwrap();
        let e = format!(
            "{:?}",
            read_channel(&zip.finish().unwrap().into_inner(), None).unwrap_err()
        );
        assert!(e.contains("index.xml"), "{e}");
    }
}
