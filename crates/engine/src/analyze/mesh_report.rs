//! The reports on a mesh (topology, curvature with the Gauss–Bonnet check,
//! roughness against a smoothed copy) and on a point set (cluster
//! dimensions), with their plots: `analyze` on what is not a height field.

use asperity_analysis::{mesh, scaling};
use asperity_core::{PointSet, TriMesh};
use asperity_render::plot::histogram_plot;
use serde_json::{Value, json};

use super::Analysis;
use crate::error::{Result, ensure};
use crate::plots::NamedPlot;
use crate::report::Measurements;

/// The finite values between the 1st and 99th percentiles (curvature on rough or
/// fractal meshes has tails that would squash a histogram into one bin).
fn central(values: &[f64]) -> Vec<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.len() < 100 {
        return v;
    }
    v.sort_by(f64::total_cmp);
    let (lo, hi) = (v[v.len() / 100], v[v.len() - 1 - v.len() / 100]);
    v.retain(|&x| x >= lo && x <= hi);
    v
}

fn curvature_plots(c: &mesh::Curvature) -> Result<Vec<NamedPlot>> {
    let mut out = Vec::new();
    for (name, values, title, x) in [
        (
            "curvature_mean.png",
            &c.mean,
            "Mean curvature per vertex (central 98 %)",
            "H",
        ),
        (
            "curvature_gaussian.png",
            &c.gaussian,
            "Gaussian curvature per vertex (central 98 %)",
            "K",
        ),
    ] {
        let plot = histogram_plot(&central(values), 60, title, x)?;
        out.push(NamedPlot { name, plot });
    }
    Ok(out)
}

/// The report on a mesh: topology, curvature, roughness, box-counting dimension.
pub(super) fn mesh_report(m: &TriMesh, plots: bool) -> Result<Analysis> {
    let c = mesh::curvature(m);
    let mut warnings = Vec::new();
    let box_counting = match mesh::box_counting(m) {
        Ok(d) => {
            if is_graph_over_a_plane(m) {
                warnings.push(format!(
                    "box counting gives this sheet's covering dimension (D = {:.3}); for a rough surface over a plane it equals 3 − H only at boxes smaller than the height steps — analyse the height field itself (asperity analyze FILE.npy) for H and D = 3 − H",
                    d.d
                ));
            }
            json!({"D": d.d, "fit_range": d.fit.range, "r2": d.fit.r2})
        }
        Err(e) => {
            warnings.push(format!(
                "fractal dimension (box counting) not estimated: {e}"
            ));
            Value::Null
        }
    };
    let topology = m.topology();
    let watertight = topology.is_watertight();
    let facts = Measurements::from_value(json!({
        "kind": "mesh",
        "vertices": m.n_vertices(),
        "triangles": m.n_faces(),
        "area": m.area(),
        "volume": if watertight { Some(m.signed_volume()) } else { None },
        "euler_characteristic": topology.euler_characteristic,
        "genus": topology.genus,
        "boundary_loops": topology.boundary_loops,
        "manifold": topology.is_manifold(),
        "watertight": watertight,
        "curvature": {
            "mean": mesh::stats(&c.mean, &c.area),
            "gaussian": mesh::stats(&c.gaussian, &c.area),
            "total_gaussian": c.total_gaussian,
            "gauss_bonnet_2pi_chi": 2.0 * std::f64::consts::PI * topology.euler_characteristic as f64,
        },
        "roughness_vs_smoothed": mesh::smoothed_roughness(m, 10),
        "fractal_dimension": {"box_counting": box_counting},
    }));
    Ok(Analysis {
        facts,
        images: Vec::new(),
        warnings,
        plots: if plots {
            curvature_plots(&c)?
        } else {
            Vec::new()
        },
    })
}

/// Whether `m` is an open sheet whose faces all face one side of their mean
/// normal: the surface of a height field (where box counting is not 3 − H).
fn is_graph_over_a_plane(m: &TriMesh) -> bool {
    let normals = m.face_normals();
    let mean = normals
        .iter()
        .fold([0.0; 3], |a, n| [a[0] + n[0], a[1] + n[1], a[2] + n[2]]);
    !m.boundary_loops().is_empty()
        && normals
            .iter()
            .all(|n| n[0] * mean[0] + n[1] * mean[1] + n[2] * mean[2] > 0.0)
}

/// The report on a point set (a growth cluster): R_g and two fractal dimensions.
pub(super) fn point_report(p: &PointSet, name: &str) -> Result<Analysis> {
    ensure(p.len() >= 256, || {
        format!(
            "{name}: {} points are too few for cluster dimensions (need ≥ 256)",
            p.len()
        )
    })?;
    let rg = scaling::radius_of_gyration(p.positions());
    let g = scaling::gyration_dimension(p.positions())?;
    let m = scaling::mass_radius_dimension(p.positions(), 0.05 * rg)?;
    let facts = Measurements::from_value(json!({
        "kind": "point set",
        "points": p.len(),
        "radius_of_gyration": rg,
        "fractal_dimension": {
            "gyration": {"D": g.d, "r2": g.fit.r2, "note": "R_g of the first n points in file order (deposition order)"},
            "mass_radius": {"D": m.d, "fit_range": m.fit.range, "r2": m.fit.r2},
        },
    }));
    Ok(Analysis {
        facts,
        images: Vec::new(),
        plots: Vec::new(),
        warnings: Vec::new(),
    })
}
