//! Gwyddion's native `.gwy` files: a serialized `GwyContainer` whose channels are
//! `GwyDataField` objects.
//!
//! Format (Gwyddion user guide, "GWY File Format"): the magic `GWYP`, then one
//! object. An object is its type name (NUL-terminated), a little-endian `u32`
//! byte size and that many bytes of components; a component is its name
//! (NUL-terminated), a one-byte type and the value: `b` bool and `c` char (one
//! byte), `i` int32, `q` int64, `d` float64, `s` NUL-terminated string, `o`
//! object, and the arrays `C I Q D S O` (a `u32` count, then the items). A
//! container's components are its keys: channel `N` is `/N/data`, its title
//! `/N/data/title`, its metadata `/N/meta`.
//!
//! A `GwyDataField` holds `xres`, `yres`, `xreal`, `yreal`, `xoff`, `yoff`,
//! `si_unit_xy` and `si_unit_z` (`GwySIUnit` objects with a `unitstr`) and
//! `data` (`xres·yres` doubles, row by row). Gwyddion's samples are pixels whose
//! edges start at `xoff` (as in [`crate::gsf`]), so asperity's sample positions
//! are `xoff + (i + ½)·xreal/xres`. Gwyddion keeps base units: a field with
//! units is written in metres (numbers scaled); a unitless field gets empty
//! unit strings.
//!
//! Reading takes the lowest-numbered channel and ignores everything else
//! (masks, graphs, spectra, volume data, metadata); units other than lengths
//! (V, A…) are read as unitless numbers. Written by hand: no Rust crate reads or
//! writes this format.

use std::io::Write;

use asperity_core::{HeightField, LengthUnit, Units};

use crate::bytes::Cursor;
use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

const MAGIC: &[u8] = b"GWYP";
/// Objects nested deeper than this are refused (Gwyddion's own files nest three
/// levels: container, data field, unit).
const MAX_DEPTH: usize = 32;

/// Serialization helpers: each appends one component to `out`.
mod put {
    pub fn name(out: &mut Vec<u8>, name: &str, kind: u8) {
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.push(kind);
    }
    pub fn int(out: &mut Vec<u8>, name: &str, v: i32) {
        self::name(out, name, b'i');
        out.extend_from_slice(&v.to_le_bytes());
    }
    pub fn double(out: &mut Vec<u8>, name: &str, v: f64) {
        self::name(out, name, b'd');
        out.extend_from_slice(&v.to_le_bytes());
    }
    pub fn string(out: &mut Vec<u8>, name: &str, v: &str) {
        self::name(out, name, b's');
        out.extend(v.bytes().filter(|&b| b != 0));
        out.push(0);
    }
    pub fn object(out: &mut Vec<u8>, name: &str, object: &[u8]) {
        self::name(out, name, b'o');
        out.extend_from_slice(object);
    }
    pub fn doubles(out: &mut Vec<u8>, name: &str, v: impl ExactSizeIterator<Item = f64>) {
        self::name(out, name, b'D');
        out.extend_from_slice(&(v.len() as u32).to_le_bytes());
        out.extend(v.flat_map(f64::to_le_bytes));
    }
}

/// An object: its type name, its size and its components.
fn object(type_name: &str, components: &[u8]) -> std::io::Result<Vec<u8>> {
    let size = u32::try_from(components.len()).map_err(|_| {
        std::io::Error::other(format!(
            "a .gwy object holds at most 4 GiB; this {type_name} needs {} bytes",
            components.len()
        ))
    })?;
    let mut out = Vec::with_capacity(components.len() + type_name.len() + 5);
    out.extend_from_slice(type_name.as_bytes());
    out.push(0);
    out.extend_from_slice(&size.to_le_bytes());
    out.extend_from_slice(components);
    Ok(out)
}

fn si_unit(unit: LengthUnit) -> std::io::Result<Vec<u8>> {
    let mut c = Vec::new();
    put::string(
        &mut c,
        "unitstr",
        if unit.metres().is_some() { "m" } else { "" },
    );
    object("GwySIUnit", &c)
}

/// The `/0/meta` string that holds the parameters a field was made with.
pub(crate) const PARAMS_KEY: &str = "asperity params";

