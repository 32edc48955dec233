//! Height data as plain text — a matrix of heights, Gwyddion's text export,
//! a profile of one or two columns, gridded `x y z` rows — read (`.asc`, and
//! `.txt` files of numbers).
//!
//! The data are the lines of numbers (separated by spaces, tabs, commas or
//! semicolons; `NaN` a missing point); the lines before them are a header of
//! `key: value` or `key = value` lines (a leading `#` dropped), of which these
//! are understood, as SurfaceTopography's plain-text reader understands them:
//!
//! - Gwyddion's export (`Export Text`, in any of its languages): `Channel`,
//!   `Width` and `Height` (the field's size, a number and a unit) and
//!   `Value units`;
//! - `x-length`, `y-length`, `x-unit`, `y-unit`, `z-unit`, `x-pixels`,
//!   `y-pixels`, `h=… w=…` (the rows and columns, checked against the data);
//! - `pixel size = 3.7e-07 m` (both directions) and `height conversion factor
//!   (-> m) = 6.3e-08` (the heights' factor and unit), as some interferometers'
//!   exports write them;
//! - a line of two length units before a two-column profile (`µm µm`), and a
//!   line with the number of points before it.
//!
//! Every header line is kept as metadata. The shape follows the columns: a
//! matrix (row *j* of the file is grid row *j*, x along a row; what
//! SurfaceTopography reads as `(x, y)` = (columns, rows)) when there are four
//! or more columns or the header gives a size; two columns are `x z`, a line
//! scan read as a profile when uniformly sampled (SurfaceTopography's test,
//! see [`crate::xz`]) and refused otherwise; one column is a profile of unit
//! step. Three columns without such a header are `x y z` rows: a height field
//! where their x and y lie on a regular grid (in any order; steps the
//! smallest gaps, nodes without a row missing points — SurfaceTopography
//! asks for every node), `x y z` points otherwise. Without sizes the step is 1
//! and the lengths unitless.

use asperity_core::{HeightField, LengthUnit, Units};

use crate::error::{FResult, FormatError, malformed};
use crate::sur::length_unit;
use crate::format::{Access, Claim, Codec, Registration};

/// Gwyddion's labels in its translations (SurfaceTopography lists the same).
const CHANNEL: [&str; 8] = [
    "Channel",
    "Kanál",
    "Kanal",
    "Canal",
    "Canale",
    "チャネル",
    "채널",
    "Канал",
];
const WIDTH: [&str; 10] = [
    "Width",
    "Šířka",
    "Breite",
    "Anchura",
    "Largeur",
    "Larghezza",
    "幅",
    "폭",
    "Largura",
    "Ширина",
];
const HEIGHT: [&str; 9] = [
    "Height",
    "Výška",
    "Höhe",
    "Altura",
    "Hauteur",
    "Altezza",
    "高さ",
    "높이",
    "Высота",
];
const VALUE_UNITS: [&str; 9] = [
    "Value units",
    "Jednotky hodnot",
    "Einheiten",
    "Unités",
    "unità valore",
    "値の単位",
    "값 단위",
    "Unidades de valor",
    "Единицы измерения",
];

/// What the header says.
#[derive(Default, Debug)]
struct Header {
    lines: Vec<(String, String)>,
    channel: Option<String>,
    /// The field's extent along x and y: a length and its unit.
    size: [Option<(f64, String)>; 2],
    pixel: Option<(f64, String)>,
    units: [Option<String>; 3],
    z_factor: Option<f64>,
    dims: [Option<usize>; 2],
    /// A lone number before the data (`23`; kept as metadata, not checked:
    /// SurfaceTopography's example has 24 points after it).
    count: Option<usize>,
}

impl Header {
    /// Whether the header gives the data a matrix's geometry.
    fn is_matrix(&self) -> bool {
        self.size.iter().any(Option::is_some)
            || self.pixel.is_some()
            || self.dims.iter().any(Option::is_some)
            || self.channel.is_some()
    }

