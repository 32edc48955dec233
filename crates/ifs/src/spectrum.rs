//! Eigen-decomposition of a barycentric operator, ordered as the DCF needs it
//! (poull-gentil §2.3): the fixed-point eigenvalue λ₀ = 1 first, then the others by
//! decreasing modulus, with αᵢ = log|λᵢ| / log|λ₁|.
//!
//! nalgebra's real Schur decomposition gives the eigenvalues (the operators are not
//! symmetric); eigenvectors are the null spaces of T − λI from an SVD. Eigenvalues
//! closer than [`CLUSTER`] are treated as one repeated eigenvalue, and a repeated
//! eigenvalue whose null space is smaller than its multiplicity is a Jordan block —
//! the operator is reported as not diagonalisable instead of producing a DCF full of
//! NaN (the classical Takagi curve, w = 1/2, is the standard example).

use nalgebra::{DMatrix, Schur};

/// Exponents within this distance of an integer are snapped to it, so that
/// t^(α−2) behaves exactly at α = 2 (issue contract: 1e-9).
pub const ALPHA_SNAP: f64 = 1e-9;

/// Eigenvalues closer than this (relative to max(1, |λ|)) are one repeated eigenvalue.
pub const CLUSTER: f64 = 1e-6;

/// One eigenvalue (complex in general).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigenvalue {
    /// Real part.
    pub re: f64,
    /// Imaginary part (0 for real eigenvalues).
    pub im: f64,
}

impl Eigenvalue {
    /// |λ|.
    pub fn modulus(self) -> f64 {
        self.re.hypot(self.im)
    }
}

/// What the eigen-decomposition found.
#[derive(Clone, Debug, PartialEq)]
pub enum Structure {
    /// Real and diagonalisable: T = V Λ V⁻¹, columns of V in the order of
    /// [`Spectrum::values`]. Column 0 is the fixed point (entries sum to 1); the
    /// others are vectors (entries sum to 0) of unit length.
    Diagonalisable {
        /// Eigenvectors as columns.
        vectors: DMatrix<f64>,
        /// V⁻¹: row k gives the k-th eigen-coordinate of a point.
        inverse: DMatrix<f64>,
        /// α₀ = 0, α₁ = 1, αₖ = log|λₖ|/log|λ₁| (+∞ for λₖ = 0), snapped to integers.
        alpha: Vec<f64>,
    },
    /// A repeated eigenvalue with fewer independent eigenvectors than its multiplicity.
    NonDiagonalisable {
        /// The repeated eigenvalue.
        value: f64,
        /// Its multiplicity as a root of the characteristic polynomial.
        algebraic: usize,
        /// The dimension of its eigenspace.
        geometric: usize,
    },
    /// A complex pair among the eigenvalues (the orbit spirals; t^α cannot follow it).
    Complex {
        /// The pair's real part.
        re: f64,
        /// Its imaginary part (positive).
        im: f64,
    },
}

/// Eigenvalues and their structure.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectrum {
    /// Eigenvalues: the one nearest 1 first, then by decreasing modulus.
    pub values: Vec<Eigenvalue>,
    /// Eigenvectors and exponents, or why there are none.
    pub structure: Structure,
}

impl Spectrum {
    /// The exponents αᵢ when the operator is diagonalisable.
    pub fn alpha(&self) -> Option<&[f64]> {
        match &self.structure {
            Structure::Diagonalisable { alpha, .. } => Some(alpha),
            _ => None,
        }
    }

    /// Largest modulus among the eigenvalues other than λ₀ (0 for a 1×1 operator).
    pub fn subdominant_modulus(&self) -> f64 {
        self.values.get(1).map_or(0.0, |v| v.modulus())
    }
}

/// Eigenvalues equal within [`CLUSTER`]: their mean and the computed values.
pub(crate) struct Cluster {
    pub(crate) re: f64,
    pub(crate) im: f64,
    pub(crate) members: Vec<(f64, f64)>,
}

impl Cluster {
    pub(crate) fn spread(&self) -> f64 {
        self.members
            .iter()
            .map(|&(r, i)| (r - self.re).hypot(i - self.im))
            .fold(0.0, f64::max)
    }
}

/// Snaps `a` to the nearest integer when within [`ALPHA_SNAP`].
pub fn snap(a: f64) -> f64 {
    let r = a.round();
    if (a - r).abs() <= ALPHA_SNAP { r } else { a }
}

