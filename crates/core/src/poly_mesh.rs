//! Polygon meshes (quads first): the input of subdivision.

use crate::{CoreError, TriMesh, tri_mesh::check_finite_points};

/// Mixed polygons in CSR layout (libigl's I/C pair): face f is
/// `face_vertices[face_offsets[f]..face_offsets[f + 1]]`, counter-clockwise from outside.
#[derive(Clone, Debug, PartialEq)]
pub struct PolyMesh {
    positions: Vec<[f64; 3]>,
    face_offsets: Vec<u32>,
    face_vertices: Vec<u32>,
}

impl PolyMesh {
    /// A mesh of polygonal `faces` over `positions`.
    ///
    /// # Errors
    /// [`CoreError::TooFewCorners`], [`CoreError::IndexOutOfRange`],
    /// [`CoreError::DegenerateFace`] (a corner repeated), [`CoreError::NonFinite`].
    pub fn new<F: AsRef<[u32]>>(positions: Vec<[f64; 3]>, faces: &[F]) -> crate::Result<Self> {
        let mut face_offsets = Vec::with_capacity(faces.len() + 1);
        let mut face_vertices = Vec::new();
        face_offsets.push(0);
        for f in faces {
            face_vertices.extend_from_slice(f.as_ref());
            let end =
                u32::try_from(face_vertices.len()).map_err(|_| CoreError::InvalidParameter {
                    name: "polygon mesh",
                    reason: "more than 2³² corners".into(),
                })?;
            face_offsets.push(end);
        }
        Self::from_csr(positions, face_offsets, face_vertices)
    }

    /// A mesh from CSR arrays (see the type docs).
    ///
    /// # Errors
    /// As [`PolyMesh::new`], plus [`CoreError::InvalidParameter`] for bad offsets.
    pub fn from_csr(
        positions: Vec<[f64; 3]>,
        face_offsets: Vec<u32>,
        face_vertices: Vec<u32>,
    ) -> crate::Result<Self> {
        check_finite_points("vertex", &positions)?;
        let bad_offsets = face_offsets.first() != Some(&0)
            || face_offsets.last().map(|&l| l as usize) != Some(face_vertices.len())
            || face_offsets.windows(2).any(|w| w[1] < w[0]);
        if bad_offsets {
            return Err(CoreError::InvalidParameter {
                name: "face offsets",
                reason: "must start at 0, never decrease, and end at the corner count".into(),
            });
        }
        let mesh = Self {
            positions,
            face_offsets,
            face_vertices,
        };
        for f in 0..mesh.n_faces() {
            let face = mesh.face(f);
            if face.len() < 3 {
                return Err(CoreError::TooFewCorners {
                    face: f,
                    corners: face.len(),
                });
            }
            for (k, &v) in face.iter().enumerate() {
                if v as usize >= mesh.positions.len() {
                    return Err(CoreError::IndexOutOfRange {
                        face: f,
                        index: v as u64,
                        len: mesh.positions.len(),
                    });
                }
                if face[..k].contains(&v) {
                    return Err(CoreError::DegenerateFace { face: f, index: v });
                }
            }
        }
        Ok(mesh)
    }

    /// A pure-quad mesh.
    ///
    /// # Errors
    /// As [`PolyMesh::new`].
    pub fn from_quads(positions: Vec<[f64; 3]>, quads: &[[u32; 4]]) -> crate::Result<Self> {
        Self::new(positions, quads)
    }