    fn read(&mut self, line: &str) {
        let line = line.trim().trim_start_matches('#').trim();
        if line.is_empty() {
            return;
        }
        // `h=650 w=650`: the rows and the columns.
        let mut dims = false;
        for token in line.split_whitespace() {
            for (k, key) in ["w=", "h="].iter().enumerate() {
                if let Some(n) = token.strip_prefix(key).and_then(|v| v.parse().ok()) {
                    self.dims[k] = Some(n);
                    self.lines.push((key[..1].to_string(), n.to_string()));
                    dims = true;
                }
            }
        }
        if dims {
            return;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if let [x, z] = words[..]
            && is_length(x)
            && is_length(z)
        {
            self.units[0] = Some(x.to_string());
            self.units[2] = Some(z.to_string());
        }
        let Some(at) = line.find([':', '=', '：']) else {
            self.lines.push((line.to_string(), String::new()));
            return;
        };
        let (key, value) = (
            line[..at].trim(),
            line[at..].chars().skip(1).collect::<String>(),
        );
        let value = value.trim().to_string();
        let lower = key.to_ascii_lowercase();
        let length = || number_and_unit(&value);
        if CHANNEL.contains(&key) {
            self.channel = Some(value.clone());
        } else if WIDTH.contains(&key) || lower == "x-length" {
            self.size[0] = length();
        } else if HEIGHT.contains(&key) || lower == "y-length" {
            self.size[1] = length();
        } else if VALUE_UNITS.contains(&key) || lower == "z-unit" {
            self.units[2] = Some(value.clone());
        } else if lower == "x-unit" {
            self.units[0] = Some(value.clone());
        } else if lower == "y-unit" {
            self.units[1] = Some(value.clone());
        } else if lower == "x-pixels" {
            self.dims[0] = value.parse().ok();
        } else if lower == "y-pixels" {
            self.dims[1] = value.parse().ok();
        } else if lower == "pixel size" {
            self.pixel = length();
        } else if let Some(unit) = lower
            .strip_prefix("height conversion factor (->")
            .and_then(|u| u.strip_suffix(')'))
        {
            self.z_factor = value.parse().ok();
            self.units[2] = Some(unit.trim().to_string());
        }
        self.lines.push((key.to_string(), value));
    }
}

/// `12.34 µm` (or `12.34µm`) as the number and the unit.
fn number_and_unit(text: &str) -> Option<(f64, String)> {
    let end = text
        .find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
        .unwrap_or(text.len());
    let value = text[..end].parse().ok()?;
    Some((value, text[end..].trim().to_string()))
}

fn is_length(unit: &str) -> bool {
    length_unit(unit).0 != LengthUnit::None
}

/// The numbers of a data line, or `None` for a line that is not all numbers.
fn numbers(line: &str) -> Option<Vec<f64>> {
    let fields: Vec<&str> = line
        .split([',', ';', ' ', '\t'])
        .filter(|s| !s.is_empty())
        .collect();
    if fields.is_empty() {
        return None;
    }
    fields.iter().map(|f| f.parse().ok()).collect()
}

/// The file as text: UTF-8, else Latin-1 (older instruments' exports).
fn decode(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec())
        .unwrap_or_else(|_| bytes.iter().map(|&b| char::from(b)).collect())
}

/// The data: rows of `cols` numbers, stored one after the other (one
/// allocation, so a file of short lines stays within the memory estimate).
struct Table {
    cols: usize,
    values: Vec<f64>,
}

impl Table {
    fn rows(&self) -> usize {
        self.values.len() / self.cols
    }

    fn column(&self, c: usize) -> impl Iterator<Item = f64> + '_ {
        self.values.iter().skip(c).step_by(self.cols).copied()
    }
}

