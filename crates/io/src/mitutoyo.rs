//! Mitutoyo SurfTest roughness testers' Excel exports (`.xlsx`), read: the
//! measured profile, with the tester's roughness parameters as metadata.
//!
//! The workbook (read with the `calamine` crate, cell by cell, so a sheet
//! that names a far cell allocates nothing for the cells between) has a sheet
//! `DATA` whose columns E and F hold the profile's positions and heights, one
//! point per row, and whose column A lists the roughness parameters the
//! tester computed (`Ra     0.018  µm`, from row 1 to the first empty cell);
//! and a sheet `Certificate` with the date in E2 and the cut-off in E48
//! (`0.08mm`), whose unit is the positions' unit. The heights' unit is the
//! first parameter's (µm), the positions' otherwise.
//!
//! The positions start at one step (each height sits at the end of its
//! step), so the profile's length is the last position and its step that
//! over the number of points — as SurfaceTopography reads it. A profile
//! whose steps differ (beyond 1e-5 relative, numpy's `isclose`) is refused
//! as non-uniformly sampled, as every line scan asperity reads. Layout learnt
//! from SurfaceTopography's `Mitutoyo.py`; checked on its three example files
//! in `python/tests/reference/check_instruments.py`.

use std::collections::BTreeMap;
use std::io::Cursor;

use asperity_core::{HeightField, LengthUnit, Units};
use calamine::{DataRef, Xlsx};

use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::sur::length_unit;
use crate::format::{Access, Codec, Registration};

/// Columns (from 0) of the sheet `DATA`.
const METRICS: u32 = 0;
const POSITIONS: u32 = 4;
const HEIGHTS: u32 = 5;

fn bad(msg: impl Into<String>) -> FormatError {
    FormatError::Malformed(msg.into())
}

/// What the workbook holds.
struct Sheets {
    /// Per row: position and height.
    points: BTreeMap<u32, (Option<f64>, Option<f64>)>,
    /// Column A: per row, the text.
    metrics: BTreeMap<u32, String>,
    date: Option<String>,
    cut_off: Option<String>,
}

fn number(v: &DataRef<'_>) -> Option<f64> {
    match v {
        DataRef::Float(f) => Some(*f),
        DataRef::Int(i) => Some(*i as f64),
        _ => None,
    }
}

fn text(v: &DataRef<'_>) -> Option<String> {
    match v {
        DataRef::String(s) => Some(s.clone()),
        DataRef::SharedString(s) => Some((*s).to_string()),
        DataRef::DateTimeIso(s) => Some(s.clone()),
        _ => None,
    }
}

/// Whether `r` is a cell reference or range Excel can write: up to three
/// letters and seven digits a cell (`XFD1048576`), `$` anchors allowed.
fn excel_reference(r: &str) -> bool {
    r.split([':', ' ']).all(|cell| {
        let cell = cell.replace('$', "");
        let letters = cell.bytes().take_while(u8::is_ascii_alphabetic).count();
        let digits = cell.len() - letters;
        letters <= 3 && digits <= 7 && cell.bytes().skip(letters).all(|b| b.is_ascii_digit())
    })
}

