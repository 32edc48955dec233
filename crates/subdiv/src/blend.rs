//! Multiscale blending of two multiresolution surfaces (velho-perlin §6,
//! after Burt's image splines).
//!
//! The details of two surfaces on one base are mixed per level,
//! Dₗ = (1 − αₗ)Dₗᴬ + αₗDₗᴮ, with αₗ = S(s(p)/wₗ), S the smoothstep from −½ to ½,
//! wₗ = c/2ˡ⁻¹ (level 0 uses 2c) and s the side function of the alpha source: a
//! plane n̂·p − offset (the paper's (1, 2, 0) example), Perlin noise, or a
//! per-vertex alpha map a − ½ (subdivided with the surface). s is evaluated on
//! the reference surface (the plain subdivision of the base), so the seam does
//! not move with the details. Coarse features therefore cross the seam and fine
//! ones switch sharply. Where αₗ is exactly 0 or 1 the detail is copied, not
//! interpolated, so far from the seam the result is bit-identical to each input.
//!
//! **Painted alpha.** The paper's central interactive idea is an alpha map
//! painted on the surface. [`painted_alpha`] takes one painted in Blender or
//! MeshLab — a mesh over the base (the base itself as exported, or any finer
//! mesh on it) with a per-vertex colour or scalar — and gives each base vertex
//! the value of the nearest painted vertex: the luminance of a colour
//! (0.2126 R + 0.7152 G + 0.0722 B of the stored sRGB bytes, so black is
//! layer a and white layer b), or a scalar as it is. Vertex order, duplicated
//! vertices (split at UV seams by exporters) and triangulation do not matter.
//!
//! # Deviations from the paper
//! - The paper blends images of the two surfaces' levels with a mask; here the
//!   mask is a side function on the reference surface, evaluated per vertex, so
//!   no parameterisation is needed.

use asperity_core::CoreError;
use noise::{NoiseFn, Perlin};
use rayon::prelude::*;

use crate::catmull_clark::{Boundary, Creased, Topology, refine_with};
use crate::multires::{Details, Multires, build};

/// Where the blend's alpha comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum AlphaSource {
    /// s = n̂·p − offset.
    Plane {
        /// Plane normal (need not be unit).
        normal: [f64; 3],
        /// Offset along the unit normal.
        offset: f64,
    },
    /// s = Perlin noise of p·frequency.
    Noise {
        /// Frequency per mesh unit.
        frequency: f64,
        /// Noise seed.
        seed: u32,
    },
    /// s = a − ½ with a per-base-vertex alpha in [0, 1], subdivided.
    Map(Vec<f64>),
}

/// A multiscale blend (§6).
#[derive(Clone, Debug, PartialEq)]
pub struct Blend {
    /// The alpha source.
    pub source: AlphaSource,
    /// c: the transition width at level 1 (level l: c/2ˡ⁻¹).
    pub width: f64,
}

fn smoothstep(u: f64) -> f64 {
    let t = (u + 0.5).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Blend {
    /// Checks the parameters against a base with `n_base` vertices.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] naming the problem.
    pub fn validate(&self, n_base: usize) -> Result<(), CoreError> {
        let bad = |reason: String| {
            Err(CoreError::InvalidParameter {
                name: "blend",
                reason,
            })
        };
        if !(self.width.is_finite() && self.width > 0.0) {
            return bad(format!("width must be > 0, got {}", self.width));
        }
        match &self.source {
            AlphaSource::Plane { normal, offset } => {
                let l = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                if !(l.is_finite() && l > 0.0 && offset.is_finite()) {
                    return bad("the plane needs a finite non-zero normal and offset".into());
                }
            }
            AlphaSource::Noise { frequency, .. } => {
                if !(frequency.is_finite() && *frequency > 0.0) {
                    return bad(format!("noise frequency must be > 0, got {frequency}"));
                }
            }
            AlphaSource::Map(a) => {
                if a.len() != n_base {
                    return bad(format!(
                        "the alpha map has {} values; the base has {n_base} vertices",
                        a.len()
                    ));
                }
                if a.iter().any(|x| !(0.0..=1.0).contains(x)) {
                    return bad("alpha map values must lie in [0, 1]".into());
                }
            }
        }
        Ok(())
    }

    /// αₗ at a point of the reference surface with subdivided map value `a`.
    pub fn alpha(&self, level: usize, p: [f64; 3], a: f64) -> f64 {
        let w = self.width * 2f64.powi(1 - level as i32);
        let s = match &self.source {
            AlphaSource::Plane { normal, offset } => {
                let l = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                (normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2]) / l - offset
            }
            AlphaSource::Noise { frequency, seed } => {
                Perlin::new(*seed).get(p.map(|x| x * frequency))
            }
            AlphaSource::Map(_) => a - 0.5,
        };
        smoothstep(s / w)
    }
}