/// The header and the rows of numbers (all of the same length).
fn parse(text: &str) -> FResult<(Header, Table)> {
    let mut header = Header::default();
    let mut lines = text.lines().map(str::trim).enumerate().peekable();
    // The header: every line before the first of the data.
    let mut first = None;
    while let Some((k, line)) = lines.next() {
        if line.is_empty() {
            continue;
        }
        match numbers(line) {
            // A lone count before rows of more columns (`23`, then `x, z`).
            Some(v) if v.len() == 1 && header.count.is_none() => {
                let next = lines
                    .clone()
                    .find(|(_, l)| !l.is_empty())
                    .and_then(|(_, l)| numbers(l));
                if next.is_some_and(|n| n.len() > 1) && v[0].fract() == 0.0 && v[0] >= 0.0 {
                    header.count = Some(v[0] as usize);
                    header.lines.push(("count".into(), line.into()));
                    continue;
                }
                first = Some((k, v));
                break;
            }
            Some(v) => {
                first = Some((k, v));
                break;
            }
            None => header.read(line),
        }
    }
    let Some((_, first)) = first else {
        return malformed("no line of numbers: not height data");
    };
    let cols = first.len();
    let mut values = first;
    for (k, line) in lines {
        if line.is_empty() {
            continue;
        }
        let row = numbers(line).ok_or_else(|| {
            FormatError::Malformed(format!(
                "line {}: {line:.40?} is not a row of numbers",
                k + 1
            ))
        })?;
        if row.len() != cols {
            return malformed(format!(
                "line {} has {} values, the first data line {cols} (truncated?)",
                k + 1,
                row.len()
            ));
        }
        values.extend(row);
    }
    Ok((header, Table { cols, values }))
}

/// Whether `head` (the start of a `.txt` file) holds numbers this reader
/// reads (anything else is left to the XYZ reader, whose message names the
/// first line that is no point).
pub(crate) fn sniff(head: &[u8]) -> bool {
    decode(head)
        .lines()
        .map(str::trim)
        .any(|l| numbers(l).is_some())
}

/// Reads the file: height data, or, for three columns that are not on a
/// regular grid, `x y z` points.
pub(crate) fn read(bytes: &[u8]) -> FResult<crate::Surface> {
    let (header, table) = parse(&decode(bytes))?;
    if table.cols == 3 && !header.is_matrix() && grid(&table).is_none() {
        let points: Vec<[f64; 3]> = table
            .values
            .chunks_exact(3)
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        let points = asperity_core::PointSet::new(points);
        points.validate()?;
        return Ok(crate::Surface::Points(points));
    }
    heights(&header, table).map(crate::Surface::Height)
}

/// Where `x y z` rows lie on a regular grid: the first x and y, the steps and
/// the number of nodes along each. Steps are the smallest gaps between the
/// distinct values; every value must sit on a node (to 1e-3 of a step); the
/// grid may have at most twice as many nodes as there are rows (absent
/// nodes are missing points), and no node two rows.
struct Grid {
    origin: [f64; 2],
    step: [f64; 2],
    nodes: [usize; 2],
}

fn axis(values: impl Iterator<Item = f64>) -> Option<(f64, f64, usize)> {
    let mut v: Vec<f64> = values.collect();
    if v.iter().any(|x| !x.is_finite()) {
        return None;
    }
    v.sort_by(f64::total_cmp);
    v.dedup();
    let (first, last) = (*v.first()?, *v.last()?);
    if v.len() == 1 {
        return Some((first, 1.0, 1));
    }
    let step = v
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let on_node = |x: f64| {
        let k = (x - first) / step;
        (k - k.round()).abs() <= 1e-3
    };
    if !v.iter().all(|&x| on_node(x)) {
        return None;
    }
    // Bounded before the conversion: the grid may hold at most twice the
    // rows, which a file can only declare a few billion of.
    let span = ((last - first) / step).round();
    if span >= 1e12 {
        return None;
    }
    Some((first, step, span as usize + 1))
}