/// The eigenvalues of `t` from its real Schur form.
///
/// nalgebra's Francis iteration deflates when a subdiagonal entry falls below
/// `eps` times its neighbours; with `eps` = machine epsilon it can fail to meet
/// that test on operators with exact structure and repeated eigenvalues (the
/// tensor square of the Takagi w = ¼ curve's T1 is one: nine eigenvalues, five of
/// them repeated). The eigenvalues of the transpose are the same, and a deflation
/// threshold of 8ε changes them by rounding only, so those are tried in turn.
fn schur_eigenvalues(t: &DMatrix<f64>) -> Result<Vec<(f64, f64)>, String> {
    let iterations = 1000 * t.nrows().max(1);
    let attempt = |m: DMatrix<f64>, eps: f64| {
        Schur::try_new(m, eps, iterations).map(|s| {
            s.complex_eigenvalues()
                .iter()
                .map(|z| (z.re, z.im))
                .collect::<Vec<_>>()
        })
    };
    attempt(t.clone(), f64::EPSILON)
        .or_else(|| attempt(t.transpose(), f64::EPSILON))
        .or_else(|| attempt(t.clone(), 8.0 * f64::EPSILON))
        .ok_or_else(|| "the eigenvalue (Schur) iteration did not converge".to_owned())
}

/// A Jordan block of size k is split by rounding into k computed eigenvalues about
/// (ε‖T‖)^{1/k} from the true one (on a circle around it, so their mean stays
/// accurate). Two clusters are merged within 10·[`JORDAN_EPS`]^{1/k} (relative,
/// at least [`CLUSTER`]) where k counts the eigenvalues near them, never beyond
/// [`MERGE_CAP`].
pub const JORDAN_EPS: f64 = 1e-15;

/// Two clusters further apart than this (relative to max(1, |λ|)) are never merged.
pub const MERGE_CAP: f64 = 1e-3;

/// Eigenvalues of `t` grouped into clusters of (numerically) equal values,
/// closest pairs first (see [`JORDAN_EPS`]).
pub(crate) fn clusters_of(t: &DMatrix<f64>) -> Result<Vec<Cluster>, String> {
    let values = schur_eigenvalues(t)?;
    let mut clusters: Vec<Cluster> = values
        .iter()
        .map(|&(re, im)| Cluster {
            re,
            im,
            members: vec![(re, im)],
        })
        .collect();
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for a in 0..clusters.len() {
            for b in a + 1..clusters.len() {
                let (ca, cb) = (&clusters[a], &clusters[b]);
                let d = (ca.re - cb.re).hypot(ca.im - cb.im);
                let scale = ca.re.hypot(ca.im).max(cb.re.hypot(cb.im)).max(1.0);
                if d > MERGE_CAP * scale {
                    continue;
                }
                let (mr, mi) = ((ca.re + cb.re) / 2.0, (ca.im + cb.im) / 2.0);
                let near = values
                    .iter()
                    .filter(|&&(r, i)| (r - mr).hypot(i - mi) <= 2.0 * d)
                    .count()
                    .max(2) as f64;
                let tol = (10.0 * JORDAN_EPS.powf(1.0 / near)).clamp(CLUSTER, MERGE_CAP) * scale;
                if d <= tol && best.is_none_or(|(bd, _, _)| d < bd) {
                    best = Some((d, a, b));
                }
            }
        }
        let Some((_, a, b)) = best else { break };
        let merged = clusters.remove(b);
        let c = &mut clusters[a];
        c.members.extend(merged.members);
        let k = c.members.len() as f64;
        c.re = c.members.iter().map(|m| m.0).sum::<f64>() / k;
        c.im = c.members.iter().map(|m| m.1).sum::<f64>() / k;
    }
    Ok(clusters)
}

/// The clusters in the order the analysis uses: the fixed-point eigenvalue
/// (nearest to 1) first, then by decreasing modulus.
pub(crate) fn order_clusters(mut clusters: Vec<Cluster>) -> Vec<Cluster> {
    let first = clusters
        .iter()
        .enumerate()
        .min_by(|a, b| {
            let da = (a.1.re - 1.0).hypot(a.1.im);
            let db = (b.1.re - 1.0).hypot(b.1.im);
            da.total_cmp(&db)
        })
        .map_or(0, |(i, _)| i);
    let head = clusters.remove(first);
    clusters.sort_by(|a, b| {
        b.re.hypot(b.im)
            .total_cmp(&a.re.hypot(a.im))
            .then(b.re.total_cmp(&a.re))
            .then(b.im.total_cmp(&a.im))
    });
    clusters.insert(0, head);
    clusters
}

