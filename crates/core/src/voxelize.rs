//! Solid voxelisation of a closed triangle mesh by parity ray casting.
//!
//! Cell (i, j, k) of the result has its centre at `origin + (i, j, k)·spacing`
//! and is inside when a ray from that centre toward +z crosses the surface an
//! odd number of times. Each column (i, j) is intersected once with every
//! triangle whose xy-projection covers it, the crossing heights are sorted and
//! cells between entry/exit pairs are filled: O(triangles · covered columns +
//! cells). Column centres are nudged by an irrational sub-cell offset
//! (10⁻⁷ of a cell) so that a column through a shared edge or vertex — where
//! parity would double count — is practically impossible.
//!
//! Used by the growth simulators (substrates grown on any closed object, the
//! future-work item of kim-machiraju-thompson §7) and by the surface tools.

use crate::{CoreError, MemoryBudget, TriMesh};

/// A solid voxelisation.
#[derive(Clone, Debug, PartialEq)]
pub struct Voxelization {
    /// Cells per axis.
    pub dims: [usize; 3],
    /// Centre of cell (0, 0, 0).
    pub origin: [f64; 3],
    /// Cell size.
    pub spacing: f64,
    /// Inside flags, x fastest.
    pub inside: Vec<bool>,
}

impl Voxelization {
    /// Index of cell (i, j, k).
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The inside cells as integer coordinates.
    pub fn cells(&self) -> Vec<[i32; 3]> {
        let [nx, ny, _] = self.dims;
        self.inside
            .iter()
            .enumerate()
            .filter(|(_, v)| **v)
            .map(|(n, _)| {
                [
                    (n % nx) as i32,
                    ((n / nx) % ny) as i32,
                    (n / (nx * ny)) as i32,
                ]
            })
            .collect()
    }
}

/// Voxelises the solid bounded by `mesh` with `resolution` cells along the
/// bounding box's longest axis and `padding` empty cells on every side.
///
/// # Errors
/// [`CoreError::InvalidParameter`] when the mesh is empty or not watertight (parity
/// needs a closed surface), or the resolution is zero; the memory budget.
pub fn voxelize(
    mesh: &TriMesh,
    resolution: usize,
    padding: usize,
    budget: &MemoryBudget,
) -> crate::Result<Voxelization> {
    if resolution == 0 {
        return Err(CoreError::InvalidParameter {
            name: "voxel resolution",
            reason: "must be at least 1".into(),
        });
    }
    let bounds = mesh.bounds().ok_or_else(|| CoreError::InvalidParameter {
        name: "mesh",
        reason: "cannot voxelise an empty mesh".into(),
    })?;
    crate::mesh_check::check_triangles(mesh, crate::mesh_check::SurfaceNeeds { closed: true })?;
    let ext = bounds.extent();
    let longest = ext.iter().copied().fold(0.0, f64::max);
    if longest <= 0.0 {
        return Err(CoreError::InvalidParameter {
            name: "mesh",
            reason: "it is flat, so it bounds no solid".into(),
        });
    }
    let spacing = longest / resolution as f64;
    let dims = [0, 1, 2].map(|a| (ext[a] / spacing).ceil() as usize + 1 + 2 * padding);
    budget.check_elements(
        dims.iter().map(|&d| d as u128).product(),
        1,
        "voxelised solid",
    )?;
    let origin = [0, 1, 2].map(|a| {
        let centre = 0.5 * (bounds.min[a] + bounds.max[a]);
        centre - 0.5 * (dims[a] - 1) as f64 * spacing
    });
    let [nx, ny, nz] = dims;
    let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); nx * ny];
    let (ox, oy) = (std::f64::consts::PI * 1e-7, std::f64::consts::E * 1e-7);
    let pos = mesh.positions();
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| pos[v as usize]);
        let to_grid = |p: [f64; 3]| [(p[0] - origin[0]) / spacing, (p[1] - origin[1]) / spacing];
        let [ga, gb, gc] = [to_grid(a), to_grid(b), to_grid(c)];
        let det = (gb[0] - ga[0]) * (gc[1] - ga[1]) - (gc[0] - ga[0]) * (gb[1] - ga[1]);
        if det.abs() < 1e-300 {
            continue; // vertical in z: no column crosses its interior
        }
        let lo = |v: f64| (v.floor().max(0.0)) as usize;
        let i0 = lo(ga[0].min(gb[0]).min(gc[0]));
        let i1 = (ga[0].max(gb[0]).max(gc[0]).ceil() as usize).min(nx - 1);
        let j0 = lo(ga[1].min(gb[1]).min(gc[1]));
        let j1 = (ga[1].max(gb[1]).max(gc[1]).ceil() as usize).min(ny - 1);
        for j in j0..=j1 {
            for i in i0..=i1 {
                let (px, py) = (i as f64 + ox, j as f64 + oy);
                // Barycentric coordinates of the column in the projected triangle.
                let wb = ((px - ga[0]) * (gc[1] - ga[1]) - (gc[0] - ga[0]) * (py - ga[1])) / det;
                let wc = ((gb[0] - ga[0]) * (py - ga[1]) - (px - ga[0]) * (gb[1] - ga[1])) / det;
                let wa = 1.0 - wb - wc;
                if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
                    let z = wa * a[2] + wb * b[2] + wc * c[2];
                    crossings[i + nx * j].push((z - origin[2]) / spacing);
                }
            }
        }
    }
    let mut inside = vec![false; nx * ny * nz];
    for j in 0..ny {
        for i in 0..nx {
            let zs = &mut crossings[i + nx * j];
            zs.sort_by(f64::total_cmp);
            for pair in zs.chunks_exact(2) {
                let k0 = pair[0].ceil().max(0.0) as usize;
                let k1 = pair[1].floor().min((nz - 1) as f64);
                if k1 < 0.0 {
                    continue;
                }
                for k in k0..=k1 as usize {
                    inside[i + nx * (j + ny * k)] = true;
                }
            }
        }
    }
    Ok(Voxelization {
        dims,
        origin,
        spacing,
        inside,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::icosphere;

    #[test]
    fn sphere_volume() {
        // An icosphere of radius 1 voxelised at 60 cells per diameter: the
        // cell count times the cell volume matches the polyhedron's volume.
        let mesh = icosphere(4, 1.0);
        let v = voxelize(&mesh, 60, 2, &MemoryBudget::unlimited()).unwrap();
        let count = v.inside.iter().filter(|b| **b).count() as f64;
        let vol = count * v.spacing.powi(3);
        let exact = mesh.signed_volume();
        assert!((vol - exact).abs() / exact < 0.01, "{vol} vs {exact}");
        // The padding stays empty.
        assert!(!v.inside[v.index(0, 0, 0)] && !v.inside[v.index(1, 30, 30)]);
        assert!(v.inside[v.index(v.dims[0] / 2, v.dims[1] / 2, v.dims[2] / 2)]);
    }

    #[test]
    fn open_mesh_is_refused() {
        let mesh = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let e = voxelize(&mesh, 10, 1, &MemoryBudget::unlimited()).unwrap_err();
        assert!(
            e.to_string()
                .contains("not closed: 3 edges belong to one face only"),
            "{e}"
        );
    }
}