fn grid(table: &Table) -> Option<Grid> {
    let (x0, dx, nx) = axis(table.column(0))?;
    let (y0, dy, ny) = axis(table.column(1))?;
    let rows = table.rows();
    (nx.checked_mul(ny)? <= 2 * rows).then_some(Grid {
        origin: [x0, y0],
        step: [dx, dy],
        nodes: [nx, ny],
    })
}

/// The heights of `x y z` rows on their grid; nodes without a row, and
/// `NaN` heights, are missing points.
fn gridded(table: &Table, g: &Grid) -> FResult<HeightField> {
    let [nx, ny] = g.nodes;
    let mut data = vec![f64::NAN; nx * ny];
    let mut filled = vec![false; nx * ny];
    for (k, row) in table.values.chunks_exact(3).enumerate() {
        let i = ((row[0] - g.origin[0]) / g.step[0]).round() as usize;
        let j = ((row[1] - g.origin[1]) / g.step[1]).round() as usize;
        let at = j * nx + i;
        if std::mem::replace(&mut filled[at], true) {
            return malformed(format!(
                "row {}: the grid node ({}, {}) has a height already",
                k + 1,
                row[0],
                row[1]
            ));
        }
        data[at] = row[2];
    }
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing(g.step)?
        .with_origin(g.origin)?)
}

/// A unit's name as asperity's unit and the factor to it (unitless: 1).
fn unit_of(text: Option<&String>) -> (LengthUnit, f64) {
    text.map_or((LengthUnit::None, 1.0), |t| length_unit(t))
}

/// `v` in the named unit `from`, in asperity's unit `to` (numbers kept
/// where either is unitless).
fn convert(v: f64, from: (LengthUnit, f64), to: LengthUnit) -> f64 {
    match (from.0.metres(), to.metres()) {
        (Some(f), Some(t)) => v * from.1 * f / t,
        _ => v * from.1,
    }
}

/// Reads plain-text height data.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (header, table) = parse(&decode(bytes))?;
    heights(&header, table)
}

/// The height field the header and the data make.
fn heights(header: &Header, table: Table) -> FResult<HeightField> {
    let cols = table.cols;
    if header.is_matrix() || cols >= 4 {
        return matrix(header, table);
    }
    let z = unit_of(header.units[2].as_ref());
    match cols {
        1 => {
            let n = table.rows();
            let data = table.column(0).map(|v| convert(v, z, z.0)).collect();
            Ok(HeightField::from_vec([n, 1], data)?.with_units(Units {
                xy: LengthUnit::None,
                z: z.0,
            }))
        }
        2 => {
            // Heights in x's unit, as every profile reader gives them.
            let x = unit_of(header.units[0].as_ref());
            let xs: Vec<f64> = table.column(0).map(|v| convert(v, x, x.0)).collect();
            let zs = table.column(1).map(|v| convert(v, z, x.0)).collect();
            let zu = if z.0 == LengthUnit::None { z.0 } else { x.0 };
            Ok(crate::xz::profile(&xs, zs, x.0)?.with_units(Units { xy: x.0, z: zu }))
        }
        _ => match grid(&table) {
            Some(g) => gridded(&table, &g),
            None => malformed(
                "three columns whose x and y are not on a regular grid: `x y z` points, not heights",
            ),
        },
    }
}

