//! General spectra: every eigenvalue with its multiplicity and its invariant
//! subspace, so that the DCF (poull-gentil §2.3) and the SDCF of a tensor operator
//! 𝒯 = T ⊗ T′ (§3.2) are defined whatever the multiplicities.
//!
//! [`crate::spectrum`] gives one eigenvector per eigenvalue and indexes the DCF
//! families by the coordinates along them. A tensor operator repeats eigenvalues
//! by construction — 𝒯 has the eigenvalues λᵢλ′ⱼ (§3.2: "each pair (λᵢ, λⱼ)
//! corresponds to a unique Λₖ = λᵢλⱼ"), so the bicubic patch's 𝒯00 has 1/8 four
//! times — and the classical Takagi curve has a Jordan block. Here each distinct
//! eigenvalue λ_c, of algebraic multiplicity m_c, gets its generalised eigenspace
//! ker (T − λ_c I)^{m_c}, the spectral projector Π_c onto it along the others, and
//! the nilpotent part N_c = (T − λ_c I) Π_c (zero exactly when T is
//! diagonalisable there). Then Tⁿ = Σ_c λ_cⁿ Σ_{k<m_c} C(n, k) λ_c^{−k} N_c^k Π_c,
//! and with n(t) = ln t / ln |λ₁| and α_c = ln |λ_c| / ln |λ₁| the DCF is
//!
//! > DCF(T, q, t) = Σ_c t^{α_c} Σ_{k<m_c} C(n(t), k) λ_c^{−k} N_c^k Π_c q.
//!
//! It is q at t = 1 and Tⁿq at t = λ₁ⁿ (positive eigenvalues). Without nilpotent
//! parts it is §2.3's Σ xᵢvᵢt^{αᵢ}, with the terms of one eigenvalue grouped into
//! Π_c q, which needs no choice of basis inside a repeated eigenspace. A Jordan
//! block adds the powers of log t that give the classical Takagi curve its
//! y ~ x log x.
//!
//! **Tensor products.** With 1 + N_c/λ_c per factor, (1 + N_c/λ_c) ⊗ (1 + N′_d/λ′_d)
//! is 𝒯's on Π_c ⊗ Π′_d, so the generalised eigenspace of 𝒯 for Λ is the sum of the
//! Π_c ⊗ Π′_d with λ_cλ′_d = Λ, and
//!
//! > DCF(𝒯, Q, t) = SDCF(𝒯, Q, t^a, t^b),  a = ln|λ₁| / ln|Λ₁|, b = ln|λ′₁| / ln|Λ₁|,
//!
//! for Q = q ⊗ q′, Λ₁ the larger of |λ₁| and |λ′₁|, and SDCF(s, t) =
//! DCF(T, q, s) ⊗ DCF(T′, q′, t) (the paper's definition). The DCF of 𝒯 is a
//! curve on its SDCF — the diagonal s = t when λ₁ = λ′₁ (Fig. 4's yellow curve).
//!
//! **Pseudo-curvature (§4.1) from the general spectra.** The SDCF's derivatives
//! at (0, 0) need only the components of q by exponent: a₀ = Π₀q (the fixed
//! point), a₁ = Σ_{α_c=1} Π_c q, a₂ = Σ_{α_c=2} Π_c q, so S_s = P(a₁⊗b₀), S_t =
//! P(a₀⊗b₁), S_st = P(a₁⊗b₁), S_ss = 2P(a₂⊗b₀), S_tt = 2P(a₀⊗b₂). A direction has
//! a finite second order when no exponent lies in (1, 2) and the α ≤ 2 eigenvalues
//! have no nilpotent part (a Jordan block there gives log t in the derivatives).
//! [`Decomposition::frame`] gives those components; `curvature::sdcf_curvature`
//! turns two of them into 𝒦 and ℋ (it lives there so that this module does not
//! depend on the curvature module, which reports these spectra).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::dcf::Frame;
use crate::spectrum::{CLUSTER, clusters_of, order_clusters, snap};

