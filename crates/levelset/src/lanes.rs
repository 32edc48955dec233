//! Eight `f32` lanes for the flow's kernels, with the instruction set chosen when
//! the program runs.
//!
//! `wide::f32x8` is portable, but it picks its instructions when `wide` itself is
//! compiled: for the baseline x86-64 target that is a pair of SSE registers per
//! vector, whatever the CPU running the program has. The kernels are therefore
//! written once, generic over [`Lanes`], and [`dispatch`] runs them with `Avx`
//! (one 256-bit AVX register) on CPUs with AVX and with `wide::f32x8` elsewhere.
//! At 256³ that is a third off the flow's time on the development machine.
//!
//! Only correctly rounded IEEE operations are used (no fused multiply-add, no
//! approximate reciprocals), and the minimum, maximum, blend and conversion
//! instructions are the AVX forms of the SSE ones `wide` uses, so both
//! instantiations give the same bits (tested).

use std::ops::{Add, AddAssign, BitAnd, Div, Mul, Sub, SubAssign};

use wide::f32x8;

/// Eight `f32` lanes. Comparisons return masks of the same type (every bit of a
/// lane set or clear).
pub(crate) trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
    + SubAssign
    + BitAnd<Output = Self>
{
    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// The lanes `x`.
    fn new(x: [f32; 8]) -> Self;
    /// The lanes as an array.
    fn to_array(self) -> [f32; 8];
    /// |x|.
    fn abs(self) -> Self;
    /// `self < o ? self : o` per lane (the `minps` rule).
    fn fast_min(self, o: Self) -> Self;
    /// `self > o ? self : o` per lane (the `maxps` rule).
    fn fast_max(self, o: Self) -> Self;
    /// √x, correctly rounded.
    fn sqrt(self) -> Self;
    /// The mask of `self < o`.
    fn simd_lt(self, o: Self) -> Self;
    /// The mask of `self ≤ o`.
    fn simd_le(self, o: Self) -> Self;
    /// The mask of `self > o`.
    fn simd_gt(self, o: Self) -> Self;
    /// Per lane, `t` where the mask `self` is set, else `f`.
    fn select(self, t: Self, f: Self) -> Self;
    /// The mask's lanes as bits, lane 0 lowest.
    fn to_bitmask(self) -> u32;
    /// The sum of the lanes truncated to integers (lanes in [0, 2³¹)).
    fn trunc_sum(self) -> u64;
}

impl Lanes for f32x8 {
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn new(x: [f32; 8]) -> Self {
        f32x8::new(x)
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        f32x8::to_array(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x8::abs(self)
    }
    #[inline(always)]
    fn fast_min(self, o: Self) -> Self {
        f32x8::fast_min(self, o)
    }
    #[inline(always)]
    fn fast_max(self, o: Self) -> Self {
        f32x8::fast_max(self, o)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn simd_lt(self, o: Self) -> Self {
        f32x8::simd_lt(self, o)
    }
    #[inline(always)]
    fn simd_le(self, o: Self) -> Self {
        f32x8::simd_le(self, o)
    }
    #[inline(always)]
    fn simd_gt(self, o: Self) -> Self {
        f32x8::simd_gt(self, o)
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        f32x8::select(self, t, f)
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        f32x8::to_bitmask(self)
    }
    #[inline(always)]
    fn trunc_sum(self) -> u64 {
        self.trunc_int().to_array().iter().map(|&x| x as u64).sum()
    }
}

/// A kernel to run with the best [`Lanes`] the CPU has.
pub(crate) trait Kernel {
    /// What it returns.
    type Output;
    /// Runs it with lanes `V`. Mark it `#[inline(always)]` (and what it calls),
    /// so that it is compiled into the AVX entry point with AVX enabled.
    fn run<V: Lanes>(self) -> Self::Output;
}

/// Runs `kernel` with `Avx` when the CPU has AVX, else with `wide::f32x8`.
pub(crate) fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX, the only feature `run_avx` enables.
        #[allow(unsafe_code)]
        return unsafe { avx::run_avx(kernel) };
    }
    kernel.run::<f32x8>()
}

/// Runs `kernel` with `wide::f32x8` whatever the CPU (for the tests that
/// compare the two).
#[cfg(test)]
pub(crate) fn portable<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<f32x8>()
}

