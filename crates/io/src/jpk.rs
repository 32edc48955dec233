//! JPK Instruments (Bruker) AFM image scans (`.jpk`), read.
//!
//! A TIFF whose first page carries the scan's private tags (0x8000…: the
//! grid's lengths `GridULength`, `GridVLength` in metres at 0x8042/0x8043
//! and `GridReflect` at 0x8045, the start date at 0x8003) and whose further
//! pages are the channels: `ChannelFancyName` (0x8052), `ChannelRetrace`
//! (0x8051), `DefaultSlot` (0x8081, a slot's name) and slots of 0x30 tags
//! from 0x8090 — `SlotName` (+0x00), `EncoderUnit` (+0x12), `ScalingType`
//! (+0x13, `LinearScaling` is read), `ScalingMultiply` (+0x14),
//! `ScalingOffset` (+0x15). A channel is a page whose default slot's unit is
//! a length; its height is raw × multiply + offset in that unit, the lines
//! stored from the image's last unless the page's own `GridReflect` is set
//! (both Gwyddion and SurfaceTopography read it from the channel's page). Channel names
//! as SurfaceTopography gives them (`(retrace)` added to retrace channels).
//! Layout from SurfaceTopography's `JPK.py` and Gwyddion's `jpkscan.c`;
//! checked against the former on a file built to that layout (no instrument
//! file is public).

use asperity_core::{HeightField, LengthUnit, Units};

use crate::channel::{Channel, ChannelInfo, pick};
use crate::error::{FResult, FormatError, malformed, unsupported};
use crate::tiff_dir::{Entry, Tiff, find, raster, text};
use crate::format::{Access, Codec, Registration};

const GRID_U: u16 = 0x8042;
const GRID_V: u16 = 0x8043;
const GRID_REFLECT: u16 = 0x8045;
const RETRACE: u16 = 0x8051;
const FANCY_NAME: u16 = 0x8052;
const DEFAULT_SLOT: u16 = 0x8081;
const SLOTS: u16 = 0x8090;
const SLOT_STRIDE: u16 = 0x30;

/// A channel page: its index among the pages, name, unit, scaling and
/// whether its lines are stored from the first.
struct ChannelPage {
    page: usize,
    reflect: bool,
    name: String,
    unit: LengthUnit,
    multiply: f64,
    offset: f64,
}

/// The page's slot named `name`: (unit, scaling type, multiply, offset).
fn slot(
    tiff: &Tiff<'_>,
    page: &[Entry<'_>],
    name: &str,
) -> Option<(String, String, Option<f64>, f64)> {
    (0..64u16).find_map(|k| {
        let base = SLOTS.checked_add(k.checked_mul(SLOT_STRIDE)?)?;
        let slot_name = find(page, base).map(text)?;
        (slot_name == name).then(|| {
            let t = |o: u16| find(page, base + o).map(text).unwrap_or_default();
            let r = |o: u16| find(page, base + o).and_then(|e| tiff.real(e));
            (t(0x12), t(0x13), r(0x14), r(0x15).unwrap_or(0.0))
        })
    })
}

/// The file's pages, its length channels and the grid.
type Scan<'a> = (Vec<Vec<Entry<'a>>>, Vec<ChannelPage>, [f64; 2]);

fn scan<'a>(tiff: &Tiff<'a>) -> FResult<Scan<'a>> {
    let pages = tiff.pages()?;
    let Some(first) = pages.first() else {
        return malformed("a TIFF without pages");
    };
    let grid = |tag: u16| find(first, tag).and_then(|e| tiff.real(e));
    let (Some(u), Some(v)) = (grid(GRID_U), grid(GRID_V)) else {
        return malformed("no GridULength/GridVLength tags: not a JPK image scan");
    };
    let mut channels = Vec::new();
    for (k, page) in pages.iter().enumerate() {
        let Some(fancy) = find(page, FANCY_NAME).map(text) else {
            continue;
        };
        let Some(default) = find(page, DEFAULT_SLOT).map(text) else {
            continue;
        };
        let Some((unit, scaling, multiply, offset)) = slot(tiff, page, &default) else {
            continue;
        };
        let Some(unit) = LengthUnit::parse(&unit)
            .ok()
            .filter(|u| *u != LengthUnit::None)
        else {
            continue; // not a length: not a channel, as in ST
        };
        if scaling != "LinearScaling" {
            return unsupported(format!(
                "channel {fancy:?}: scaling {scaling:?} (LinearScaling is read)"
            ));
        }
        let multiply = multiply.ok_or_else(|| {
            FormatError::Malformed(format!(
                "channel {fancy:?}: its slot has no ScalingMultiply"
            ))
        })?;
        let retrace = find(page, RETRACE)
            .and_then(|e| tiff.number(e))
            .unwrap_or(0)
            != 0;
        let name = match (retrace, fancy.strip_suffix(')')) {
            (false, _) => fancy,
            (true, Some(stem)) => format!("{stem}, retrace)"),
            (true, None) => format!("{fancy} (retrace)"),
        };
        let reflect = find(page, GRID_REFLECT)
            .and_then(|e| tiff.number(e))
            .is_some_and(|v| v != 0);
        channels.push(ChannelPage {
            page: k,
            reflect,
            name,
            unit,
            multiply,
            offset,
        });
    }
    if channels.is_empty() {
        return malformed("no channel whose default slot is a length");
    }
    Ok((pages, channels, [u, v]))
}

