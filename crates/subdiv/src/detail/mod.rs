//! Procedural detail functions d = F(p, l) (velho-perlin §3–4), evaluated level
//! by level on the predicted surface of each level, returning offsets in the
//! local frames of [`crate::multires`] (t₁, t₂, n).
//!
//! | Procedure | Paper | Coordinates | Amplitude law (default) |
//! | --- | --- | --- | --- |
//! | [`Rock`] | §4.2 "Rock" | intrinsic (vertex id) or extrinsic (x, y, z) | fractal: A·decayˡ⁻¹ |
//! | [`Fbm`] | §4.2 (the Perlin-noise rock) | extrinsic | fractal |
//! | [`Berry`] | §4.2 "Berry": domes R·√(1 − r²/R²) | surface seeds, Euclidean r | fractal: R·ratioˡ⁻¹ |
//! | [`Tentacle`] | §4.2 pseudo-code; the mine of Fig. 6 | intrinsic (seed vertex) | morphogenic: length·l |
//! | [`Mushroom`] | §4.2 "Mushroom cloud" | extrinsic around surface seeds | morphogenic |
//! | [`Spur`] | §5.1, Fig. 9 | intrinsic (seed vertex) | relative to the level's edge length |
//!
//! Every law is selectable: inversely proportional to scale (fractal,
//! A·decayˡ⁻¹), proportional to scale (morphogenic, A·l), or independent (A).
//!
//! **Seeds** of local features are vertices ("features are placed only at the
//! control points", §5.1): base-level vertex ids, points snapped to the nearest
//! vertex of the level where the feature starts, or a Poisson-disk set over
//! that level. A seed vertex v of level l lives on as its vertex point at level
//! l + 1 (the last V entries of the finer level), so "the intrinsic
//! coordinates of the seed point correspond at all levels".
//!
//! **Randomness** is counter-based — a hash of (seed, level, vertex) — so
//! adding levels never changes coarser ones (stable under re-subdivision) and
//! results do not depend on the thread count.
//!
//! # Readings where the paper gives no formula
//!
//! The berry's child seeds are
//! a Poisson-disk set of up to `children` vertices inside the parent dome with
//! radius R·ratio; the mushroom lifts a stem along the seed's normal with a
//! smooth radial profile and spreads a cap outward near the top, both ∝ l;
//! the mine is the tentacle without twist or sign alternation (straight horns);
//! the tentacle grows as a tapering limb by default (two readings of its
//! pseudo-code, see [`Tentacle`]).

use noise::{NoiseFn, Perlin, Value};
use rayon::prelude::*;

use crate::multires::LevelInput;

mod grow;

pub use grow::Grower;

/// How the amplitude changes with the level l ≥ 1 (§4.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// Inversely proportional to scale: A·decayˡ⁻¹ (decay ½ is 1/f).
    Fractal {
        /// Factor per level.
        decay: f64,
    },
    /// Proportional to the level: A·l.
    Morphogenic,
    /// The same at every level.
    Independent,
}

impl Law {
    /// The factor at level `l`.
    pub fn factor(&self, l: usize) -> f64 {
        match self {
            Law::Fractal { decay } => decay.powi(l as i32 - 1),
            Law::Morphogenic => l as f64,
            Law::Independent => 1.0,
        }
    }
}

/// The cubic drop-off w(x) = 1 − 3x² + 2x³ on [0, 1], 0 beyond.
pub fn drop_off(x: f64) -> f64 {
    if x >= 1.0 {
        0.0
    } else {
        let x = x.max(0.0);
        1.0 - 3.0 * x * x + 2.0 * x * x * x
    }
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Uniform in [−1, 1) keyed by (seed, level, vertex).
pub fn random_value(seed: u64, level: usize, vertex: usize) -> f64 {
    let h = mix(mix(seed ^ 0x726f_636b) ^ (level as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15))
        ^ (vertex as u64).wrapping_mul(0xd1b5_4a32_d192_ed03);
    let u = (mix(h) >> 11) as f64 / (1u64 << 53) as f64;
    2.0 * u - 1.0
}

fn noise_seed(seed: u64, level: usize) -> u32 {
    (mix(seed ^ (level as u64).wrapping_mul(0x9e37_79b9)) >> 32) as u32
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// Where rock values come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coords {
    /// A random value per (level, vertex id) — the paper's intrinsic rock.
    Intrinsic,
    /// Value noise of (x, y, z) at `frequency`·2ˡ⁻¹ — the extrinsic rock.
    Extrinsic {
        /// Lattice frequency at level 1 (per mesh unit).
        frequency: f64,
    },
}

/// The rock (§4.2): a random value at every control point of every level,
/// along the normal, with a 1/f amplitude by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rock {
    /// Displacement amplitude at level 1 (mesh units).
    pub amplitude: f64,
    /// The amplitude law.
    pub law: Law,
    /// Intrinsic or extrinsic values.
    pub coords: Coords,
}