/// One distinct eigenvalue and its generalised eigenspace.
#[derive(Clone, Debug)]
pub struct Invariant {
    /// The eigenvalue λ_c (real).
    pub value: f64,
    /// Its algebraic multiplicity m_c.
    pub multiplicity: usize,
    /// The dimension of its eigenspace (its geometric multiplicity).
    pub eigenvectors: usize,
    /// α_c = ln|λ_c| / ln|λ₁| (0 for the fixed point, +∞ for λ = 0), snapped to integers.
    pub alpha: f64,
    /// The spectral projector Π_c onto the generalised eigenspace.
    pub projector: DMatrix<f64>,
    /// N_c = (T − λ_c I) Π_c; exactly zero when diagonalisable on this subspace.
    pub nilpotent: DMatrix<f64>,
}

impl Invariant {
    /// Whether T is diagonalisable on this subspace.
    pub fn is_diagonalisable(&self) -> bool {
        self.eigenvectors == self.multiplicity
    }
}

/// One distinct eigenvalue of an operator and the dimensions of its spaces.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpectrumEntry {
    /// λ.
    pub value: f64,
    /// Its algebraic multiplicity (the dimension of its generalised eigenspace).
    pub multiplicity: usize,
    /// Its geometric multiplicity (the dimension of its eigenspace): below
    /// `multiplicity` for a Jordan block.
    pub eigenvectors: usize,
    /// α = ln|λ| / ln|λ₁| (null for λ = 0).
    pub alpha: Option<f64>,
}

/// The general spectral decomposition T = Σ_c (λ_c Π_c + N_c).
#[derive(Clone, Debug)]
pub struct Decomposition {
    /// The fixed-point eigenvalue first, then by decreasing modulus.
    pub parts: Vec<Invariant>,
}

/// Binomial coefficient C(n, k) for real n.
fn binomial(n: f64, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, j| acc * (n - j as f64) / (j + 1) as f64)
}

/// The right singular vectors of the `k` smallest singular values of `a`, and the
/// largest of those values.
fn smallest_right_singular(a: &DMatrix<f64>, k: usize) -> Result<(Vec<DVector<f64>>, f64), String> {
    let svd = a.clone().svd(false, true);
    let v_t = svd
        .v_t
        .as_ref()
        .ok_or_else(|| "SVD without right singular vectors".to_owned())?;
    let mut order: Vec<usize> = (0..a.ncols()).collect();
    order.sort_by(|&x, &y| svd.singular_values[x].total_cmp(&svd.singular_values[y]));
    let chosen = &order[..k.min(order.len())];
    let largest = chosen
        .iter()
        .map(|&i| svd.singular_values[i])
        .fold(0.0, f64::max);
    Ok((
        chosen.iter().map(|&i| v_t.row(i).transpose()).collect(),
        largest,
    ))
}

/// Rank of `m` at tolerance `tol` (singular values above it).
fn rank(m: &DMatrix<f64>, tol: f64) -> usize {
    m.singular_values().iter().filter(|&&s| s > tol).count()
}

