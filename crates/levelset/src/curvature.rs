//! The level-set function's normal and mean curvature, after
//! [kim-machiraju-thompson] §5.1 Eqs. 1–2: n = ∇φ/|∇φ| and κ = ∇·(∇φ/|∇φ|), by
//! central differences on the grid.
//!
//! Used by the regularised flow's curvature term (module `evolve`, Zhao's model
//! that §6 contrasts with the paper's) and by marching cubes' per-vertex mean
//! curvature attribute (module `marching_cubes`).
//!
//! # Deviations from the paper
//! - The paper states the continuous formulas only; this is the standard
//!   second-order central-difference discretisation, with κ = 0 where |∇φ| is
//!   below 10⁻⁶ (flat or singular points, where the paper's formula divides by 0).
//!
//! [kim-machiraju-thompson]: https://doi.org/10.1007/978-3-662-07443-5 "Kim, Machiraju, Thompson: Modeling Rough Surfaces. In Geometric Modeling for Scientific Visualization, Springer 2004, pp. 123-138"

/// Read access to φ for the scalar stencils (the curvature term and marching
/// cubes' curvature attribute).
pub(crate) trait Phi: Sync {
    /// φ at node `u`.
    fn at(&self, u: usize) -> f64;
}

impl Phi for [f32] {
    #[inline]
    fn at(&self, u: usize) -> f64 {
        f64::from(self[u])
    }
}

/// κ = ∇·(∇φ/|∇φ|) (Eq. 2) and |∇φ| at node `u` by central differences:
/// κ = (|∇φ|² tr H − ∇φᵀ H ∇φ) / |∇φ|³ with H the Hessian.
pub(crate) fn curvature_and_gradient<P: Phi + ?Sized>(
    phi: &P,
    u: usize,
    strides: [usize; 3],
    h: f64,
) -> (f64, f64) {
    let p = |x: usize| phi.at(x);
    let mut g = [0.0; 3];
    let mut hess = [[0.0; 3]; 3];
    for a in 0..3 {
        let s = strides[a];
        g[a] = (p(u + s) - p(u - s)) / (2.0 * h);
        hess[a][a] = (p(u + s) - 2.0 * p(u) + p(u - s)) / (h * h);
        for b in (a + 1)..3 {
            let t = strides[b];
            let v = (p(u + s + t) - p(u + s - t) - p(u - s + t) + p(u - s - t)) / (4.0 * h * h);
            hess[a][b] = v;
            hess[b][a] = v;
        }
    }
    let g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if g2 < 1e-12 {
        return (0.0, g2.sqrt());
    }
    let mut num = 0.0;
    for a in 0..3 {
        for b in 0..3 {
            let delta = if a == b { g2 } else { 0.0 };
            num += (delta - g[a] * g[b]) * hess[a][b];
        }
    }
    let len = g2.sqrt();
    (num / (g2 * len), len)
}