/// Eigenvector `v` normalised: the fixed point's to sum 1 (barycentric), the
/// others to unit length with the largest component positive (a deterministic
/// choice).
fn normalise(v: &mut [f64], fixed_point: bool) {
    if fixed_point {
        let s: f64 = v.iter().sum();
        if s.abs() > 1e-12 {
            v.iter_mut().for_each(|x| *x /= s);
        }
    } else {
        let big = v
            .iter()
            .copied()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(1.0);
        let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let f = big.signum() / len;
        v.iter_mut().for_each(|x| *x *= f);
    }
}

/// The eigenvectors of every cluster as the columns of a matrix (from the null
/// space of T − λI by SVD), or the structure when a cluster has fewer
/// independent eigenvectors than members.
fn eigenvectors(
    t: &DMatrix<f64>,
    clusters: &[Cluster],
) -> Result<Result<DMatrix<f64>, Structure>, String> {
    let n = t.nrows();
    let norm = t.norm().max(1.0);
    let mut vectors = DMatrix::<f64>::zeros(n, n);
    let mut col = 0;
    for (ci, c) in clusters.iter().enumerate() {
        let shifted = t - DMatrix::<f64>::identity(n, n) * c.re;
        let svd = shifted.svd(false, true);
        let v_t = svd
            .v_t
            .as_ref()
            .ok_or_else(|| "SVD without right singular vectors".to_owned())?;
        let tol = (1e-9f64).max(10.0 * c.spread()) * norm;
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
        let geometric = order
            .iter()
            .filter(|&&k| svd.singular_values[k] <= tol)
            .count();
        let algebraic = c.members.len();
        if geometric < algebraic {
            return Ok(Err(Structure::NonDiagonalisable {
                value: c.re,
                algebraic,
                geometric,
            }));
        }
        for &k in order.iter().take(algebraic) {
            let mut v: Vec<f64> = v_t.row(k).iter().copied().collect();
            normalise(&mut v, ci == 0);
            for (r, x) in v.into_iter().enumerate() {
                vectors[(r, col)] = x;
            }
            col += 1;
        }
    }
    Ok(Ok(vectors))
}

/// α_k = log|λ_k| / log|λ_1| (α₀ = 0, α₁ = 1; ∞ where undefined), snapped to
/// integers within [`ALPHA_SNAP`].
fn alphas(values: &[Eigenvalue]) -> Vec<f64> {
    let l1 = values.get(1).map_or(0.0, |v| v.modulus());
    values
        .iter()
        .enumerate()
        .map(|(k, v)| match k {
            0 => 0.0,
            1 => 1.0,
            _ if v.modulus() == 0.0 => f64::INFINITY,
            _ if l1 == 0.0 || l1 == 1.0 => f64::INFINITY,
            _ => snap(v.modulus().ln() / l1.ln()),
        })
        .collect()
}