impl Decomposition {
    /// Decomposes `t` (square, finite, real spectrum).
    ///
    /// # Errors
    /// A complex eigenvalue pair; a Schur iteration that does not converge;
    /// generalised eigenspaces that are numerically dependent.
    pub fn new(t: &DMatrix<f64>) -> Result<Self, String> {
        let n = t.nrows();
        if n == 0 || t.ncols() != n {
            return Err(format!("the operator is {}×{}, not square", n, t.ncols()));
        }
        let clusters = order_clusters(clusters_of(t)?);
        if let Some(c) = clusters.iter().find(|c| c.im.abs() > CLUSTER) {
            return Err(format!(
                "complex eigenvalue pair {} ± {}i (the orbit spirals)",
                c.re,
                c.im.abs()
            ));
        }
        let identity = DMatrix::<f64>::identity(n, n);
        let norm = t.norm().max(1.0);
        // Columns: a basis of each generalised eigenspace, cluster after cluster.
        let mut basis = DMatrix::<f64>::zeros(n, n);
        let mut col = 0;
        for c in &clusters {
            let m = c.members.len();
            let shifted = t - &identity * c.re;
            let tol = (1e-9f64).max(10.0 * c.spread()) * norm;
            // The eigenspace when it is the whole generalised eigenspace (the
            // diagonalisable case, best conditioned), else ker (T − λI)^m.
            let mut space = smallest_right_singular(&shifted, m)?;
            if space.1 > tol {
                let mut power = identity.clone();
                for _ in 0..m {
                    power = &power * &shifted;
                }
                space = smallest_right_singular(&power, m)?;
            }
            for v in space.0 {
                basis.set_column(col, &v);
                col += 1;
            }
        }
        let inverse = basis.clone().try_inverse().ok_or_else(|| {
            "the generalised eigenspaces are numerically dependent (eigenvalues too close \
             to separate)"
                .to_owned()
        })?;
        let lambda1 = clusters.get(1).map_or(0.0, |c| c.re.abs());
        let mut parts = Vec::with_capacity(clusters.len());
        let mut start = 0;
        for (ci, c) in clusters.iter().enumerate() {
            let m = c.members.len();
            let cols = basis.columns(start, m);
            let projector = cols * inverse.rows(start, m);
            let shifted = t - &identity * c.re;
            let tol = (1e-9f64).max(10.0 * c.spread()) * norm;
            let eigenvectors = m - rank(&(&shifted * cols), tol);
            let nilpotent = if eigenvectors == m {
                DMatrix::zeros(n, n)
            } else {
                &shifted * &projector
            };
            let alpha = match ci {
                0 => 0.0,
                _ if c.re == 0.0 || lambda1 == 0.0 || lambda1 == 1.0 => f64::INFINITY,
                _ => snap(c.re.abs().ln() / lambda1.ln()),
            };
            parts.push(Invariant {
                value: c.re,
                multiplicity: m,
                eigenvectors,
                alpha,
                projector,
                nilpotent,
            });
            start += m;
        }
        Ok(Self { parts })
    }

    /// Each distinct eigenvalue with its multiplicities and α, for reports.
    pub fn entries(&self) -> Vec<SpectrumEntry> {
        self.parts
            .iter()
            .map(|p| SpectrumEntry {
                value: p.value,
                multiplicity: p.multiplicity,
                eigenvectors: p.eigenvectors,
                alpha: p.alpha.is_finite().then_some(p.alpha),
            })
            .collect()
    }

    /// |λ₁|, the largest modulus after the fixed point's (0 for a 1×1 operator).
    pub fn lambda1(&self) -> f64 {
        self.parts.get(1).map_or(0.0, |p| p.value.abs())
    }

    /// Whether every generalised eigenspace is an eigenspace.
    pub fn is_diagonalisable(&self) -> bool {
        self.parts.iter().all(Invariant::is_diagonalisable)
    }

    /// DCF(T, q, t) for t ∈ (0, 1] (the module formula; t = 1 gives q).
    pub fn dcf(&self, q: &DVector<f64>, t: f64) -> DVector<f64> {
        let l1 = self.lambda1();
        let steps = if l1 > 0.0 && l1 < 1.0 {
            t.ln() / l1.ln()
        } else {
            0.0
        };
        let mut out = DVector::<f64>::zeros(q.len());
        for p in &self.parts {
            let weight = if p.alpha.is_infinite() {
                if t == 1.0 { 1.0 } else { 0.0 }
            } else {
                t.powf(p.alpha)
            };
            if weight == 0.0 {
                continue;
            }
            let mut term = &p.projector * q;
            let mut sum = term.clone();
            if !p.is_diagonalisable() && p.value != 0.0 {
                for k in 1..p.multiplicity {
                    term = &p.nilpotent * term / p.value;
                    sum.axpy(binomial(steps, k), &term, 1.0);
                }
            }
            out.axpy(weight, &sum, 1.0);
        }
        out
    }

    /// Σ_{α_c = α} Π_c q, the component of q with exponent α.
    pub fn component(&self, q: &DVector<f64>, alpha: f64) -> DVector<f64> {
        self.parts
            .iter()
            .filter(|p| p.alpha == alpha)
            .fold(DVector::zeros(q.len()), |acc, p| acc + &p.projector * q)
    }