/// Refuses a workbook whose parts hold a cell reference longer than Excel's.
/// calamine 0.38 parses references with unchecked u32 arithmetic, which
/// overflows on such a reference (a panic where overflow checks are on,
/// a wrong cell where not); found by fuzzing, so checked here first.
fn check_references(bytes: &[u8]) -> FResult<()> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| bad(format!("not a readable Excel workbook: {e}")))?;
    for k in 0..zip.len() {
        let mut part = zip
            .by_index(k)
            .map_err(|e| bad(format!("part {k} of the workbook: {e}")))?;
        if !part.name().is_ok_and(|n| n.ends_with(".xml")) {
            continue;
        }
        let mut xml = Vec::new();
        std::io::Read::read_to_end(&mut part, &mut xml)
            .map_err(|e| bad(format!("part {k} of the workbook: {e}")))?;
        let xml = String::from_utf8_lossy(&xml);
        // The references calamine's cell reader parses: cells, rows and
        // the sheet's dimension (charts' `r=` margins are no references).
        for attr in ["<c r=\"", "<row r=\"", "<dimension ref=\""] {
            for (at, _) in xml.match_indices(attr) {
                let value = xml[at + attr.len()..].split('"').next().unwrap_or_default();
                if !excel_reference(value) {
                    return malformed(format!(
                        "the cell reference {:.40?} is longer than Excel's (XFD1048576)",
                        value
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Reads the cells asperity needs from the two sheets.
fn sheets(bytes: &[u8]) -> FResult<Sheets> {
    check_references(bytes)?;
    let mut book: Xlsx<_> = calamine::open_workbook_from_rs(Cursor::new(bytes))
        .map_err(|e| bad(format!("not a readable Excel workbook: {e}")))?;
    let mut out = Sheets {
        points: BTreeMap::new(),
        metrics: BTreeMap::new(),
        date: None,
        cut_off: None,
    };
    {
        let mut cells = book.worksheet_cells_reader("DATA").map_err(|e| {
            bad(format!(
                "no sheet DATA ({e}): not a Mitutoyo SurfTest export"
            ))
        })?;
        while let Some(cell) = cells
            .next_cell()
            .map_err(|e| bad(format!("sheet DATA: {e}")))?
        {
            let ((row, col), v) = (cell.get_position(), cell.get_value());
            let which = |k: usize| {
                let value = number(v).ok_or_else(|| {
                    bad(format!(
                        "sheet DATA, row {}: column {} holds {v:?}, not a number",
                        row + 1,
                        ["E", "F"][k]
                    ))
                });
                value.map(Some)
            };
            match col {
                POSITIONS if !matches!(v, DataRef::Empty) => {
                    out.points.entry(row).or_default().0 = which(0)?;
                }
                HEIGHTS if !matches!(v, DataRef::Empty) => {
                    out.points.entry(row).or_default().1 = which(1)?;
                }
                METRICS => {
                    if let Some(t) = text(v) {
                        out.metrics.insert(row, t);
                    }
                }
                _ => {}
            }
        }
    }
    let mut cells = book.worksheet_cells_reader("Certificate").map_err(|e| {
        bad(format!(
            "no sheet Certificate ({e}): not a Mitutoyo SurfTest export"
        ))
    })?;
    while let Some(cell) = cells
        .next_cell()
        .map_err(|e| bad(format!("sheet Certificate: {e}")))?
    {
        match cell.get_position() {
            (1, 4) => out.date = text(cell.get_value()),
            (47, 4) => out.cut_off = text(cell.get_value()),
            _ => {}
        }
    }
    Ok(out)
}

/// The roughness parameters of column A (from row 1 to the first gap):
/// name, value and unit (`Ra     0.018  µm`).
fn metrics(s: &Sheets) -> Vec<(String, String, String)> {
    let mut out = Vec::new();
    for (k, (&row, t)) in s.metrics.iter().enumerate() {
        if row as usize != k {
            break;
        }
        let mut words = t.split_whitespace();
        if let (Some(key), Some(value)) = (words.next(), words.next())
            && value.parse::<f64>().is_ok()
        {
            let unit = words.next().unwrap_or_default();
            out.push((key.to_string(), value.to_string(), unit.to_string()));
        }
    }
    out
}

/// `0.08mm` or `2.5 mm` as its unit.
fn cut_off_unit(text: &str) -> Option<String> {
    let t = text.trim();
    let end = t.find(|c: char| !(c.is_ascii_digit() || "+-.".contains(c)))?;
    t[..end].parse::<f64>().ok()?;
    Some(t[end..].trim().to_string()).filter(|u| !u.is_empty())
}

/// Metres per unit named `text` (1 where it is no length).
fn metres(text: &str) -> f64 {
    let (unit, factor) = length_unit(text);
    unit.metres().map_or(1.0, |m| m * factor)
}

/// Reads the profile.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let s = sheets(bytes)?;
    let x_unit = s.cut_off.as_deref().and_then(cut_off_unit).ok_or_else(|| {
        bad("the Certificate sheet gives no cut-off (E48) whose unit is the positions'")
    })?;
    let h_unit = metrics(&s)
        .into_iter()
        .map(|(_, _, u)| u)
        .next()
        .filter(|u| length_unit(u).0 != LengthUnit::None)
        .unwrap_or(x_unit.clone());
    let (unit, _) = length_unit(&h_unit);
    let to = metres(&x_unit) / metres(&h_unit);
    let mut x = Vec::with_capacity(s.points.len());
    let mut z = Vec::with_capacity(s.points.len());
    for (row, p) in &s.points {
        match *p {
            (Some(xi), Some(zi)) => {
                x.push(xi * to);
                z.push(zi * length_unit(&h_unit).1);
            }
            _ => {
                return malformed(format!(
                    "sheet DATA, row {}: a position without a height or a height without a position",
                    row + 1
                ));
            }
        }
    }
    let n = x.len();
    if n < 2 {
        return malformed(format!("{n} points: not a profile"));
    }
    let first = x[1] - x[0];
    let (lo, hi) = x
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        });
    if !(first.is_finite() && first > 0.0) {
        return malformed("the positions do not increase");
    }
    // numpy's isclose(d, first): |d − first| ≤ 1e-8 + 1e-5 |first|.
    let tol = 1e-8 + 1e-5 * first.abs();
    if (hi - first).abs().max((lo - first).abs()) > tol {
        return unsupported(format!(
            "a non-uniformly sampled line scan ({n} points, steps from {lo} to {hi}); asperity analyses uniformly sampled profiles: resample it first"
        ));
    }
    let length = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let step = length / n as f64;
    Ok(HeightField::from_vec([n, 1], z)?
        .with_spacing([step, step])?
        .with_units(Units { xy: unit, z: unit }))
}

/// The tester's roughness parameters, the date and the cut-off.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    let s = sheets(bytes)?;
    let mut out: Vec<(String, String)> = metrics(&s)
        .into_iter()
        .map(|(k, v, u)| (k, format!("{v} {u}").trim().to_string()))
        .collect();
    if let Some(d) = &s.date {
        out.push(("date".into(), d.split_whitespace().collect()));
    }
    if let Some(c) = &s.cut_off {
        out.push(("cut-off".into(), c.trim().to_string()));
    }
    Ok(out)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Mitutoyo SurfTest (.xlsx)",
    extensions: &["xlsx"],
    height: Access::Read,
    notes: "the DATA sheet's positions (E) and heights (F) as a uniformly sampled profile (non-uniform refused), heights in the first roughness parameter's unit, positions in the cut-off's; the tester's roughness parameters, date and cut-off kept as metadata",
    codec: Some(Codec::new(|b, _| read_height(b))
        .metadata(metadata)
        .declared(crate::zipped::declared_twice)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    /// A worksheet of `(cell, value)`: numbers, or text as inline strings.
    fn sheet(cells: &[(&str, &str)]) -> String {
        let mut rows: BTreeMap<u32, String> = BTreeMap::new();
        for (at, v) in cells {
            let row: u32 = at.trim_start_matches(char::is_alphabetic).parse().unwrap();
            let cell = if v.parse::<f64>().is_ok() {
                format!(r#"<c r="{at}"><v>{v}</v></c>"#)
            } else {
                format!(r#"<c r="{at}" t="inlineStr"><is><t>{v}</t></is></c>"#)
            };
            rows.entry(row).or_default().push_str(&cell);
        }
        let rows: String = rows
            .iter()
            .map(|(r, c)| format!(r#"<row r="{r}">{c}</row>"#))
            .collect();
        format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>{rows}</sheetData></worksheet>"#
        )
    }

    /// A workbook with the sheets Certificate and DATA.
    fn workbook(certificate: &[(&str, &str)], data: &[(&str, &str)]) -> Vec<u8> {
        let main = "http://schemas.openxmlformats.org";
        let parts = [
            (
                "[Content_Types].xml",
                format!(
                    r#"<?xml version="1.0"?><Types xmlns="{main}/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/></Types>"#
                ),
            ),
            (
                "_rels/.rels",
                format!(
                    r#"<?xml version="1.0"?><Relationships xmlns="{main}/package/2006/relationships"><Relationship Id="rId1" Type="{main}/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#
                ),
            ),
            (
                "xl/workbook.xml",
                format!(
                    r#"<?xml version="1.0"?><workbook xmlns="{main}/spreadsheetml/2006/main" xmlns:r="{main}/officeDocument/2006/relationships"><sheets><sheet name="Certificate" sheetId="1" r:id="rId1"/><sheet name="DATA" sheetId="2" r:id="rId2"/></sheets></workbook>"#
                ),
            ),
            (
                "xl/_rels/workbook.xml.rels",
                format!(
                    r#"<?xml version="1.0"?><Relationships xmlns="{main}/package/2006/relationships"><Relationship Id="rId1" Type="{main}/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet1.xml"/><Relationship Id="rId2" Type="{main}/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet2.xml"/></Relationships>"#
                ),
            ),
            ("xl/worksheets/sheet1.xml", sheet(certificate)),
            ("xl/worksheets/sheet2.xml", sheet(data)),
        ];
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        for (name, text) in parts {
            zip.start_file(name, zip::write::SimpleFileOptions::default())
                .unwrap();
            zip.write_all(text.as_bytes()).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    const CERTIFICATE: [(&str, &str); 2] = [("E2", "10- Oct -2022"), ("E48", "0.08mm")];

    /// Four points 0.5 µm apart, written in mm; heights in µm.
    fn profile(xs: [&str; 4]) -> Vec<u8> {
        let data = [
            ("A1", "Ra     0.018  µm      "),
            ("A2", "Rsk    -0.144         "),
            ("E1", xs[0]),
            ("F1", "0.25"),
            ("E2", xs[1]),
            ("F2", "-1"),
            ("E3", xs[2]),
            ("F3", "2"),
            ("E4", xs[3]),
            ("F4", "3"),
        ];
        workbook(&CERTIFICATE, &data)
    }

    use crate::error::refused as err;

    #[test]
    fn a_uniform_profile_in_the_first_parameters_unit_with_its_metadata() {
        let file = profile(["0.0005", "0.001", "0.0015", "0.002"]);
        let h = read_height(&file).unwrap();
        assert_eq!(h.dims(), [4, 1]);
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Um
            }
        );
        // The length is the last position, 2 µm: four steps of 0.5 µm.
        assert!((h.spacing()[0] - 0.5).abs() < 1e-12, "{:?}", h.spacing());
        assert_eq!((*h.get(0, 0), *h.get(3, 0)), (0.25, 3.0));
        let meta = metadata(&file).unwrap();
        assert!(meta.contains(&("Ra".into(), "0.018 µm".into())));
        assert!(meta.contains(&("Rsk".into(), "-0.144".into())));
        assert!(meta.contains(&("date".into(), "10-Oct-2022".into())));
        assert!(meta.contains(&("cut-off".into(), "0.08mm".into())));
        assert!(crate::zipped::declared_bytes(&file).unwrap() > 1000);
    }

    #[test]
    fn cell_references_longer_than_excels_are_refused_before_calamine_parses_them() {
        assert!(
            excel_reference("A1") && excel_reference("$XFD$1048576") && excel_reference("A1:C3 E5")
        );
        assert!(
            !excel_reference("AAAAAAAA1")
                && !excel_reference("A12345678")
                && !excel_reference("A1x")
        );
        let long = workbook(&CERTIFICATE, &[("AAAAAAAAAAAAAAAAA1", "1")]);
        assert!(err(read_height(&long)).contains("longer than Excel's"));
    }

    #[test]
    fn uneven_steps_missing_cells_and_other_workbooks_are_refused() {
        let uneven = profile(["0.0005", "0.001", "0.0016", "0.002"]);
        assert!(err(read_height(&uneven)).contains("non-uniformly sampled"));
        let holed = workbook(
            &CERTIFICATE,
            &[("E1", "0.0005"), ("F1", "1"), ("E2", "0.001")],
        );
        assert!(err(read_height(&holed)).contains("row 2: a position without a height"));
        let words = workbook(&CERTIFICATE, &[("E1", "x (mm)"), ("F1", "1")]);
        assert!(err(read_height(&words)).contains("not a number"));
        let no_cut_off = workbook(&[("E2", "today")], &[("E1", "1"), ("F1", "1")]);
        assert!(err(read_height(&no_cut_off)).contains("cut-off"));
        assert!(err(read_height(b"PK\x03\x04 not a zip")).contains("Excel workbook"));
        let good = profile(["0.0005", "0.001", "0.0015", "0.002"]);
        for cut in (0..good.len()).step_by(7) {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
    }

    /// The fuzz target's committed seed (`fuzz/seeds/mitutoyo/profile4.xlsx`) is
    /// the workbook built here, read back. `fuzz/make_seeds.sh` sets
    /// `ASPERITY_WRITE_SEEDS` to write it.
    #[test]
    fn the_fuzz_seed_is_a_workbook_this_reader_reads() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fuzz/seeds/mitutoyo/profile4.xlsx");
        if std::env::var_os("ASPERITY_WRITE_SEEDS").is_some() {
            std::fs::write(&path, profile(["0.0005", "0.001", "0.0015", "0.002"])).unwrap();
        }
        let h = read_height(&std::fs::read(&path).unwrap()).unwrap();
        assert_eq!((h.dims(), *h.get(3, 0)), ([4, 1], 3.0));
    }
}
