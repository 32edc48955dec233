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

#[cfg(feature = "reference")]
/// Read access to φ for the scalar stencils (the curvature term and marching
/// cubes' curvature attribute).
pub(crate) trait Phi: Sync {
    /// φ at node `u`.
    fn at(&self, u: usize) -> f64;
}

#[cfg(feature = "reference")]
impl Phi for [f32] {
    #[inline]
    fn at(&self, u: usize) -> f64 {
        f64::from(self[u])
    }
}

#[cfg(feature = "reference")]
/// κ = ∇·(∇φ/|∇φ|) (Eq. 2) and |∇φ| at node `u` by central differences:
/// κ = (|∇φ|² tr H − ∇φᵀ H ∇φ) / |∇φ|³ with H the Hessian.
pub(crate) fn curvature_and_gradient<P: Phi + ?Sized>(
    phi: &P,
    u: usize,
    strides: [usize; 3],
    h: f64,
) -> (f64, f64) {
    let at = |o: [isize; 3]| {
        let offset: isize = (0..3).map(|a| o[a] * strides[a] as isize).sum();
        phi.at(u.wrapping_add_signed(offset))
    };
    curvature_from(at, h)
}

/// [`curvature_and_gradient`] with φ read by `p(offset)`, the offset in nodes
/// from the node itself (the sparse layout's reader).
#[allow(clippy::needless_range_loop)] // the Hessian's symmetric entries read best by index
pub(crate) fn curvature_from(p: impl Fn([isize; 3]) -> f64, h: f64) -> (f64, f64) {
    let unit = |a: usize, s: isize| {
        let mut o = [0isize; 3];
        o[a] = s;
        o
    };
    let sum = |x: [isize; 3], y: [isize; 3]| [x[0] + y[0], x[1] + y[1], x[2] + y[2]];
    let mut g = [0.0; 3];
    let mut hess = [[0.0; 3]; 3];
    for a in 0..3 {
        let (up, down) = (unit(a, 1), unit(a, -1));
        g[a] = (p(up) - p(down)) / (2.0 * h);
        hess[a][a] = (p(up) - 2.0 * p([0; 3]) + p(down)) / (h * h);
        for b in (a + 1)..3 {
            let (bu, bd) = (unit(b, 1), unit(b, -1));
            let v = (p(sum(up, bu)) - p(sum(up, bd)) - p(sum(down, bu)) + p(sum(down, bd)))
                / (4.0 * h * h);
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