/// A matrix: rows of the file are grid rows.
fn matrix(header: &Header, table: Table) -> FResult<HeightField> {
    let (nx, ny) = (table.cols, table.rows());
    for (k, (want, got)) in header.dims.iter().zip([nx, ny]).enumerate() {
        if let Some(want) = want
            && *want != got
        {
            return malformed(format!(
                "the header gives {want} {}, the data have {got}",
                ["columns", "rows"][k]
            ));
        }
    }
    // Each direction's step and its unit: the size over the points, else
    // the pixel size; a size without a unit takes `x-unit`/`y-unit`.
    let [sx, sy] = [0, 1].map(|k| {
        let n = [nx, ny][k] as f64;
        let (v, u) = match (&header.size[k], &header.pixel) {
            (Some((v, u)), _) => (v / n, u.clone()),
            (None, Some((v, u))) => (*v, u.clone()),
            (None, None) => return (1.0, (LengthUnit::None, 1.0)),
        };
        let u = if u.is_empty() {
            header.units[k].clone()
        } else {
            Some(u)
        };
        (v, unit_of(u.as_ref()))
    });
    let xy = if sx.1.0 == LengthUnit::None {
        sy.1.0
    } else {
        sx.1.0
    };
    let (dx, dy) = (convert(sx.0, sx.1, xy), convert(sy.0, sy.1, xy));
    let z = unit_of(header.units[2].as_ref());
    let factor = header.z_factor.unwrap_or(1.0);
    let data = table
        .values
        .into_iter()
        .map(|v| convert(v * factor, z, z.0))
        .collect();
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx, dy])?
        .with_units(Units { xy, z: z.0 }))
}

/// The header's lines, as key and value.
pub(crate) fn metadata(bytes: &[u8]) -> FResult<Vec<(String, String)>> {
    Ok(parse(&decode(bytes))?.0.lines)
}


