//! Composing multiscale details (velho-perlin §5): growing a layer of
//! features level by level, with features placed at chosen vertices and local
//! edits of the summed details.
//!
//! **Local detail modification** (§5.2): around a vertex, the details of a
//! band of levels are scaled by 1 + (factor − 1)·w(d/Rₗ) — factor 0 smooths,
//! factors above 1 exaggerate — with d the topological distance (edge hops,
//! breadth-first at each level), Rₗ = radius·2ˡ (the radius is given in
//! base-level edges, and every subdivision doubles the hops), and the cubic
//! drop-off w(x) = 1 − 3x² + 2x³ ([`drop_off`]).
//!
//! Blending two surfaces is [`crate::blend`], the scalar mode and the planet
//! shader [`crate::scalar`], and the evaluation of a whole scene
//! [`crate::evaluate`].

use std::collections::VecDeque;

use asperity_core::{CoreError, NoProgress, Progress};
use rayon::prelude::*;

use crate::catmull_clark::{Boundary, Creased};
use crate::detail::{Feature, Grower, Procedure, Rock, Seeds, drop_off, nearest_vertex};
use crate::multires::{LevelInput, Multires, build};

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

impl Layer {
    /// One layer named "rock" of fractal rock detail over the whole surface
    /// (amplitude 0.02 of the base's size, halving per level): the workload of
    /// the subdivision benchmark, `asperity bench` and the thread-scaling series.
    pub fn rock() -> Self {
        Self {
            name: "rock".into(),
            features: vec![Feature::global(Procedure::Rock(Rock::fractal(0.02, 0.5)))],
            edits: Vec::new(),
        }
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
pub(crate) fn validate_features(features: &[Feature], n_base: usize) -> Result<(), CoreError> {
    for f in features {
        let bad = |reason: String| CoreError::InvalidParameter {
            name: "detail",
            reason: format!("{}: {reason}", f.procedure.name()),
        };
        f.validate().map_err(bad)?;
        if let Seeds::Vertices(v) = &f.seeds
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
