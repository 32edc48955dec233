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

use super::layout::{BRICK_NODES, EMPTY_MASK, Mask, NO_SLOT, SIDE, X_LOW, Y_LOW, shifted};
use super::surface::SparseLevelSet;
use crate::grid::GridSpec;
use crate::marching_cubes::{
    CENTRE, Cubes, ExtractOptions, ExtractStats, Vertices, Volume, cube_key_of,
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

/// Each slot's nodes inside (φ < 0), and its sign over the nodes in the grid.
fn insides(ls: &SparseLevelSet) -> (Vec<Mask>, Vec<Sign>) {
    let bricks = &ls.bricks;
    ls.phi
        .par_chunks(BRICK_NODES)
        .enumerate()
        .map(|(s, phi)| {
            let grid_nodes = bricks.in_grid(bricks.slot_coords(s));
            let mut m = EMPTY_MASK;
            for (l, &v) in phi.iter().enumerate() {
                m[l / 64] |= u64::from(v < 0.0) << (l % 64);
            }
            let (any, all) = (0..SIDE).fold((false, true), |(any, all), z| {
                let inside = m[z] & grid_nodes[z];
                (any || inside != 0, all && inside == grid_nodes[z])
            });
            let sign = match (any, all) {
                (false, _) => Sign::Outside,
                (true, true) => Sign::Inside,
                (true, false) => Sign::Mixed,
            };
            (m, sign)
        })
        .unzip()
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

/// The grid edges cut by {φ = 0} that start at the nodes of the slot's or
/// inactive brick at `b` (a vertex each: key = the node's dense index · 3 +
/// axis), appended to `out` in increasing order; `inside` gives a slot's
/// nodes with φ < 0.
fn cut_edges(ls: &SparseLevelSet, inside: &[Mask], b: [usize; 3], out: &mut Vec<u64>) {
    let bricks = &ls.bricks;
    let grid = &bricks.grid;
    let of_brick = |n: [usize; 3]| -> Mask {
        let bi = bricks.brick_index(n);
        match bricks.slot_of(bi) {
            NO_SLOT if ls.background(bi) < 0.0 => [u64::MAX; SIDE],
            NO_SLOT => EMPTY_MASK,
            s => inside[s as usize],
        }
    };
    let own = of_brick(b);
    // Per axis, the nodes whose upper neighbour along it differs in sign:
    // within the brick by a shift, across its upper face from the neighbour.
    let cut: [Mask; 3] = std::array::from_fn(|a| {
        let moved = shifted(&own, 2 * a + 1);
        let mut n = b;
        n[a] += 1;
        let across = if n[a] < bricks.bdims[a] {
            let theirs = of_brick(n);
            match a {
                0 => theirs.map(|w| (w & X_LOW) << (SIDE - 1)),
                1 => theirs.map(|w| (w & Y_LOW) << (SIDE * (SIDE - 1))),
                _ => {
                    let mut m = EMPTY_MASK;
                    m[SIDE - 1] = theirs[0];
                    m
                }
            }
        } else {
            EMPTY_MASK
        };
        // Nodes whose upper neighbour lies in the grid.
        let reach = bricks.within_upper(b, a);
        std::array::from_fn(|z| (own[z] ^ (moved[z] | across[z])) & reach[z])
    });
    for z in 0..SIDE {
        let mut any = cut[0][z] | cut[1][z] | cut[2][z];
        while any != 0 {
            let l = any.trailing_zeros() as usize;
            any &= any - 1;
            let c = [
                b[0] * SIDE + l % SIDE,
                b[1] * SIDE + l / SIDE,
                b[2] * SIDE + z,
            ];
            let base = grid.index(c[0], c[1], c[2]) as u64;
            for (axis, m) in cut.iter().enumerate() {
                if m[z] >> l & 1 == 1 {
                    out.push(base * 3 + axis as u64);
                }
            }
        }
    }
}

/// The triangles of the cubes whose lowest corner lies in the brick at `b`,
/// as (cube's dense index · 16 + its triangle number, vertex keys).
fn cube_triangles(
    cubes: &Cubes<SparseLevelSet>,
    ls: &SparseLevelSet,
    b: [usize; 3],
    out: &mut Vec<(u64, [u64; 3])>,
) {
    let grid = &ls.bricks.grid;
    let v = block(ls, b);
    let at = |x: usize, y: usize, z: usize| v[x + BLOCK * (y + BLOCK * z)];
    let cells = |a: usize| (grid.dims[a] - 1).saturating_sub(b[a] * SIDE).min(SIDE);
    let mut tris = Vec::new();
    for z in 0..cells(2) {
        for y in 0..cells(1) {
            for x in 0..cells(0) {
                let corners: [f32; 8] =
                    std::array::from_fn(|k| at(x + (k & 1), y + (k >> 1 & 1), z + (k >> 2)));
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

/// The sorted edge keys of one layer of bricks, with the start of each row
/// of nodes among them, to find a key in a few steps.
struct LayerKeys {
    keys: Vec<u64>,
    first_row: usize,
    starts: Vec<u32>,
}

impl LayerKeys {
    fn new(keys: Vec<u64>, grid: &GridSpec, z: usize) -> Self {
        let [nx, ny, nz] = grid.dims;
        let (k0, k1) = (z * SIDE, ((z + 1) * SIDE).min(nz));
        let first_row = k0 * ny;
        let starts = (first_row..=k1 * ny)
            .map(|row| keys.partition_point(|&k| k < (row * nx) as u64 * 3) as u32)
            .collect();
        Self {
            keys,
            first_row,
            starts,
        }
    }

    /// The place of `key` (an edge key of this layer's nodes).
    fn find(&self, key: u64, nx: usize) -> Option<usize> {
        let row = (key / 3) as usize / nx;
        let r = row.checked_sub(self.first_row)?;
        let (lo, hi) = (
            *self.starts.get(r)? as usize,
            *self.starts.get(r + 1)? as usize,
        );
        self.keys[lo..hi].binary_search(&key).ok().map(|at| lo + at)
    }
}

/// A triangle corner before the layers' offsets are known: its layer's own
/// edge keys, the next layer's (edges starting on the plane above the
/// layer's cubes), or the layer's loop centres; and the place among them.
const OWN: u32 = 0;
const NEXT: u32 = 1 << 30;
const CENTRES: u32 = 2 << 30;
const PLACE: u32 = (1 << 30) - 1;

/// The triangle mesh of {φ = 0} (φ < 0 inside), as [`crate::extract`] makes
/// it from the dense φ.
pub fn sparse_extract(ls: &SparseLevelSet, options: &ExtractOptions) -> (TriMesh, ExtractStats) {
    let cubes = Cubes::new(ls);
    let (inside, signs) = insides(ls);
    let grid = ls.bricks.grid;
    let [bx, by, bz] = ls.bricks.bdims;
    let cut = |b: [usize; 3]| may_cut(ls, &signs, b);
    // Pass 1, layer by layer of bricks (eight node planes): the vertices on
    // grid edges, which are the cut edges starting at the layer's nodes.
    // One task a layer: the layers' work differs tenfold (a deposit's bottom
    // layers hold most of its surface), and a chunk of layers left last
    // would run on one core.
    let edges: Vec<LayerKeys> = (0..bz)
        .into_par_iter()
        .with_max_len(1)
        .map(|z| {
            let mut keys = Vec::new();
            for y in 0..by {
                for x in 0..bx {
                    if cut([x, y, z]) {
                        cut_edges(ls, &inside, [x, y, z], &mut keys);
                    }
                }
            }
            keys.sort_unstable();
            LayerKeys::new(keys, &grid, z)
        })
        .collect();
    // Pass 2: each layer's triangles in the dense order (by cube, then as
    // the table lists them), their corners placed among the layers' keys; the
    // loop centres, whose keys follow the cubes' order.
    let layers: Vec<Layer> = (0..bz)
        .into_par_iter()
        .with_max_len(1)
        .map(|z| {
            // A closed surface has about two triangles per vertex: sized at
            // once, the list rarely moves (a move faults fresh pages in).
            let mut keyed = Vec::with_capacity(edges[z].keys.len() * 9 / 4 + 64);
            for y in 0..by {
                for x in 0..bx {
                    if cut([x, y, z]) {
                        cube_triangles(&cubes, ls, [x, y, z], &mut keyed);
                    }
                }
            }
            keyed.sort_unstable_by_key(|k| k.0);
            let mut centres: Vec<u64> = keyed
                .iter()
                .flat_map(|k| k.1)
                .filter(|&k| k & CENTRE != 0)
                .collect();
            centres.sort_unstable();
            centres.dedup();
            let nx = grid.dims[0];
            let place = |k: u64| -> u32 {
                if k & CENTRE != 0 {
                    let at = centres.binary_search(&k).expect("a loop centre");
                    return CENTRES | at as u32;
                }
                match edges[z].find(k, nx) {
                    Some(at) => OWN | at as u32,
                    None => {
                        let at = edges[z + 1].find(k, nx).expect("a vertex key");
                        NEXT | at as u32
                    }
                }
            };
            let triangles = keyed.iter().map(|k| k.1.map(place)).collect();
            (triangles, centres)
        })
        .collect();
    drop((signs, inside));
    assemble_layers(&cubes, edges, layers, options)
}

/// A layer's triangles (corners placed as [`OWN`], [`NEXT`] or [`CENTRES`])
/// and its loop centres' keys.
type Layer = (Vec<[u32; 3]>, Vec<u64>);

/// The mesh of the layers: the vertices are the edge keys layer after layer,
/// then the loop centres; the triangles' corners become indices into them.
fn assemble_layers(
    cubes: &Cubes<SparseLevelSet>,
    edges: Vec<LayerKeys>,
    layers: Vec<Layer>,
    options: &ExtractOptions,
) -> (TriMesh, ExtractStats) {
    let bz = edges.len();
    let edge_count: usize = edges.iter().map(|l| l.keys.len()).sum();
    let mut edge_start = Vec::with_capacity(bz + 1);
    let mut centre_start = Vec::with_capacity(bz);
    let (mut e, mut c) = (0, edge_count);
    for (layer, (_, centres)) in edges.iter().zip(&layers) {
        edge_start.push(e);
        centre_start.push(c);
        e += layer.keys.len();
        c += centres.len();
    }
    edge_start.push(e);
    let count: usize = layers.iter().map(|l| l.0.len()).sum();
    let mut triangles = Vec::with_capacity(count);
    let mut centres = Vec::with_capacity(bz);
    for (z, (tris, layer_centres)) in layers.into_iter().enumerate() {
        centres.push(layer_centres);
        triangles.extend(tris.into_iter().map(|t| {
            t.map(|p| {
                let base = match p & !PLACE {
                    OWN => edge_start[z],
                    NEXT => edge_start[z + 1],
                    _ => centre_start[z],
                };
                (base + (p & PLACE) as usize) as u32
            })
        }));
    }
    // The vertices from the layers' keys, each layer's freed once read (the
    // keys of the whole mesh are never held beside its vertices).
    let mut vertices = Vertices::with_capacity(c, options.curvature);
    for layer in edges {
        vertices.extend(cubes, &layer.keys);
    }
    for layer in centres {
        vertices.extend(cubes, &layer);
    }
    vertices.into_mesh(triangles, options)
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
