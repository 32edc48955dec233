//! Composing multiscale details (velho-perlin §5–6): growing layers of
//! features with local edits, blending two multiresolution surfaces level by
//! level, and the scalar mode with a post-shader (the planet).
//!
//! **Local detail modification** (§5.2): around a vertex, the details of a
//! band of levels are scaled by 1 + (factor − 1)·w(d/Rₗ) — factor 0 smooths,
//! factors above 1 exaggerate — with d the topological distance (edge hops,
//! breadth-first at each level), Rₗ = radius·2ˡ (the radius is given in
//! base-level edges, and every subdivision doubles the hops), and the cubic
//! drop-off w(x) = 1 − 3x² + 2x³.
//!
//! **Multiscale blending** (§6, after Burt's image splines): the details of
//! two surfaces on one base are mixed per level, Dₗ = (1 − αₗ)Dₗᴬ + αₗDₗᴮ, with
//! αₗ = S(s(p)/wₗ), S the smoothstep from −½ to ½, wₗ = c/2ˡ⁻¹ (level 0 uses 2c)
//! and s the side function of the alpha source: a plane n̂·p − offset (the
//! paper's (1, 2, 0) example), Perlin noise, or a per-vertex alpha map a − ½
//! (subdivided with the surface). s is evaluated on the reference surface (the
//! plain subdivision of the base), so the seam does not move with the details.
//! Coarse features therefore cross the seam and fine ones switch sharply.
//! Where αₗ is exactly 0 or 1 the detail is copied, not interpolated, so far
//! from the seam the result is bit-identical to each input.
//!
//! **Scalar mode** (§6.2): the same machinery carries a scalar per vertex —
//! subdivided like positions, with the procedures' normal components as
//! scalar details — blended the same way, then shaded and used as relief with
//! a sea-level clamp ([`Planet`]).

use std::collections::VecDeque;

use asperity_core::{CoreError, NoProgress, Progress};
use noise::{NoiseFn, Perlin};
use rayon::prelude::*;

use crate::catmull_clark::{Boundary, Creased, Topology, refine_with};
use crate::detail::{Feature, Grower, Procedure, nearest_vertex};
use crate::multires::{Details, LevelInput, Multires, build, frame_at};

/// Where an edit is centred.
#[derive(Clone, Debug, PartialEq)]
pub enum Anchor {
    /// A base-level vertex id (followed through the levels).
    Vertex(u32),
    /// The vertex nearest to this point at each level.
    Point([f64; 3]),
}

/// A local detail modification (§5.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Edit {
    /// The centre.
    pub at: Anchor,
    /// Radius in base-level edges.
    pub radius: f64,
    /// First and last level affected (inclusive, ≥ 1).
    pub levels: (usize, usize),
    /// 0 removes the details (smooths), 1 keeps them, > 1 exaggerates.
    pub factor: f64,
}

/// A named stack of features and edits grown on a base.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// Name (for blends).
    pub name: String,
    /// The features, summed level by level.
    pub features: Vec<Feature>,
    /// Edits applied to the summed details.
    pub edits: Vec<Edit>,
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

/// Breadth-first edge hops from `start` up to `max_hops`: (vertex, hops).
pub fn hops(input: &LevelInput<'_>, start: u32, max_hops: usize) -> Vec<(u32, usize)> {
    let fv = input.mesh.mesh.face_vertices();
    let topo = input.topo;
    let n = input.positions().len();
    let mut dist = std::collections::HashMap::new();
    let mut queue = VecDeque::new();
    if (start as usize) < n {
        dist.insert(start, 0usize);
        queue.push_back(start);
    }
    let mut out = Vec::new();
    while let Some(v) = queue.pop_front() {
        let d = dist[&v];
        out.push((v, d));
        if d == max_hops {
            continue;
        }
        for &c in topo.v_corners.of(v as usize) {
            let c = c as usize;
            for w in [fv[topo.next(c)], fv[topo.prev(c)]] {
                if let std::collections::hash_map::Entry::Vacant(e) = dist.entry(w) {
                    e.insert(d + 1);
                    queue.push_back(w);
                }
            }
        }
    }
    out
}

