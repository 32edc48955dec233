//! Olympus (Evident) LEXT `.lext` (OLS laser scanning confocal
//! microscopes), read.
//!
//! A TIFF of several pages: the page whose `ImageDescription` is `HEIGHT`
//! holds the heights (an uncompressed raster, file rows are asperity's grid
//! rows); the page whose `ImageDescription` is the XML `TiffTagDescData`
//! holds the measurement (`HeightInfo`: `HeightDataPerPixelX/Y/Z` and their
//! units, which must agree), and its EXIF directory's
//! `DeviceSettingDescription` (tag 41995) the XML `ExifTagDescData` with the
//! calibration (`ImageCommonSettingsInfo/MakerCalibrationValueX/Y/Z`). In
//! µm: the pixel is 10⁻¹² × per-pixel × calibration, a height the raw value
//! × 10⁻¹² × per-pixel Z × calibration Z. Layout from SurfaceTopography's
//! `LEXT.py`; checked against it on a file built to that layout (no
//! instrument file is public).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::error::{FResult, FormatError, malformed};
use crate::tiff_dir::{Entry, Tiff, find, raster, text};
use crate::format::{Access, Codec, Registration};

const DESCRIPTION: u16 = 270;
const EXIF: u16 = 34665;
const DEVICE_SETTINGS: u16 = 41995;

/// The XML element `path` (from the root's children down) as text.
fn xml_text(doc: &roxmltree::Document<'_>, path: &[&str]) -> Option<String> {
    let mut node = doc.root_element();
    for tag in path {
        node = node.children().find(|c| c.has_tag_name(*tag))?;
    }
    node.text().map(|t| t.trim().to_owned())
}

/// The height page, the measurement XML and the calibration XML.
fn parts<'a>(tiff: &Tiff<'a>) -> FResult<(Vec<Entry<'a>>, String, String)> {
    let mut height = None;
    let mut measurement = None;
    for page in tiff.pages()? {
        let desc = find(&page, DESCRIPTION).map(text).unwrap_or_default();
        if desc == "HEIGHT" {
            height = Some(page);
        } else if desc.contains("TiffTagDescData") {
            let exif = find(&page, EXIF).and_then(|e| tiff.number(e));
            measurement = Some((desc, exif));
        }
    }
    let (Some(height), Some((desc, exif))) = (height, measurement) else {
        return malformed("no HEIGHT page and LEXT measurement page: not an Olympus LEXT file");
    };
    let exif = exif.ok_or_else(|| {
        FormatError::Malformed("the measurement page has no EXIF directory".into())
    })?;
    let (entries, _) = tiff.directory(exif as usize)?;
    let settings = find(&entries, DEVICE_SETTINGS).map(text).ok_or_else(|| {
        FormatError::Malformed("the EXIF directory has no device settings".into())
    })?;
    Ok((height, desc, settings))
}

/// Reads a `.lext` height field.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let tiff = Tiff::new(bytes)?;
    let (page, desc, settings) = parts(&tiff)?;
    let parse = |x: &str, what: &str| -> FResult<String> {
        roxmltree::Document::parse(x)
            .map(|_| x.to_owned())
            .map_err(|e| FormatError::Malformed(format!("the {what} is not XML: {e}")))
    };
    let (desc, settings) = (
        parse(&desc, "measurement")?,
        parse(&settings, "device settings")?,
    );
    let m = roxmltree::Document::parse(&desc).expect("parsed above");
    let s = roxmltree::Document::parse(&settings).expect("parsed above");
    let number = |doc: &roxmltree::Document<'_>, path: &[&str]| -> FResult<f64> {
        xml_text(doc, path)
            .and_then(|t| t.parse().ok())
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| FormatError::Malformed(format!("no number at {}", path.join("/"))))
    };
    let units: Vec<Option<String>> = ["X", "Y", "Z"]
        .iter()
        .map(|a| xml_text(&m, &["HeightInfo", &format!("HeightDataUnit{a}")]))
        .collect();
    if units[0] != units[2] || units[1] != units[2] {
        return malformed(format!("the x, y and height units differ: {units:?}"));
    }
    let scale = |a: &str| -> FResult<f64> {
        Ok(1e-12
            * number(&m, &["HeightInfo", &format!("HeightDataPerPixel{a}")])?
            * number(
                &s,
                &[
                    "ImageCommonSettingsInfo",
                    &format!("MakerCalibrationValue{a}"),
                ],
            )?)
    };
    let (dx, dy, dz) = (scale("X")?, scale("Y")?, scale("Z")?);
    if !(dx > 0.0 && dy > 0.0) {
        return malformed(format!("pixels of {dx} × {dy} µm"));
    }
    let (w, h, raw) = raster(&tiff, &page)?;
    let um = Units::same(LengthUnit::Um);
    Ok(
        HeightField::from_vec([w, h], raw.into_iter().map(|v| v * dz).collect())?
            .with_spacing([dx, dy])?
            .with_units(um),
    )
}

