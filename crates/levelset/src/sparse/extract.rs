//! Marching cubes (§6, ref. \[13\]) on a sparse level set.
//!
//! The cubes, their table, the vertex positions, normals and curvatures are
//! those of [`crate::marching_cubes`]; only the cubes that can hold the
//! surface are visited. A brick's cubes (those whose lowest corner lies in
//! it) read its 8³ nodes and one layer of its upper neighbours: a 9³ block.
//! Each brick's sign is summarised first (all outside, all inside, or
//! mixed; bricks without storage by their tag), and a brick whose block
//! lies within bricks of one uniform sign is skipped without reading it —
//! every brick far from the front. A visited brick gives its cubes'
//! triangles and the vertices it owns: the cut grid edges that start at its
//! nodes, and the centres of its cubes' fanned loops. Layer after layer of
//! bricks, the triangles come out in the dense order (by cube, then as the
//! table lists them) and the vertices in the order of their keys, so the
//! mesh is the dense extraction's, to the bit.

use asperity_core::TriMesh;
use rayon::prelude::*;

use super::layout::{BRICK_NODES, NO_SLOT, SIDE};
use super::surface::SparseLevelSet;
use crate::grid::GridSpec;
use crate::marching_cubes::{
    CENTRE, Cubes, ExtractOptions, ExtractStats, Volume, assemble, cube_key_of,
};

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

/// A brick's sign: every node outside (φ ≥ 0), every node inside, or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sign {
    Outside,
    Inside,
    Mixed,
}

/// The sign of each slot's nodes in the grid.
fn signs(ls: &SparseLevelSet) -> Vec<Sign> {
    let bricks = &ls.bricks;
    ls.phi
        .par_chunks(BRICK_NODES)
        .enumerate()
        .map(|(s, phi)| {
            let inside = bricks.in_grid(bricks.slot_coords(s));
            let (mut any, mut all) = (false, true);
            for (l, &v) in phi.iter().enumerate() {
                if inside[l / 64] >> (l % 64) & 1 == 1 {
                    any |= v < 0.0;
                    all &= v < 0.0;
                }
            }
            match (any, all) {
                (false, _) => Sign::Outside,
                (true, true) => Sign::Inside,
                (true, false) => Sign::Mixed,
            }
        })
        .collect()
}

/// The sign of brick `n`: its slot's, or its tag's without storage.
fn sign_of(ls: &SparseLevelSet, signs: &[Sign], n: [usize; 3]) -> Sign {
    let bi = ls.bricks.brick_index(n);
    match ls.bricks.slot_of(bi) {
        NO_SLOT if ls.background(bi) < 0.0 => Sign::Inside,
        NO_SLOT => Sign::Outside,
        s => signs[s as usize],
    }
}

/// Whether the block of the brick at `b` (it and its upper neighbours) can
/// hold the surface.
fn may_cut(ls: &SparseLevelSet, signs: &[Sign], b: [usize; 3]) -> bool {
    let bdims = ls.bricks.bdims;
    let first = sign_of(ls, signs, b);
    first == Sign::Mixed
        || (1..8).any(|o| {
            let n = [b[0] + (o & 1), b[1] + (o >> 1 & 1), b[2] + (o >> 2)];
            (0..3).all(|a| n[a] < bdims[a]) && sign_of(ls, signs, n) != first
        })
}

/// φ on the 9³ nodes from the brick at `b`'s first node, x fastest (nodes
/// beyond the grid are left at 0 and never read).
fn block(ls: &SparseLevelSet, b: [usize; 3]) -> [f32; BLOCK * BLOCK * BLOCK] {
    let bricks = &ls.bricks;
    let dims = bricks.grid.dims;
    // The eight bricks the block reads: their slots, or their backgrounds.
    let sources: [(u32, f32); 8] = std::array::from_fn(|o| {
        let n = [b[0] + (o & 1), b[1] + (o >> 1 & 1), b[2] + (o >> 2)];
        if (0..3).any(|a| n[a] >= bricks.bdims[a]) {
            return (NO_SLOT, 0.0);
        }
        let bi = bricks.brick_index(n);
        (bricks.slot_of(bi), ls.background(bi))
    });
    let mut out = [0f32; BLOCK * BLOCK * BLOCK];
    let span = |a: usize| (dims[a] - b[a] * SIDE).min(BLOCK);
    let (sx, sy, sz) = (span(0), span(1), span(2));
    for z in 0..sz {
        for y in 0..sy {
            for x in 0..sx {
                let o = usize::from(x == SIDE)
                    | usize::from(y == SIDE) << 1
                    | usize::from(z == SIDE) << 2;
                let (slot, background) = sources[o];
                out[x + BLOCK * (y + BLOCK * z)] = if slot == NO_SLOT {
                    background
                } else {
                    ls.phi[slot as usize * BRICK_NODES
                        + x % SIDE
                        + SIDE * (y % SIDE + SIDE * (z % SIDE))]
                };
            }
        }
    }
    out
}