impl Default for Rock {
    fn default() -> Self {
        Self {
            amplitude: 0.08,
            law: Law::Fractal { decay: 0.5 },
            coords: Coords::Intrinsic,
        }
    }
}

impl Rock {
    /// Rock with amplitude `a` and decay `d` per level, intrinsic.
    pub fn fractal(amplitude: f64, decay: f64) -> Self {
        Self {
            amplitude,
            law: Law::Fractal { decay },
            coords: Coords::Intrinsic,
        }
    }

    /// The scalar value (along n) at every vertex of a level.
    pub fn values(&self, seed: u64, level: usize, positions: &[[f64; 3]]) -> Vec<f64> {
        let a = self.amplitude * self.law.factor(level);
        match self.coords {
            Coords::Intrinsic => (0..positions.len())
                .into_par_iter()
                .map(|v| a * random_value(seed, level, v))
                .collect(),
            Coords::Extrinsic { frequency } => {
                let noise = Value::new(noise_seed(seed, level));
                let f = frequency * 2f64.powi(level as i32 - 1);
                positions
                    .par_iter()
                    .map(|p| a * noise.get([p[0] * f, p[1] * f, p[2] * f]))
                    .collect()
            }
        }
    }
}

/// Noise fBm split over the levels (§3: "a procedural displacement as a sum of
/// scale-limited components"): level l adds one Perlin octave at frequency
/// f·2ˡ⁻¹ (the `noise` crate's Perlin), along the normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fbm {
    /// Amplitude at level 1.
    pub amplitude: f64,
    /// Frequency at level 1 (per mesh unit).
    pub frequency: f64,
    /// The amplitude law (fractal ½ = fBm with H = 1).
    pub law: Law,
}

impl Fbm {
    /// The scalar value (along n) at every vertex of a level.
    pub fn values(&self, seed: u64, level: usize, positions: &[[f64; 3]]) -> Vec<f64> {
        let a = self.amplitude * self.law.factor(level);
        let noise = Perlin::new(noise_seed(seed ^ 0x0066_626d, level));
        let f = self.frequency * 2f64.powi(level as i32 - 1);
        positions
            .par_iter()
            .map(|p| a * noise.get([p[0] * f, p[1] * f, p[2] * f]))
            .collect()
    }
}

/// Berry (§4.2): domes of height `height`·R·√(1 − r²/R²) around Poisson-disk
/// seeds, grown again from clusters of child seeds at every level along the
/// evolving normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Berry {
    /// Dome radius R at the first level.
    pub radius: f64,
    /// Radius factor per level (½ = fractal).
    pub ratio: f64,
    /// At most this many child seeds per dome.
    pub children: usize,
    /// Dome height as a fraction of R (1 = hemisphere).
    pub height: f64,
}

