//! Gwyddion Simple Field (`.gsf`), so Gwyddion opens our height fields natively.
//!
//! Spec: gwyddion.net/documentation/user-guide-en/gsf.html. The file is the line
//! `Gwyddion Simple Field 1.0`, `Key = Value` lines, 1–4 NUL bytes that pad the
//! header to a multiple of 4, then `XRes·YRes` little-endian `float32`, row by row.
//!
//! Gwyddion treats samples as pixels of size `XReal/XRes` whose *edges* start at
//! `XOffset`; asperity samples sit at `origin + i·dx`. So we write
//! `XReal = nx·dx` and `XOffset = x0 − dx/2` (likewise y), and invert that on
//! reading. Heights are `f32` (relative error near 6e-8).
//!
//! Units: a unitless field (synthetic data) is written without `XYUnits` and
//! `ZUnits`, which Gwyddion reads as unitless (writing `m` made it show a 256 m
//! field, #24). A field with units is written in base units, as the GSF
//! specification asks: `XYUnits = m`, `ZUnits = m`, lengths and heights in
//! metres; reading gives a field in the file's units (metres for our files).

use std::io::Write;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::header_keys::HeaderKeys;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: &[u8] = b"Gwyddion Simple Field 1.0\n";

/// The header field that holds the parameters a field was made with.
pub(crate) const PARAMS_FIELD: &str = "AsperityParams";

/// Writes a GSF file.
pub(crate) fn write_height(
    w: &mut dyn Write,
    h: &HeightField,
    title: &str,
    params: Option<&str>,
) -> std::io::Result<()> {
    let units = h.units();
    let (fx, fz) = units.metre_factors();
    let [dx, dy] = h.spacing().map(|v| v * fx);
    let [x0, y0] = h.origin().map(|v| v * fx);
    let mut head = String::from_utf8_lossy(MAGIC).into_owned();
    head += &format!("XRes = {}\nYRes = {}\n", h.nx(), h.ny());
    head += &format!(
        "XReal = {:e}\nYReal = {:e}\n",
        h.nx() as f64 * dx,
        h.ny() as f64 * dy
    );
    head += &format!(
        "XOffset = {:e}\nYOffset = {:e}\n",
        x0 - 0.5 * dx,
        y0 - 0.5 * dy
    );
    if units.xy.metres().is_some() {
        head += "XYUnits = m\n";
    }
    if units.z.metres().is_some() {
        head += "ZUnits = m\n";
    }
    let title: String = title.chars().filter(|c| !c.is_control()).collect();
    head += &format!(
        "Title = {title}\nGenerator = asperity {}\n",
        env!("CARGO_PKG_VERSION")
    );
    if let Some(p) = params {
        head += &format!("{PARAMS_FIELD} = {p}\n");
    }
    let pad = 4 - head.len() % 4; // 1..=4 NULs, as Gwyddion's reader expects
    w.write_all(head.as_bytes())?;
    w.write_all(&[0u8; 4][..pad])?;
    let data: Vec<u8> = h
        .data()
        .iter()
        .flat_map(|&z| ((z * fz) as f32).to_le_bytes())
        .collect();
    w.write_all(&data)
}

/// The header's `Key = value` fields and where the data starts.
fn header(bytes: &[u8]) -> FResult<(std::collections::HashMap<String, String>, usize)> {
    if !bytes.starts_with(MAGIC) {
        return malformed("missing the `Gwyddion Simple Field 1.0` line");
    }
    let nul = bytes.iter().position(|&b| b == 0).ok_or_else(|| {
        FormatError::Malformed("header is not NUL-terminated (truncated?)".into())
    })?;
    let data_start = nul + (4 - nul % 4);
    let text = std::str::from_utf8(&bytes[MAGIC.len()..nul])
        .map_err(|_| FormatError::Malformed("header is not UTF-8".into()))?;
    let mut keys = std::collections::HashMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let (k, v) = line
            .split_once('=')
            .ok_or_else(|| FormatError::Malformed(format!("header line {line:?} has no '='")))?;
        keys.insert(k.trim().to_owned(), v.trim().to_owned());
    }
    Ok((keys, data_start))
}

/// The header field `key`, if the file has it.
pub(crate) fn header_field(bytes: &[u8], key: &str) -> FResult<Option<String>> {
    Ok(header(bytes)?.0.remove(key))
}

/// Reads a GSF file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let (map, data_start) = header(bytes)?;
    let keys = HeaderKeys::new(&map);
    let (nx, ny) = (keys.count("XRes")?, keys.count("YRes")?);
    let need = nx
        .checked_mul(ny)
        .and_then(|n| n.checked_mul(4))
        .ok_or_else(|| FormatError::Malformed("XRes·YRes too large".into()))?;
    let body = bytes.get(data_start..).unwrap_or(&[]);
    if body.len() != need {
        return malformed(format!(
            "{nx}×{ny} floats need {need} data bytes but the file has {} (truncated?)",
            body.len()
        ));
    }
    let data = body
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
        .collect();
    let (spacing, origin) = geometry(&keys, nx, ny)?;
    // Units other than lengths (V, A…) cannot be represented: the numbers are
    // kept, unitless.
    let unit = |k: &str| {
        keys.get(k)
            .and_then(|v| LengthUnit::parse(v).ok())
            .unwrap_or_default()
    };
    let units = Units {
        xy: unit("XYUnits"),
        z: unit("ZUnits"),
    };
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing(spacing)?
        .with_origin(origin)?
        .with_units(units))
}

/// The spacings (from XReal and YReal, a pixel's size by default) and the
/// first sample's centre (the offsets plus half a pixel).
fn geometry(keys: &HeaderKeys<'_>, nx: usize, ny: usize) -> FResult<([f64; 2], [f64; 2])> {
    let (dx, dy) = (
        keys.real_or("XReal", nx as f64)? / nx as f64,
        keys.real_or("YReal", ny as f64)? / ny as f64,
    );
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return Err(FormatError::Malformed(format!(
            "XReal and YReal must be positive lengths, got {} and {}",
            dx * nx as f64,
            dy * ny as f64
        )));
    }
    let (xo, yo) = (keys.real_or("XOffset", 0.0)?, keys.real_or("YOffset", 0.0)?);
    Ok(([dx.abs(), dy.abs()], [xo + 0.5 * dx, yo + 0.5 * dy]))
}

/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Gwyddion Simple Field",
    extensions: &["gsf"],
    height: Access::ReadWrite,
    notes: "float32; XReal/XOffset follow Gwyddion's pixel convention; unitless; missing points NaN (Gwyddion masks them)",
    magic: Magic::Starts(&[b"Gwyddion Simple Field"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};