/// [`read`], with a height field's heights checked (missing points are
/// carried; ±∞ and a field with no measured point are refused).
fn read_surface(bytes: &[u8]) -> FResult<crate::Surface> {
    let s = read(bytes)?;
    if let crate::Surface::Height(h) = &s {
        h.validate_measured()?;
    }
    Ok(s)
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Plain-text heights (.asc; .txt by content)",
    extensions: &["asc"],
    points: Access::Read,
    height: Access::Read,
    notes: "a matrix of heights (file rows are grid rows), Gwyddion's text export in any language (Width, Height, Value units), x-length/y-length/pixel size/height conversion factor headers; two columns x z a uniformly sampled profile (non-uniform refused), one column a profile; three columns x y z on a regular grid a height field (absent nodes missing), otherwise points; NaN missing",
    claim: Some(Claim { extensions: &["txt"], test: sniff }),
    codec: Some(Codec::new(|b, _| read_height(b)).metadata(metadata)),
    read: Some(read_surface),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    use crate::error::refused as err;

    const GWYDDION: &str = "# Channel: Height\n# Width: 3 µm\n# Height: 2000 nm\n# Value units: nm\n\
                            1 2 3\n4 NaN 6\n";

    #[test]
    fn gwyddions_export_is_a_matrix_with_its_sizes_and_units() {
        let h = read_height(GWYDDION.as_bytes()).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::Um,
                z: LengthUnit::Nm
            }
        );
        let [dx, dy] = h.spacing();
        assert!(
            (dx - 1.0).abs() < 1e-12 && (dy - 1.0).abs() < 1e-12,
            "{dx} {dy}"
        );
        assert_eq!((*h.get(2, 0), *h.get(0, 1)), (3.0, 4.0));
        assert!(h.get(1, 1).is_nan());
        let meta = metadata(GWYDDION.as_bytes()).unwrap();
        assert_eq!(meta[0], ("Channel".into(), "Height".into()));
        // A German export, with its labels.
        let de = GWYDDION
            .replace("Channel", "Kanal")
            .replace("Width", "Breite")
            .replace("# Height", "# Höhe");
        assert_eq!(read_height(de.as_bytes()).unwrap().spacing(), h.spacing());
    }

    #[test]
    fn a_pixel_size_and_a_height_conversion_factor_scale_the_matrix() {
        let t = "h=2 w=4\npixel size=2e-07 m\ndata unit=rad\nheight conversion factor (-> m)=1e-08\n\
                 1 2 3 4\n5 6 7 8\n";
        let h = read_height(t.as_bytes()).unwrap();
        assert_eq!((h.dims(), h.spacing()), ([4, 2], [2e-7, 2e-7]));
        assert_eq!(
            h.units(),
            Units {
                xy: LengthUnit::M,
                z: LengthUnit::M
            }
        );
        assert!((*h.get(3, 1) - 8e-8).abs() < 1e-20);
        let wrong = t.replace("h=2", "h=3");
        assert!(err(read_height(wrong.as_bytes())).contains("3 rows, the data have 2"));
    }

    #[test]
    fn one_and_two_columns_are_profiles() {
        let one = read_height(b"1\n2\n3\n4\n").unwrap();
        assert_eq!((one.dims(), one.spacing()), ([4, 1], [1.0, 1.0]));
        let two = read_height("mm µm\n0 1\n0.5 2\n1.0 NaN\n".as_bytes()).unwrap();
        assert_eq!(two.dims(), [3, 1]);
        assert_eq!(two.units().xy, LengthUnit::Mm);
        assert!((two.spacing()[0] - 0.5).abs() < 1e-12);
        assert!((*two.get(1, 0) - 2e-3).abs() < 1e-15);
        assert!(two.get(2, 0).is_nan());
        assert!(err(read_height(b"0 1\n1 2\n3 3\n")).contains("non-uniformly sampled"));
        // A .txt of numbers is this reader's; words alone are not.
        assert!(sniff(b"0 1\n1 2\n") && sniff(b"# points\n0 1 2\n") && sniff(GWYDDION.as_bytes()));
        assert!(!sniff(b"words only\n"));
    }

    #[test]
    fn x_y_z_rows_on_a_grid_are_heights_with_absent_nodes_missing_and_others_points() {
        // A 3 × 2 grid of step 0.5 × 2 from (1, 10), in any order, node
        // (1.5, 12) absent and (2, 10) NaN.
        let rows = "1.5 10 2\n1 10 1\n2 10 NaN\n1 12 4\n2 12 6\n";
        let h = read_height(rows.as_bytes()).unwrap();
        assert_eq!(
            (h.dims(), h.spacing(), h.origin()),
            ([3, 2], [0.5, 2.0], [1.0, 10.0])
        );
        assert_eq!((*h.get(0, 0), *h.get(1, 0), *h.get(2, 1)), (1.0, 2.0, 6.0));
        assert!(h.get(1, 1).is_nan() && h.get(2, 0).is_nan());
        assert!(matches!(
            read(rows.as_bytes()).unwrap(),
            crate::Surface::Height(_)
        ));
        // Scattered points are points; a node given twice is refused.
        let scattered = b"0 0 1\n0.3 0.7 2\n5 0.1 3\n";
        assert!(matches!(
            read(scattered).unwrap(),
            crate::Surface::Points(_)
        ));
        assert!(err(read_height(scattered)).contains("not on a regular grid"));
        assert!(err(read_height(b"0 0 1\n1 0 2\n0 0 3\n1 1 4\n")).contains("has a height already"));
    }

    #[test]
    fn ragged_truncated_and_empty_files_are_refused() {
        assert!(err(read_height(b"1 2 3 4\n5 6 7\n")).contains("line 2 has 3 values"));
        assert!(err(read_height(b"1 2 3 4\n5 6 x 8\n")).contains("not a row of numbers"));
        assert!(err(read_height(b"# Width: 1 m\n")).contains("no line of numbers"));
        assert!(err(read_height(b"")).contains("no line of numbers"));
        // A file cut inside its last row is refused (a short row), not
        // read as a smaller field.
        let good = GWYDDION.as_bytes();
        let last = good.len() - "4 NaN 6\n".len();
        for cut in last + 1..good.len() - 2 {
            assert!(read_height(&good[..cut]).is_err(), "cut at {cut}");
        }
        assert_eq!(read_height(&good[..last]).unwrap().dims(), [3, 1]);
    }
}
