//! Evaluating DCFs and SDCFs as geometry (poull-gentil §2.3 Fig. 2, §3 Fig. 4).
//!
//! DCF(T, q, t) for t ∈ [0, 1] runs from the fixed point of T (t = 0) to the
//! starting point q (t = 1); the SDCF of 𝒯 = T⊗T′ at Q = q⊗q′ is the tensor
//! product DCF(T, q, s) ⊗ DCF(T′, q′, t), projected with the control grid —
//! evaluated like the attractor, as P(a(s) ⊗ b(t)).

use nalgebra::DVector;

use asperity_core::{MemoryBudget, TriMesh};

use crate::dcf::OperatorAnalysis;
use crate::error::{IfsError, Result, invalid};
use crate::invariant::Decomposition;
use crate::pifs::{CurveIfs, Pifs, SurfaceIfs, grid_mesh, project as pifs_project};

/// Which member of the family to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// The attractor point at this parameter.
    Parameter(f64),
    /// The lower-bound member (smallest c₂).
    Lower,
    /// The upper-bound member (largest c₂).
    Upper,
}

fn no_dcf(a: &OperatorAnalysis, name: &str) -> IfsError {
    IfsError::NoDcf {
        operator: name.to_owned(),
        reason: a
            .reason
            .clone()
            .unwrap_or_else(|| "no family member".to_owned()),
    }
}

/// The barycentric starting point for `start`.
///
/// # Errors
/// No DCF for this operator; a parameter outside [0, 1].
pub fn start_point(pifs: &Pifs, a: &OperatorAnalysis, start: Start) -> Result<DVector<f64>> {
    let name = format!("T{}", a.operator);
    let dcf = a.dcf.as_ref().ok_or_else(|| no_dcf(a, &name))?;
    match start {
        Start::Parameter(s) => pifs.point_at(s),
        Start::Lower => Ok(dcf.lower().ok_or_else(|| no_dcf(a, &name))?.point.clone()),
        Start::Upper => Ok(dcf.upper().ok_or_else(|| no_dcf(a, &name))?.point.clone()),
    }
}

/// Refuses a sample count outside 1..=2²⁰.
fn check_samples(samples: usize) -> Result<()> {
    if (1..=1 << 20).contains(&samples) {
        Ok(())
    } else {
        Err(invalid("samples", format!("{samples} is outside 1..=2^20")))
    }
}

/// Barycentric DCF samples t = j/samples, j = 0…samples, flattened.
fn dcf_samples(a: &OperatorAnalysis, q: &DVector<f64>, samples: usize) -> Result<Vec<f64>> {
    let dcf = a
        .dcf
        .as_ref()
        .ok_or_else(|| no_dcf(a, &format!("T{}", a.operator)))?;
    check_samples(samples)?;
    Ok((0..=samples)
        .flat_map(|j| {
            dcf.evaluate(q, j as f64 / samples as f64)
                .iter()
                .copied()
                .collect::<Vec<_>>()
        })
        .collect())
}

/// The DCF of a curve operator from its fixed point (t = 0) to `q` (t = 1),
/// projected into the modelling space.
///
/// # Errors
/// No DCF for this operator; `samples` outside 1..=2²⁰.
pub fn dcf_polyline(
    curve: &CurveIfs,
    a: &OperatorAnalysis,
    q: &DVector<f64>,
    samples: usize,
) -> Result<Vec<[f64; 3]>> {
    let n = curve.pifs.size();
    Ok(dcf_samples(a, q, samples)?
        .chunks_exact(n)
        .map(|b| curve.project(b))
        .collect())
}

/// The SDCF of 𝒯ᵢⱼ = Tᵢ⊗T′ⱼ (operators `a`, `b`) at Q = q⊗q′ on a (resolution + 1)² grid of (s, t) ∈ [0, 1]²,
/// as a mesh with uv = (s, t).
///
/// # Errors
/// No DCF for an operator; resolution outside 1..=4096; the memory budget.
pub fn sdcf_mesh(
    surface: &SurfaceIfs,
    (a, q): (&OperatorAnalysis, &DVector<f64>),
    (b, q2): (&OperatorAnalysis, &DVector<f64>),
    resolution: usize,
    budget: &MemoryBudget,
) -> Result<TriMesh> {
    if !(1..=4096).contains(&resolution) {
        return Err(invalid(
            "resolution",
            format!("{resolution} is outside 1..=4096"),
        ));
    }
    let bs = dcf_samples(a, q, resolution)?;
    let bt = dcf_samples(b, q2, resolution)?;
    grid_mesh(surface, &bs, &bt, budget, true)
}

/// The DCF of the tensor operator 𝒯ᵢⱼ itself at Q = q ⊗ q′, from 𝒯ᵢⱼ's own
/// general spectrum ([`crate::invariant`]: its repeated eigenvalues grouped by
/// invariant subspace), projected: t = j/samples, j = 0…samples. It lies on the
/// SDCF — along s = t when λ₁ = λ′₁ (Fig. 4's yellow curve).
///
/// # Errors
/// A spectrum with a complex pair (no DCF); `samples` outside 1..=2²⁰.
pub fn tensor_dcf_polyline(
    surface: &SurfaceIfs,
    (i, j): (usize, usize),
    (q, q2): (&DVector<f64>, &DVector<f64>),
    samples: usize,
) -> Result<Vec<[f64; 3]>> {
    check_samples(samples)?;
    let d = Decomposition::new(&surface.operator(i, j)).map_err(|reason| IfsError::NoDcf {
        operator: format!("T{i}⊗T'{j}"),
        reason,
    })?;
    let big_q = q.kronecker(q2);
    Ok((0..=samples)
        .map(|k| {
            // t = 0 is the fixed point; ln 0 would make the Jordan terms NaN.
            let t = (k as f64 / samples as f64).max(f64::MIN_POSITIVE);
            pifs_project(surface.control(), d.dcf(&big_q, t).as_slice())
        })
        .collect())
}