/// Grows a layer on `base`: every feature's details summed at each level,
/// then the edits.
///
/// # Errors
/// As [`build`]; [`CoreError::InvalidParameter`] for a bad feature or edit.
pub fn grow(
    base: &Creased,
    levels: usize,
    boundary: Boundary,
    layer: &Layer,
    seed: u64,
) -> Result<Multires, CoreError> {
    grow_observed(base, levels, boundary, layer, seed, &NoProgress)
}

/// [`grow`], advancing `progress` by one per level built.
///
/// # Errors
/// As [`grow`].
pub fn grow_observed(
    base: &Creased,
    levels: usize,
    boundary: Boundary,
    layer: &Layer,
    seed: u64,
    progress: &dyn Progress,
) -> Result<Multires, CoreError> {
    validate_features(&layer.features, base.mesh.n_vertices())?;
    for e in &layer.edits {
        validate_edit(e, base.mesh.n_vertices())?;
    }
    let mut growers: Vec<Grower> = layer
        .features
        .iter()
        .enumerate()
        .map(|(i, f)| Grower::new(f.clone(), seed.wrapping_add(i as u64 * 0x9e37_79b9)))
        .collect();
    let mut centres: Vec<Option<u32>> = vec![None; layer.edits.len()];
    build(base, levels, boundary, |input| {
        progress.advance(1);
        let mut sum: Option<Vec<[f64; 3]>> = None;
        for g in &mut growers {
            if let Some(d) = g.details(input) {
                match &mut sum {
                    None => sum = Some(d),
                    Some(s) => s.par_iter_mut().zip(d.par_iter()).for_each(|(a, b)| {
                        for k in 0..3 {
                            a[k] += b[k];
                        }
                    }),
                }
            }
        }
        for (e, centre) in layer.edits.iter().zip(&mut centres) {
            let c = match &e.at {
                Anchor::Vertex(v) => {
                    let c = match *centre {
                        None => input.descend(*v),
                        Some(prev) => input.descend(prev),
                    };
                    *centre = Some(c);
                    c
                }
                Anchor::Point(p) => nearest_vertex(input.positions(), *p),
            };
            let l = input.level;
            if l < e.levels.0 || l > e.levels.1 {
                continue;
            }
            let Some(s) = &mut sum else { continue };
            let r = e.radius * 2f64.powi(l as i32);
            for (v, d) in hops(input, c, r.floor() as usize) {
                let w = drop_off(d as f64 / r);
                let k = 1.0 + (e.factor - 1.0) * w;
                s[v as usize] = s[v as usize].map(|x| x * k);
            }
        }
        Ok(sum)
    })
}

/// Checks every feature's parameters and that its seed vertices exist.
fn validate_features(features: &[Feature], n_base: usize) -> Result<(), CoreError> {
    for f in features {
        let bad = |reason: String| CoreError::InvalidParameter {
            name: "detail",
            reason: format!("{}: {reason}", f.procedure.name()),
        };
        f.validate().map_err(bad)?;
        if let crate::detail::Seeds::Vertices(v) = &f.seeds
            && let Some(x) = v.iter().find(|&&x| x as usize >= n_base)
        {
            return Err(bad(format!(
                "seed vertex {x} is not a base vertex (the base has {n_base})"
            )));
        }
    }
    Ok(())
}

fn validate_edit(e: &Edit, n_base: usize) -> Result<(), CoreError> {
    let bad = |reason: String| {
        Err(CoreError::InvalidParameter {
            name: "edit",
            reason,
        })
    };
    if !(e.radius.is_finite() && e.radius > 0.0) {
        return bad(format!("radius must be > 0 base edges, got {}", e.radius));
    }
    if !e.factor.is_finite() {
        return bad(format!("factor must be finite, got {}", e.factor));
    }
    if e.levels.0 == 0 || e.levels.1 < e.levels.0 {
        return bad(format!(
            "levels must be first ≥ 1 and last ≥ first, got {:?}",
            e.levels
        ));
    }
    match &e.at {
        Anchor::Vertex(v) if *v as usize >= n_base => bad(format!(
            "vertex {v} is not a base vertex (the base has {n_base})"
        )),
        Anchor::Point(p) if p.iter().any(|x| !x.is_finite()) => {
            bad("the point must be finite".into())
        }
        _ => Ok(()),
    }
}

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

