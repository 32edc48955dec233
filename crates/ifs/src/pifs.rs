//! Projected IFS (poull-gentil §2.1–2.2): two barycentric operators T0, T1 on 𝔹ᴺ
//! (N×N real matrices whose columns sum to 1, acting on column vectors) and N
//! control points P that project a barycentric point ω to Pω = Σ ωᵢ Pᵢ.
//!
//! [`Pifs::new`] validates what the paper requires of a curve-generating IFS and
//! names the constraint an input breaks:
//! - **barycentric**: every column sums to 1 (so points stay points, §2.2);
//! - **contractivity**: apart from the fixed-point eigenvalue 1, every eigenvalue
//!   has modulus < 1 (each operator contracts the barycentric vector space, §2.1);
//! - **C⁰ adjacency**: T0·c1 = T1·c0 with cᵢ the fixed point of Tᵢ (§2.1, as in
//!   Barnsley's fractal interpolation functions) — without it the attractor is a
//!   dust, not a curve.
//!
//! Attractor points are indexed by dyadic parameters: the point at
//! s = 0.b₁b₂…b_n (binary) is T_{b₁}T_{b₂}…T_{b_n}c0, so T0(𝒜) is the half s ∈ [0, ½]
//! and T1(𝒜) the half [½, 1].
//!
//! The tensor-product surface of two P-IFS (§3.1) uses the operators Tᵢ⊗T′ⱼ
//! (Kronecker products) and an N×M grid of control points; since
//! (Tᵢ⊗T′ⱼ)(q⊗q′) = Tᵢq ⊗ T′ⱼq′, its attractor point at (s, t) is
//! Σₐ Σ_b aₐ(s) b_b(t) P_ab with a, b the factors' barycentric attractor points —
//! evaluated that way (N·M operations per vertex) rather than with NM×NM matrices.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use asperity_core::{MemoryBudget, TriMesh};

use crate::error::{Constraint, Result, invalid, violated};
use crate::spectrum::{Spectrum, spectrum};

/// Tolerance of the barycentric and adjacency constraints.
pub const CONSTRAINT_TOL: f64 = 1e-9;

/// Largest barycentric dimension accepted.
pub const MAX_SIZE: usize = 64;

/// Deepest dyadic subdivision of a surface (4^14 ≈ 2.7·10⁸ vertices).
pub const MAX_SURFACE_DEPTH: u32 = 14;

/// Deepest dyadic subdivision of a curve.
pub const MAX_CURVE_DEPTH: u32 = 26;

/// One direction of a P-IFS: two validated barycentric operators.
#[derive(Clone, Debug)]
pub struct Pifs {
    operators: [DMatrix<f64>; 2],
    fixed_points: [DVector<f64>; 2],
    spectra: [Spectrum; 2],
}

fn name(i: usize) -> String {
    format!("T{i}")
}

fn fmt_vec(v: &DVector<f64>) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:.6}")).collect();
    format!("({})", parts.join(", "))
}

/// The fixed point of a barycentric operator: (T − I)c = 0 with Σc = 1.
pub(crate) fn fixed_point(t: &DMatrix<f64>) -> Option<DVector<f64>> {
    let n = t.nrows();
    let mut a = t - DMatrix::<f64>::identity(n, n);
    // The rows of T − I sum to zero, so one equation is redundant: replace it by Σc = 1.
    a.row_mut(n - 1).fill(1.0);
    let mut b = DVector::<f64>::zeros(n);
    b[n - 1] = 1.0;
    a.lu().solve(&b)
}