/// The AVX lanes. Every `unsafe` block here runs an AVX instruction; they are
/// sound because an `Avx` value is only ever made inside `run_avx`, which
/// [`dispatch`] calls only after detecting AVX (the type is private to this
/// crate and used nowhere else).
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx {
    use super::{Add, AddAssign, BitAnd, Div, Kernel, Lanes, Mul, Sub, SubAssign};
    use std::arch::x86_64::{
        __m256, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _mm256_add_ps, _mm256_and_ps, _mm256_andnot_ps,
        _mm256_blendv_ps, _mm256_cmp_ps, _mm256_cvttps_epi32, _mm256_div_ps, _mm256_loadu_ps,
        _mm256_max_ps, _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps, _mm256_set1_ps,
        _mm256_sqrt_ps, _mm256_storeu_ps, _mm256_storeu_si256, _mm256_sub_ps,
    };

    /// Eight lanes in one AVX register.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Avx(__m256);

    /// `kernel` with AVX lanes, compiled with AVX enabled.
    ///
    /// # Safety
    /// The CPU must have AVX.
    #[target_feature(enable = "avx")]
    pub(super) unsafe fn run_avx<K: Kernel>(kernel: K) -> K::Output {
        kernel.run::<Avx>()
    }

    macro_rules! binary {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for Avx {
                type Output = Self;
                #[inline(always)]
                fn $method(self, o: Self) -> Self {
                    // SAFETY: see the module docs.
                    Self(unsafe { $intrinsic(self.0, o.0) })
                }
            }
        };
    }
    binary!(Add, add, _mm256_add_ps);
    binary!(Sub, sub, _mm256_sub_ps);
    binary!(Mul, mul, _mm256_mul_ps);
    binary!(Div, div, _mm256_div_ps);
    binary!(BitAnd, bitand, _mm256_and_ps);

    impl AddAssign for Avx {
        #[inline(always)]
        fn add_assign(&mut self, o: Self) {
            *self = *self + o;
        }
    }

    impl SubAssign for Avx {
        #[inline(always)]
        fn sub_assign(&mut self, o: Self) {
            *self = *self - o;
        }
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn splat(x: f32) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        fn new(x: [f32; 8]) -> Self {
            // SAFETY: see the module docs; reads the eight floats of `x`.
            Self(unsafe { _mm256_loadu_ps(x.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f32; 8] {
            let mut out = [0.0; 8];
            // SAFETY: see the module docs; writes the eight floats of `out`.
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        fn abs(self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
        }
        #[inline(always)]
        fn fast_min(self, o: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn fast_max(self, o: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_max_ps(self.0, o.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn simd_lt(self, o: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn simd_le(self, o: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn simd_gt(self, o: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0) })
        }
        #[inline(always)]
        fn select(self, t: Self, f: Self) -> Self {
            // SAFETY: see the module docs.
            Self(unsafe { _mm256_blendv_ps(f.0, t.0, self.0) })
        }
        #[inline(always)]
        fn to_bitmask(self) -> u32 {
            // SAFETY: see the module docs.
            (unsafe { _mm256_movemask_ps(self.0) }) as u32
        }
        #[inline(always)]
        fn trunc_sum(self) -> u64 {
            let mut ints = [0i32; 8];
            // SAFETY: see the module docs; writes the 32 bytes of `ints`.
            unsafe {
                _mm256_storeu_si256(ints.as_mut_ptr().cast(), _mm256_cvttps_epi32(self.0));
            }
            ints.iter().map(|&x| x as u64).sum()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation on a spread of values (signed zeros, ties, tiny and large
    /// magnitudes), as bits.
    struct AllOps(Vec<[f32; 8]>);

    impl Kernel for AllOps {
        type Output = Vec<u32>;
        #[inline(always)]
        fn run<V: Lanes>(self) -> Vec<u32> {
            let mut out = Vec::new();
            let push = |out: &mut Vec<u32>, v: V| out.extend(v.to_array().map(f32::to_bits));
            for pair in self.0.windows(2) {
                let (a, b) = (V::new(pair[0]), V::new(pair[1]));
                for v in [a + b, a - b, a * b, a / b, a.abs(), a.abs().sqrt()] {
                    push(&mut out, v);
                }
                for v in [a.fast_min(b), a.fast_max(b), V::splat(pair[0][3])] {
                    push(&mut out, v);
                }
                for m in [a.simd_lt(b), a.simd_le(b), a.simd_gt(b)] {
                    push(&mut out, m);
                    push(&mut out, m.select(a, b));
                    push(&mut out, m & a.simd_lt(V::splat(0.0)));
                    out.push(m.to_bitmask());
                }
                let sum = a.abs().fast_min(V::splat(1e6)).trunc_sum();
                out.extend([sum as u32, (sum >> 32) as u32]);
            }
            out
        }
    }

    #[test]
    fn avx_and_portable_lanes_give_the_same_bits() {
        // Each lane pairs values five places apart: +0 with −0 and 2 with 2, where
        // the minimum and maximum rules decide which operand comes out.
        let values = [
            0.0, 2.0, -1.0, 0.5, 3.25, -0.0, 2.0, 1e-30, -1e-30, 1e30, 1.0, -7.75, 1e6, 123.456,
            -0.1, 0.3,
        ];
        let rows: Vec<[f32; 8]> = (0..24)
            .map(|r| std::array::from_fn(|l| values[(r * 5 + l * 3) % values.len()]))
            .collect();
        let portable = portable(AllOps(rows.clone()));
        let dispatched = dispatch(AllOps(rows.clone()));
        assert_eq!(portable, dispatched);
        // The lanes compute what scalar code does: the first eight values are
        // the first sum.
        let sum: Vec<u32> = (0..8)
            .map(|l| (rows[0][l] + rows[1][l]).to_bits())
            .collect();
        assert_eq!(portable[..8], sum[..]);
    }
}
