//! Line scans exported as text: `.hfm` (`X;Y;valid` profiles) and Bruker
//! Dektak CSV, read.
//!
//! - `.hfm`: the line `X;Y;valid`, the units (`[mm];[mm];[1/0]`), then rows
//!   `x;z;valid`. A row marked 0 is a point not measured (NaN); Surface-
//!   Topography ignores that column, so on files with such rows the two
//!   differ by design.
//! - Dektak CSV: a `Scan Parameters` block of `key,value` lines, an
//!   `Analytical Results` block, then `Scan Data`, the column titles
//!   (`Lateral um,Raw Micrometer`: the units are found in them) and rows
//!   `x,z`.
//! - Titled CSV line scans (what spreadsheets and instrument software export,
//!   SurfaceTopography's `csv-1…3`): a line of column titles, then rows `x,z`
//!   or `index,x,z` (a first column counting 0, 1, 2… or 1, 2, 3… is the
//!   index), separated by commas, semicolons or tabs; UTF-8, or UTF-16 with
//!   its byte-order mark (Excel's "Unicode text"). Units from the titles
//!   (`x in µm`, `X_(microns)`); heights whose title names none are taken in
//!   x's unit, and a file naming neither is unitless.
//!
//! asperity analyses uniformly sampled profiles: a line scan whose steps
//! differ from their mean by less than 1e-6 in x's unit (SurfaceTopography's
//! test) is read as a profile — a height field of one row, its spacing the
//! mean step, heights converted to x's unit. A non-uniformly sampled line
//! scan is refused with its smallest and largest step (it would have to be
//! resampled first, which asperity does not do silently).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::format::{Access, Claim, Codec, Magic, Registration};

/// Whether `bytes` start like a Dektak export.
pub(crate) fn is_dektak(bytes: &[u8]) -> bool {
    bytes.starts_with(b"Scan Parameters")
}

/// Whether `bytes` start like an `.hfm` profile.
pub(crate) fn is_hfm(bytes: &[u8]) -> bool {
    bytes.starts_with(b"X;Y;valid")
}

/// A length unit named in a title or a bracket (`um`, `Micrometer`, `[mm]`).
fn unit_in(text: &str) -> Option<LengthUnit> {
    let t = text.trim().trim_start_matches('[').trim_end_matches(']');
    let words = t.split(|c: char| !c.is_alphanumeric() && c != 'µ');
    words.into_iter().find_map(|w| match w {
        "m" | "meter" | "Meter" => Some(LengthUnit::M),
        "mm" | "Millimeter" | "millimeter" => Some(LengthUnit::Mm),
        "um" | "µm" | "Micrometer" | "micrometer" | "Micron" | "micron" | "microns" | "Microns" => {
            Some(LengthUnit::Um)
        }
        "nm" | "Nanometer" | "nanometer" => Some(LengthUnit::Nm),
        _ => None,
    })
}

/// The profile of `x` and `z` (z already in x's unit), if uniform.
pub(crate) fn profile(x: &[f64], z: Vec<f64>, unit: LengthUnit) -> FResult<HeightField> {
    let n = x.len();
    if n < 2 {
        return malformed(format!("{n} points: not a profile"));
    }
    let step = (x[n - 1] - x[0]) / (n - 1) as f64;
    let (lo, hi) = x
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        });
    if !(step.is_finite() && step > 0.0) {
        return malformed("the x values do not increase");
    }
    if (hi - step).abs().max((lo - step).abs()) >= 1e-6 {
        return unsupported(format!(
            "a non-uniformly sampled line scan ({n} points, steps from {lo} to {hi}); asperity analyses uniformly sampled profiles: resample it first"
        ));
    }
    Ok(HeightField::from_vec([n, 1], z)?
        .with_spacing([step, step])?
        .with_units(Units { xy: unit, z: unit }))
}