/// A scalar field on the plain subdivision of a base (scalar mode, §6.2).
#[derive(Clone, Debug)]
pub struct ScalarField {
    /// The reference surface at the finest level.
    pub mesh: Creased,
    /// Unit normals of the reference surface (its frames' n).
    pub normals: Vec<[f64; 3]>,
    /// The blended scalar per vertex.
    pub value: Vec<f64>,
    /// The blend weight per vertex (0 = all A).
    pub alpha: Vec<f64>,
    /// (vertices, faces) of every level, base first.
    pub counts: Vec<(usize, usize)>,
}

/// Scalar details of a set of features at one level (their normal components).
fn scalar_details(growers: &mut [Grower], input: &LevelInput<'_>) -> Vec<f64> {
    let n = input.positions().len();
    let mut s = vec![0.0; n];
    for g in growers {
        if let Some(d) = g.details(input) {
            s.par_iter_mut()
                .zip(d.par_iter())
                .for_each(|(a, b)| *a += b[2]);
        }
    }
    s
}

/// The scalar mode: features A (and B with a blend) grown as scalars on the
/// plain subdivision of `base`, blended level by level.
///
/// # Errors
/// As [`grow`] and [`blend`].
pub fn scalar_field(
    base: &Creased,
    levels: usize,
    boundary: Boundary,
    a: &[Feature],
    b: Option<(&[Feature], &Blend)>,
    seed: u64,
) -> Result<ScalarField, CoreError> {
    validate_features(a, base.mesh.n_vertices())?;
    if let Some((fb, _)) = b {
        validate_features(fb, base.mesh.n_vertices())?;
    }
    for f in a.iter().chain(b.iter().flat_map(|(f, _)| f.iter())) {
        if matches!(f.procedure, Procedure::Mushroom(_)) {
            return Err(CoreError::InvalidParameter {
                name: "detail",
                reason: "mushroom displaces sideways and has no scalar form".into(),
            });
        }
    }
    let how = b.map(|(_, h)| h);
    if let Some(h) = how {
        h.validate(base.mesh.n_vertices())?;
    }
    let grow_set = |fs: &[Feature], salt: u64| -> Vec<Grower> {
        fs.iter()
            .enumerate()
            .map(|(i, f)| Grower::new(f.clone(), seed ^ salt ^ (i as u64 * 0x9e37_79b9)))
            .collect()
    };
    let mut ga = grow_set(a, 0);
    let mut gb = b.map(|(f, _)| grow_set(f, 0xb1e7_d000)).unwrap_or_default();
    let map = how.and_then(|h| match &h.source {
        AlphaSource::Map(m) => Some(m.clone()),
        _ => None,
    });
    // Values carried: x, y, z, scalar, alpha-map.
    let mut vals: Vec<[f64; 5]> = base
        .mesh
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| [p[0], p[1], p[2], 0.0, map.as_ref().map_or(0.0, |m| m[i])])
        .collect();
    let mut mesh = base.clone();
    let mut topo = Topology::new(base)?;
    topo.check_base(base.mesh.face_vertices())?;
    crate::catmull_clark::check_nondegenerate(&base.mesh)?;
    let mut alpha = vec![0.0; vals.len()];
    let mut counts = vec![(mesh.mesh.n_vertices(), mesh.mesh.n_faces())];
    for l in 1..=levels {
        vals = topo.subdivide_values(mesh.mesh.face_vertices(), &vals, boundary);
        let mut next = refine_with(&mesh, &topo, boundary)?;
        next.mesh
            .set_positions(vals.iter().map(|v| [v[0], v[1], v[2]]).collect())?;
        let next_topo = topo.refined(next.mesh.face_vertices(), &next.creases);
        let input = LevelInput::new(l, &next, &next_topo, topo.n_faces(), topo.edges.len());
        let da = scalar_details(&mut ga, &input);
        let d = match how {
            Some(h) => {
                let db = scalar_details(&mut gb, &input);
                alpha = vals
                    .par_iter()
                    .map(|v| h.alpha(l, [v[0], v[1], v[2]], v[4]))
                    .collect();
                (0..da.len())
                    .into_par_iter()
                    .map(|v| {
                        let t = alpha[v];
                        if t == 0.0 {
                            da[v]
                        } else if t == 1.0 {
                            db[v]
                        } else {
                            (1.0 - t) * da[v] + t * db[v]
                        }
                    })
                    .collect()
            }
            None => {
                alpha = vec![0.0; da.len()];
                da
            }
        };
        vals.par_iter_mut()
            .zip(d.par_iter())
            .for_each(|(v, d)| v[3] += d);
        counts.push((next.mesh.n_vertices(), next.mesh.n_faces()));
        mesh = next;
        topo = next_topo;
    }
    let normals = (0..mesh.mesh.n_vertices())
        .into_par_iter()
        .map(|v| frame_at(&mesh.mesh, &topo, v)[2])
        .collect();
    Ok(ScalarField {
        mesh,
        normals,
        value: vals.iter().map(|v| v[3]).collect(),
        alpha,
        counts,
    })
}