/// Tentacle (§4.2 pseudo-code): at level l the seed moves by
/// length·l·(sin(θ + πl/3), cos(θ + πl/3), 1), negated on even levels; the
/// mine (Fig. 6) drops the twist and the sign.
///
/// Two readings of the pseudo-code (the paper gives no more):
/// - [`TentacleReading::Literal`]: the offset moves the seed vertex alone, in
///   its own local frame at each level. Subdivision then smooths a one-vertex
///   push into a short spike, and the sign flip digs every other level back
///   in: nothing like Fig. 5's limb.
/// - [`TentacleReading::Limb`] (the default): the offset is a growth step of
///   the tip. At level l a ball of radius r·taperˡ⁻¹ around the tip's current
///   position moves by length·l along the direction (sin(θ + πl/3),
///   cos(θ + πl/3), 1) of the seed's *starting* frame, with a smooth fall-off
///   (1 − ρ²/r²)². Each level extrudes a narrower cap further out along a
///   direction turned by π/3: a tapered limb that twists as it grows over the
///   levels, as Fig. 5 shows. The sign flip would undo each step, so this
///   reading ignores it (the steps are all outward).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tentacle {
    /// Reference length.
    pub length: f64,
    /// Rotation angle θ (radians).
    pub theta: f64,
    /// Negate on even levels (the paper's pseudo-code; the literal reading only).
    pub alternate: bool,
    /// Turn by π/3 per level and lean sideways (false: straight along n).
    pub twist: bool,
    /// How the offset is applied.
    pub reading: TentacleReading,
}

/// How a [`Tentacle`]'s per-level offset is applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TentacleReading {
    /// To the seed vertex alone, in its local frame.
    Literal,
    /// As a growth step of a tapering limb (see [`Tentacle`]).
    Limb {
        /// Radius r of the ball moved at level 1 (world units).
        radius: f64,
        /// Factor on the radius per level (< 1 tapers).
        taper: f64,
    },
}

impl Tentacle {
    /// The offset at level `l` in the local frame.
    pub fn offset(&self, l: usize) -> [f64; 3] {
        let m = self.length * l as f64;
        let p = std::f64::consts::FRAC_PI_3 * l as f64;
        let mut d = if self.twist {
            [(self.theta + p).sin(), (self.theta + p).cos(), 1.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        if self.alternate && l.is_multiple_of(2) {
            d = d.map(|x| -x);
        }
        d.map(|x| x * m)
    }
}

/// Mushroom cloud (§4.2): around each seed, a stem lifted along the seed's
/// normal with a smooth profile, and a cap pushed outward near the top — both
/// growing in proportion to the level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mushroom {
    /// Stem lift at level 1 (grows ∝ l).
    pub height: f64,
    /// Stem radius.
    pub radius: f64,
}

/// Spur (§5.1, Fig. 9): the seed vertex pushed along n by `height` times the
/// mean length of its edges at that level — a spike whose size follows the
/// level it is placed at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spur {
    /// Height in edge lengths.
    pub height: f64,
}

/// A detail procedure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Procedure {
    /// See [`Rock`].
    Rock(Rock),
    /// See [`Fbm`].
    Fbm(Fbm),
    /// See [`Berry`].
    Berry(Berry),
    /// See [`Tentacle`].
    Tentacle(Tentacle),
    /// See [`Mushroom`].
    Mushroom(Mushroom),
    /// See [`Spur`].
    Spur(Spur),
}

impl Procedure {
    /// Whether the procedure grows from seeds (the others cover the surface).
    pub fn is_local(&self) -> bool {
        !matches!(self, Procedure::Rock(_) | Procedure::Fbm(_))
    }

    /// The name used in scenes and on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Procedure::Rock(_) => "rock",
            Procedure::Fbm(_) => "fbm",
            Procedure::Berry(_) => "berry",
            Procedure::Tentacle(t) if !t.twist && !t.alternate => "mine",
            Procedure::Tentacle(_) => "tentacle",
            Procedure::Mushroom(_) => "mushroom",
            Procedure::Spur(_) => "spur",
        }
    }
}

/// Where local features grow.
#[derive(Clone, Debug, PartialEq)]
pub enum Seeds {
    /// Base-level vertex ids.
    Vertices(Vec<u32>),
    /// Points snapped to the nearest vertex of the level where the feature starts.
    Points(Vec<[f64; 3]>),
    /// A Poisson-disk set with this spacing over the level where the feature starts.
    Poisson {
        /// Minimum distance between seeds.
        spacing: f64,
    },
}