/// Positions and a scalar of one level.
type LevelValues = (Vec<[f64; 3]>, Vec<f64>);

/// The plain subdivision of `base` with a scalar carried along: per level,
/// (positions, scalars).
fn reference(
    base: &Creased,
    levels: usize,
    boundary: Boundary,
    scalar: Option<&[f64]>,
) -> Result<Vec<LevelValues>, CoreError> {
    let n = base.mesh.n_vertices();
    let mut vals: Vec<[f64; 4]> = base
        .mesh
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| [p[0], p[1], p[2], scalar.map_or(0.0, |s| s[i])])
        .collect();
    let split = |v: &[[f64; 4]]| {
        (
            v.iter().map(|x| [x[0], x[1], x[2]]).collect::<Vec<_>>(),
            v.iter().map(|x| x[3]).collect::<Vec<_>>(),
        )
    };
    let mut out = vec![split(&vals)];
    let mut mesh = base.clone();
    let mut topo = Topology::new(base)?;
    debug_assert_eq!(topo.n_vertices(), n);
    for k in 1..=levels {
        vals = topo.subdivide_values(mesh.mesh.face_vertices(), &vals, boundary);
        let next = refine_with(&mesh, &topo, boundary)?;
        if k < levels {
            topo = topo.refined(next.mesh.face_vertices(), &next.creases);
        }
        mesh = next;
        out.push(split(&vals));
    }
    Ok(out)
}

fn mix_details(a: &[[f64; 3]], b: &[[f64; 3]], alpha: &[f64]) -> Vec<[f64; 3]> {
    (0..alpha.len())
        .into_par_iter()
        .map(|v| {
            let da = a.get(v).copied().unwrap_or([0.0; 3]);
            let db = b.get(v).copied().unwrap_or([0.0; 3]);
            let t = alpha[v];
            if t == 0.0 {
                da
            } else if t == 1.0 {
                db
            } else {
                std::array::from_fn(|k| (1.0 - t) * da[k] + t * db[k])
            }
        })
        .collect()
}

/// Blends surfaces A and B (details `a`, `b` on the same base connectivity;
/// B's base positions `base_b` may differ and are blended at level 0) and
/// returns the blended surface and α at the finest level.
///
/// # Errors
/// As [`build`]; [`CoreError::InvalidParameter`] for a bad blend or a base of
/// different size.
pub fn blend(
    base: &Creased,
    base_b: Option<&Creased>,
    (a, b): (&Details, &Details),
    levels: usize,
    boundary: Boundary,
    how: &Blend,
) -> Result<(Multires, Vec<f64>), CoreError> {
    how.validate(base.mesh.n_vertices())?;
    let map = match &how.source {
        AlphaSource::Map(m) => Some(m.as_slice()),
        _ => None,
    };
    let refs = reference(base, levels, boundary, map)?;
    let alphas: Vec<Vec<f64>> = refs
        .iter()
        .enumerate()
        .map(|(l, (p, s))| {
            p.par_iter()
                .zip(s.par_iter())
                .map(|(p, s)| how.alpha(l, *p, *s))
                .collect()
        })
        .collect();
    let mut start = base.clone();
    if let Some(bb) = base_b {
        if bb.mesh.n_vertices() != base.mesh.n_vertices() {
            return Err(CoreError::InvalidParameter {
                name: "blend",
                reason: format!(
                    "the bases differ in size ({} and {} vertices)",
                    base.mesh.n_vertices(),
                    bb.mesh.n_vertices()
                ),
            });
        }
        let pa = base.mesh.positions();
        let pb = bb.mesh.positions();
        let mixed: Vec<[f64; 3]> = (0..pa.len())
            .map(|v| {
                let t = alphas[0][v];
                if t == 0.0 {
                    pa[v]
                } else if t == 1.0 {
                    pb[v]
                } else {
                    std::array::from_fn(|k| (1.0 - t) * pa[v][k] + t * pb[v][k])
                }
            })
            .collect();
        start.mesh.set_positions(mixed)?;
    }
    let empty = Vec::new();
    let m = build(&start, levels, boundary, |input| {
        let l = input.level;
        let (da, db) = (
            a.get(l - 1).unwrap_or(&empty),
            b.get(l - 1).unwrap_or(&empty),
        );
        if da.is_empty() && db.is_empty() {
            return Ok(None);
        }
        Ok(Some(mix_details(da, db, &alphas[l])))
    })?;
    let last = alphas.last().cloned().unwrap_or_default();
    Ok((m, last))
}