    /// The same faces over new positions (one per vertex).
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] for a different count, [`CoreError::NonFinite`].
    pub fn with_positions(mut self, positions: Vec<[f64; 3]>) -> crate::Result<Self> {
        self.set_positions(positions)?;
        Ok(self)
    }

    /// Replaces the positions in place (one per vertex).
    ///
    /// # Errors
    /// As [`PolyMesh::with_positions`].
    pub fn set_positions(&mut self, positions: Vec<[f64; 3]>) -> crate::Result<()> {
        if positions.len() != self.positions.len() {
            return Err(CoreError::LengthMismatch {
                what: "positions".into(),
                got: positions.len(),
                expected: self.positions.len(),
            });
        }
        check_finite_points("vertex", &positions)?;
        self.positions = positions;
        Ok(())
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }
    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    /// Corners of face `f`.
    ///
    /// # Panics
    /// If `f >= n_faces()`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }
    /// Iterator over all faces.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + Clone {
        (0..self.n_faces()).map(|f| self.face(f))
    }
    /// CSR offsets (length `n_faces() + 1`).
    pub fn face_offsets(&self) -> &[u32] {
        &self.face_offsets
    }
    /// CSR corner list.
    pub fn face_vertices(&self) -> &[u32] {
        &self.face_vertices
    }
    /// Whether every face is a quad.
    pub fn is_all_quads(&self) -> bool {
        self.faces().all(|f| f.len() == 4)
    }
    /// Number of undirected edges.
    pub fn n_edges(&self) -> usize {
        let mut e: Vec<(u32, u32)> = self
            .faces()
            .flat_map(|f| (0..f.len()).map(move |k| (f[k], f[(k + 1) % f.len()])))
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        e.sort_unstable();
        e.dedup();
        e.len()
    }
    /// Euler characteristic V − E + F.
    pub fn euler_characteristic(&self) -> i64 {
        self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64
    }

    /// Fan-triangulates every face from its first corner (exact for convex faces).
    pub fn triangulate(&self) -> TriMesh {
        use rayon::prelude::*;
        // On every core, in face order (a fine subdivision has millions).
        let tris = (0..self.n_faces())
            .into_par_iter()
            .flat_map_iter(|i| {
                let f = &self.face_vertices
                    [self.face_offsets[i] as usize..self.face_offsets[i + 1] as usize];
                (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]])
            })
            .collect();
        TriMesh::new(self.positions.clone(), tris).expect("indices were validated on construction")
    }

    /// A polygon mesh with the triangles of `mesh` as faces.
    ///
    /// # Errors
    /// [`CoreError`] for a triangle that repeats a corner (a [`TriMesh`] may hold
    /// one, a polygon mesh may not).
    pub fn from_trimesh(mesh: &TriMesh) -> crate::Result<Self> {
        Self::new(mesh.positions().to_vec(), mesh.triangles())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> PolyMesh {
        crate::shapes::cube_cage()
    }

    #[test]
    fn quad_cube() {
        let c = cube();
        assert!(c.is_all_quads());
        assert_eq!((c.n_vertices(), c.n_edges(), c.n_faces()), (8, 12, 6));
        assert_eq!(c.euler_characteristic(), 2);
        let t = c.triangulate();
        assert_eq!(t.n_faces(), 12);
        assert!(t.is_watertight());
        assert!((t.signed_volume() - 8.0).abs() < 1e-12);
    }

    #[test]
    fn mixed_faces_and_errors() {
        let p = vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 2.0, 0.0],
        ];
        let m = PolyMesh::new(p.clone(), &[vec![0, 1, 2, 3], vec![3, 2, 4]]).unwrap();
        assert_eq!(m.face(1), &[3, 2, 4]);
        assert!(!m.is_all_quads());
        assert_eq!(m.triangulate().n_faces(), 3);
        assert_eq!(
            PolyMesh::new(p.clone(), &[vec![0, 1]]).unwrap_err(),
            CoreError::TooFewCorners {
                face: 0,
                corners: 2
            }
        );
        assert_eq!(
            PolyMesh::new(p.clone(), &[vec![0, 1, 9]]).unwrap_err(),
            CoreError::IndexOutOfRange {
                face: 0,
                index: 9,
                len: 5
            }
        );
        assert_eq!(
            PolyMesh::new(p.clone(), &[vec![0, 1, 0]]).unwrap_err(),
            CoreError::DegenerateFace { face: 0, index: 0 }
        );
        assert!(PolyMesh::from_csr(p, vec![0, 2], vec![0, 1, 2]).is_err());
    }
}
