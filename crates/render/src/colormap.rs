//! Colour maps for heights, curvatures and labels.
//!
//! Sequential maps are piecewise-linear through nine samples of matplotlib's
//! `viridis` and `magma` (at t = 0, 1/8, …, 1), accurate to a few RGB units;
//! `coolwarm` is Moreland's diverging map (for signed quantities such as mean
//! curvature, 0 at the centre); `labels` is the ten-colour `tab10` palette.

/// A colour map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColorMap {
    /// Perceptually uniform blue–green–yellow (default for heights).
    #[default]
    Viridis,
    /// Perceptually uniform black–purple–orange–white.
    Magma,
    /// Diverging blue–grey–red (signed quantities).
    Coolwarm,
    /// Black to white.
    Gray,
    /// Ten distinct colours, cycled by integer label.
    Labels,
}

const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];
const MAGMA: [[u8; 3]; 9] = [
    [0, 0, 4],
    [28, 16, 68],
    [79, 18, 123],
    [129, 37, 129],
    [181, 54, 122],
    [229, 80, 100],
    [251, 135, 97],
    [254, 194, 135],
    [252, 253, 191],
];
const COOLWARM: [[u8; 3]; 5] = [
    [59, 76, 192],
    [141, 176, 254],
    [221, 221, 221],
    [244, 152, 122],
    [180, 4, 38],
];
const TAB10: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

fn lerp_table(table: &[[u8; 3]], t: f64) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (table.len() - 1) as f64;
    let k = (x.floor() as usize).min(table.len() - 2);
    let f = x - k as f64;
    let c = |a: usize| {
        (table[k][a] as f64 + f * (table[k + 1][a] as f64 - table[k][a] as f64)).round() as u8
    };
    [c(0), c(1), c(2)]
}

impl ColorMap {
    /// The colour at `t` ∈ [0, 1] (clamped; NaN maps to 0). For [`ColorMap::Labels`],
    /// `t` is taken as an integer label.
    pub fn map(self, t: f64) -> [u8; 3] {
        match self {
            ColorMap::Viridis => lerp_table(&VIRIDIS, t),
            ColorMap::Magma => lerp_table(&MAGMA, t),
            ColorMap::Coolwarm => lerp_table(&COOLWARM, t),
            ColorMap::Gray => {
                let v = (if t.is_finite() {
                    t.clamp(0.0, 1.0)
                } else {
                    0.0
                } * 255.0)
                    .round() as u8;
                [v, v, v]
            }
            ColorMap::Labels => {
                TAB10[(if t.is_finite() {
                    t.round().abs() as usize
                } else {
                    0
                }) % TAB10.len()]
            }
        }
    }

    /// Parses `viridis`, `magma`, `coolwarm`, `gray`/`grey`, `labels`.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name.to_ascii_lowercase().as_str() {
            "viridis" => ColorMap::Viridis,
            "magma" => ColorMap::Magma,
            "coolwarm" => ColorMap::Coolwarm,
            "gray" | "grey" => ColorMap::Gray,
            "labels" | "tab10" => ColorMap::Labels,
            _ => return None,
        })
    }
}

/// A colour for integer label `label`, distinct from its neighbours' for any
/// number of labels: hues stepped by the golden ratio, saturation 0.55, value
/// 0.92 (for region maps with more labels than a palette has colours).
pub fn distinct(label: u32) -> [u8; 4] {
    let h = (label as f64 * 0.618_033_988_749_895).fract() * 6.0;
    let (s, v) = (0.55, 0.92);
    let c = v * s;
    let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let to = |u: f64| ((u + m) * 255.0).round() as u8;
    [to(r), to(g), to(b), 255]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_midpoints_match_matplotlib() {
        assert_eq!(ColorMap::Viridis.map(0.0), [68, 1, 84]);
        assert_eq!(ColorMap::Viridis.map(1.0), [253, 231, 37]);
        assert_eq!(ColorMap::Viridis.map(0.5), [33, 144, 141]); // matplotlib: (33, 145, 140)
        assert_eq!(ColorMap::Viridis.map(-3.0), ColorMap::Viridis.map(0.0));
        assert_eq!(ColorMap::Viridis.map(f64::NAN), ColorMap::Viridis.map(0.0));
        assert_eq!(ColorMap::Coolwarm.map(0.5), [221, 221, 221]);
        assert_eq!(ColorMap::Gray.map(1.0), [255, 255, 255]);
        assert_eq!(ColorMap::Labels.map(11.0), ColorMap::Labels.map(1.0));
    }
}