/// Writes a `.gwy` file with one channel.
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
    let (nx, ny) = (h.nx(), h.ny());
    let res = |n: usize| {
        i32::try_from(n)
            .map_err(|_| std::io::Error::other(".gwy holds at most 2³¹ − 1 samples a side"))
    };
    // A data field of the file's geometry holding `values`.
    let data_field = |values: &[f64]| -> std::io::Result<Vec<u8>> {
        let mut field = Vec::with_capacity(h.data().len() * 8 + 256);
        put::int(&mut field, "xres", res(nx)?);
        put::int(&mut field, "yres", res(ny)?);
        put::double(&mut field, "xreal", nx as f64 * dx);
        put::double(&mut field, "yreal", ny as f64 * dy);
        put::double(&mut field, "xoff", x0 - 0.5 * dx);
        put::double(&mut field, "yoff", y0 - 0.5 * dy);
        put::object(&mut field, "si_unit_xy", &si_unit(units.xy)?);
        put::object(&mut field, "si_unit_z", &si_unit(units.z)?);
        put::doubles(&mut field, "data", values.iter().copied());
        Ok(field)
    };
    // Missing points as Gwyddion's importers leave them: the mean measured
    // height in the data, 1 in the channel's mask.
    let missing = h.has_missing();
    let fill = if missing {
        let values = h.measured_values();
        values.iter().sum::<f64>() / values.len() as f64
    } else {
        0.0
    };
    let values: Vec<f64> = h
        .data()
        .iter()
        .map(|&z| if z.is_nan() { fill } else { z } * fz)
        .collect();
    let field = data_field(&values)?;
    let mut meta = Vec::new();
    put::string(
        &mut meta,
        "Generator",
        &format!("asperity {}", env!("CARGO_PKG_VERSION")),
    );
    if let Some(p) = params {
        put::string(&mut meta, PARAMS_KEY, p);
    }
    let mut container = Vec::new();
    put::object(&mut container, "/0/data", &object("GwyDataField", &field)?);
    if missing {
        let bits: Vec<f64> = h
            .data()
            .iter()
            .map(|z| f64::from(u8::from(z.is_nan())))
            .collect();
        let mask = data_field(&bits)?;
        put::object(&mut container, "/0/mask", &object("GwyDataField", &mask)?);
    }
    put::string(&mut container, "/0/data/title", title);
    put::object(&mut container, "/0/meta", &object("GwyContainer", &meta)?);
    w.write_all(MAGIC)?;
    w.write_all(&object("GwyContainer", &container)?)
}

/// A component value, as far as reading a data field needs it.
#[derive(Debug)]
enum Value<'a> {
    Int(i64),
    Double(f64),
    Str(&'a str),
    Object(Object<'a>),
    Doubles(&'a [u8]),
    /// Any other type (bools, chars, other arrays): skipped.
    Other,
}

#[derive(Debug)]
struct Object<'a> {
    type_name: &'a str,
    components: Vec<(&'a str, Value<'a>)>,
}

impl<'a> Object<'a> {
    fn get(&self, name: &str) -> Option<&Value<'a>> {
        self.components
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v)
    }
    fn double(&self, name: &str, default: f64) -> FResult<f64> {
        match self.get(name) {
            None => Ok(default),
            Some(Value::Double(v)) if v.is_finite() => Ok(*v),
            Some(v) => malformed(format!("{} {name} is {v:?}, not a number", self.type_name)),
        }
    }
    fn unit(&self, name: &str) -> LengthUnit {
        match self.get(name) {
            Some(Value::Object(u)) => match u.get("unitstr") {
                Some(Value::Str(s)) => LengthUnit::parse(s).unwrap_or_default(),
                _ => LengthUnit::None,
            },
            _ => LengthUnit::None,
        }
    }
}

