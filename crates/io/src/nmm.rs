//! SIOS nanomeasuring machine (NMM) scans, zipped (`.zip`), read.
//!
//! The archive holds the scan procedure description `PREFIX.dsc` (the
//! shortest file stem in the archive) and, for scan s and line i, the pair
//! `PREFIX_s_i.dsc` / `PREFIX_s_i.dat`. The procedure description is text: a
//! line of dashes, `Scan procedure description file`, `key : value` lines
//! (the creation time among them), then sections (`N name`, `key : value`
//! lines, dashes) of which `Scan field` gives `Number of scans`, `Number of
//! lines`, `Scan line length`, `Scan field width`, `Distance beetween
//! points` and `Distance beetween lines` (sic), each `value [unit]` in one
//! length unit. A line's `.dsc` names the columns of its `.dat` (`index :
//! date : name : points : description` after one line), whose
//! whitespace-separated rows hold them; the heights are the column `-Lz+Az`,
//! in metres. Along x there are length / spacing + 1 points (checked to
//! 1e-6), along y one line each; scan s is channel `Scan s`. Layout from
//! SurfaceTopography's `NMM.py`; checked against it on an archive built to
//! that layout (no instrument file is public).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::Metadata;
use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed};
use crate::zipped::{self, Archive};
use crate::format::{Access, Codec, Registration};

const DASHES: &str = "------------------------------------------";
/// A text member larger than this is refused (a line of an NMM scan is a
/// few hundred kilobytes).
const TEXT_LIMIT: u64 = 256 << 20;

fn bad(e: String) -> FormatError {
    FormatError::Malformed(format!("not a readable NMM archive: {e}"))
}

fn text(zip: &mut Archive<'_>, name: &str) -> FResult<String> {
    let out = zipped::required(zip, name, TEXT_LIMIT, bad)?;
    Ok(String::from_utf8_lossy(&out).into_owned())
}

/// The scan: prefix, scans, grid, spacing, unit and the top-level keys.
struct Scan {
    prefix: String,
    scans: usize,
    nx: usize,
    ny: usize,
    step: [f64; 2],
    unit: LengthUnit,
    meta: Metadata,
}

/// The shortest stem among the files whose name starts with neither `.`
/// nor `_` (macOS and editor debris), as SurfaceTopography picks it.
fn prefix(zip: &Archive<'_>) -> FResult<String> {
    zip.file_names()
        .filter_map(Result::ok)
        .filter(|n| !n.rsplit('/').next().unwrap_or("").starts_with(['.', '_']))
        .filter_map(|n| n.split_once('.').map(|(stem, _)| stem.to_owned()))
        .min_by_key(String::len)
        .ok_or_else(|| FormatError::Malformed("no member with a file stem".into()))
}

/// The description's top-level `key : value` pairs and its `Scan field`
/// section's.
fn description(dsc: &str, name: &str) -> FResult<(Metadata, Metadata)> {
    let mut lines = dsc.lines().map(str::trim);
    if lines.next() != Some(DASHES) || lines.next() != Some("Scan procedure description file") {
        return malformed(format!("{name} is no NMM scan procedure description"));
    }
    let (mut meta, mut field) = (Vec::new(), Vec::new());
    let mut section: Option<String> = None; // None: still the top level
    for line in lines.filter(|l| !l.is_empty()) {
        if line == DASHES {
            section = Some(String::new());
            continue;
        }
        match (line.split_once(':'), &section) {
            (Some((k, v)), None) => meta.push((k.trim().to_owned(), v.trim().to_owned())),
            (Some((k, v)), Some(s)) if s == "Scan field" => {
                field.push((k.trim().to_owned(), v.trim().to_owned()));
            }
            (None, Some(_)) => {
                let title = line.split_once(' ').map_or("", |(_, t)| t);
                section = Some(title.trim().to_owned());
            }
            _ => {}
        }
    }
    Ok((meta, field))
}

/// A `Scan field` count.
fn count(field: &Metadata, k: &str) -> FResult<usize> {
    let v = field_value(field, k)?;
    v.parse()
        .map_err(|_| FormatError::Malformed(format!("{k}: {v:?} is no count")))
}