/// Operator `i` is square, N×N like T0, 2 ≤ N ≤ [`MAX_SIZE`], and finite.
fn check_shape(i: usize, t: &DMatrix<f64>, n: usize) -> Result<()> {
    if t.nrows() != t.ncols() {
        return Err(violated(
            Constraint::Shape,
            format!(
                "{} is {}×{}; operators are square",
                name(i),
                t.nrows(),
                t.ncols()
            ),
        ));
    }
    if t.nrows() != n {
        return Err(violated(
            Constraint::Shape,
            format!(
                "T0 is {n}×{n} but {} is {}×{}",
                name(i),
                t.nrows(),
                t.ncols()
            ),
        ));
    }
    if !(2..=MAX_SIZE).contains(&n) {
        return Err(violated(
            Constraint::Shape,
            format!("operators must be N×N with 2 ≤ N ≤ {MAX_SIZE}, got N = {n}"),
        ));
    }
    if let Some((k, x)) = t.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(violated(
            Constraint::Finite,
            format!(
                "{} entry ({}, {}) is {x}",
                name(i),
                k % n, // column-major storage
                k / n
            ),
        ));
    }
    Ok(())
}

/// Every column of operator `i` sums to 1.
fn check_barycentric(i: usize, t: &DMatrix<f64>, n: usize) -> Result<()> {
    for c in 0..n {
        let s: f64 = t.column(c).sum();
        if (s - 1.0).abs() > CONSTRAINT_TOL {
            return Err(violated(
                Constraint::Barycentric,
                format!(
                    "column {c} of {} sums to {s} (every column of a barycentric operator sums to 1)",
                    name(i)
                ),
            ));
        }
    }
    Ok(())
}

/// The spectrum and fixed point of operator `i`, which must contract: the
/// eigenvalue 1 simple, every other of modulus in (0, 1).
fn contraction(i: usize, t: &DMatrix<f64>) -> Result<(Spectrum, DVector<f64>)> {
    let s = spectrum(t)
        .map_err(|e| violated(Constraint::Contractivity, format!("{}: {e}", name(i))))?;
    let lead = s.values[0];
    let repeated = s
        .values
        .get(1)
        .is_some_and(|v| (v.re - lead.re).hypot(v.im - lead.im) <= crate::spectrum::CLUSTER);
    let refuse = |why: String| Err(violated(Constraint::Contractivity, why));
    if (lead.re - 1.0).abs() > 1e-6 || repeated {
        return refuse(format!(
            "{} has eigenvalue 1 more than once: it fixes a whole line, so it does not contract",
            name(i)
        ));
    }
    let sub = s.subdominant_modulus();
    if sub >= 1.0 - 1e-12 {
        return refuse(format!(
            "{} has an eigenvalue of modulus {sub} besides the fixed-point eigenvalue 1 \
             (every other eigenvalue must have modulus < 1)",
            name(i)
        ));
    }
    if sub == 0.0 {
        return refuse(format!(
            "{} maps everything to its fixed point (all other eigenvalues are 0)",
            name(i)
        ));
    }
    let c = fixed_point(t).ok_or_else(|| {
        violated(
            Constraint::Contractivity,
            format!("{} has no unique fixed point", name(i)),
        )
    })?;
    Ok((s, c))
}

/// The fixed points differ, and T0·c1 = T1·c0: the pieces of the attractor meet.
fn check_adjacency(operators: &[DMatrix<f64>], fixed: &[DVector<f64>]) -> Result<()> {
    if (&fixed[0] - &fixed[1]).amax() <= CONSTRAINT_TOL {
        return Err(violated(
            Constraint::Adjacency,
            format!(
                "T0 and T1 have the same fixed point {}: the attractor is a single point, not a curve",
                fmt_vec(&fixed[0])
            ),
        ));
    }
    let left = &operators[0] * &fixed[1];
    let right = &operators[1] * &fixed[0];
    let gap = (&left - &right).amax();
    if gap > CONSTRAINT_TOL {
        return Err(violated(
            Constraint::Adjacency,
            format!(
                "T0·c1 = {} but T1·c0 = {} (differ by {gap:.3e}); the pieces T0(A) and T1(A) \
                 would not meet and the attractor would be a dust, not a curve",
                fmt_vec(&left),
                fmt_vec(&right)
            ),
        ));
    }
    Ok(())
}

