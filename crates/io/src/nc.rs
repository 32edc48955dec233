//! NetCDF (`.nc`) topographies in SurfaceTopography's layout, read.
//!
//! The container (NetCDF-3 classic and 64-bit offset) is parsed by the
//! pure-Rust `netcdf-reader` crate (no libnetcdf, so the Python wheel stays
//! portable). The layout on top of it is SurfaceTopography's own (its
//! `NC.py` documents it): a variable `heights` — two-dimensional with
//! dimensions `(x, y)` for a topography, one-dimensional `(x)` for a profile
//! — whose first index is x, so row j of the field is `heights[:, j]`; the
//! variables `x` and `y` carry the physical sizes as their attribute
//! `length`, and `unit` (on `x`, else on `heights`) names the length unit;
//! without a `length` the spacing is one sample, unitless. An optional
//! variable `mask` (non-zero where a point is masked) marks points not
//! measured, read as missing points (NaN), as are NaN heights.

use asperity_core::{HeightField, LengthUnit, Units};
use netcdf_reader::{NcAttrValue, NcFile, NcVariable};

use crate::error::{FResult, FormatError, malformed};
use crate::format::{Access, Codec, Magic, Registration};

fn nc_error(e: netcdf_reader::Error) -> FormatError {
    FormatError::Malformed(format!("not a readable NetCDF-3 file: {e}"))
}

fn attribute(var: Option<&NcVariable>, name: &str) -> Option<NcAttrValue> {
    var?.attribute(name).map(|a| a.value.clone())
}

/// The points along x and y of a `heights` variable of `shape`, checked
/// against the file's `len` bytes.
fn dims(shape: &[u64], len: usize) -> FResult<[usize; 2]> {
    let (nx, ny) = match shape {
        [nx] => (*nx as usize, 1),
        [nx, ny] => (*nx as usize, *ny as usize),
        s => {
            return malformed(format!(
                "`heights` has {} dimensions (1 or 2 are read)",
                s.len()
            ));
        }
    };
    if nx == 0 || ny == 0 {
        return malformed(format!("`heights` is {nx} × {ny}: no data"));
    }
    // Every value takes a byte at least: a larger shape is a corrupt header
    // (checked before the crate allocates for it).
    if nx.checked_mul(ny).is_none_or(|n| n > len) {
        return malformed(format!(
            "`heights` of {nx} × {ny} values cannot fit in the file's {len} bytes"
        ));
    }
    Ok([nx, ny])
}

/// The spacings (from the `length` of `x` and `y`, else 1) and the lateral
/// unit (`x`'s, else `heights`'s).
fn geometry(
    vars: &[NcVariable],
    heights: &NcVariable,
    [nx, ny]: [usize; 2],
) -> FResult<([f64; 2], LengthUnit)> {
    let find = |name: &str| vars.iter().find(|v| v.name() == name);
    let unit = attribute(find("x"), "unit")
        .or_else(|| attribute(Some(heights), "unit"))
        .and_then(|v| v.as_string());
    let length = |name: &str| attribute(find(name), "length").and_then(|v| v.as_f64());
    let (lx, ly) = (length("x"), length("y"));
    let spacing = match (lx, ly) {
        (Some(lx), Some(ly)) if ny > 1 => [lx / nx as f64, ly / ny as f64],
        (Some(lx), _) if ny == 1 => [lx / nx as f64, lx / nx as f64],
        _ => [1.0, 1.0],
    };
    let xy = match unit.as_deref().map(str::trim) {
        None => LengthUnit::None,
        Some(u) => LengthUnit::parse(u)
            .map_err(|_| FormatError::Malformed(format!("the unit {u:?} is not a length")))?,
    };
    Ok((spacing, xy))
}

/// The `mask` variable's values (non-zero: not measured), if there is one,
/// checked to match `heights`' shape and size.
fn mask(
    file: &NcFile,
    var: Option<&NcVariable>,
    shape: &[u64],
    len: usize,
) -> FResult<Option<Vec<f64>>> {
    let Some(var) = var else { return Ok(None) };
    if var.shape() != shape {
        return malformed("`mask` and `heights` differ in shape");
    }
    let mask: Vec<f64> = file
        .read_variable_as_f64("mask")
        .map_err(nc_error)?
        .iter()
        .copied()
        .collect();
    if mask.len() != len {
        return malformed("`mask` and `heights` differ in size");
    }
    Ok(Some(mask))
}

/// Reads the `heights` of a NetCDF file.
pub(crate) fn read_height(bytes: &[u8]) -> FResult<HeightField> {
    if !bytes.starts_with(b"CDF") {
        return malformed("missing the NetCDF-3 magic `CDF` (NetCDF-4/HDF5 files are not read)");
    }
    let file = NcFile::from_bytes(bytes).map_err(nc_error)?;
    let vars = file.variables().map_err(nc_error)?;
    let find = |name: &str| vars.iter().find(|v| v.name() == name);
    let Some(heights) = find("heights") else {
        return malformed("no variable named `heights` (SurfaceTopography's layout)");
    };
    let shape = heights.shape();
    let [nx, ny] = dims(&shape, bytes.len())?;
    let count = nx * ny;
    let values = file.read_variable_as_f64("heights").map_err(nc_error)?;
    let raw: Vec<f64> = values.iter().copied().collect();
    if raw.len() != count {
        return malformed(format!(
            "`heights` holds {} values, its shape {nx} × {ny}",
            raw.len()
        ));
    }
    let mask = mask(&file, find("mask"), &shape, raw.len())?;
    // Stored x slowest: row j is heights[:, j].
    let mut data = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let k = i * ny + j;
            let masked = mask.as_ref().is_some_and(|m| m[k] != 0.0);
            data.push(if masked { f64::NAN } else { raw[k] });
        }
    }
    let (spacing, xy) = geometry(vars, heights, [nx, ny])?;
    Ok(HeightField::from_vec([nx, ny], data)?
        .with_spacing(spacing)?
        .with_units(Units::same(xy)))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "NetCDF (.nc, SurfaceTopography's layout)",
    extensions: &["nc"],
    height: Access::Read,
    notes: "NetCDF-3 (classic, 64-bit offsets): the variable heights(x, y) or heights(x), sizes from the length of x and y, unit attribute; a mask variable and NaN read as missing",
    magic: Magic::Starts(&[b"CDF\x01", b"CDF\x02"]),
    codec: Some(Codec::new(|b, _| read_height(b))),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    use crate::error::refused as err;

    #[test]
    fn other_files_and_truncation_are_refused() {
        assert!(err(read_height(b"\x89HDF\r\n\x1a\n")).contains("NetCDF-3"));
        assert!(err(read_height(b"CDF\x01\0\0")).contains("NetCDF"));
    }
}