/// A `Scan field` length, `value [unit]`.
fn length(field: &Metadata, k: &str) -> FResult<(f64, String)> {
    let v = field_value(field, k)?;
    let (n, u) = v.split_once(' ').unwrap_or((v, ""));
    let n: f64 = n
        .parse()
        .map_err(|_| FormatError::Malformed(format!("{k}: {v:?}")))?;
    let unit = u.trim().trim_start_matches('[').trim_end_matches(']');
    Ok((n, unit.to_owned()))
}

fn field_value<'f>(field: &'f Metadata, k: &str) -> FResult<&'f str> {
    field
        .iter()
        .find(|(key, _)| key == k)
        .map(|(_, v)| v.as_str())
        .ok_or_else(|| FormatError::Malformed(format!("the Scan field section has no {k:?}")))
}

fn scan(zip: &mut Archive<'_>) -> FResult<Scan> {
    let prefix = prefix(zip)?;
    let name = format!("{prefix}.dsc");
    if zip.index_for_name(&name).is_none() {
        return malformed(format!(
            "no scan procedure description {name}: asperity reads a .zip as SIOS NMM scans"
        ));
    }
    let (meta, field) = description(&text(zip, &name)?, &name)?;
    let (scans, ny) = (
        count(&field, "Number of scans")?,
        count(&field, "Number of lines")?,
    );
    let (lx, ux) = length(&field, "Scan line length")?;
    let (ly, uy) = length(&field, "Scan field width")?;
    let (dx, udx) = length(&field, "Distance beetween points")?;
    let (dy, udy) = length(&field, "Distance beetween lines")?;
    if [&uy, &udx, &udy].iter().any(|u| **u != ux) {
        return malformed(format!(
            "lengths in several units ({ux}, {uy}, {udx}, {udy})"
        ));
    }
    let unit = LengthUnit::parse(&ux)
        .ok()
        .filter(|u| *u != LengthUnit::None)
        .ok_or_else(|| FormatError::Malformed(format!("the unit {ux:?} is no length")))?;
    let intervals = lx / dx;
    if !(lx > 0.0
        && dx > 0.0
        && dy > 0.0
        && intervals < 1e9
        && (1..=1 << 20).contains(&scans)
        && ny > 1)
    {
        return malformed(format!(
            "a scan field of {lx} × {ly} {ux}, steps {dx} and {dy}, {ny} lines, {scans} scans"
        ));
    }
    let intervals = intervals as usize;
    let even = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-6;
    if !even(intervals as f64 * dx, lx) || !even((ny - 1) as f64 * dy, ly) {
        return malformed("the points do not divide the scan field evenly");
    }
    Ok(Scan {
        prefix,
        scans,
        nx: intervals + 1,
        ny,
        step: [dx, dy],
        unit,
        meta,
    })
}

fn open(bytes: &[u8]) -> FResult<(Archive<'_>, Scan)> {
    let mut zip = zipped::open(bytes, bad)?;
    let s = scan(&mut zip)?;
    Ok((zip, s))
}

fn infos(s: &Scan) -> Vec<ChannelInfo> {
    (0..s.scans)
        .map(|k| ChannelInfo {
            index: k,
            name: format!("Scan {}", k + 1),
            height: true,
        })
        .collect()
}

/// The scans as channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    Ok(infos(&open(bytes)?.1))
}

/// One line's heights (metres).
fn line(zip: &mut Archive<'_>, s: &Scan, scan: usize, i: usize) -> FResult<Vec<f64>> {
    let stem = format!("{}_{}_{}", s.prefix, scan + 1, i + 1);
    let dsc = text(zip, &format!("{stem}.dsc"))?;
    let names: Vec<String> = dsc
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(" : ").collect();
            (f.len() >= 4 && f[3].trim().parse::<f64>().is_ok()).then(|| f[2].trim().to_owned())
        })
        .collect();
    let column = names
        .iter()
        .position(|n| n == "-Lz+Az")
        .ok_or_else(|| FormatError::Malformed(format!("{stem}.dsc names no column -Lz+Az")))?;
    let dat = text(zip, &format!("{stem}.dat"))?;
    let mut out = Vec::with_capacity(s.nx);
    for (r, row) in dat.lines().filter(|l| !l.trim().is_empty()).enumerate() {
        let fields: Vec<&str> = row.split_whitespace().collect();
        if fields.len() != names.len() {
            return malformed(format!(
                "{stem}.dat row {}: {} columns, its .dsc names {}",
                r + 1,
                fields.len(),
                names.len()
            ));
        }
        out.push(fields[column].parse().map_err(|_| {
            FormatError::Malformed(format!(
                "{stem}.dat row {}: {:?} is not a number",
                r + 1,
                fields[column]
            ))
        })?);
    }
    if out.len() != s.nx {
        return malformed(format!(
            "{stem}.dat has {} points, the scan field {}",
            out.len(),
            s.nx
        ));
    }
    Ok(out)
}

