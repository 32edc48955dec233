//! Analytic Bézier curves and patches, computed from their control points
//! alone (forward differences and Bernstein polynomials), independent of the
//! IFS: the truth the pseudo-curvature tests compare with.

use asperity_core::vec3::{cross, dot};
use asperity_ifs::SurfaceIfs;

fn binom(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |a, i| a * (n - i) as f64 / (i + 1) as f64)
}

fn bernstein(n: usize, i: usize, u: f64) -> f64 {
    binom(n, i) * u.powi(i as i32) * (1.0 - u).powi((n - i) as i32)
}

/// B^(r)(u) of a Bézier curve by differencing the control points (zero above
/// the degree).
pub fn bezier_derivative(pts: &[[f64; 3]], r: usize, u: f64) -> [f64; 3] {
    let n = pts.len() - 1;
    if r > n {
        return [0.0; 3];
    }
    let mut d: Vec<[f64; 3]> = pts.to_vec();
    for _ in 0..r {
        d = d
            .windows(2)
            .map(|w| [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]])
            .collect();
    }
    let m = n - r;
    let f = (0..r).fold(1.0, |a, k| a * (n - k) as f64);
    let mut out = [0.0; 3];
    for (i, p) in d.iter().enumerate() {
        let b = bernstein(m, i, u) * f;
        for k in 0..3 {
            out[k] += b * p[k];
        }
    }
    out
}

/// Analytic 𝒦 and ℋ at (u, v) of the Bézier patch of `s`'s control grid (any
/// degrees), normal ∂/∂u × ∂/∂v.
pub fn patch_curvature(s: &SurfaceIfs, u: f64, v: f64) -> (f64, f64) {
    let grid = s.control();
    let (n, m) = s.grid_size();
    let der = |ru: usize, rv: usize| -> [f64; 3] {
        // Derivative rows in v for every u-row, then in u.
        let rows: Vec<[f64; 3]> = (0..n)
            .map(|a| bezier_derivative(&grid[a * m..(a + 1) * m], rv, v))
            .collect();
        bezier_derivative(&rows, ru, u)
    };
    let (su, sv) = (der(1, 0), der(0, 1));
    let (suu, suv, svv) = (der(2, 0), der(1, 1), der(0, 2));
    let nn = cross(su, sv);
    let len = dot(nn, nn).sqrt();
    let nrm = [nn[0] / len, nn[1] / len, nn[2] / len];
    let (e, f, g) = (dot(su, su), dot(su, sv), dot(sv, sv));
    let (l, mm, nc) = (dot(suu, nrm), dot(suv, nrm), dot(svv, nrm));
    let det = e * g - f * f;
    (
        (l * nc - mm * mm) / det,
        (e * nc + g * l - 2.0 * f * mm) / (2.0 * det),
    )
}