/// The planet post-shader (§6.2): colours from the blended scalar and the
/// blend weight, and relief with a sea-level clamp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Planet {
    /// Scalar value of the sea surface.
    pub sea_level: f64,
    /// Relief: displacement per unit of scalar above the sea.
    pub relief: f64,
    /// Fraction of the land range above which mountains begin.
    pub mountain: f64,
    /// Fraction of the land range above which snow lies.
    pub snow: f64,
}

impl Default for Planet {
    fn default() -> Self {
        Self {
            sea_level: 0.0,
            relief: 0.25,
            mountain: 0.45,
            snow: 0.75,
        }
    }
}

fn lerp_rgb(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t.clamp(0.0, 1.0))
}

impl Planet {
    /// Vertex colours and displaced positions of a scalar field.
    pub fn shade(&self, f: &ScalarField) -> (Vec<[u8; 4]>, Vec<[f64; 3]>) {
        let hi = f.value.iter().copied().fold(self.sea_level, f64::max);
        let lo = f.value.iter().copied().fold(self.sea_level, f64::min);
        let land = (hi - self.sea_level).max(1e-12);
        let deep = (self.sea_level - lo).max(1e-12);
        let colours = f
            .value
            .par_iter()
            .zip(f.alpha.par_iter())
            .map(|(&s, &a)| {
                let c = if s < self.sea_level {
                    let t = (self.sea_level - s) / deep;
                    // Earth seas blue, alien seas teal.
                    let shallow = lerp_rgb([70.0, 140.0, 200.0], [60.0, 170.0, 160.0], a);
                    lerp_rgb(shallow, [12.0, 30.0, 90.0], t.sqrt())
                } else {
                    let h = (s - self.sea_level) / land;
                    let low = lerp_rgb([70.0, 140.0, 60.0], [150.0, 90.0, 150.0], a);
                    let rock = lerp_rgb([125.0, 105.0, 85.0], [110.0, 80.0, 70.0], a);
                    if h > self.snow {
                        lerp_rgb(rock, [245.0, 245.0, 250.0], (h - self.snow) / 0.05)
                    } else if h > self.mountain {
                        lerp_rgb(low, rock, (h - self.mountain) / 0.1)
                    } else {
                        low
                    }
                };
                [c[0] as u8, c[1] as u8, c[2] as u8, 255]
            })
            .collect();
        let p = f.mesh.mesh.positions();
        let positions = (0..p.len())
            .into_par_iter()
            .map(|v| {
                let r = self.relief * (f.value[v].max(self.sea_level) - self.sea_level);
                std::array::from_fn(|k| p[v][k] + r * f.normals[v][k])
            })
            .collect();
        (colours, positions)
    }
}