/// What a layer of bricks gives: triangles keyed by (cube's dense index · 16
/// + its triangle number), and the vertex keys its bricks own.
#[derive(Default)]
struct Layer {
    triangles: Vec<(u64, [u64; 3])>,
    vertices: Vec<u64>,
}

/// The triangles and vertices of the cubes whose lowest corner lies in the
/// brick at `b`.
fn brick(cubes: &Cubes<SparseLevelSet>, ls: &SparseLevelSet, b: [usize; 3], out: &mut Layer) {
    let grid = &ls.bricks.grid;
    let v = block(ls, b);
    let at = |x: usize, y: usize, z: usize| v[x + BLOCK * (y + BLOCK * z)];
    // Nodes in the grid, and cubes (their lowest corners), per axis.
    let nodes = |a: usize| (grid.dims[a] - b[a] * SIDE).min(SIDE);
    let cells = |a: usize| (grid.dims[a] - 1).saturating_sub(b[a] * SIDE).min(SIDE);
    let mut tris = Vec::new();
    for z in 0..nodes(2) {
        for y in 0..nodes(1) {
            for x in 0..nodes(0) {
                let c = [b[0] * SIDE + x, b[1] * SIDE + y, b[2] * SIDE + z];
                let base = grid.index(c[0], c[1], c[2]);
                // The cut grid edges starting here.
                let inside = at(x, y, z) < 0.0;
                let ends = [at(x + 1, y, z), at(x, y + 1, z), at(x, y, z + 1)];
                for (axis, &end) in ends.iter().enumerate() {
                    if c[axis] + 1 < grid.dims[axis] && (end < 0.0) != inside {
                        out.vertices.push(base as u64 * 3 + axis as u64);
                    }
                }
                if x >= cells(0) || y >= cells(1) || z >= cells(2) {
                    continue;
                }
                let corners: [f32; 8] =
                    std::array::from_fn(|k| at(x + (k & 1), y + (k >> 1 & 1), z + (k >> 2)));
                let key = cube_key_of(cubes.tab, &cubes.faces, corners);
                let case = key & 255;
                if case == 0 || case == 255 {
                    continue;
                }
                tris.clear();
                cubes.triangles(base, key, &mut tris);
                for (n, t) in tris.iter().enumerate() {
                    out.triangles.push(((base as u64) << 4 | n as u64, *t));
                }
                for l in 0..cubes.tab.centres[key].len() {
                    out.vertices.push(CENTRE | (base as u64) << 2 | l as u64);
                }
            }
        }
    }
}

/// The triangle mesh of {φ = 0} (φ < 0 inside), as [`crate::extract`] makes
/// it from the dense φ.
pub fn sparse_extract(ls: &SparseLevelSet, options: &ExtractOptions) -> (TriMesh, ExtractStats) {
    let cubes = Cubes::new(ls);
    let signs = signs(ls);
    let [bx, by, bz] = ls.bricks.bdims;
    // Layer by layer of bricks (the cubes of eight node planes): each layer's
    // triangles sorted into the dense order, and its vertex keys (those of
    // the layer's nodes, contiguous in key order) sorted.
    let mut layers: Vec<Layer> = (0..bz)
        .into_par_iter()
        .map(|z| {
            let mut layer = Layer::default();
            for y in 0..by {
                for x in 0..bx {
                    if may_cut(ls, &signs, [x, y, z]) {
                        brick(&cubes, ls, [x, y, z], &mut layer);
                    }
                }
            }
            layer.triangles.sort_unstable_by_key(|k| k.0);
            layer.vertices.sort_unstable();
            layer
        })
        .collect();
    drop(signs);
    // The layers' parts moved into one list each, freed as they go.
    let total = |f: fn(&Layer) -> usize| layers.iter().map(f).sum::<usize>();
    let mut keyed = Vec::with_capacity(total(|l| l.triangles.len()));
    let mut edge_keys = Vec::with_capacity(total(|l| l.vertices.len()));
    let mut centres = Vec::new();
    for layer in &mut layers {
        keyed.extend(
            std::mem::take(&mut layer.triangles)
                .into_iter()
                .map(|k| k.1),
        );
        let vertices = std::mem::take(&mut layer.vertices);
        let split = vertices.partition_point(|&k| k & CENTRE == 0);
        edge_keys.extend_from_slice(&vertices[..split]);
        centres.extend_from_slice(&vertices[split..]);
    }
    drop(layers);
    // Edge keys, then loop centres (the order of their keys).
    centres.sort_unstable();
    edge_keys.append(&mut centres);
    assemble(&cubes, keyed, Some(edge_keys), options)
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
                pts.push([
                    r * th.sin() * ph.cos(),
                    r * th.sin() * ph.sin(),
                    r * th.cos(),
                ]);
                pts.push([
                    6.0 + 0.7 * th.sin() * ph.cos(),
                    0.7 * th.sin() * ph.sin(),
                    0.7 * th.cos(),
                ]);
            }
        }
        let grid = GridSpec::around(
            &pts,
            Sizing::Resolution(60),
            |_| 10,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
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