/// A procedure placed on a surface (§5.1): its seeds and the levels it acts at
/// (`None` = every level).
#[derive(Clone, Debug, PartialEq)]
pub struct Feature {
    /// What grows.
    pub procedure: Procedure,
    /// Where (ignored by rock and fbm).
    pub seeds: Seeds,
    /// At which levels (1-based); `None` = all.
    pub levels: Option<Vec<usize>>,
}

impl Feature {
    /// A feature over the whole surface at every level.
    pub fn global(procedure: Procedure) -> Self {
        Self {
            procedure,
            seeds: Seeds::Poisson { spacing: 0.5 },
            levels: None,
        }
    }

    /// Whether it acts at level `l`.
    pub fn acts_at(&self, l: usize) -> bool {
        self.levels.as_ref().is_none_or(|ls| ls.contains(&l))
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// A message naming the bad parameter.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(format!("{name} must be finite, got {x}"))
            }
        };
        let positive = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be > 0, got {x}"))
            }
        };
        let law = |l: &Law| match l {
            Law::Fractal { decay } if !(decay.is_finite() && *decay >= 0.0) => {
                Err(format!("decay must be finite and ≥ 0, got {decay}"))
            }
            _ => Ok(()),
        };
        match &self.procedure {
            Procedure::Rock(r) => {
                finite("amplitude", r.amplitude)?;
                law(&r.law)?;
                if let Coords::Extrinsic { frequency } = r.coords {
                    positive("frequency", frequency)?;
                }
            }
            Procedure::Fbm(f) => {
                finite("amplitude", f.amplitude)?;
                positive("frequency", f.frequency)?;
                law(&f.law)?;
            }
            Procedure::Berry(b) => {
                positive("radius", b.radius)?;
                positive("ratio", b.ratio)?;
                finite("height", b.height)?;
                if b.ratio >= 1.0 {
                    return Err(format!("ratio must be < 1, got {}", b.ratio));
                }
            }
            Procedure::Tentacle(t) => {
                finite("length", t.length)?;
                finite("theta", t.theta)?;
                if let TentacleReading::Limb { radius, taper } = t.reading {
                    positive("radius", radius)?;
                    positive("taper", taper)?;
                }
            }
            Procedure::Mushroom(m) => {
                finite("height", m.height)?;
                positive("radius", m.radius)?;
            }
            Procedure::Spur(s) => finite("height", s.height)?,
        }
        match &self.seeds {
            Seeds::Poisson { spacing } => positive("spacing", *spacing)?,
            Seeds::Points(p) if p.iter().flatten().any(|x| !x.is_finite()) => {
                return Err("seed points must be finite".into());
            }
            _ => {}
        }
        if let Some(ls) = &self.levels
            && ls.contains(&0)
        {
            return Err("levels count from 1 (level 0 is the base)".into());
        }
        Ok(())
    }
}

/// A uniform grid over points for radius queries.
struct Grid {
    cell: f64,
    map: std::collections::HashMap<[i64; 3], Vec<u32>>,
}

impl Grid {
    fn new(points: impl Iterator<Item = (u32, [f64; 3])>, cell: f64) -> Self {
        let mut map: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
        for (i, p) in points {
            map.entry(Self::key(p, cell)).or_default().push(i);
        }
        Self { cell, map }
    }
    fn key(p: [f64; 3], cell: f64) -> [i64; 3] {
        p.map(|x| (x / cell).floor() as i64)
    }
    /// Ids in the cells within `r` of `p` (a superset of the ball).
    fn near(&self, p: [f64; 3], r: f64) -> impl Iterator<Item = u32> + '_ {
        let lo = Self::key(p.map(|x| x - r), self.cell);
        let hi = Self::key(p.map(|x| x + r), self.cell);
        (lo[0]..=hi[0]).flat_map(move |i| {
            (lo[1]..=hi[1]).flat_map(move |j| {
                (lo[2]..=hi[2])
                    .flat_map(move |k| self.map.get(&[i, j, k]).into_iter().flatten().copied())
            })
        })
    }
}

