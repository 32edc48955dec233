//! Marching cubes (§6, ref. \[13\]) on a sparse level set.
//!
//! The cubes, their table, the vertex positions, normals and curvatures are
//! those of [`crate::marching_cubes`]; only the cubes that can hold the
//! surface are visited. A brick's cubes (those whose lowest corner lies in
//! it) read its 8³ nodes and one layer of its upper neighbours: a 9³ block,
//! gathered once. Blocks of one sign are skipped — every brick far from the
//! front, with or without storage. The triangles come out in the dense
//! order (by cube, then as the table lists them), layer of bricks after layer
//! of bricks, and the vertices are numbered by their grid edge as in the
//! dense extraction, so the mesh is the dense mesh, to the bit.

use asperity_core::TriMesh;
use rayon::prelude::*;

use super::layout::{BRICK_NODES, NO_SLOT, SIDE};
use super::surface::SparseLevelSet;
use crate::grid::GridSpec;
use crate::marching_cubes::{Cubes, ExtractOptions, ExtractStats, Volume, assemble, cube_key_of};

/// Nodes along each axis of a brick's block of cubes.
const BLOCK: usize = SIDE + 1;

impl Volume for SparseLevelSet {
    fn grid(&self) -> &GridSpec {
        &self.bricks.grid
    }

    #[inline]
    fn at(&self, c: [usize; 3]) -> f32 {
        SparseLevelSet::at(self, c)
    }
}

/// φ on the 9³ nodes from the brick at `b`'s first node (those beyond the
/// grid are left at 0 and never read), x fastest.
fn block(ls: &SparseLevelSet, b: [usize; 3]) -> [f32; BLOCK * BLOCK * BLOCK] {
    let bricks = &ls.bricks;
    let dims = bricks.grid.dims;
    let mut out = [0f32; BLOCK * BLOCK * BLOCK];
    let own = bricks.slot_of(bricks.brick_index(b));
    let background = ls.background(bricks.brick_index(b));
    for z in 0..BLOCK {
        for y in 0..BLOCK {
            for x in 0..BLOCK {
                let c = [b[0] * SIDE + x, b[1] * SIDE + y, b[2] * SIDE + z];
                if c[0] >= dims[0] || c[1] >= dims[1] || c[2] >= dims[2] {
                    continue;
                }
                out[x + BLOCK * (y + BLOCK * z)] = if x < SIDE && y < SIDE && z < SIDE {
                    if own == NO_SLOT {
                        background
                    } else {
                        ls.phi[own as usize * BRICK_NODES + x + SIDE * (y + SIDE * z)]
                    }
                } else {
                    ls.at(c)
                };
            }
        }
    }
    out
}

/// Whether the brick at `b` and its upper neighbours all lack storage and
/// share one background: then its cubes are all of one sign.
fn plainly_uniform(ls: &SparseLevelSet, b: [usize; 3]) -> bool {
    let bricks = &ls.bricks;
    let first = ls.background(bricks.brick_index(b));
    (0..8).all(|o| {
        let n = [b[0] + (o & 1), b[1] + (o >> 1 & 1), b[2] + (o >> 2)];
        if (0..3).any(|a| n[a] >= bricks.bdims[a]) {
            return true;
        }
        let bi = bricks.brick_index(n);
        bricks.slot_of(bi) == NO_SLOT && ls.background(bi) == first
    })
}

/// The triangles of the cubes whose lowest corner lies in the brick at `b`,
/// as (cube's dense index · 16 + its triangle number, vertex keys).
fn brick_triangles(
    cubes: &Cubes<SparseLevelSet>,
    ls: &SparseLevelSet,
    b: [usize; 3],
    out: &mut Vec<(u64, [u64; 3])>,
) {
    if plainly_uniform(ls, b) {
        return;
    }
    let grid = &ls.bricks.grid;
    let v = block(ls, b);
    let span = |a: usize| (grid.dims[a] - 1).saturating_sub(b[a] * SIDE).min(SIDE);
    let (sx, sy, sz) = (span(0), span(1), span(2));
    // One sign on every node the cubes use: nothing here.
    let (mut any, mut all) = (false, true);
    for z in 0..=sz {
        for y in 0..=sy {
            for x in 0..=sx {
                let inside = v[x + BLOCK * (y + BLOCK * z)] < 0.0;
                any |= inside;
                all &= inside;
            }
        }
    }
    if !any || all {
        return;
    }
    let mut tris = Vec::new();
    for z in 0..sz {
        for y in 0..sy {
            for x in 0..sx {
                let corners: [f32; 8] = std::array::from_fn(|c| {
                    v[(x + (c & 1)) + BLOCK * ((y + (c >> 1 & 1)) + BLOCK * (z + (c >> 2)))]
                });
                let key = cube_key_of(cubes.tab, &cubes.faces, corners);
                let case = key & 255;
                if case == 0 || case == 255 {
                    continue;
                }
                let base = grid.index(b[0] * SIDE + x, b[1] * SIDE + y, b[2] * SIDE + z);
                tris.clear();
                cubes.triangles(base, key, &mut tris);
                for (n, t) in tris.iter().enumerate() {
                    out.push(((base as u64) << 4 | n as u64, *t));
                }
            }
        }
    }
}