impl Pifs {
    /// Validates two operators (see the module docs).
    ///
    /// # Errors
    /// [`crate::IfsError::Violated`] naming the constraint and the operator.
    pub fn new(operators: Vec<DMatrix<f64>>) -> Result<Self> {
        if operators.len() != 2 {
            return Err(violated(
                Constraint::Shape,
                format!(
                    "a curve P-IFS has exactly 2 operators (T0, T1), got {}",
                    operators.len()
                ),
            ));
        }
        let n = operators[0].nrows();
        for (i, t) in operators.iter().enumerate() {
            check_shape(i, t, n)?;
            check_barycentric(i, t, n)?;
        }
        let mut spectra = Vec::with_capacity(2);
        let mut fixed = Vec::with_capacity(2);
        for (i, t) in operators.iter().enumerate() {
            let (s, c) = contraction(i, t)?;
            spectra.push(s);
            fixed.push(c);
        }
        check_adjacency(&operators, &fixed)?;
        let [s0, s1]: [Spectrum; 2] = spectra.try_into().expect("two spectra");
        let [c0, c1]: [DVector<f64>; 2] = fixed.try_into().expect("two fixed points");
        let [t0, t1]: [DMatrix<f64>; 2] = operators.try_into().expect("two operators");
        Ok(Self {
            operators: [t0, t1],
            fixed_points: [c0, c1],
            spectra: [s0, s1],
        })
    }

    /// Builds from row-major matrices (as written in model files).
    ///
    /// # Errors
    /// As [`Pifs::new`]; ragged rows are a shape violation.
    pub fn from_rows(operators: &[Vec<Vec<f64>>]) -> Result<Self> {
        let mut mats = Vec::with_capacity(operators.len());
        for (i, rows) in operators.iter().enumerate() {
            let n = rows.len();
            if let Some((r, row)) = rows.iter().enumerate().find(|(_, r)| r.len() != n) {
                return Err(violated(
                    Constraint::Shape,
                    format!(
                        "{} has {n} rows but row {r} has {} entries (operators are square)",
                        name(i),
                        row.len()
                    ),
                ));
            }
            mats.push(DMatrix::from_fn(n, n, |r, c| rows[r][c]));
        }
        Self::new(mats)
    }

    /// Row-major copies of the operators (for model files).
    pub fn to_rows(&self) -> Vec<Vec<Vec<f64>>> {
        self.operators
            .iter()
            .map(|t| {
                (0..t.nrows())
                    .map(|r| t.row(r).iter().copied().collect())
                    .collect()
            })
            .collect()
    }

    /// Barycentric dimension N.
    pub fn size(&self) -> usize {
        self.operators[0].nrows()
    }

    /// Operator Tᵢ (i ∈ {0, 1}).
    pub fn operator(&self, i: usize) -> &DMatrix<f64> {
        &self.operators[i]
    }

    /// Fixed point cᵢ of Tᵢ (barycentric, Σ = 1): the attractor's end at s = i.
    pub fn fixed_point(&self, i: usize) -> &DVector<f64> {
        &self.fixed_points[i]
    }

    /// Eigen-decomposition of Tᵢ.
    pub fn spectrum(&self, i: usize) -> &Spectrum {
        &self.spectra[i]
    }

    /// The word T_{b₁}…T_{b_n} of the n binary digits of `k` (most significant first).
    pub fn word(&self, k: u64, n: u32) -> DMatrix<f64> {
        let size = self.size();
        let mut w = DMatrix::<f64>::identity(size, size);
        for d in (0..n).rev() {
            w *= &self.operators[((k >> d) & 1) as usize];
        }
        w
    }

    /// `T_w x` for every word w of `depth` digits, flattened (2^depth × N); entry k
    /// uses the binary digits of k, most significant outermost.
    pub fn apply_words(&self, x: &[f64], depth: u32) -> Vec<f64> {
        let n = self.size();
        let mut cur = x.to_vec();
        for _ in 0..depth {
            let count = cur.len() / n;
            let mut next = vec![0.0; 2 * cur.len()];
            for (b, t) in self.operators.iter().enumerate() {
                let out = &mut next[b * count * n..(b + 1) * count * n];
                for (src, dst) in cur.chunks_exact(n).zip(out.chunks_exact_mut(n)) {
                    for (r, d) in dst.iter_mut().enumerate() {
                        *d = (0..n).map(|c| t[(r, c)] * src[c]).sum();
                    }
                }
            }
            cur = next;
        }
        cur
    }