/// Numbers of the first columns of `rows` split by `sep`; `None` where a
/// row ends the data (an empty line).
fn columns<'a>(
    rows: impl Iterator<Item = &'a str>,
    sep: &[char],
    want: usize,
) -> FResult<Vec<Vec<f64>>> {
    let mut out = vec![Vec::new(); want];
    for (k, row) in rows.enumerate() {
        let row = row.trim();
        if row.is_empty() {
            continue;
        }
        let fields: Vec<&str> = row.split(sep).collect();
        if fields.len() < want {
            return malformed(format!(
                "data row {} has {} columns, {want} are needed (truncated?)",
                k + 1,
                fields.len()
            ));
        }
        for (c, col) in out.iter_mut().enumerate() {
            let v = fields[c].trim();
            col.push(if v.is_empty() && c == 2 {
                0.0 // an `.hfm` row cut before its validity
            } else {
                v.parse().map_err(|_| {
                    FormatError::Malformed(format!("data row {}: {v:?} is not a number", k + 1))
                })?
            });
        }
    }
    Ok(out)
}

fn text(bytes: &[u8]) -> String {
    bytes.iter().map(|&b| char::from(b)).collect()
}

/// Reads an `.hfm` profile.
pub(crate) fn read_hfm(bytes: &[u8]) -> FResult<HeightField> {
    if !is_hfm(bytes) {
        return malformed("does not start with `X;Y;valid`");
    }
    let t = text(bytes);
    let mut lines = t.lines().skip(1);
    let units: Vec<&str> = lines.next().unwrap_or_default().split(';').collect();
    let (Some(xu), Some(zu)) = (
        units.first().and_then(|u| unit_in(u)),
        units.get(1).and_then(|u| unit_in(u)),
    ) else {
        return malformed("the second line names no length units (`[mm];[mm];[1/0]`)");
    };
    let [x, z, valid] =
        <[Vec<f64>; 3]>::try_from(columns(lines, &[';'], 3)?).expect("three columns");
    let to = zu.metres().zip(xu.metres()).map_or(1.0, |(a, b)| a / b);
    let z = z
        .iter()
        .zip(&valid)
        .map(|(z, v)| if *v == 0.0 { f64::NAN } else { z * to })
        .collect();
    profile(&x, z, xu)
}

/// Reads a Dektak CSV profile.
pub(crate) fn read_dektak(bytes: &[u8]) -> FResult<HeightField> {
    if !is_dektak(bytes) {
        return malformed("does not start with `Scan Parameters`");
    }
    let t = text(bytes);
    let mut lines = t.lines().skip_while(|l| !l.starts_with("Scan Data"));
    if lines.next().is_none() {
        return malformed("no `Scan Data` block (truncated?)");
    }
    let mut lines = lines.skip_while(|l| l.trim().is_empty());
    let titles: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let (Some(xu), Some(zu)) = (
        titles.first().and_then(|u| unit_in(u)),
        titles.get(1).and_then(|u| unit_in(u)),
    ) else {
        return malformed(format!("the column titles {titles:?} name no length units"));
    };
    let [x, z] = <[Vec<f64>; 2]>::try_from(columns(lines, &[','], 2)?).expect("two columns");
    let to = zu.metres().zip(xu.metres()).map_or(1.0, |(a, b)| a / b);
    profile(&x, z.iter().map(|z| z * to).collect(), xu)
}

/// The text of a titled CSV: UTF-16 (little or big endian) when it starts
/// with that byte-order mark, UTF-8 otherwise (invalid bytes replaced).
fn decoded(bytes: &[u8]) -> String {
    let utf16 = |le: bool| {
        let units: Vec<u16> = bytes[2..]
            .chunks_exact(2)
            .map(|c| {
                let pair = [c[0], c[1]];
                if le {
                    u16::from_le_bytes(pair)
                } else {
                    u16::from_be_bytes(pair)
                }
            })
            .collect();
        String::from_utf16_lossy(&units)
    };
    match bytes {
        [0xFF, 0xFE, ..] => utf16(true),
        [0xFE, 0xFF, ..] => utf16(false),
        [0xEF, 0xBB, 0xBF, rest @ ..] => String::from_utf8_lossy(rest).into_owned(),
        _ => String::from_utf8_lossy(bytes).into_owned(),
    }
}