    /// Whether the DCF has a finite second order at the fixed point: every
    /// exponent outside (1, 2), λ₁ real positive, and no nilpotent part with α ≤ 2.
    pub fn second_order_is_finite(&self) -> bool {
        self.parts.get(1).is_some_and(|p| p.value > 0.0)
            && self.parts.iter().skip(1).all(|p| {
                !(p.alpha > 1.0 && p.alpha < 2.0) && (p.alpha > 2.0 || p.is_diagonalisable())
            })
    }

    /// The first- and second-order data of DCF(T, q, ·) at the fixed point,
    /// transported by `word`: a₀, a₁ and a₂ (see the module docs). `sigma` is +1
    /// when the DCF leaves the fixed point towards increasing parameter.
    pub fn frame(&self, q: &DVector<f64>, word: &DMatrix<f64>, sigma: f64) -> Frame {
        Frame {
            sigma,
            point: word * self.component(q, 0.0),
            tangent: word * self.component(q, 1.0),
            second: vec![word * self.component(q, 2.0)],
        }
    }
}

/// SDCF(𝒯, q ⊗ q′, s, t) = DCF(T, q, s) ⊗ DCF(T′, q′, t) (§3.2).
pub fn sdcf(
    (ds, q): (&Decomposition, &DVector<f64>),
    (dt, q2): (&Decomposition, &DVector<f64>),
    s: f64,
    t: f64,
) -> DVector<f64> {
    ds.dcf(q, s).kronecker(&dt.dcf(q2, t))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(rows: &[&[f64]]) -> DMatrix<f64> {
        DMatrix::from_fn(rows.len(), rows.len(), |r, c| rows[r][c])
    }

    #[test]
    fn jordan_block_dcf_follows_the_orbit() {
        // Classical Takagi, w = ½: eigenvalue ½ twice with one eigenvector.
        let t0 = m(&[&[1.0, 0.0, 0.5], &[0.0, 0.5, 0.0], &[0.0, 0.5, 0.5]]);
        let d = Decomposition::new(&t0).unwrap();
        assert_eq!(d.parts.len(), 2);
        assert_eq!((d.parts[1].multiplicity, d.parts[1].eigenvectors), (2, 1));
        assert!(!d.is_diagonalisable() && !d.second_order_is_finite());
        let q = DVector::from_vec(vec![0.2, 0.3, 0.5]);
        let mut orbit = q.clone();
        for n in 0..8 {
            let got = d.dcf(&q, 0.5f64.powi(n));
            assert!((&got - &orbit).amax() < 1e-12, "n = {n}: {got} vs {orbit}");
            orbit = &t0 * orbit;
        }
        // Projectors: complete and idempotent.
        let sum = d
            .parts
            .iter()
            .fold(DMatrix::zeros(3, 3), |a, p| a + &p.projector);
        assert!((sum - DMatrix::identity(3, 3)).amax() < 1e-12);
    }

    #[test]
    fn repeated_diagonalisable_eigenvalue_is_one_part() {
        // T = ½I + ½·e₀·1ᵀ: eigenvalue ½ twice with two eigenvectors.
        let t = m(&[&[1.0, 0.5, 0.5], &[0.0, 0.5, 0.0], &[0.0, 0.0, 0.5]]);
        let d = Decomposition::new(&t).unwrap();
        assert_eq!(d.parts.len(), 2);
        assert_eq!((d.parts[1].multiplicity, d.parts[1].eigenvectors), (2, 2));
        assert!(d.is_diagonalisable() && d.parts[1].nilpotent.amax() == 0.0);
        assert_eq!(d.parts[1].alpha, 1.0);
    }

    #[test]
    fn complex_pair_is_refused() {
        let t = m(&[&[1.0, 0.5, 1.5], &[0.0, 0.0, -0.5], &[0.0, 0.5, 0.0]]);
        assert!(Decomposition::new(&t).unwrap_err().contains("complex"));
    }
}