    /// Barycentric attractor points at s = k/2^depth, k = 0…2^depth, flattened
    /// ((2^depth + 1) × N).
    pub fn dyadic_points(&self, depth: u32) -> Vec<f64> {
        let mut pts = self.apply_words(self.fixed_points[0].as_slice(), depth);
        pts.extend_from_slice(self.fixed_points[1].as_slice());
        pts
    }

    /// The barycentric attractor point at parameter s ∈ [0, 1] (53 binary digits:
    /// exact for dyadic s, within contraction⁵³ otherwise).
    ///
    /// # Errors
    /// [`crate::IfsError::InvalidParameter`] outside [0, 1] or for NaN.
    pub fn point_at(&self, s: f64) -> Result<DVector<f64>> {
        if !(0.0..=1.0).contains(&s) {
            return Err(invalid("parameter", format!("{s} is outside [0, 1]")));
        }
        if s == 1.0 {
            return Ok(self.fixed_points[1].clone());
        }
        let mut digits = Vec::with_capacity(53);
        let mut x = s;
        for _ in 0..53 {
            x *= 2.0;
            let b = usize::from(x >= 1.0);
            x -= b as f64;
            digits.push(b);
        }
        let mut p = self.fixed_points[0].clone();
        for &b in digits.iter().rev() {
            p = &self.operators[b] * p;
        }
        Ok(p)
    }

    /// The fixed point of the word `digits` (the periodic point 0.(digits)^∞).
    pub fn periodic_point(&self, digits: &[usize]) -> Option<DVector<f64>> {
        let n = self.size();
        let mut w = DMatrix::<f64>::identity(n, n);
        for &b in digits {
            w *= &self.operators[b];
        }
        fixed_point(&w)
    }
}

/// Checks a dyadic depth against a limit.
fn check_depth(depth: u32, max: u32) -> Result<()> {
    if depth > max {
        return Err(invalid(
            "depth",
            format!("{depth} is above the limit {max}"),
        ));
    }
    Ok(())
}

fn check_points(
    points: &[Vec<f64>],
    expected: usize,
    what: &str,
) -> Result<(usize, Vec<[f64; 3]>)> {
    if points.len() != expected {
        return Err(violated(
            Constraint::Shape,
            format!(
                "{what}: the operators act on {expected} barycentric coordinates, so {expected} control points are needed, got {}",
                points.len()
            ),
        ));
    }
    let dim = points.first().map_or(3, Vec::len);
    let mut out = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        if p.len() != dim || !(2..=3).contains(&p.len()) {
            return Err(violated(
                Constraint::Shape,
                format!(
                    "{what}: control point {i} has {} coordinates; all must have 2 or all 3",
                    p.len()
                ),
            ));
        }
        if let Some(x) = p.iter().find(|x| !x.is_finite()) {
            return Err(violated(
                Constraint::Finite,
                format!("{what}: control point {i} has coordinate {x}"),
            ));
        }
        out.push([p[0], p[1], p.get(2).copied().unwrap_or(0.0)]);
    }
    Ok((dim, out))
}

/// A P-IFS curve: one [`Pifs`] and its N control points in 2-D or 3-D.
#[derive(Clone, Debug)]
pub struct CurveIfs {
    /// The operators.
    pub pifs: Pifs,
    control: Vec<[f64; 3]>,
    dim: usize,
}

impl CurveIfs {
    /// Pairs operators with control points (all 2-D or all 3-D).
    ///
    /// # Errors
    /// Shape (count, dimension) or finiteness violations.
    pub fn new(pifs: Pifs, control: &[Vec<f64>]) -> Result<Self> {
        let (dim, control) = check_points(control, pifs.size(), "curve")?;
        Ok(Self { pifs, control, dim })
    }