/// The fields of a CSV line (commas, semicolons or tabs).
fn fields(line: &str) -> Vec<&str> {
    line.split([',', ';', '\t']).map(str::trim).collect()
}

/// Whether `head` (a file's first bytes) is a titled CSV line scan: a first
/// line of two or three titles, not all numbers, and a second of numbers.
pub(crate) fn is_titled_csv(head: &[u8]) -> bool {
    let text = decoded(head);
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let (Some(titles), Some(first_row)) = (lines.next(), lines.next()) else {
        return false;
    };
    let titles = fields(titles);
    let row = fields(first_row);
    (2..=3).contains(&titles.len())
        && titles.iter().any(|t| t.parse::<f64>().is_err())
        && row.len() == titles.len()
        && row.iter().all(|v| v.parse::<f64>().is_ok())
}

/// Reads a titled CSV line scan.
pub(crate) fn read_titled_csv(bytes: &[u8]) -> FResult<HeightField> {
    let text = decoded(bytes);
    let mut lines = text.lines().skip_while(|l| l.trim().is_empty());
    let titles = fields(lines.next().unwrap_or_default());
    if !(2..=3).contains(&titles.len()) {
        return malformed(format!(
            "{} column titles; a line scan has `x,z` or `index,x,z`",
            titles.len()
        ));
    }
    let mut cols = columns(lines, &[',', ';', '\t'], titles.len())?;
    if cols.len() == 3 {
        let counts = |start: f64| {
            cols[0]
                .iter()
                .enumerate()
                .all(|(k, &v)| v == start + k as f64)
        };
        if !(counts(0.0) || counts(1.0)) {
            return unsupported(
                "three columns whose first is no index (0, 1, 2…): x y z points are read from .xyz or .txt",
            );
        }
        cols.remove(0);
    }
    let (xt, zt) = (titles[titles.len() - 2], titles[titles.len() - 1]);
    let [x, z] = <[Vec<f64>; 2]>::try_from(cols).expect("two columns");
    let xu = unit_in(xt).unwrap_or(LengthUnit::None);
    let to = unit_in(zt)
        .and_then(|zu| zu.metres().zip(xu.metres()))
        .map_or(1.0, |(a, b)| a / b);
    profile(&x, z.iter().map(|z| z * to).collect(), xu)
}

/// The registration of Hfm: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const HFM: Registration = Registration {
    name: "HFM line scan (.hfm)",
    extensions: &["hfm"],
    height: Access::Read,
    notes: "X;Y;valid rows: a uniformly sampled profile (one row), heights in x's unit, rows marked 0 missing; non-uniform scans refused",
    magic: Magic::Test(is_hfm),
    codec: Some(Codec::new(|b, _| read_hfm(b))),
    ..Registration::NONE
};

/// The registration of Dektak: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const DEKTAK: Registration = Registration {
    name: "Bruker Dektak CSV (.csv, told by content)",
    extensions: &["csv"],
    height: Access::Read,
    notes: "the Scan Data block, units from the column titles: a uniformly sampled profile (one row); non-uniform scans refused with their steps",
    magic: Magic::Test(is_dektak),
    claim: Some(Claim {
        extensions: &["csv"],
        test: is_dektak,
    }),
    codec: Some(Codec::new(|b, _| read_dektak(b))),
    ..Registration::NONE
};

