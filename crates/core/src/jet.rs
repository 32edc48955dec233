//! The osculating jet: the quadric z = c₀ + c₁x + c₂y + c₃x² + c₄xy + c₅y²
//! fitted by least squares to points around an origin, in the frame of a
//! normal (Cazals & Pouget 2005, "Estimating differential quantities using
//! polynomial fitting of osculating jets", CAGD 22:121–146). One fit serves
//! the reconstruction's point denoising and vertex projection (its height c₀
//! at the origin: the moving-least-squares projection) and the analysis's
//! curvature at a scale (its derivatives). The basis {1, x, y, x², xy, y²}
//! is closed under rotations of the tangent plane, so the fit does not depend
//! on which tangent axes the frame takes.

use nalgebra::{SMatrix, SVector, Vector3};

/// A fitted quadric, its coefficients in units of the fit's radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    c: SVector<f64, 6>,
    scale: f64,
    /// The frame: tangent axes and normal.
    frame: [Vector3<f64>; 3],
}

impl Jet {
    /// Fits the quadric to `points` about `origin` in the frame of the unit
    /// `normal`, coordinates divided by `scale` (the neighbourhood's radius).
    /// `None` for a degenerate fit (fewer than six points in general
    /// position, a non-finite input).
    pub fn fit(
        origin: [f64; 3],
        normal: [f64; 3],
        points: impl IntoIterator<Item = [f64; 3]>,
        scale: f64,
    ) -> Option<Self> {
        let n = Vector3::from(normal);
        if !(scale > 0.0 && scale.is_finite() && (n.norm() - 1.0).abs() < 1e-6) {
            return None;
        }
        let helper = if n.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = (helper - n * n.dot(&helper)).normalize();
        let e2 = n.cross(&e1);
        let o = Vector3::from(origin);
        let mut ata = SMatrix::<f64, 6, 6>::zeros();
        let mut atb = SVector::<f64, 6>::zeros();
        for q in points {
            let d = (Vector3::from(q) - o) / scale;
            let (x, y, z) = (d.dot(&e1), d.dot(&e2), d.dot(&n));
            let row = SVector::<f64, 6>::from([1.0, x, y, x * x, x * y, y * y]);
            ata += row * row.transpose();
            atb += row * z;
        }
        let c = ata.cholesky()?.solve(&atb);
        c.iter().all(|v| v.is_finite()).then_some(Self {
            c,
            scale,
            frame: [e1, e2, n],
        })
    }

    /// The quadric's height over the origin along the normal (world units).
    pub fn height(&self) -> f64 {
        self.c[0] * self.scale
    }

    /// The unit normal of the quadric's graph at the origin, on the side of
    /// the frame's normal: (−f_x, −f_y, 1)/√(1 + f_x² + f_y²) in the frame.
    pub fn normal(&self) -> [f64; 3] {
        let [e1, e2, n] = &self.frame;
        let v = (n - e1 * self.c[1] - e2 * self.c[2]).normalize();
        [v.x, v.y, v.z]
    }

    /// The mean curvature H = (κ₁ + κ₂)/2 and the Gaussian curvature K of the
    /// quadric's graph at the origin: with E = 1 + f_x², F = f_x f_y,
    /// G = 1 + f_y², (L, M, N) = (f_xx, f_xy, f_yy)/√(1 + f_x² + f_y²),
    /// K = (LN − M²)/(EG − F²), H = −(EN − 2FM + GL)/(2(EG − F²)) — H positive
    /// where the surface bends away from its normal (1/r on a sphere with
    /// outward normals).
    pub fn curvatures(&self) -> (f64, f64) {
        let (c, r) = (&self.c, self.scale);
        let (fx, fy) = (c[1], c[2]);
        let (fxx, fxy, fyy) = (2.0 * c[3] / r, c[4] / r, 2.0 * c[5] / r);
        let w = (1.0 + fx * fx + fy * fy).sqrt();
        let (e, f, g) = (1.0 + fx * fx, fx * fy, 1.0 + fy * fy);
        let (l, m, n) = (fxx / w, fxy / w, fyy / w);
        let det = e * g - f * f;
        (
            -(e * n - 2.0 * f * m + g * l) / (2.0 * det),
            (l * n - m * m) / det,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of the paraboloid z = 1 + (x² + 3y²)/2 about (0, 0, 0) with
    /// normal +z: the height 1, H = −2 (it bends toward +z, its normal) and
    /// K = 3, whatever the tangent axes.
    #[test]
    fn a_quadric_is_fitted_exactly() {
        let pts: Vec<[f64; 3]> = (0..49)
            .map(|k| {
                let (x, y) = ((k % 7) as f64 * 0.1 - 0.3, (k / 7) as f64 * 0.1 - 0.3);
                [x, y, 1.0 + 0.5 * (x * x + 3.0 * y * y)]
            })
            .collect();
        let j = Jet::fit([0.0; 3], [0.0, 0.0, 1.0], pts, 0.4).unwrap();
        assert!((j.height() - 1.0).abs() < 1e-12);
        let (h, k) = j.curvatures();
        assert!((h + 2.0).abs() < 1e-9 && (k - 3.0).abs() < 1e-9, "{h} {k}");
        assert!(Jet::fit([0.0; 3], [0.0, 0.0, 1.0], [[0.0; 3]; 3], 1.0).is_none());
    }

    /// The plane z = 0.3x − 0.4y fitted in the frame of +z: its normal is
    /// (−0.3, 0.4, 1)/√1.25, and in the frame of that normal the fit has no
    /// slope (the same normal again).
    #[test]
    fn the_normal_is_the_graph_s() {
        let pts: Vec<[f64; 3]> = (0..49)
            .map(|k| {
                let (x, y) = ((k % 7) as f64 * 0.1 - 0.3, (k / 7) as f64 * 0.1 - 0.3);
                [x, y, 0.3 * x - 0.4 * y]
            })
            .collect();
        let j = Jet::fit([0.0; 3], [0.0, 0.0, 1.0], pts.iter().copied(), 0.4).unwrap();
        let l = 1.25f64.sqrt();
        let want = [-0.3 / l, 0.4 / l, 1.0 / l];
        let got = j.normal();
        for k in 0..3 {
            assert!((got[k] - want[k]).abs() < 1e-12, "{got:?}");
        }
        let again = Jet::fit([0.0; 3], got, pts, 0.4).unwrap().normal();
        for k in 0..3 {
            assert!((again[k] - want[k]).abs() < 1e-12, "{again:?}");
        }
    }
}