    /// Control points (z = 0 for 2-D curves).
    pub fn control(&self) -> &[[f64; 3]] {
        &self.control
    }

    /// 2 or 3.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Moves control point `i`.
    ///
    /// # Errors
    /// Index out of range or a non-finite coordinate.
    pub fn move_point(&mut self, i: usize, to: [f64; 3]) -> Result<()> {
        let n = self.control.len();
        let p = self.control.get_mut(i).ok_or_else(|| {
            invalid(
                "move",
                format!("control point {i} does not exist (N = {n})"),
            )
        })?;
        if to.iter().any(|x| !x.is_finite()) {
            return Err(invalid("move", "coordinates must be finite"));
        }
        *p = to;
        Ok(())
    }

    /// Pω = Σ ωᵢ Pᵢ.
    pub fn project(&self, bary: &[f64]) -> [f64; 3] {
        project(&self.control, bary)
    }

    /// Attractor points at s = k/2^depth.
    ///
    /// # Errors
    /// Depth above [`MAX_CURVE_DEPTH`].
    pub fn attractor(&self, depth: u32) -> Result<Vec<[f64; 3]>> {
        check_depth(depth, MAX_CURVE_DEPTH)?;
        let n = self.pifs.size();
        Ok(self
            .pifs
            .dyadic_points(depth)
            .chunks_exact(n)
            .map(|b| self.project(b))
            .collect())
    }
}

/// Σ ωᵢ Pᵢ.
pub fn project(control: &[[f64; 3]], bary: &[f64]) -> [f64; 3] {
    let mut p = [0.0; 3];
    for (w, c) in bary.iter().zip(control) {
        for k in 0..3 {
            p[k] += w * c[k];
        }
    }
    p
}

/// A tensor-product P-IFS surface (§3.1): factors in s (N×N) and t (M×M) and an
/// N×M control grid, stored row-major (index a·M + b).
#[derive(Clone, Debug)]
pub struct SurfaceIfs {
    /// The s-direction factor 𝕋.
    pub s: Pifs,
    /// The t-direction factor 𝕋′.
    pub t: Pifs,
    control: Vec<[f64; 3]>,
}

impl SurfaceIfs {
    /// Pairs two factors with an N×M grid of 3-D control points (`grid[a][b]`).
    ///
    /// # Errors
    /// Shape or finiteness violations.
    pub fn new(s: Pifs, t: Pifs, grid: &[Vec<Vec<f64>>]) -> Result<Self> {
        let (n, m) = (s.size(), t.size());
        if grid.len() != n {
            return Err(violated(
                Constraint::Shape,
                format!(
                    "surface: the control grid needs {n} rows (the s operators are {n}×{n}), got {}",
                    grid.len()
                ),
            ));
        }
        let mut control = Vec::with_capacity(n * m);
        for (a, row) in grid.iter().enumerate() {
            let (dim, pts) = check_points(row, m, &format!("surface row {a}"))?;
            if dim != 3 {
                return Err(violated(
                    Constraint::Shape,
                    format!("surface row {a}: surface control points are 3-D"),
                ));
            }
            control.extend(pts);
        }
        Ok(Self { s, t, control })
    }

    /// The control grid, row-major (a·M + b).
    pub fn control(&self) -> &[[f64; 3]] {
        &self.control
    }

    /// (N, M).
    pub fn grid_size(&self) -> (usize, usize) {
        (self.s.size(), self.t.size())
    }

    /// Moves control point (a, b).
    ///
    /// # Errors
    /// Index out of range or a non-finite coordinate.
    pub fn move_point(&mut self, a: usize, b: usize, to: [f64; 3]) -> Result<()> {
        let (n, m) = self.grid_size();
        if a >= n || b >= m {
            return Err(invalid(
                "move",
                format!("control point ({a}, {b}) does not exist (grid {n}×{m})"),
            ));
        }
        if to.iter().any(|x| !x.is_finite()) {
            return Err(invalid("move", "coordinates must be finite"));
        }
        self.control[a * m + b] = to;
        Ok(())
    }

