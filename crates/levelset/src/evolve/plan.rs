//! The passes of one time step of the flow, shared by the dense sweep
//! (`sweep`, the reference) and the sparse driver (`sparse::flow`).

/// One of the two buffers φ lives in during a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Buf {
    /// `LevelSet::phi`: φⁿ at the start of a step, φⁿ⁺¹ at its end.
    Phi,
    /// The scratch buffer.
    Scratch,
}

/// One pass of a time step. Each reads one buffer with a stencil and writes a
/// buffer on its own nodes, plane by plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    /// Stage 1 of RK2 on T: scratch = φ¹ = φⁿ + Δt L(φⁿ).
    Advance,
    /// Stage 2 on T, in place: φⁿ⁺¹ = ½φⁿ + ½(φ¹ + Δt L(φ¹)); measures the
    /// front movement.
    Finish,
    /// One redistancing iteration on N from the other buffer into `into`,
    /// clamped to ±γ when `clamp` (Eq. 12).
    Redistance { into: Buf, clamp: bool },
    /// φ = scratch on N (after an odd number of redistancing iterations).
    CopyBack,
    /// φ clamped to ±γ on N (no redistancing).
    Clamp,
    /// The new T from φ on the old N with its largest speed; scratch = φ there.
    Rebuild,
}

impl Op {
    /// The buffer read with a stencil, the stencil's reach in planes, and the
    /// buffer written.
    pub(crate) fn access(self) -> (Buf, usize, Buf) {
        match self {
            Op::Advance => (Buf::Phi, 2, Buf::Scratch),
            Op::Finish => (Buf::Scratch, 2, Buf::Phi),
            Op::Redistance {
                into: Buf::Scratch, ..
            } => (Buf::Phi, 1, Buf::Scratch),
            Op::Redistance { into: Buf::Phi, .. } => (Buf::Scratch, 1, Buf::Phi),
            Op::CopyBack => (Buf::Scratch, 0, Buf::Phi),
            Op::Clamp => (Buf::Phi, 0, Buf::Phi),
            Op::Rebuild => (Buf::Phi, 0, Buf::Scratch),
        }
    }
}

/// The passes of one time step: advance, finish, `redistance_iterations`
/// redistancing iterations alternating between the buffers (the last clamps),
/// a copy back or a clamp as the count requires, and the tube rebuild.
pub(crate) fn step_ops(redistance_iterations: usize) -> Vec<Op> {
    let mut ops = vec![Op::Advance, Op::Finish];
    for pass in 0..redistance_iterations {
        ops.push(Op::Redistance {
            into: if pass % 2 == 0 {
                Buf::Scratch
            } else {
                Buf::Phi
            },
            clamp: pass + 1 == redistance_iterations,
        });
    }
    if redistance_iterations % 2 == 1 {
        ops.push(Op::CopyBack);
    } else if redistance_iterations == 0 {
        ops.push(Op::Clamp);
    }
    ops.push(Op::Rebuild);
    ops
}

/// Fixed-point front movement: (Σ|Δφ|/h · 2¹⁶, node count).
pub(crate) type Movement = (u64, u64);
