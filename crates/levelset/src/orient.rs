//! Consistent normals for an unorganised point set: each point's covariance
//! normal (the least eigenvector of its k nearest neighbours' covariance),
//! signs made to agree along a minimum spanning tree of the k-nearest-
//! neighbour graph weighted by 1 − |nᵢ·nⱼ|, so that the orientation travels
//! first between neighbours whose planes agree (Hoppe, DeRose, Duchamp,
//! McDonald & Stuetzle 1992, "Surface reconstruction from unorganized
//! points", SIGGRAPH, §3.3). Each connected part of the graph is turned so
//! that its normals point up in sum (+z, or a given direction): the two sides
//! of an open sheet cannot be told apart otherwise.
//!
//! Written here (no crate gives Hoppe's orientation over a k-d tree); the MST
//! is Prim's with a binary heap, ties broken by index, so the result does not
//! depend on the thread count.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::cloud::{Tree, nearest, pca_normal};

/// The neighbours each point's normal is fitted to and its graph edges.
pub const ORIENT_NEIGHBOURS: usize = 12;

/// Unit normals of `points`, consistently oriented within each connected
/// part of their k-nearest-neighbour graph, each part pointing along `up`
/// in sum. A point whose neighbourhood gives no normal gets `up`.
pub fn oriented_normals(points: &[[f64; 3]], tree: &Tree, up: [f64; 3]) -> Vec<[f64; 3]> {
    let k = ORIENT_NEIGHBOURS.min(points.len());
    let (mut normals, hoods): (Vec<[f64; 3]>, Vec<Vec<u32>>) = points
        .par_iter()
        .map(|p| {
            let hood: Vec<u32> = nearest(tree, p, k + 1).into_iter().map(|n| n.1).collect();
            let n = pca_normal(tree, points, p, k).unwrap_or(up);
            (n, hood)
        })
        .unzip();
    let mut done = vec![false; points.len()];
    let mut heap = BinaryHeap::new();
    for seed in 0..points.len() {
        if done[seed] {
            continue;
        }
        let mut part = vec![seed as u32];
        done[seed] = true;
        push_edges(&mut heap, seed as u32, &hoods, &normals, &done);
        while let Some(Reverse((_, from, to))) = heap.pop() {
            if done[to as usize] {
                continue;
            }
            done[to as usize] = true;
            if dot(normals[from as usize], normals[to as usize]) < 0.0 {
                normals[to as usize] = normals[to as usize].map(|c| -c);
            }
            part.push(to);
            push_edges(&mut heap, to, &hoods, &normals, &done);
        }
        let sum: f64 = part.iter().map(|&i| dot(normals[i as usize], up)).sum();
        if sum < 0.0 {
            for &i in &part {
                normals[i as usize] = normals[i as usize].map(|c| -c);
            }
        }
    }
    normals
}

/// The graph edges from `i` to its neighbours not yet reached, by weight
/// 1 − |nᵢ·nⱼ| (as an order-preserving integer: the heap needs `Ord`).
fn push_edges(
    heap: &mut BinaryHeap<Reverse<(u64, u32, u32)>>,
    i: u32,
    hoods: &[Vec<u32>],
    normals: &[[f64; 3]],
    done: &[bool],
) {
    for &j in &hoods[i as usize] {
        if !done[j as usize] {
            let w = 1.0 - dot(normals[i as usize], normals[j as usize]).abs();
            heap.push(Reverse((w.max(0.0).to_bits(), i, j)));
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::tree;
    use rand::{Rng, SeedableRng};

    /// A wavy sheet z = 0.2 sin(3x) cos(2y) sampled at random, and a sheet
    /// folded on edge (two half-planes at right angles, like a box's corner):
    /// every normal agrees with the analytic one's orientation, pointing up.
    #[test]
    fn a_sheet_is_oriented_one_way() {
        let seed: u64 = rand::random();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let pts: Vec<[f64; 3]> = (0..5000)
            .map(|_| {
                let (x, y) = (
                    rng.random::<f64>() * 2.0 - 1.0,
                    rng.random::<f64>() * 2.0 - 1.0,
                );
                [x, y, 0.2 * (3.0 * x).sin() * (2.0 * y).cos()]
            })
            .collect();
        let n = oriented_normals(&pts, &tree(&pts), [0.0, 0.0, 1.0]);
        for (p, n) in pts.iter().zip(&n) {
            let (x, y) = (p[0], p[1]);
            let g = [
                -0.6 * (3.0 * x).cos() * (2.0 * y).cos(),
                0.4 * (3.0 * x).sin() * (2.0 * y).sin(),
                1.0,
            ];
            assert!(dot(*n, g) > 0.0, "seed {seed}: at {p:?} {n:?}");
        }
        // Folded: z = 0 for x < 0, x = 0 for z > 0 (a roof seen from +x, +z).
        let pts: Vec<[f64; 3]> = (0..5000)
            .map(|_| {
                let (a, y) = (rng.random::<f64>(), rng.random::<f64>() * 2.0 - 1.0);
                if rng.random::<bool>() {
                    [-a, y, 0.0]
                } else {
                    [0.0, y, a]
                }
            })
            .collect();
        let n = oriented_normals(&pts, &tree(&pts), [0.3, 0.0, 1.0]);
        for (p, n) in pts.iter().zip(&n) {
            // Away from the fold, the half-planes' normals: +z and −x... or
            // +x, the side the +z half's orientation carries around the fold.
            if p[0] < -0.1 {
                assert!(n[2] > 0.9, "seed {seed}: at {p:?} {n:?}");
            } else if p[2] > 0.1 {
                assert!(n[0] < -0.9, "seed {seed}: at {p:?} {n:?}");
            }
        }
    }
}
