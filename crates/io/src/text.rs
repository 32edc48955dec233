//! Plain-text formats: CSV height grids and XYZ point lists.
//!
//! **CSV** height fields: one line per grid row j, values separated by commas, in
//! Rust's shortest round-trip decimal form (so reading gives back the same `f64`).
//! A first comment line `# asperity height field: nx=… ny=… dx=… dy=… x0=… y0=…`
//! (and `xy_unit=… z_unit=…` when the field has units)
//! records the geometry; `numpy.loadtxt(f, delimiter=",")` skips it. Reading
//! accepts commas, semicolons, tabs or spaces, and `#` comment lines.
//!
//! **XYZ** point sets: `x y z` per line; reading takes the first three columns of
//! each non-comment line (extra columns, e.g. colours, are ignored).
//!
//! **XY** point lists (curves to drape, points to interpolate at): `x,y` per line
//! (commas, semicolons, tabs or spaces), `#` comment lines skipped, every value
//! finite.

use std::io::Write;

use asperity_core::{HeightField, LengthUnit, PointSet, Units};

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Registration};

fn text(bytes: &[u8]) -> FResult<&str> {
    std::str::from_utf8(bytes).map_err(|_| FormatError::Malformed("not UTF-8 text".into()))
}

fn numbers(line: &str) -> impl Iterator<Item = &str> {
    line.split([',', ';', ' ', '\t'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
}

/// Writes a CSV height field.
pub(crate) fn write_csv(
    w: &mut dyn Write,
    h: &HeightField,
    params: Option<&str>,
) -> std::io::Result<()> {
    let [dx, dy] = h.spacing();
    let [x0, y0] = h.origin();
    let units = h.units();
    let units = if units.is_none() {
        String::new()
    } else {
        format!(" xy_unit={} z_unit={}", units.xy.ascii(), units.z.ascii())
    };
    writeln!(
        w,
        "# asperity height field: nx={} ny={} dx={dx} dy={dy} x0={x0} y0={y0}{units}",
        h.nx(),
        h.ny()
    )?;
    if let Some(p) = params {
        writeln!(w, "{}{p}", crate::metadata::CSV_PREFIX)?;
    }
    let mut line = String::new();
    for j in 0..h.ny() {
        line.clear();
        for (i, z) in h.row(j).iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            line += &z.to_string();
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// Reads a CSV height field.
pub(crate) fn read_csv(bytes: &[u8]) -> FResult<HeightField> {
    let mut meta = std::collections::HashMap::new();
    let mut data = Vec::new();
    let (mut nx, mut ny) = (0usize, 0usize);
    for (n, line) in text(bytes)?.lines().enumerate() {
        let line = line.trim();
        if line.starts_with(crate::metadata::CSV_PREFIX.trim_end()) {
            continue; // the parameters (JSON, whose `=` are no header fields)
        }
        if let Some(c) = line.strip_prefix('#') {
            for kv in c.split_whitespace() {
                if let Some((k, v)) = kv.split_once('=') {
                    meta.insert(k.to_owned(), v.to_owned());
                }
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let before = data.len();
        for tok in numbers(line) {
            data.push(tok.parse::<f64>().map_err(|_| {
                FormatError::Malformed(format!("line {}: {tok:?} is not a number", n + 1))
            })?);
        }
        let count = data.len() - before;
        if ny == 0 {
            nx = count;
        } else if count != nx {
            return malformed(format!(
                "line {} has {count} values but the first row has {nx}",
                n + 1
            ));
        }
        ny += 1;
    }
    if ny == 0 {
        return malformed("no data rows");
    }
    let get = |k: &str| -> FResult<Option<f64>> {
        meta.get(k)
            .map(|v| {
                v.parse().map_err(|_| {
                    FormatError::Malformed(format!("header {k}={v:?} is not a number"))
                })
            })
            .transpose()
    };
    let pair = |a: Option<f64>, b: Option<f64>| a.zip(b).map(|(a, b)| [a, b]);
    let spacing = pair(get("dx")?, get("dy")?);
    let origin = pair(get("x0")?, get("y0")?);
    let unit = |k: &str| -> FResult<LengthUnit> {
        meta.get(k).map_or(Ok(LengthUnit::None), |v| {
            LengthUnit::parse(v).map_err(|e| FormatError::Malformed(format!("header {k}: {e}")))
        })
    };
    let units = Units {
        xy: unit("xy_unit")?,
        z: unit("z_unit")?,
    };
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_geometry(spacing, origin)?
        .with_units(units))
}

/// Writes an XYZ point list.
pub(crate) fn write_xyz(w: &mut dyn Write, p: &PointSet) -> std::io::Result<()> {
    for q in p.positions() {
        writeln!(w, "{} {} {}", q[0], q[1], q[2])?;
    }
    Ok(())
}

/// Reads an XYZ point list.
pub(crate) fn read_xyz(bytes: &[u8]) -> FResult<PointSet> {
    let mut pts = Vec::new();
    for (n, line) in text(bytes)?.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') || line.starts_with("//") {
            continue;
        }
        let mut it = numbers(line);
        let mut p = [0.0; 3];
        for v in &mut p {
            let tok = it.next().ok_or_else(|| {
                FormatError::Malformed(format!("line {}: fewer than 3 columns", n + 1))
            })?;
            *v = tok.parse().map_err(|_| {
                FormatError::Malformed(format!("line {}: {tok:?} is not a number", n + 1))
            })?;
        }
        pts.push(p);
    }
    let ps = PointSet::new(pts);
    ps.validate()?;
    Ok(ps)
}

/// Reads `x,y` rows.
pub(crate) fn read_xy(bytes: &[u8]) -> FResult<Vec<[f64; 2]>> {
    let mut pts = Vec::new();
    for (n, line) in text(bytes)?.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut it = numbers(line);
        let mut p = [0.0; 2];
        for v in &mut p {
            let tok = it
                .next()
                .ok_or_else(|| FormatError::Malformed(format!("line {}: need x,y", n + 1)))?;
            *v = tok
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    FormatError::Malformed(format!(
                        "line {}: {tok:?} is not a finite number",
                        n + 1
                    ))
                })?;
        }
        pts.push(p);
    }
    Ok(pts)
}