/// The triangle mesh of {φ = 0} (φ < 0 inside), as [`crate::extract`] makes
/// it from the dense φ.
pub fn sparse_extract(ls: &SparseLevelSet, options: &ExtractOptions) -> (TriMesh, ExtractStats) {
    let cubes = Cubes::new(ls, options.curvature);
    let bricks = &ls.bricks;
    let [bx, by, bz] = bricks.bdims;
    // Layer by layer of bricks (the cubes of eight node planes), each layer's
    // triangles sorted into the dense order: the concatenation is that order.
    let layers: Vec<Vec<[u64; 3]>> = (0..bz)
        .into_par_iter()
        .map(|z| {
            let mut keyed = Vec::new();
            for y in 0..by {
                for x in 0..bx {
                    brick_triangles(&cubes, ls, [x, y, z], &mut keyed);
                }
            }
            keyed.sort_unstable_by_key(|k| k.0);
            keyed.into_iter().map(|k| k.1).collect()
        })
        .collect();
    let keyed = layers.concat();
    drop(layers);
    assemble(&cubes, &keyed, options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::{DistanceMethod, unsigned_distance};
    use crate::evolve::{EvolveParams, evolve, from_tags};
    use crate::grid::Sizing;
    use crate::marching_cubes::{extract, table};
    use crate::sparse::{sparse_distance, sparse_evolve, sparse_initial, sparse_tag};
    use crate::tagging::{TagRule, tag};
    use asperity_core::{MemoryBudget, NoProgress};

    #[test]
    fn no_cube_has_sixteen_triangles() {
        assert!(table().triangles.iter().all(|t| t.len() < 16));
    }

    /// The mesh of the evolved sparse level set equals the dense mesh, bit for
    /// bit: positions, normals, curvature, triangles and their order.
    #[test]
    fn sparse_mesh_equals_the_dense_mesh() {
        let mut pts = Vec::new();
        for a in 0..50 {
            for b in 0..100 {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / 50.0;
                let ph = std::f64::consts::PI * b as f64 / 50.0;
                let r = 2.0 + 0.5 * (4.0 * ph).cos() * (3.0 * th).sin();
                pts.push([r * th.sin() * ph.cos(), r * th.sin() * ph.sin(), r * th.cos()]);
                pts.push([6.0 + 0.7 * th.sin() * ph.cos(), 0.7 * th.sin() * ph.sin(), 0.7 * th.cos()]);
            }
        }
        let grid = GridSpec::around(&pts, Sizing::Resolution(60), |_| 10, &MemoryBudget::unlimited()).unwrap();
        let h = grid.spacing;
        let (eps, gamma) = (3.0 * h, 3.0 * h);
        let cap = eps + gamma + 2.0 * h;
        let params = EvolveParams {
            iterations: 15,
            ..EvolveParams::paper(h)
        };
        let d = unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
        let tags = tag(&d, eps, TagRule::Paper, &NoProgress);
        let mut dense = from_tags(&d, &tags, eps, gamma, &NoProgress);
        evolve(&mut dense, &d, &params, &NoProgress, &mut |_, _| {});
        let (mut sd, _) = sparse_distance(&pts, &grid, cap, &NoProgress);
        let mut st = sparse_tag(&mut sd, eps, TagRule::Paper, &NoProgress);
        let mut ls = sparse_initial(&mut sd, &mut st, eps, gamma, &NoProgress);
        sparse_evolve(&mut ls, &mut sd, &params, &NoProgress, &mut |_, _| {});
        assert_eq!(ls.to_dense(), dense.phi);
        for options in [
            ExtractOptions::default(),
            ExtractOptions {
                curvature: true,
                min_shell_triangles: 500,
            },
        ] {
            let (want, want_stats) = extract(&dense.phi, &grid, &options);
            let (got, got_stats) = sparse_extract(&ls, &options);
            assert!(want.n_faces() > 1000);
            assert_eq!(got_stats, want_stats);
            assert_eq!(got.triangles(), want.triangles());
            assert_eq!(got.positions(), want.positions());
            assert_eq!(got.normals(), want.normals());
            assert_eq!(
                got.scalar("mean_curvature").map(<[f64]>::to_vec),
                want.scalar("mean_curvature").map(<[f64]>::to_vec)
            );
        }
    }
}