/// What a painted mesh's alpha is read from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Paint {
    /// The luminance of the vertex colours (sRGB bytes, alpha ignored).
    Colour,
    /// A named per-vertex scalar, in [0, 1].
    Scalar(String),
}

/// Farthest a base vertex may be from the painted mesh's nearest vertex, as a
/// share of the base's bounding-box diagonal (beyond it the painting is not of
/// this base).
pub const PAINT_TOLERANCE: f64 = 0.05;

/// The alpha of each base vertex (`base` positions) from a mesh painted over
/// the base: the value of its nearest painted vertex (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`]: no colours or no such scalar (the message
/// lists those present), values outside [0, 1], an empty painted mesh, or a
/// painting farther than [`PAINT_TOLERANCE`] from the base.
pub fn painted_alpha(
    base: &[[f64; 3]],
    painted: &asperity_core::TriMesh,
    from: &Paint,
) -> Result<Vec<f64>, CoreError> {
    let bad = |reason: String| CoreError::InvalidParameter {
        name: "alpha map",
        reason,
    };
    let values = paint_values(painted, from).map_err(bad)?;
    let points = painted.positions();
    if points.is_empty() || base.is_empty() {
        return Err(bad("the painted mesh or the base has no vertices".into()));
    }
    let (lo, hi) = bounds(base);
    let diagonal = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
    let limit = PAINT_TOLERANCE * diagonal;
    // A brute-force nearest search: bases are coarse (the painted mesh may be
    // fine), and the searches are independent, so rayon spreads them.
    base.par_iter()
        .enumerate()
        .map(|(v, p)| {
            let (d2, k) = points
                .iter()
                .enumerate()
                .map(|(k, q)| ((0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f64>(), k))
                .fold((f64::INFINITY, 0), |best, c| if c.0 < best.0 { c } else { best });
            if d2.sqrt() > limit {
                return Err(bad(format!(
                    "base vertex {v} is {:.3} from the nearest painted vertex, more than {:.0} % of the base's size: paint the base itself (asperity subdiv --levels 0 exports it)",
                    d2.sqrt(),
                    100.0 * PAINT_TOLERANCE
                )));
            }
            Ok(values[k])
        })
        .collect()
}

/// The painted values, one per painted vertex, checked to lie in [0, 1].
fn paint_values(painted: &asperity_core::TriMesh, from: &Paint) -> Result<Vec<f64>, String> {
    let names = || {
        let n: Vec<&str> = painted.scalars().iter().map(|a| a.name.as_str()).collect();
        if n.is_empty() {
            "none".to_string()
        } else {
            n.join(", ")
        }
    };
    let values: Vec<f64> = match from {
        Paint::Colour => painted
            .colors()
            .ok_or_else(|| {
                format!(
                    "the painted mesh has no vertex colours (its scalars: {})",
                    names()
                )
            })?
            .iter()
            .map(|c| {
                // Integer weights (Rec. 709 × 10⁴, summing to 10⁴): a grey c
                // gives exactly c/255, so black and white are exactly 0 and 1.
                let w = 2126 * u32::from(c[0]) + 7152 * u32::from(c[1]) + 722 * u32::from(c[2]);
                f64::from(w) / 2_550_000.0
            })
            .collect(),
        Paint::Scalar(name) => painted
            .scalar(name)
            .ok_or_else(|| {
                format!(
                    "the painted mesh has no scalar {name:?} (its scalars: {})",
                    names()
                )
            })?
            .to_vec(),
    };
    match values.iter().find(|v| !(0.0..=1.0).contains(*v)) {
        Some(v) => Err(format!("painted values must lie in [0, 1], found {v}")),
        None => Ok(values),
    }
}

fn bounds(p: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    p.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), q| {
            (
                std::array::from_fn(|a| lo[a].min(q[a])),
                std::array::from_fn(|a| hi[a].max(q[a])),
            )
        },
    )
}

/// An alpha map from text: one number in [0, 1] per base vertex, separated by
/// white space or commas (a text or CSV column). The range is checked by
/// [`Blend::validate`].
///
/// # Errors
/// A message naming the first token that is not a number.
pub fn parse_alpha_map(text: &str) -> Result<Vec<f64>, String> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>()
                .map_err(|_| format!("{s:?} is not a number"))
        })
        .collect()
}