/// A Poisson-disk subset of `candidates` (dart throwing in a seeded random
/// order): no two chosen points closer than `spacing`, at most `max`.
pub fn poisson_disk(
    positions: &[[f64; 3]],
    candidates: &[u32],
    spacing: f64,
    max: usize,
    seed: u64,
    level: usize,
) -> Vec<u32> {
    let mut order: Vec<(u64, u32)> = candidates
        .iter()
        .map(|&v| (mix(seed ^ mix(level as u64 ^ 0x7073) ^ u64::from(v)), v))
        .collect();
    order.sort_unstable();
    let mut chosen: Vec<u32> = Vec::new();
    let mut grid: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
    let s2 = spacing * spacing;
    for (_, v) in order {
        if chosen.len() >= max {
            break;
        }
        let p = positions[v as usize];
        let k = Grid::key(p, spacing);
        let mut ok = true;
        'search: for i in -1..=1 {
            for j in -1..=1 {
                for l in -1..=1 {
                    if let Some(list) = grid.get(&[k[0] + i, k[1] + j, k[2] + l])
                        && list.iter().any(|&w| dist2(positions[w as usize], p) < s2)
                    {
                        ok = false;
                        break 'search;
                    }
                }
            }
        }
        if ok {
            chosen.push(v);
            grid.entry(k).or_default().push(v);
        }
    }
    chosen
}

/// The vertex of `positions` nearest to `p` (lowest id on ties).
pub fn nearest_vertex(positions: &[[f64; 3]], p: [f64; 3]) -> u32 {
    positions
        .par_iter()
        .enumerate()
        .map(|(i, q)| (dist2(*q, p), i))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map_or(0, |(_, i)| i as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rock_is_fractal_uniform_and_stable() {
        let r = Rock::default();
        let at = |n: usize| vec![[0.0; 3]; n];
        let d1 = r.values(3, 1, &at(10_000));
        let d3 = r.values(3, 3, &at(10_000));
        let rms = |d: &[f64]| (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
        // Uniform on [−A, A]: rms A/√3; two levels down a quarter of it.
        assert!((rms(&d1) / (0.08 / 3f64.sqrt()) - 1.0).abs() < 0.03);
        assert!((rms(&d3) / rms(&d1) - 0.25).abs() < 0.02);
        assert_eq!(r.values(3, 1, &at(100)), d1[..100].to_vec(), "stable");
        assert_ne!(r.values(4, 1, &at(100)), d1[..100].to_vec(), "seeded");
        let bad = Feature::global(Procedure::Rock(Rock::fractal(0.1, -1.0)));
        assert!(bad.validate().is_err());
    }

    #[test]
    fn laws_and_the_tentacle_pseudo_code() {
        assert_eq!(Law::Fractal { decay: 0.5 }.factor(3), 0.25);
        assert_eq!(Law::Morphogenic.factor(3), 3.0);
        assert_eq!(Law::Independent.factor(7), 1.0);
        let t = Tentacle {
            length: 0.1,
            theta: 0.3,
            alternate: true,
            twist: true,
            reading: TentacleReading::Literal,
        };
        // Level 2: magnitude 0.2, angle θ + 2π/3, negated (even level).
        let o = t.offset(2);
        let p = 0.3 + 2.0 * std::f64::consts::FRAC_PI_3;
        assert!((o[0] + 0.2 * p.sin()).abs() < 1e-15);
        assert!((o[1] + 0.2 * p.cos()).abs() < 1e-15);
        assert!((o[2] + 0.2).abs() < 1e-15);
        assert!(t.offset(3)[2] > 0.0);
    }

    #[test]
    fn poisson_disk_keeps_its_spacing() {
        let pts: Vec<[f64; 3]> = (0..2000)
            .map(|i| {
                let a = random_value(1, 0, i);
                let b = random_value(2, 0, i);
                [a, b, 0.0]
            })
            .collect();
        let all: Vec<u32> = (0..2000).collect();
        let s = poisson_disk(&pts, &all, 0.2, usize::MAX, 5, 1);
        assert!(s.len() > 20, "{}", s.len());
        for (i, &a) in s.iter().enumerate() {
            for &b in &s[i + 1..] {
                assert!(dist2(pts[a as usize], pts[b as usize]) >= 0.04);
            }
        }
        assert_eq!(s, poisson_disk(&pts, &all, 0.2, usize::MAX, 5, 1));
    }
}