/// Eigen-decomposition of `t` (square, finite).
///
/// # Errors
/// A message when the Schur iteration does not converge.
pub fn spectrum(t: &DMatrix<f64>) -> Result<Spectrum, String> {
    let clusters = order_clusters(clusters_of(t)?);
    let values: Vec<Eigenvalue> = clusters
        .iter()
        .flat_map(|c| {
            std::iter::repeat_n(
                Eigenvalue {
                    re: c.re,
                    im: if c.im.abs() <= CLUSTER { 0.0 } else { c.im },
                },
                c.members.len(),
            )
        })
        .collect();
    let done = |structure| {
        Ok(Spectrum {
            values: values.clone(),
            structure,
        })
    };
    if let Some(c) = clusters.iter().find(|c| c.im.abs() > CLUSTER) {
        return done(Structure::Complex {
            re: c.re,
            im: c.im.abs(),
        });
    }
    let vectors = match eigenvectors(t, &clusters)? {
        Ok(v) => v,
        Err(structure) => return done(structure),
    };
    let Some(inverse) = vectors.clone().try_inverse() else {
        let c = &clusters[1.min(clusters.len() - 1)];
        return done(Structure::NonDiagonalisable {
            value: c.re,
            algebraic: c.members.len(),
            geometric: 0,
        });
    };
    let alpha = alphas(&values);
    done(Structure::Diagonalisable {
        vectors,
        inverse,
        alpha,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(rows: &[&[f64]]) -> DMatrix<f64> {
        DMatrix::from_fn(rows.len(), rows.len(), |r, c| rows[r][c])
    }

    #[test]
    fn quadratic_de_casteljau_operator() {
        let t0 = m(&[&[1.0, 0.5, 0.25], &[0.0, 0.5, 0.5], &[0.0, 0.0, 0.25]]);
        let s = spectrum(&t0).unwrap();
        let got: Vec<f64> = s.values.iter().map(|v| v.re).collect();
        assert_eq!(got, vec![1.0, 0.5, 0.25]);
        let Structure::Diagonalisable {
            vectors,
            inverse,
            alpha,
        } = &s.structure
        else {
            panic!("{s:?}")
        };
        assert_eq!(alpha, &vec![0.0, 1.0, 2.0]);
        // T V = V Λ and V V⁻¹ = I.
        for (k, &lambda) in got.iter().enumerate() {
            let v = vectors.column(k);
            let tv = &t0 * v;
            assert!((tv - v * lambda).amax() < 1e-14);
        }
        assert!((vectors * inverse - DMatrix::identity(3, 3)).norm() < 1e-13);
        // The fixed point (1, 0, 0) and v2 ∝ (1, −2, 1).
        assert!((vectors[(0, 0)] - 1.0).abs() < 1e-14);
        let v2 = vectors.column(2);
        assert!((v2[1] / v2[0] + 2.0).abs() < 1e-12 && (v2[2] / v2[0] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn jordan_block_is_detected() {
        // Takagi w = 1/2: eigenvalue 1/2 twice with one eigenvector.
        let w = 0.5;
        let t0 = m(&[&[1.0, 0.0, 1.0 - w], &[0.0, 0.5, 0.0], &[0.0, 0.5, w]]);
        let s = spectrum(&t0).unwrap();
        assert!(
            matches!(
                s.structure,
                Structure::NonDiagonalisable {
                    algebraic: 2,
                    geometric: 1,
                    ..
                }
            ),
            "{s:?}"
        );
        // A repeated eigenvalue with two eigenvectors is diagonalisable:
        // T = ½I + ½·c·1ᵀ with c = (1, 0, 0).
        let d = m(&[&[1.0, 0.5, 0.5], &[0.0, 0.5, 0.0], &[0.0, 0.0, 0.5]]);
        let s = spectrum(&d).unwrap();
        assert!(
            matches!(s.structure, Structure::Diagonalisable { .. }),
            "{s:?}"
        );
    }

    #[test]
    fn schur_retries_a_structured_tensor_operator() {
        // T1 ⊗ T1 of the Takagi w = ¼ curve: the plain Francis iteration cycles.
        let w = 0.25;
        let t1 = m(&[&[0.0, 0.0, -w], &[0.5, 1.0, 0.5], &[0.5, 0.0, 0.5 + w]]);
        let s = spectrum(&t1.kronecker(&t1)).unwrap();
        let mut got: Vec<f64> = s.values.iter().map(|v| v.re).collect();
        got.sort_by(f64::total_cmp);
        let mut want: Vec<f64> = [1.0, 0.5, w]
            .iter()
            .flat_map(|a| [1.0, 0.5, w].map(|b| a * b))
            .collect();
        want.sort_by(f64::total_cmp);
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-9, "{got:?} vs {want:?}");
        }
        assert!(matches!(s.structure, Structure::Diagonalisable { .. }));
    }

    #[test]
    fn complex_pair_is_detected() {
        // Fixed point e0; on the vectors u1 = e1 − e0, u2 = e2 − e0 it is a
        // quarter turn scaled by ½: T u1 = ½u2, T u2 = −½u1.
        let t = m(&[&[1.0, 0.5, 1.5], &[0.0, 0.0, -0.5], &[0.0, 0.5, 0.0]]);
        let s = spectrum(&t).unwrap();
        assert!(matches!(s.structure, Structure::Complex { .. }), "{s:?}");
        assert!((s.subdominant_modulus() - s.values[2].modulus()).abs() < 1e-12);
    }
}