/// The registration of Xyz: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const XYZ: Registration = Registration {
    name: "XYZ text",
    extensions: &["xyz", "txt"],
    points: Access::ReadWrite,
    notes: "x y z per line",
    read: Some(|b| read_xyz(b).map(crate::Surface::Points)),
    ..Registration::NONE
};

/// The registration of Csv: its row of `asperity formats`, how its files
/// are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const CSV: Registration = Registration {
    name: "CSV grid",
    extensions: &["csv"],
    height: Access::ReadWrite,
    notes: "one row per line, geometry in a # comment line; missing points NaN",
    codec: Some(Codec::new(|b, _| read_csv(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_ragged_and_bad_numbers() {
        let FormatError::Malformed(m) = read_csv(b"1,2,3\n4,5\n").unwrap_err() else {
            panic!()
        };
        assert!(m.contains("line 2 has 2 values"), "{m}");
        let FormatError::Malformed(m) = read_csv(b"1,2\n3,x\n").unwrap_err() else {
            panic!()
        };
        assert!(m.contains("line 2: \"x\""), "{m}");
        let h = read_csv(b"# dx=0.5 dy=2\n1 2\n3 4\n").unwrap();
        assert_eq!(h.spacing(), [0.5, 2.0]);
        assert_eq!(*h.get(0, 1), 3.0);
    }

    #[test]
    fn xyz_columns() {
        let p = read_xyz(b"# c\n1 2 3 255 0 0\n4,5,6\n").unwrap();
        assert_eq!(p.positions(), &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
        assert!(read_xyz(b"1 2\n").is_err());
        assert!(read_xyz(b"1 2 nan\n").is_err());
    }

    #[test]
    fn xy_rows_comments_and_errors() {
        let p = read_xy(b"# x,y\n0.5,1\n2;3\n\n4 5 6\n").unwrap();
        assert_eq!(p, vec![[0.5, 1.0], [2.0, 3.0], [4.0, 5.0]]);
        let FormatError::Malformed(m) = read_xy(b"1,2\n3\n").unwrap_err() else {
            panic!()
        };
        assert!(m.contains("line 2: need x,y"), "{m}");
        assert!(read_xy(b"1,inf\n").is_err());
    }
}