/// The result of evaluating a scene.
#[derive(Clone, Debug)]
pub struct Composed {
    /// The finest level's connectivity and final positions.
    pub mesh: Creased,
    /// Vertex colours (scalar mode).
    pub colors: Option<Vec<[u8; 4]>>,
    /// Named per-vertex scalars (scalar mode: `height`, `alpha`; blends: `alpha`).
    pub scalars: Vec<(String, Vec<f64>)>,
    /// The details of every level (displacement mode).
    pub details: Details,
    /// (vertices, faces) per level.
    pub counts: Vec<(usize, usize)>,
}

fn merged(layers: &[Layer]) -> Layer {
    Layer {
        name: "main".into(),
        features: layers.iter().flat_map(|l| l.features.clone()).collect(),
        edits: layers.iter().flat_map(|l| l.edits.clone()).collect(),
    }
}

/// A captured surface analysed into a layer: its base positions and details.
#[derive(Clone, Debug)]
pub struct Captured {
    /// The layer it stands for.
    pub layer: String,
    /// Base positions (the scene base's connectivity).
    pub base: Creased,
    /// Details of every level.
    pub details: Details,
}

/// What the caller read for a scene: the blend's alpha map and the captured
/// surfaces.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    /// One alpha in [0, 1] per base vertex, when the blend names a map.
    pub alpha_map: Option<Vec<f64>>,
    /// The scene's `[[surface]]` layers, analysed.
    pub captured: Vec<Captured>,
}

/// Evaluates a scene on its base (loaded by the caller) with the files the
/// scene names already read (`inputs`).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for an inconsistent scene; as [`grow`],
/// [`blend`] and [`scalar_field`].
pub fn evaluate(
    scene: &crate::scene::Scene,
    base: &Creased,
    inputs: &Inputs,
    progress: &dyn Progress,
) -> Result<Composed, CoreError> {
    let bad = |reason: String| CoreError::InvalidParameter {
        name: "scene",
        reason,
    };
    let (levels, boundary, seed) = (scene.levels, scene.boundary, scene.seed);
    let find = |name: &str| {
        scene
            .layers
            .iter()
            .find(|l| l.name == name)
            .ok_or_else(|| bad(format!("no layer {name:?}")))
    };
    let captured = |name: &str| inputs.captured.iter().find(|c| c.layer == name);
    for (layer, _) in &scene.surfaces {
        if captured(layer).is_none() {
            return Err(bad(format!(
                "the captured surface of layer {layer:?} was not read"
            )));
        }
    }
    let blend_parts = match &scene.blend {
        Some((a, b, how)) => {
            if let Some(l) = scene.layers.iter().find(|l| &l.name != a && &l.name != b) {
                return Err(bad(format!(
                    "layer {:?} is neither side of the blend ({a:?}, {b:?})",
                    l.name
                )));
            }
            let mut how = how.clone();
            if let AlphaSource::Map(m) = &mut how.source {
                *m = inputs
                    .alpha_map
                    .clone()
                    .ok_or_else(|| bad("the blend's alpha map was not read".into()))?;
            }
            Some((find(a)?, find(b)?, how))
        }
        None => None,
    };
    if !inputs.captured.is_empty() {
        if matches!(scene.mode, crate::scene::Mode::Scalar(_)) {
            return Err(bad(
                "captured surfaces displace; scalar mode cannot use them".into(),
            ));
        }
        if blend_parts.is_none() && scene.layers.len() > 1 {
            return Err(bad(
                "a captured surface combines with other layers only through [blend]".into(),
            ));
        }
    }
    // One side of a blend (or the only layer): its base and details.
    let side = |layer: &Layer, salt: u64| -> Result<(Creased, Details), CoreError> {
        match captured(&layer.name) {
            Some(c) => Ok((c.base.clone(), c.details.clone())),
            None => Ok((
                base.clone(),
                grow_observed(base, levels, boundary, layer, seed ^ salt, progress)?.details,
            )),
        }
    };
    // One unit per level of every procedural surface grown.
    let surfaces = match (&blend_parts, &scene.mode) {
        (_, crate::scene::Mode::Scalar(_)) => 0,
        (Some((a, b, _)), _) => [a, b]
            .iter()
            .filter(|l| captured(&l.name).is_none())
            .count(),
        (None, _) => usize::from(inputs.captured.is_empty()),
    };
    progress.start((surfaces * levels) as u64, "subdivision levels");
    let out = evaluate_mode(scene, base, inputs, progress, blend_parts.as_ref(), &side);
    progress.finish();
    out
}