    /// The tensor operator 𝒯ᵢⱼ = Tᵢ ⊗ T′ⱼ (NM×NM).
    pub fn operator(&self, i: usize, j: usize) -> DMatrix<f64> {
        self.s.operator(i).kronecker(self.t.operator(j))
    }

    /// Contracts the grid with an s-barycentric vector: Q_b = Σₐ aₐ P_ab (M points).
    pub fn contract_s(&self, a: &[f64]) -> Vec<[f64; 3]> {
        let m = self.t.size();
        let mut q = vec![[0.0; 3]; m];
        for (ai, &w) in a.iter().enumerate() {
            for (b, qb) in q.iter_mut().enumerate() {
                let p = self.control[ai * m + b];
                for k in 0..3 {
                    qb[k] += w * p[k];
                }
            }
        }
        q
    }

    /// P(a ⊗ b).
    pub fn project(&self, a: &[f64], b: &[f64]) -> [f64; 3] {
        project(&self.contract_s(a), b)
    }

    /// The attractor on the dyadic grid (2^depth + 1)² as a triangle mesh, vertex
    /// (k, l) at index k·(2^depth + 1) + l with uv = (s, t); two triangles per
    /// cell, oriented so the normal is ∂/∂s × ∂/∂t.
    ///
    /// # Errors
    /// Depth above [`MAX_SURFACE_DEPTH`]; the memory estimate above `budget`.
    pub fn attractor_mesh(&self, depth: u32, budget: &MemoryBudget) -> Result<TriMesh> {
        check_depth(depth, MAX_SURFACE_DEPTH)?;
        let bs = self.s.dyadic_points(depth);
        let bt = self.t.dyadic_points(depth);
        grid_mesh(self, &bs, &bt, budget, true)
    }
}

/// Meshes P(a_k ⊗ b_l) over all pairs of the flattened barycentric rows `bs`
/// (stride N) and `bt` (stride M); uv = (k/(K−1), l/(L−1)).
pub(crate) fn grid_mesh(
    surface: &SurfaceIfs,
    bs: &[f64],
    bt: &[f64],
    budget: &MemoryBudget,
    with_uv: bool,
) -> Result<TriMesh> {
    let (n, m) = surface.grid_size();
    let (rows, cols) = (bs.len() / n, bt.len() / m);
    // positions + normals + uv (f64) and two triangles per cell.
    budget.check_elements((rows * cols) as u128, 72, "the attractor mesh vertices")?;
    budget.check_elements(
        (2 * rows * cols) as u128,
        12,
        "the attractor mesh triangles",
    )?;
    let mut positions = vec![[0.0; 3]; rows * cols];
    positions
        .par_chunks_mut(cols)
        .zip(bs.par_chunks(n))
        .for_each(|(out, a)| {
            let q = surface.contract_s(a);
            for (p, b) in out.iter_mut().zip(bt.chunks_exact(m)) {
                *p = project(&q, b);
            }
        });
    let mut triangles = Vec::with_capacity(2 * (rows - 1) * (cols - 1));
    for k in 0..rows - 1 {
        for l in 0..cols - 1 {
            let v = |kk: usize, ll: usize| (kk * cols + ll) as u32;
            triangles.push([v(k, l), v(k + 1, l), v(k + 1, l + 1)]);
            triangles.push([v(k, l), v(k + 1, l + 1), v(k, l + 1)]);
        }
    }
    let mut mesh = TriMesh::new(positions, triangles)?;
    if with_uv {
        let uvs = (0..rows * cols)
            .map(|i| {
                [
                    (i / cols) as f64 / (rows - 1) as f64,
                    (i % cols) as f64 / (cols - 1) as f64,
                ]
            })
            .collect();
        mesh = mesh.with_uvs(uvs)?;
    }
    Ok(mesh.with_computed_normals())
}
