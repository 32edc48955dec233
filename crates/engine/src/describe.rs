//! Facts about a file's contents (`asperity info`): counts, bounds, topology,
//! attributes of a mesh; range and spread of a height field; bounds of a point set.

use asperity_core::{HeightField, PointSet, TriMesh};
use asperity_io::Surface;
use serde_json::json;

use crate::report::Measurements;

/// Facts about whatever `s` holds.
pub fn describe(s: &Surface) -> Measurements {
    Measurements::from_value(match s {
        Surface::Mesh(m) => mesh_facts(m),
        Surface::Points(p) => point_facts(p),
        Surface::Height(h) => height_facts(h),
    })
}

fn mesh_facts(m: &TriMesh) -> serde_json::Value {
    let topology = m.topology();
    let watertight = topology.is_watertight();
    json!({
        "kind": "mesh",
        "vertices": m.n_vertices(),
        "triangles": m.n_faces(),
        "edges": topology.edges,
        "euler_characteristic": topology.euler_characteristic,
        "components": m.n_components(),
        "boundary_loops": topology.boundary_loops,
        "manifold": topology.is_manifold(),
        "watertight": watertight,
        "genus": topology.genus,
        "area": m.area(),
        "volume": if watertight { Some(m.signed_volume()) } else { None },
        "bounds": m.bounds(),
        "normals": m.normals().is_some(),
        "colors": m.colors().is_some(),
        "uvs": m.uvs().is_some(),
        "scalars": m.scalars().iter().map(|a| a.name.clone()).collect::<Vec<_>>(),
    })
}

fn height_facts(h: &HeightField) -> serde_json::Value {
    // Statistics of the measured points; missing ones (NaN) are counted.
    let (lo, hi) = h.min_max();
    let measured = h.measured_values();
    let n = measured.len().max(1) as f64;
    let mean = measured.iter().sum::<f64>() / n;
    let rms = (measured.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n).sqrt();
    json!({
        "kind": "height field",
        "nx": h.nx(), "ny": h.ny(),
        "spacing": h.spacing(), "origin": h.origin(), "extent": h.extent(),
        "units": crate::analyze::units_json(h),
        "min": lo, "max": hi, "mean": mean, "rms_deviation": rms,
        "missing_points": h.len() - measured.len(),
    })
}

fn point_facts(p: &PointSet) -> serde_json::Value {
    json!({
        "kind": "point set",
        "points": p.len(),
        "bounds": p.bounds(),
        "normals": p.normals().is_some(),
        "colors": p.colors().is_some(),
        "attributes": p.attributes().iter().map(|a| a.name.clone()).collect::<Vec<_>>(),
    })
}