/// A reader of the file's objects (over the shared bounded cursor).
struct Reader<'a>(Cursor<'a>);

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Reader(Cursor::le(bytes))
    }
    fn cstr(&mut self) -> FResult<&'a str> {
        let s = self.0.c_string().map_err(|_| {
            FormatError::Malformed("a name or string has no terminating NUL".into())
        })?;
        std::str::from_utf8(s)
            .map_err(|_| FormatError::Malformed("a name or string is not UTF-8".into()))
    }
    fn u32(&mut self) -> FResult<usize> {
        Ok(self.0.u32()? as usize)
    }
    fn array(&mut self, item: usize) -> FResult<&'a [u8]> {
        let n = self.u32()?;
        self.0.take(n.saturating_mul(item))
    }

    fn object(&mut self, depth: usize) -> FResult<Object<'a>> {
        if depth > MAX_DEPTH {
            return malformed(format!("objects nested more than {MAX_DEPTH} deep"));
        }
        let type_name = self.cstr()?;
        let size = self.u32()?;
        let mut inner = Reader::new(self.0.take(size)?);
        let mut components = Vec::new();
        while !inner.0.is_done() {
            let name = inner.cstr()?;
            let kind = inner.0.u8()?;
            components.push((name, inner.value(kind, depth)?));
        }
        Ok(Object {
            type_name,
            components,
        })
    }

    fn value(&mut self, kind: u8, depth: usize) -> FResult<Value<'a>> {
        Ok(match kind {
            b'b' | b'c' => {
                self.0.skip(1)?;
                Value::Other
            }
            b'i' => Value::Int(self.0.i32()?.into()),
            b'q' => Value::Int(self.0.i64()?),
            b'd' => Value::Double(self.0.f64()?),
            b's' => Value::Str(self.cstr()?),
            b'o' => Value::Object(self.object(depth + 1)?),
            b'C' => {
                self.array(1)?;
                Value::Other
            }
            b'I' => {
                self.array(4)?;
                Value::Other
            }
            b'Q' => {
                self.array(8)?;
                Value::Other
            }
            b'D' => Value::Doubles(self.array(8)?),
            b'S' => {
                for _ in 0..self.u32()? {
                    self.cstr()?;
                }
                Value::Other
            }
            b'O' => {
                for _ in 0..self.u32()? {
                    self.object(depth + 1)?;
                }
                Value::Other
            }
            other => return malformed(format!("unknown component type {:?}", other as char)),
        })
    }
}

/// The channel number of a container key `/N/data`.
fn channel(key: &str) -> Option<u32> {
    key.strip_prefix('/')?.strip_suffix("/data")?.parse().ok()
}

/// String `key` of the first channel's metadata container (`/N/meta`).
pub(crate) fn meta_string(bytes: &[u8], key: &str) -> FResult<Option<String>> {
    let Some(body) = bytes.strip_prefix(MAGIC) else {
        return malformed("does not start with GWYP (a .gwy file from Gwyddion 2 does)");
    };
    let top = Reader::new(body).object(0)?;
    let meta = top
        .components
        .iter()
        .filter_map(|(k, v)| {
            let n: u32 = k.strip_prefix('/')?.strip_suffix("/meta")?.parse().ok()?;
            match v {
                Value::Object(o) => Some((n, o)),
                _ => None,
            }
        })
        .min_by_key(|(n, _)| *n);
    Ok(match meta.and_then(|(_, o)| o.get(key)) {
        Some(Value::Str(s)) => Some((*s).to_owned()),
        _ => None,
    })
}

