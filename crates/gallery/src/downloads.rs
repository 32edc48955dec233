//! The gallery's download copies of large meshes: a mesh above the demo's
//! triangle budget is written at a resolution that still shows the method,
//! and its card says so and how to get the whole one (`asperity demo
//! --full-meshes`, or the card's CLI line).
//!
//! The copy is a subset of the mesh's own vertices, each with all its data
//! (position, normal, colour, texture coordinates, named scalars), so a file
//! reduced here reads like the whole one in Blender, MeshLab or numpy:
//! 1. vertices equal in every datum are merged (a cell mesh repeats each
//!    corner once per cell of the same colour);
//! 2. if that is not enough, meshoptimizer's edge collapse (the `meshopt`
//!    crate, bindings to the reference implementation; the simplifier is not
//!    the product here) removes vertices, keeping open borders where they are
//!    and the seams where colours or scalars jump, with the least error (0.2,
//!    1 or 5 % of the mesh's size) that meets the budget.
//!
//! A mesh made of seams alone (every cell its own colour) cannot be reduced
//! this way; it is written with what the merge left, and the card gives the
//! triangle count as written.

use std::collections::HashMap;

use asperity_engine::Result;
use asperity_engine::core::TriMesh;
use asperity_engine::error::invalid;
use meshopt::{SimplifyOptions, VertexDataAdapter};

/// Download budgets in triangles: (quick demo, full demo).
pub const TRIANGLE_BUDGETS: (usize, usize) = (6_144, 131_072);

/// How far simplification may move the surface, relative to the mesh's size:
/// the first that meets the budget.
const SIMPLIFY_ERRORS: [f32; 3] = [0.002, 0.01, 0.05];

/// A copy of `m` with about `budget` triangles at most (more when seams stop
/// the simplifier), made of `m`'s own vertices; `m` itself when it is within
/// the budget.
///
/// # Errors
/// None in practice: the copy's indices come from `m`.
pub fn reduced(m: &TriMesh, budget: usize) -> Result<TriMesh> {
    if m.n_faces() <= budget {
        return Ok(m.clone());
    }
    let (origin, mut indices) = merged(m);
    if indices.len() / 3 > budget {
        // positions as meshoptimizer reads them: three native-order f32s
        let bytes: Vec<u8> = origin
            .iter()
            .flat_map(|&o| m.positions()[o as usize])
            .flat_map(|c| (c as f32).to_ne_bytes())
            .collect();
        let adapter = VertexDataAdapter::new(&bytes, 12, 0)
            .map_err(|e| invalid(format!("download copy: {e}")))?;
        let whole = indices.clone();
        for error in SIMPLIFY_ERRORS {
            indices = meshopt::simplify(
                &whole,
                &adapter,
                budget * 3,
                error,
                // open borders stay: a cell mesh's colour seams are not always
                // matched edge for edge, and unmatched ones would be collapsed
                // from each side apart and open cracks
                SimplifyOptions::LockBorder,
                None,
            );
            if indices.len() / 3 <= budget {
                break;
            }
        }
    }
    // the vertices still used, in their first use's order
    let mut new_index = vec![u32::MAX; origin.len()];
    let mut kept = Vec::new();
    let triangles = indices
        .chunks_exact(3)
        .map(|t| {
            [0, 1, 2].map(|k| {
                let v = t[k] as usize;
                if new_index[v] == u32::MAX {
                    new_index[v] = kept.len() as u32;
                    kept.push(origin[v]);
                }
                new_index[v]
            })
        })
        .collect();
    Ok(m.with_vertices_from(&kept, triangles)?)
}

/// The card's fact for `file`, written with `kept` of its `whole` triangles;
/// `with_cli` when the card has a CLI line that makes the whole mesh.
pub fn fact(file: &str, kept: usize, whole: usize, with_cli: bool) -> (String, String) {
    let how = match with_cli {
        true => "the CLI line or asperity demo --full-meshes",
        false => "asperity demo --full-meshes",
    };
    crate::fact(
        "download",
        format!(
            "{file} reduced to {kept} of {whole} triangles for the gallery; {how} writes it whole"
        ),
    )
}