fn infos(channels: &[ChannelPage]) -> Vec<ChannelInfo> {
    channels
        .iter()
        .enumerate()
        .map(|(index, c)| ChannelInfo {
            index,
            name: c.name.clone(),
            height: true,
        })
        .collect()
}

/// The length channels.
pub(crate) fn channels(bytes: &[u8]) -> FResult<Vec<ChannelInfo>> {
    let tiff = Tiff::new(bytes)?;
    Ok(infos(&scan(&tiff)?.1))
}

/// Reads the channel `choice` names (default the first).
pub(crate) fn read_channel(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    let tiff = Tiff::new(bytes)?;
    let (pages, channels, [u, v]) = scan(&tiff)?;
    let c = &channels[pick(&infos(&channels), choice)?];
    let (w, h, raw) = raster(&tiff, &pages[c.page])?;
    let to_unit = c.unit.metres().unwrap_or(1.0);
    let (dx, dy) = (u / to_unit / w as f64, v / to_unit / h as f64);
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return malformed(format!("a grid of {u} × {v} m"));
    }
    let row = |j: usize| if c.reflect { j } else { h - 1 - j };
    let data = (0..h)
        .flat_map(|j| raw[row(j) * w..(row(j) + 1) * w].iter())
        .map(|r| r * c.multiply + c.offset)
        .collect();
    Ok(HeightField::from_vec([w, h], data)?
        .with_spacing([dx, dy])?
        .with_units(Units {
            xy: c.unit,
            z: c.unit,
        }))
}


/// This format's registration: its row of `asperity formats`, how its
/// files are told and how they are decoded (the registry in `lib.rs` lists it).
pub(crate) const FORMAT: Registration = Registration {
    name: "JPK image scan (.jpk)",
    extensions: &["jpk"],
    height: Access::Read,
    notes: "the TIFF pages whose default slot is a length, as channels by their names (retrace marked): raw × ScalingMultiply + ScalingOffset, grid lengths from the first page, lines from the last unless reflected",
    codec: Some(Codec::new(read_channel).channels(channels)),
    ..Registration::NONE
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Built by `fuzz/make_seeds.sh` to SurfaceTopography's layout: a
    /// thumbnail, a 3 × 2 height channel (counts −2…3 × 2.5e-10 m + 1e-7 m),
    /// its retrace and a deflection in V; grid 2 × 1.5 µm, not reflected.
    const SMALL: &[u8] = include_bytes!("../tests/data/small.jpk");

    #[test]
    fn length_channels_are_read_from_their_last_line() {
        let names: Vec<String> = channels(SMALL)
            .unwrap()
            .into_iter()
            .map(|c| c.name)
            .collect();
        assert_eq!(names, ["Height (measured)", "Height (measured, retrace)"]);
        let h = read_channel(SMALL, None).unwrap();
        assert_eq!(h.dims(), [3, 2]);
        assert_eq!(h.units().z, LengthUnit::M);
        assert!((h.spacing()[0] - 2e-6 / 3.0).abs() < 1e-21);
        // Stored rows [-2, -1, 0] and [1, 2, 3]: the last comes first.
        let want = |c: f64| c * 2.5e-10 + 1e-7;
        assert_eq!(h.row(0), &[want(1.0), want(2.0), want(3.0)]);
        let r = read_channel(SMALL, Some(&Channel::parse("1"))).unwrap();
        assert_eq!(r.row(1)[0], want(2.0));
    }

    #[test]
    fn truncated_files_and_other_tiffs_are_refused() {
        for cut in [0, 4, 100, SMALL.len() / 2, SMALL.len() - 1] {
            assert!(read_channel(&SMALL[..cut], None).is_err(), "cut at {cut}");
        }
        let mut plain = SMALL.to_vec();
        // Rename the GridULength tag: no longer a JPK scan.
        let at = plain.windows(2).position(|w| w == [0x42, 0x80]).unwrap();
        plain[at] = 0x41;
        let e = format!("{:?}", read_channel(&plain, None).unwrap_err());
        assert!(e.contains("not a JPK"), "{e}");
    }
}