/// The registration of CsvLineScan: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const CSV_LINE_SCAN: Registration = Registration {
    name: "Line scan CSV (.csv with column titles, told by content)",
    extensions: &["csv"],
    height: Access::Read,
    notes: "a line of titles, then `x,z` or `index,x,z` rows (commas, semicolons or tabs; UTF-8 or UTF-16 with its BOM), units from the titles (`x in µm`): a uniformly sampled profile (one row); non-uniform scans refused with their steps",
    claim: Some(Claim {
        extensions: &["csv"],
        test: is_titled_csv,
    }),
    codec: Some(Codec::new(|b, _| read_titled_csv(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_hfm_profile_in_its_units_with_invalid_rows_missing() {
        let f = b"X;Y;valid\r\n[mm];[um];[1/0]\r\n1.0;5;1\r\n1.5;6;0\r\n2.0;7;1\r\n";
        let h = read_hfm(f).unwrap();
        assert_eq!(h.dims(), [3, 1]);
        assert_eq!(h.spacing(), [0.5, 0.5]);
        assert_eq!(h.units().z, LengthUnit::Mm);
        assert!((h.data()[0] - 5e-3).abs() < 1e-15 && h.data()[1].is_nan());
        for cut in [0, 12, 25] {
            assert!(read_hfm(&f[..cut]).is_err(), "cut at {cut}");
        }
    }

    #[test]
    fn a_dektak_scan_is_read_when_uniform_and_refused_when_not() {
        let head =
            "Scan Parameters\r\nLength,1.0 um\r\n\r\nScan Data\r\nLateral um,Raw Micrometer,\r\n";
        let uniform = format!("{head}0.0,0.5,,\r\n0.5,0.25,,\r\n1.0,0.0,,\r\n");
        let h = read_dektak(uniform.as_bytes()).unwrap();
        assert_eq!(h.data(), &[0.5, 0.25, 0.0]);
        assert_eq!(h.units().xy, LengthUnit::Um);
        let rounded = format!("{head}0.0,0.5,,\r\n0.2,0.25,,\r\n0.3,0.0,,\r\n");
        let e = format!("{:?}", read_dektak(rounded.as_bytes()).unwrap_err());
        assert!(e.contains("non-uniformly sampled"), "{e}");
        assert!(read_dektak(b"Scan Parameters\r\n").is_err());
    }

    #[test]
    fn a_titled_csv_is_read_in_utf8_and_utf16_with_or_without_an_index() {
        let plain = "x in µm;height in nm\n0.0;1\n0.5;2\n1.0;3\n";
        assert!(is_titled_csv(plain.as_bytes()));
        let h = read_titled_csv(plain.as_bytes()).unwrap();
        assert_eq!(h.units().xy, LengthUnit::Um);
        assert_eq!(h.spacing(), [0.5, 0.5]);
        // Heights in nm, brought to x's µm.
        assert!((h.data()[2] - 3e-3).abs() < 1e-15);
        let indexed = "index,x in µm,y in µm\r\n0,1.0,5\r\n1,1.5,6\r\n2,2.0,7\r\n";
        let mut utf16 = vec![0xFF, 0xFE];
        utf16.extend(indexed.encode_utf16().flat_map(u16::to_le_bytes));
        assert!(is_titled_csv(&utf16));
        let h = read_titled_csv(&utf16).unwrap();
        assert_eq!(h.data(), &[5.0, 6.0, 7.0]);
        let mut be = vec![0xFE, 0xFF];
        be.extend(indexed.encode_utf16().flat_map(u16::to_be_bytes));
        assert_eq!(read_titled_csv(&be).unwrap().data(), &[5.0, 6.0, 7.0]);
    }

    #[test]
    fn titled_csvs_that_are_no_profile_are_told_apart_or_refused() {
        // A CSV grid (numbers from the first line) is no titled CSV.
        assert!(!is_titled_csv(b"1,2,3\n4,5,6\n"));
        assert!(!is_titled_csv(b"a,b,c,d\n1,2,3,4\n"));
        let xyz = "x,y,z\n0.5,0,1\n1.5,0,2\n2.5,0,3\n";
        let e = format!("{:?}", read_titled_csv(xyz.as_bytes()).unwrap_err());
        assert!(e.contains("no index"), "{e}");
        let rounded = "x (microns),z\n0.0386,1\n0.0772,2\n0.1159,3\n";
        let e = format!("{:?}", read_titled_csv(rounded.as_bytes()).unwrap_err());
        assert!(e.contains("non-uniformly sampled"), "{e}");
        assert!(read_titled_csv(b"x,z\n").is_err());
        assert!(read_titled_csv(b"\xff\xfe\x00").is_err());
    }
}
