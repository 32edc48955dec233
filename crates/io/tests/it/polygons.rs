//! Non-convex polygon faces in OBJ and PLY files, read as triangle meshes:
//! the triangles cover the face exactly once (its area by the shoelace
//! formula, an answer independent of any triangulation), for random
//! star-shaped faces drawn per case in a random plane.

use proptest::prelude::*;

/// A star-shaped polygon of radii `radii` at evenly spaced angles, in the
/// plane spanned by the unit vectors `u` and `v`; and its area.
fn star(radii: &[f64], u: [f64; 3], v: [f64; 3]) -> (Vec<[f64; 3]>, f64) {
    let n = radii.len();
    let flat: Vec<[f64; 2]> = radii
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let t = k as f64 * std::f64::consts::TAU / n as f64;
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    let shoelace = 0.5
        * (0..n)
            .map(|k| {
                let (a, b) = (flat[k], flat[(k + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>();
    let corners = flat
        .iter()
        .map(|[x, y]| std::array::from_fn(|i| 5.0 + x * u[i] + y * v[i]))
        .collect();
    (corners, shoelace)
}

fn obj_text(corners: &[[f64; 3]]) -> String {
    let mut s: String = corners
        .iter()
        .map(|p| format!("v {:.17e} {:.17e} {:.17e}\n", p[0], p[1], p[2]))
        .collect();
    s.push('f');
    for k in 1..=corners.len() {
        s.push_str(&format!(" {k}"));
    }
    s.push('\n');
    s
}

fn ply_text(corners: &[[f64; 3]]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
         property double z\nelement face 1\nproperty list uint uint vertex_indices\nend_header\n",
        corners.len()
    );
    for p in corners {
        s.push_str(&format!("{:.17e} {:.17e} {:.17e}\n", p[0], p[1], p[2]));
    }
    s.push_str(&corners.len().to_string());
    for k in 0..corners.len() {
        s.push_str(&format!(" {k}"));
    }
    s.push('\n');
    s
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn a_star_face_is_covered_once(
        radii in prop::collection::vec(0.05f64..1.0, 5..400),
        normal in prop::array::uniform3(-1.0f64..1.0),
    ) {
        prop_assume!(normal.iter().map(|c| c * c).sum::<f64>() > 0.01);
        let n = unit(normal);
        let helper = if n[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
        let u = unit([
            helper[1] * n[2] - helper[2] * n[1],
            helper[2] * n[0] - helper[0] * n[2],
            helper[0] * n[1] - helper[1] * n[0],
        ]);
        let v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]];
        let (corners, area) = star(&radii, u, v);
        let dir = tempfile::tempdir().unwrap();
        for (name, text) in [("star.obj", obj_text(&corners)), ("star.ply", ply_text(&corners))] {
            let path = dir.path().join(name);
            std::fs::write(&path, text).unwrap();
            let mesh = asperity_io::read_mesh(&path).unwrap();
            prop_assert_eq!(mesh.triangles().len(), radii.len() - 2);
            let covered = mesh.area();
            prop_assert!(
                (covered - area).abs() <= 1e-9 * area,
                "{}: {} corners, triangles cover {} of {}", name, radii.len(), covered, area
            );
        }
    }
}