/// Reads the first channel of a `.gwy` file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    let Some(body) = bytes.strip_prefix(MAGIC) else {
        return malformed("does not start with GWYP (a .gwy file from Gwyddion 2 does)");
    };
    let top = Reader::new(body).object(0)?;
    if top.type_name != "GwyContainer" {
        return malformed(format!("holds a {}, not a GwyContainer", top.type_name));
    }
    let field = top
        .components
        .iter()
        .filter_map(|(k, v)| match (channel(k), v) {
            (Some(n), Value::Object(o)) if o.type_name == "GwyDataField" => Some((n, o)),
            _ => None,
        })
        .min_by_key(|(n, _)| *n)
        .ok_or_else(|| {
            FormatError::Malformed(
                "holds no image channel (GwyDataField); graphs, spectra and volume data are not height fields"
                    .into(),
            )
        })?;
    let (number, field) = field;
    let res = |name: &str| match field.get(name) {
        Some(Value::Int(n)) if *n > 0 => Ok(*n as usize),
        other => malformed(format!(
            "GwyDataField {name} is {other:?}, not a positive integer"
        )),
    };
    let (nx, ny) = (res("xres")?, res("yres")?);
    let Some(Value::Doubles(raw)) = field.get("data") else {
        return malformed("GwyDataField has no data array");
    };
    // xres and yres may be 64-bit in the file: their product can overflow.
    let needed = nx.checked_mul(ny);
    if needed != Some(raw.len() / 8) {
        let needed = needed.map_or("more than fit in memory".into(), |n| n.to_string());
        return malformed(format!(
            "GwyDataField data holds {} values, xres × yres = {nx} × {ny} needs {needed}",
            raw.len() / 8,
        ));
    }
    let mut data: Vec<f64> = raw
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect();
    // The channel's mask (`/N/mask`, 1 where set) marks points left out:
    // Gwyddion's importers mark unmeasured points so, and asperity writes
    // them so. Masked points are read as missing (NaN).
    let mask_key = format!("/{number}/mask");
    if let Some((_, Value::Object(m))) = top.components.iter().find(|(k, _)| *k == mask_key)
        && let Some(Value::Doubles(bits)) = m.get("data")
        && bits.len() == raw.len()
    {
        for (z, c) in data.iter_mut().zip(bits.chunks_exact(8)) {
            if f64::from_le_bytes(c.try_into().expect("8 bytes")) > 0.5 {
                *z = f64::NAN;
            }
        }
    }
    let (dx, dy) = (
        field.double("xreal", nx as f64)? / nx as f64,
        field.double("yreal", ny as f64)? / ny as f64,
    );
    if !(dx > 0.0 && dy > 0.0) {
        return malformed(format!(
            "xreal and yreal must be positive, got {} and {}",
            dx * nx as f64,
            dy * ny as f64
        ));
    }
    let (xoff, yoff) = (field.double("xoff", 0.0)?, field.double("yoff", 0.0)?);
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing([dx, dy])?
        .with_origin([xoff + 0.5 * dx, yoff + 0.5 * dy])?
        .with_units(Units {
            xy: field.unit("si_unit_xy"),
            z: field.unit("si_unit_z"),
        }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "Gwyddion native (.gwy)",
    extensions: &["gwy"],
    height: Access::ReadWrite,
    notes: "GwyContainer with one GwyDataField (the first channel is read); f64; base units (metres) or unitless; missing points as the channel's mask",
    magic: Magic::Starts(&[b"GWYP"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    fn field(units: Units) -> HeightField {
        HeightField::from_vec([3, 2], vec![1.0, -2.0, 3.5, 4.0, 5.0, 6.25])
            .unwrap()
            .with_spacing([0.5, 0.25])
            .unwrap()
            .with_origin([1.0, -2.0])
            .unwrap()
            .with_units(units)
    }

    fn written(h: &HeightField) -> Vec<u8> {
        let mut out = Vec::new();
        write_height(&mut out, h, "a title", None).unwrap();
        out
    }

    #[test]
    fn round_trips_unitless_exactly_and_with_units_in_metres() {
        let plain = field(Units::default());
        assert_eq!(read_height(&written(&plain)).unwrap(), plain);
        let um = field(Units {
            xy: LengthUnit::Um,
            z: LengthUnit::Nm,
        });
        let back = read_height(&written(&um)).unwrap();
        let metres = Units::same(LengthUnit::M);
        assert_eq!(back.units(), metres);
        let expected = um.in_units(metres);
        for (a, b) in back.data().iter().zip(expected.data()) {
            assert!((a - b).abs() <= 1e-15 * b.abs());
        }
        for k in 0..2 {
            assert!((back.spacing()[k] - expected.spacing()[k]).abs() <= 1e-20);
            assert!((back.origin()[k] - expected.origin()[k]).abs() <= 1e-20);
        }
    }

    #[test]
    fn truncation_anywhere_is_an_error_not_a_panic() {
        let bytes = written(&field(Units::default()));
        for n in 0..bytes.len() {
            assert!(read_height(&bytes[..n]).is_err(), "{n} bytes");
        }
    }

    #[test]
    fn the_lowest_channel_is_read_and_other_objects_are_skipped() {
        let mut graph = Vec::new();
        put::int(&mut graph, "n", 1);
        let graph = object("GwyGraphModel", &graph).unwrap();
        let one = field(Units::default());
        let mut two = Vec::new();
        write_height(
            &mut two,
            &HeightField::from_vec([1, 1], vec![9.0]).unwrap(),
            "",
            None,
        )
        .unwrap();
        // Container: /3/data (1×1 field), /0/graph, /1/data (the 3×2 field).
        // The serialized GwyDataField inside a file written by write_height.
        let inner = |bytes: &[u8]| -> Vec<u8> {
            let at = bytes
                .windows(13)
                .position(|w| w == b"GwyDataField\0")
                .unwrap();
            let size = u32::from_le_bytes(bytes[at + 13..at + 17].try_into().unwrap()) as usize;
            bytes[at..at + 17 + size].to_vec()
        };
        let mut c = Vec::new();
        put::object(&mut c, "/3/data", &inner(&two));
        put::object(&mut c, "/0/graph", &graph);
        put::object(&mut c, "/1/data", &inner(&written(&one)));
        let mut file = MAGIC.to_vec();
        file.extend(object("GwyContainer", &c).unwrap());
        assert_eq!(read_height(&file).unwrap(), one);
    }
}