/// Reads the scan `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let (mut zip, s) = open(bytes)?;
    let k = pick(&infos(&s), choice)?;
    let to_unit = 1.0 / s.unit.metres().unwrap_or(1.0);
    let mut data = Vec::with_capacity(s.nx.saturating_mul(s.ny).min(bytes.len()));
    for i in 0..s.ny {
        data.extend(line(&mut zip, &s, k, i)?.into_iter().map(|h| h * to_unit));
    }
    Ok(HeightField::from_vec([s.nx, s.ny], data)?
        .with_spacing(s.step)?
        .with_units(Units {
            xy: s.unit,
            z: s.unit,
        }))
}

/// The procedure description's top-level keys (creation time…).
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Metadata> {
    Ok(open(bytes)?.1.meta)
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "SIOS nanomeasuring machine (.zip of .dsc/.dat)",
    extensions: &["zip"],
    height: Access::Read,
    notes: "the scan procedure description's field (points, lines, spacing, unit) and each line's -Lz+Az column (m, brought to the field's unit); every scan a channel; the description's keys kept as metadata",
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

    const DASHES_N: &str = "------------------------------------------\n";

    /// One scan of 2 lines × 3 points (µm field), heights `h` in m.
    fn nmm(h: [[f64; 3]; 2], drop_line: bool) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default();
        let dsc = format!(
            "{DASHES_N}Scan procedure description file\nCreation time : 2026-11-28\n{DASHES_N}\
             1 Scan field\nNumber of scans : 1\nNumber of lines : 2\nScan line length : 1 [µm]\n\
             Scan field width : 0.5 [µm]\nDistance beetween points : 0.5 [µm]\n\
             Distance beetween lines : 0.5 [µm]\n{DASHES_N}"
        );
        zip.start_file("s.dsc", opts).unwrap();
        zip.write_all(dsc.as_bytes()).unwrap();
        for (i, row) in h.iter().enumerate().take(if drop_line { 1 } else { 2 }) {
            zip.start_file(format!("s_1_{}.dsc", i + 1), opts).unwrap();
            zip.write_all(b"head\n0 : d : Lx : 3 : x\n1 : d : -Lz+Az : 3 : z\n")
                .unwrap();
            zip.start_file(format!("s_1_{}.dat", i + 1), opts).unwrap();
            for (k, z) in row.iter().enumerate() {
                writeln!(zip, "{} {z}", k as f64 * 5e-7).unwrap();
            }
        }
        zip.finish().unwrap().into_inner()
    }

    #[test]
    fn lines_are_rows_in_the_field_unit() {
        let h = read_channel(&nmm([[1e-9, 2e-9, 3e-9], [4e-9, 5e-9, 6e-9]], false), None).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([3, 2], [0.5, 0.5]));
        assert_eq!(h.units().z, LengthUnit::Um);
        assert!((h.row(1)[2] - 6e-3).abs() < 1e-15);
        let m = metadata(&nmm([[0.0; 3]; 2], false)).unwrap();
        assert_eq!(m[0], ("Creation time".to_owned(), "2026-11-28".to_owned()));
    }

    #[test]
    fn missing_lines_and_other_zips_are_refused() {
        let e = format!(
            "{:?}",
            read_channel(&nmm([[0.0; 3]; 2], true), None).unwrap_err()
        );
        assert!(e.contains("s_1_2.dsc"), "{e}");
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        zip.start_file("meta.yml", zip::write::SimpleFileOptions::default())
            .unwrap();
        let e = format!(
            "{:?}",
            read_channel(&zip.finish().unwrap().into_inner(), None).unwrap_err()
        );
        assert!(e.contains("SIOS NMM"), "{e}");
    }
}