/// Vertices equal in every datum merged: (each merged vertex's first
/// original, the triangles over merged vertices without degenerate ones).
fn merged(m: &TriMesh) -> (Vec<u32>, Vec<u32>) {
    let key = |i: usize| -> Vec<u64> {
        let mut k: Vec<u64> = m.positions()[i].iter().map(|c| c.to_bits()).collect();
        if let Some(n) = m.normals() {
            k.extend(n[i].iter().map(|c| c.to_bits()));
        }
        if let Some(c) = m.colors() {
            k.push(u64::from(u32::from_le_bytes(c[i])));
        }
        if let Some(uv) = m.uvs() {
            k.extend(uv[i].iter().map(|c| c.to_bits()));
        }
        k.extend(m.scalars().iter().map(|a| a.values[i].to_bits()));
        k
    };
    let mut first: HashMap<Vec<u64>, u32> = HashMap::new();
    let mut origin = Vec::new();
    let remap: Vec<u32> = (0..m.n_vertices())
        .map(|i| {
            *first.entry(key(i)).or_insert_with(|| {
                origin.push(i as u32);
                origin.len() as u32 - 1
            })
        })
        .collect();
    let indices = m
        .triangles()
        .iter()
        .map(|t| t.map(|v| remap[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .flatten()
        .collect();
    (origin, indices)
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_engine::core::{Diagonal, HeightField};

    /// A 101 × 101 wavy height field as a mesh with a scalar (20,000 triangles).
    fn wavy() -> TriMesh {
        let n = 101;
        let z: Vec<f64> = (0..n * n)
            .map(|i| ((i % n) as f64 * 0.2).sin() * ((i / n) as f64 * 0.15).cos() * 3.0)
            .collect();
        let h = HeightField::from_vec([n, n], z.clone()).unwrap();
        h.to_trimesh(Diagonal::Forward)
            .unwrap()
            .with_computed_normals()
            .with_scalar("height", z)
            .unwrap()
    }

    #[test]
    fn a_mesh_within_the_budget_is_kept_whole() {
        let m = wavy();
        let r = reduced(&m, m.n_faces()).unwrap();
        assert_eq!(r.positions(), m.positions());
        assert_eq!(r.triangles(), m.triangles());
    }

    #[test]
    fn a_large_mesh_meets_the_budget_with_its_own_vertices_and_data() {
        let m = wavy();
        let r = reduced(&m, 4_000).unwrap();
        assert!(
            (2_000..=4_000).contains(&r.n_faces()),
            "{} triangles",
            r.n_faces()
        );
        // every vertex is one of the mesh's, with its height and normal
        let index: HashMap<[u64; 3], usize> = m
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| (p.map(f64::to_bits), i))
            .collect();
        for (v, p) in r.positions().iter().enumerate() {
            let i = index[&p.map(f64::to_bits)];
            assert_eq!(
                r.scalar("height").unwrap()[v],
                m.scalar("height").unwrap()[i]
            );
            assert_eq!(r.normals().unwrap()[v], m.normals().unwrap()[i]);
        }
        // the same open sheet: one piece, one boundary, about the same area
        assert_eq!(r.n_components(), 1);
        assert_eq!(r.boundary_loops().len(), 1);
        assert!(
            (r.area() / m.area() - 1.0).abs() < 0.01,
            "{} / {}",
            r.area(),
            m.area()
        );
    }

    /// Two halves of the wavy sheet, each with its own vertices and colour,
    /// meeting along x = 50 (as a cell mesh's base triangles meet): the right
    /// one's samples `step` apart.
    fn two_patches(step: usize) -> TriMesh {
        let z = |x: usize, y: usize| (x as f64 * 0.2).sin() * (y as f64 * 0.15).cos() * 3.0;
        let patch = |first: usize, step: usize| {
            let n = 100 / step + 1;
            let m = 50 / step + 1;
            let data = (0..n)
                .flat_map(|j| (0..m).map(move |i| z(first + i * step, j * step)))
                .collect();
            HeightField::from_vec([m, n], data)
                .unwrap()
                .with_spacing([step as f64; 2])
                .unwrap()
                .with_origin([first as f64, 0.0])
                .unwrap()
                .to_trimesh(Diagonal::Forward)
                .unwrap()
        };
        let (left, right) = (patch(0, 1), patch(50, step));
        TriMesh::merge_colored(&[(&left, RED), (&right, BLUE)]).unwrap()
    }

    const RED: [u8; 4] = [200, 0, 0, 255];
    const BLUE: [u8; 4] = [0, 0, 200, 255];

    /// The y of the vertices of colour `color` on x = 50, sorted.
    fn on_seam(m: &TriMesh, color: [u8; 4]) -> Vec<f64> {
        let mut ys: Vec<f64> = (0..m.n_vertices())
            .filter(|&v| m.colors().unwrap()[v] == color && m.positions()[v][0] == 50.0)
            .map(|v| m.positions()[v][1])
            .collect();
        ys.sort_by(f64::total_cmp);
        ys
    }

    #[test]
    fn patches_meeting_vertex_for_vertex_are_reduced_alike_on_both_sides() {
        let r = reduced(&two_patches(1), 4_000).unwrap();
        assert!(r.n_faces() <= 4_000, "{} triangles", r.n_faces());
        let (left, right) = (on_seam(&r, RED), on_seam(&r, BLUE));
        assert!(left.len() < 101, "the seam is simplified too");
        assert_eq!(left, right, "no crack: both sides keep the same vertices");
    }

    #[test]
    fn patches_meeting_at_t_junctions_keep_their_border_whole() {
        // the right patch has every other vertex of the left's border: the
        // border is not a matched seam, so each side would collapse on its own
        let r = reduced(&two_patches(2), 4_000).unwrap();
        assert!(r.n_faces() <= 4_000, "{} triangles", r.n_faces());
        assert_eq!(on_seam(&r, RED).len(), 101);
        assert_eq!(on_seam(&r, BLUE).len(), 51);
    }

    #[test]
    fn merging_joins_corners_repeated_per_cell_and_keeps_colour_seams() {
        // two triangles of one colour and one of another, each with its own corners
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let positions = vec![p[0], p[1], p[2], p[1], p[3], p[2], p[1], p[3], p[2]];
        let triangles = vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]];
        let colors = [[9, 9, 9, 255]; 6]
            .into_iter()
            .chain([[200, 0, 0, 255]; 3])
            .collect();
        let m = TriMesh::new(positions, triangles)
            .unwrap()
            .with_colors(colors)
            .unwrap();
        let (origin, indices) = merged(&m);
        assert_eq!(
            origin,
            [0, 1, 2, 4, 6, 7, 8],
            "grey corners shared, red kept"
        );
        assert_eq!(indices, [0, 1, 2, 1, 3, 2, 4, 5, 6]);
    }
}
