//! The feature parameters of a height field's report (ISO 25178-2:2021
//! clause 5; see `asperity_analysis::feature`): the segmentation into hills
//! and dales by watershed and Wolf pruning, the parameters read off the
//! significant motifs, and the segmentation maps `--plot` writes.

use asperity_analysis::feature::{self, FeatureOptions, Features, NO_MOTIF, Segmentation};
use asperity_core::{HeightField, RgbaImage};
use asperity_render::colormap::distinct;
use serde_json::{Value, json};

use super::params::AnalyzeOptions;
use crate::error::{Result, invalid};

/// A picture `--plot` writes, with its file name.
#[derive(Clone, Debug)]
pub struct NamedImage {
    /// File name, e.g. `hills.png`.
    pub name: &'static str,
    /// The picture.
    pub image: RgbaImage,
}

/// The segmentation of the scale-limited surface `lv` into significant motifs
/// (`None` for a profile, which has no areal features).
pub(super) fn segment(
    lv: &HeightField,
    periodic: bool,
    o: &AnalyzeOptions,
) -> Result<Option<Features>> {
    if lv.ny() == 1 {
        return Ok(None);
    }
    let options = FeatureOptions {
        pruning_percent: o.pruning,
        incomplete: o.incomplete_motifs,
        periodic,
    };
    Ok(Some(feature::features(lv, &options)?))
}

/// The report's feature parameters and the `features` entry that says how
/// they were found.
pub(super) fn facts(f: &Features, o: &AnalyzeOptions) -> Result<Value> {
    let p = &f.parameters;
    let mut v = serde_json::to_value(p).map_err(|e| invalid(format!("feature parameters: {e}")))?;
    if let Some(map) = v.as_object_mut() {
        for key in ["peaks", "pits", "pruning_height"] {
            map.remove(key);
        }
    }
    v["features"] = json!({
        "segmentation": "watershed (steepest descent over 8 neighbours), Wolf pruning (ISO 25178-2:2021 clause 5)",
        "pruning_percent_of_Sz": o.pruning,
        "pruning_height": p.pruning_height,
        "incomplete_motifs": if o.incomplete_motifs { "counted" } else { "left out (touching the edge or a missing point)" },
        "hills": {"significant": f.hills.motifs.len(), "counted": p.peaks, "before_pruning": f.hills.unpruned},
        "dales": {"significant": f.dales.motifs.len(), "counted": p.pits, "before_pruning": f.dales.unpruned},
    });
    Ok(v)
}

/// The hill and dale maps: each motif in its own colour over the heights'
/// shading, incomplete motifs grey, borders black, each peak or pit a white
/// dot. Row 0 of the field is the picture's top row; small fields are
/// enlarged so a point stays visible, large ones sampled down to 2048 pixels.
pub(super) fn maps(lv: &HeightField, f: &Features) -> Vec<NamedImage> {
    vec![
        NamedImage {
            name: "hills.png",
            image: map(lv, &f.hills),
        },
        NamedImage {
            name: "dales.png",
            image: map(lv, &f.dales),
        },
    ]
}

fn map(lv: &HeightField, s: &Segmentation) -> RgbaImage {
    let (nx, ny) = (lv.nx(), lv.ny());
    let longest = nx.max(ny) as f64;
    let scale = if longest < 512.0 {
        (512.0 / longest).ceil()
    } else {
        (2048.0 / longest).min(1.0)
    };
    let (w, h) = (
        ((nx as f64 * scale).round() as u32).max(1),
        ((ny as f64 * scale).round() as u32).max(1),
    );
    let (lo, hi) = lv.min_max();
    let shade = |z: f64| {
        if hi > lo {
            0.45 + 0.55 * (z - lo) / (hi - lo)
        } else {
            1.0
        }
    };
    let at = |x: u32, y: u32| -> usize {
        let i = ((x as f64 / scale) as usize).min(nx - 1);
        let j = ((y as f64 / scale) as usize).min(ny - 1);
        j * nx + i
    };
    let mut img = RgbaImage::filled(w, h, [0, 0, 0, 255]);
    for y in 0..h {
        for x in 0..w {
            let p = at(x, y);
            let label = s.labels[p];
            let border = [(x + 1, y), (x, y + 1)]
                .iter()
                .any(|&(a, b)| a < w && b < h && s.labels[at(a, b)] != label);
            let colour = if label == NO_MOTIF || border {
                [0, 0, 0, 255]
            } else {
                let z = lv.data()[p];
                let base = if s.motifs[label as usize].incomplete {
                    [200, 200, 200, 255]
                } else {
                    distinct(label)
                };
                base.map(|c| (c as f64 * shade(z)).round() as u8)
            };
            img.put(x, y, [colour[0], colour[1], colour[2], 255]);
        }
    }
    let dot = (scale.ceil() as i64 + 1).max(2);
    for m in &s.motifs {
        let (cx, cy) = (
            ((m.critical % nx) as f64 + 0.5) * scale,
            ((m.critical / nx) as f64 + 0.5) * scale,
        );
        for dy in -dot..=dot {
            for dx in -dot..=dot {
                let (x, y) = (cx as i64 + dx, cy as i64 + dy);
                if (0..w as i64).contains(&x) && (0..h as i64).contains(&y) {
                    let edge = dx.abs() == dot || dy.abs() == dot;
                    img.put(
                        x as u32,
                        y as u32,
                        if edge { [0, 0, 0, 255] } else { [255; 4] },
                    );
                }
            }
        }
    }
    img
}
