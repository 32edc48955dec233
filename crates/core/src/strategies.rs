//! proptest strategies for the shared types (feature `proptest`).

use crate::{HeightField, TriMesh};
use proptest::prelude::*;

/// Height fields of 2..=max_n samples per side with heights in [-100, 100].
pub fn height_field(max_n: usize) -> impl Strategy<Value = HeightField> {
    (2..=max_n, 2..=max_n).prop_flat_map(|(nx, ny)| {
        (
            proptest::collection::vec(-100.0f64..100.0, nx * ny),
            0.01f64..10.0,
            0.01f64..10.0,
        )
            .prop_map(move |(data, dx, dy)| {
                HeightField::from_vec([nx, ny], data)
                    .and_then(|h| h.with_spacing([dx, dy]))
                    .expect("valid by construction")
            })
    })
}

/// Arbitrary valid triangle soups: up to `max_v` vertices and `max_f` faces.
pub fn tri_mesh(max_v: usize, max_f: usize) -> impl Strategy<Value = TriMesh> {
    (3..=max_v).prop_flat_map(move |nv| {
        let pos = proptest::collection::vec(proptest::array::uniform3(-1e3f64..1e3), nv);
        let tri = proptest::collection::vec(proptest::array::uniform3(0..nv as u32), 1..=max_f);
        (pos, tri).prop_map(|(p, t)| TriMesh::new(p, t).expect("indices in range"))
    })
}
