//! The scalar mode and its post-shader (velho-perlin §6.2): the same
//! multiresolution machinery carries a scalar per vertex — subdivided like the
//! positions, with the procedures' normal components as scalar details —
//! blended as in [`crate::blend`], then shaded and used as relief with a
//! sea-level clamp ([`Planet`], the paper's mushroom planet).

use asperity_core::CoreError;
use asperity_core::mesh_check::{SurfaceNeeds, check_polygons};
use rayon::prelude::*;

use crate::blend::{AlphaSource, Blend};
use crate::catmull_clark::{Boundary, Creased, Topology, refine_with};
use crate::compose::validate_features;
use crate::detail::{Feature, Grower, Procedure};
use crate::multires::{LevelInput, frame_at};

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
/// As [`crate::compose::grow`] and [`crate::blend::blend`].
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
    // The one surface check every command makes (degenerate faces, manifold
    // edges and vertices, orientation), before the topology is built.
    check_polygons(&base.mesh, SurfaceNeeds::default())?;
    let mut topo = Topology::new(base)?;
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