/// The measurement's `HeightInfo` values.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    let tiff = Tiff::new(bytes)?;
    let (_, desc, _) = parts(&tiff)?;
    let m = roxmltree::Document::parse(&desc)
        .map_err(|e| FormatError::Malformed(format!("the measurement is not XML: {e}")))?;
    let info = m
        .root_element()
        .children()
        .find(|c| c.has_tag_name("HeightInfo"));
    Ok(info
        .into_iter()
        .flat_map(|i| i.children().filter(|c| c.is_element()))
        .filter_map(|c| Some((c.tag_name().name().to_owned(), c.text()?.trim().to_owned())))
        .collect())
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Olympus LEXT (.lext)",
    extensions: &["lext"],
    height: Access::Read,
    notes: "the TIFF's HEIGHT page (uncompressed) × 1e-12 × per-pixel Z × calibration Z in µm, pixel sizes from the measurement XML and the EXIF calibration; the measurement's HeightInfo kept as metadata",
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// A little-endian LEXT: page 0 the 3 × 2 u32 HEIGHT raster, page 1 the
    /// measurement with an EXIF directory holding the calibration.
    fn lext() -> Vec<u8> {
        let measure = "<TiffTagDescData><HeightInfo><HeightDataPerPixelX>125000</HeightDataPerPixelX>\
            <HeightDataPerPixelY>125000</HeightDataPerPixelY><HeightDataPerPixelZ>1000</HeightDataPerPixelZ>\
            <HeightDataUnitX>0</HeightDataUnitX><HeightDataUnitY>0</HeightDataUnitY>\
            <HeightDataUnitZ>0</HeightDataUnitZ></HeightInfo></TiffTagDescData>\0";
        let settings = "<ExifTagDescData><ImageCommonSettingsInfo><MakerCalibrationValueX>4</MakerCalibrationValueX>\
            <MakerCalibrationValueY>2</MakerCalibrationValueY><MakerCalibrationValueZ>1</MakerCalibrationValueZ>\
            </ImageCommonSettingsInfo></ExifTagDescData>\0";
        let mut b = b"II*\0".to_vec();
        b.extend(8u32.to_le_bytes());
        let entry = |b: &mut Vec<u8>, tag: u16, kind: u16, count: u32, value: u32| {
            b.extend(tag.to_le_bytes());
            b.extend(kind.to_le_bytes());
            b.extend(count.to_le_bytes());
            b.extend(value.to_le_bytes());
        };
        // Page 0 at 8: 7 entries (2 + 84 + 4 = 90 bytes), then its data.
        let (page1, height_txt) = (8 + 90, 8 + 90 + 30);
        let (pixels, measure_at) = (height_txt + 7, height_txt + 7 + 24);
        let exif = measure_at + measure.len();
        let settings_at = exif + 2 + 12 + 4;
        b.extend(7u16.to_le_bytes());
        entry(&mut b, 256, 4, 1, 3);
        entry(&mut b, 257, 4, 1, 2);
        entry(&mut b, 258, 3, 1, 32);
        entry(&mut b, 270, 2, 7, height_txt as u32);
        entry(&mut b, 273, 4, 1, pixels as u32);
        entry(&mut b, 277, 3, 1, 1);
        entry(&mut b, 279, 4, 1, 24);
        b.extend((page1 as u32).to_le_bytes());
        // Page 1: the measurement and the EXIF pointer.
        b.extend(2u16.to_le_bytes());
        entry(&mut b, 270, 2, measure.len() as u32, measure_at as u32);
        entry(&mut b, 34665, 4, 1, exif as u32);
        b.extend(0u32.to_le_bytes());
        b.extend(b"HEIGHT\0");
        for v in [0u32, 1, 2, 3, 4, 5] {
            b.extend(v.to_le_bytes());
        }
        b.extend(measure.as_bytes());
        b.extend(1u16.to_le_bytes());
        entry(&mut b, 41995, 7, settings.len() as u32, settings_at as u32);
        b.extend(0u32.to_le_bytes());
        b.extend(settings.as_bytes());
        b
    }

    #[test]
    fn the_height_page_is_scaled_by_the_measurement_and_the_calibration() {
        let h = read_height(&lext()).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        // 1e-12 × 125000 × 4 = 5e-7 µm along x, half that along y.
        assert!((h.spacing()[0] - 5e-7).abs() < 1e-20 && (h.spacing()[1] - 2.5e-7).abs() < 1e-20);
        assert!((h.row(1)[2] - 5.0 * 1e-9).abs() < 1e-22);
        assert_eq!(metadata(&lext()).unwrap()[0].0, "HeightDataPerPixelX");
    }

    #[test]
    fn truncated_files_and_other_tiffs_are_refused() {
        let f = lext();
        for cut in [0, 4, 20, 120, f.len() - 20] {
            assert!(read_height(&f[..cut]).is_err(), "cut at {cut}");
        }
        let mut other = f;
        other[8 + 90 + 30] = b'X'; // no HEIGHT page
        let e = format!("{:?}", read_height(&other).unwrap_err());
        assert!(e.contains("not an Olympus LEXT"), "{e}");
    }
}