/// Builds one side of a blend: its base and details.
type SideFn<'a> = dyn Fn(&Layer, u64) -> Result<(Creased, Details), CoreError> + 'a;

/// The two sides of a blend and how.
type BlendParts<'a> = (&'a Layer, &'a Layer, Blend);

/// [`evaluate`] after the checks.
fn evaluate_mode(
    scene: &crate::scene::Scene,
    base: &Creased,
    inputs: &Inputs,
    progress: &dyn Progress,
    blend_parts: Option<&BlendParts<'_>>,
    side: &SideFn<'_>,
) -> Result<Composed, CoreError> {
    let (levels, boundary, seed) = (scene.levels, scene.boundary, scene.seed);
    let counts = |m: &Multires| {
        m.levels
            .iter()
            .map(|l| (l.mesh.n_vertices(), l.mesh.n_faces()))
            .collect::<Vec<_>>()
    };
    match &scene.mode {
        crate::scene::Mode::Displace => {
            let (m, alpha) = match &blend_parts {
                None => match inputs.captured.first() {
                    Some(c) => {
                        let d = &c.details;
                        let m = build(&c.base, levels, boundary, |l| {
                            Ok(d.get(l.level - 1).filter(|x| !x.is_empty()).cloned())
                        })?;
                        (m, None)
                    }
                    None => (
                        grow_observed(
                            base,
                            levels,
                            boundary,
                            &merged(&scene.layers),
                            seed,
                            progress,
                        )?,
                        None,
                    ),
                },
                Some((a, b, how)) => {
                    let (ba, da) = side(a, 0)?;
                    let (bb, db) = side(b, 0xb1e7_d000)?;
                    let base_b = (bb.mesh.positions() != ba.mesh.positions()).then_some(&bb);
                    let (m, alpha) = blend(&ba, base_b, (&da, &db), levels, boundary, how)?;
                    (m, Some(alpha))
                }
            };
            let mut mesh = m.finest().clone();
            if scene.limit && levels > 0 {
                let lim = crate::catmull_clark::limit_positions(&mesh, boundary)?;
                mesh.mesh.set_positions(lim)?;
            }
            Ok(Composed {
                counts: counts(&m),
                mesh,
                colors: None,
                scalars: alpha.map(|a| vec![("alpha".into(), a)]).unwrap_or_default(),
                details: m.details,
            })
        }
        crate::scene::Mode::Scalar(planet) => {
            if scene.layers.iter().any(|l| !l.edits.is_empty()) {
                return Err(CoreError::InvalidParameter {
                    name: "scene",
                    reason: "edits act on displacement details; scalar mode has none".into(),
                });
            }
            let f = match &blend_parts {
                None => scalar_field(
                    base,
                    levels,
                    boundary,
                    &merged(&scene.layers).features,
                    None,
                    seed,
                )?,
                Some((a, b, how)) => scalar_field(
                    base,
                    levels,
                    boundary,
                    &a.features,
                    Some((&b.features, how)),
                    seed,
                )?,
            };
            let (colors, positions) = planet.shade(&f);
            let mut mesh = f.mesh.clone();
            mesh.mesh.set_positions(positions)?;
            Ok(Composed {
                mesh,
                colors: Some(colors),
                scalars: vec![("height".into(), f.value), ("alpha".into(), f.alpha)],
                details: Vec::new(),
                counts: f.counts.clone(),
            })
        }
    }
}
