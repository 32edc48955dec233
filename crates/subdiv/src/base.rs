//! Built-in base meshes: cube, quad sphere, torus, cylinder (n-gon caps), plane
//! patch (open, with boundary), surfaces of revolution, and the paper's fuse
//! (velho-perlin §6.1).

use asperity_core::PolyMesh;

/// The cube [−1, 1]³ as 8 vertices and 6 outward quads (see
/// [`asperity_core::shapes::cube_cage`] for the vertex order).
pub fn cube() -> PolyMesh {
    asperity_core::shapes::cube_cage()
}

/// A unit quad sphere: the cube with each face split n × n, pushed onto the sphere.
pub fn quad_sphere(n: usize) -> PolyMesh {
    let c = asperity_core::shapes::cube_quads(n);
    let pos = c
        .positions()
        .iter()
        .map(|p| {
            let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [p[0] / l, p[1] / l, p[2] / l]
        })
        .collect();
    c.with_positions(pos).expect("same vertex count")
}

/// A torus of radii `big` and `small` with `nu × nv` quads, outward (see
/// [`asperity_core::shapes::torus_quads`]).
pub fn torus(big: f64, small: f64, nu: usize, nv: usize) -> PolyMesh {
    asperity_core::shapes::torus_quads(big, small, nu, nv)
}

/// A capped cylinder of radius `r` from z = −h to h: `n` side quads, each
/// cap one n-gon (Catmull–Clark rounds it).
pub fn cylinder(r: f64, h: f64, n: usize) -> PolyMesh {
    let n = n.max(3);
    let tau = std::f64::consts::TAU;
    let mut pos = Vec::with_capacity(2 * n);
    for z in [-h, h] {
        for i in 0..n {
            let a = tau * i as f64 / n as f64;
            pos.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let n32 = n as u32;
    let mut faces: Vec<Vec<u32>> = (0..n32)
        .map(|i| vec![i, (i + 1) % n32, n32 + (i + 1) % n32, n32 + i])
        .collect();
    faces.push((0..n32).rev().collect());
    faces.push((n32..2 * n32).collect());
    PolyMesh::new(pos, &faces).expect("valid cylinder")
}

/// An open n × n quad patch over [−1, 1]² in the plane z = 0 (normal +z).
pub fn plane(n: usize) -> PolyMesh {
    let n = n.max(1);
    let m = n + 1;
    let pos: Vec<[f64; 3]> = (0..m * m)
        .map(|k| {
            let (i, j) = (k % m, k / m);
            [
                -1.0 + 2.0 * i as f64 / n as f64,
                -1.0 + 2.0 * j as f64 / n as f64,
                0.0,
            ]
        })
        .collect();
    let faces: Vec<[u32; 4]> = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let v = (j * m + i) as u32;
            [v, v + 1, v + m as u32 + 1, v + m as u32]
        })
        .collect();
    PolyMesh::new(pos, &faces).expect("valid plane")
}

/// A closed surface of revolution about z: `profile` gives (radius, z) from
/// the bottom pole to the top pole (both ends on the axis are implied: the
/// first and last samples must have r > 0); quads between rings, triangle fans
/// at the poles.
pub fn revolution(profile: &[[f64; 2]], segments: usize) -> PolyMesh {
    let s = segments.max(3);
    let rings = profile.len();
    let tau = std::f64::consts::TAU;
    let mut pos = Vec::with_capacity(rings * s + 2);
    let z0 = profile.first().map_or(0.0, |p| p[1]);
    let z1 = profile.last().map_or(0.0, |p| p[1]);
    let dz = (z1 - z0) / (rings.max(1) as f64 * 2.0);
    pos.push([0.0, 0.0, z0 - dz]);
    for p in profile {
        for i in 0..s {
            let a = tau * i as f64 / s as f64;
            pos.push([p[0] * a.cos(), p[0] * a.sin(), p[1]]);
        }
    }
    pos.push([0.0, 0.0, z1 + dz]);
    let top = (rings * s + 1) as u32;
    let at = |ring: usize, i: usize| (1 + ring * s + i % s) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..s {
        faces.push(vec![0, at(0, i + 1), at(0, i)]);
    }
    for r in 0..rings.saturating_sub(1) {
        for i in 0..s {
            faces.push(vec![at(r, i), at(r, i + 1), at(r + 1, i + 1), at(r + 1, i)]);
        }
    }
    for i in 0..s {
        faces.push(vec![at(rings - 1, i), at(rings - 1, i + 1), top]);
    }
    PolyMesh::new(pos, &faces).expect("valid surface of revolution")
}

/// The paper's fuse profile sin(Σᵢ sin(t^(2ⁱ))/2ⁱ), i = 0…3 (§6.1).
pub fn fuse_profile(t: f64) -> f64 {
    (0..4)
        .map(|i| (t.powi(1 << i)).sin() / f64::from(1 << i))
        .sum::<f64>()
        .sin()
}

/// The fuse (§6.1): a surface of revolution along z ∈ [−1.5, 1.5] whose
/// radius is 0.3 + 0.15·(1 + p(t)) with p the fuse profile at t ∈ [0, 2]
/// (our mapping of the profile to a radius; the paper gives only p).
pub fn fuse(rings: usize, segments: usize) -> PolyMesh {
    let rings = rings.max(2);
    let profile: Vec<[f64; 2]> = (0..rings)
        .map(|k| {
            let u = k as f64 / (rings - 1) as f64;
            [0.3 + 0.15 * (1.0 + fuse_profile(2.0 * u)), -1.5 + 3.0 * u]
        })
        .collect();
    revolution(&profile, segments)
}

/// A profile for [`revolution`] from text: one `r z` pair per line (white
/// space or commas), bottom to top, every r > 0; `#` starts a comment.
///
/// # Errors
/// A message naming the bad line, or too few rows.
pub fn parse_profile(text: &str) -> Result<Vec<[f64; 2]>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .map(str::parse)
            .collect::<Result<_, _>>()
            .ok()
            .filter(|v: &Vec<f64>| v.len() == 2 && v.iter().all(|x| x.is_finite()) && v[0] > 0.0)
            .ok_or_else(|| format!("line {}: expected `r z` with r > 0, got {line:?}", i + 1))?;
        out.push([v[0], v[1]]);
    }
    if out.len() < 2 {
        return Err("a profile needs at least two `r z` rows".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bases_are_closed_and_outward() {
        for (m, chi) in [
            (cube(), 2),
            (quad_sphere(3), 2),
            (torus(1.0, 0.3, 12, 6), 0),
            (cylinder(0.5, 1.0, 8), 2),
            (fuse(24, 12), 2),
        ] {
            let t = m.triangulate();
            assert!(t.is_watertight() && t.is_consistently_oriented());
            assert_eq!(t.euler_characteristic(), chi);
            assert!(t.signed_volume() > 0.0);
        }
        let p = plane(3).triangulate();
        assert_eq!(p.euler_characteristic(), 1);
        assert!(p.face_normals().iter().all(|n| n[2] > 0.0));
        // The profile at t = 0 is sin(0) = 0; at t = 1 it is sin(Σ sin(1)/2ⁱ).
        assert_eq!(fuse_profile(0.0), 0.0);
        let s1 = 1f64.sin();
        assert!((fuse_profile(1.0) - (s1 * (1.0 + 0.5 + 0.25 + 0.125)).sin()).abs() < 1e-15);
    }
}
