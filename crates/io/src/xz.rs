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
//!
//! asperity analyses uniformly sampled profiles: a line scan whose steps
//! differ from their mean by less than 1e-6 in x's unit (SurfaceTopography's
//! test) is read as a profile — a height field of one row, its spacing the
//! mean step, heights converted to x's unit. A non-uniformly sampled line
//! scan is refused with its smallest and largest step (it would have to be
//! resampled first, which asperity does not do silently).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::error::{FResult, FormatError, malformed, unsupported};

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
        "um" | "µm" | "Micrometer" | "micrometer" | "Micron" | "micron" => Some(LengthUnit::Um),
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
    sep: char,
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
    let [x, z, valid] = <[Vec<f64>; 3]>::try_from(columns(lines, ';', 3)?).expect("three columns");
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
    let [x, z] = <[Vec<f64>; 2]>::try_from(columns(lines, ',', 2)?).expect("two columns");
    let to = zu.metres().zip(xu.metres()).map_or(1.0, |(a, b)| a / b);
    profile(&x, z.iter().map(|z| z * to).collect(), xu)
}

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
}
