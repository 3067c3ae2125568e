//! The vector instructions the ray kernels (the BVH walk and the triangle packet test) are
//! written in, picked at run time.
//!
//! A program built for any x86-64 may only assume SSE2: eight lanes then take two four-lane
//! instructions, and `a · b − c` takes two roundings and two instructions. Most processors of
//! the last decade also have AVX2 and FMA, which do both in one. Building for them alone would
//! lock everyone else out, so the kernels are written once, generic over an [`Isa`] (the set
//! of instructions), and compiled twice: for the baseline with the `wide` crate's portable
//! types, and for AVX2 + FMA with the processor's own eight- and four-lane instructions. Each
//! call asks which the processor has ([`dispatch`]: a cached flag, a load and a test) and runs
//! that copy; on other architectures only the portable one exists.
//!
//! Soundness: an [`Avx2`] value exists only once the processor has been seen to have AVX2 and
//! FMA, and the vectors of that set can only be made from one, so having one of its vectors
//! proves its instructions are there.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};
use wide::{f32x4, f32x8};

/// Four `f32` lanes; a comparison gives a lane of all ones (true) or all zeros (false).
pub(crate) trait Lanes4:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
{
    /// `c − self · b` (one rounding where the set has a fused multiply-add).
    fn mul_neg_add(self, b: Self, c: Self) -> Self;
    /// `self < other`, lane by lane.
    fn lt(self, other: Self) -> Self;
    /// `self > other`.
    fn gt(self, other: Self) -> Self;
    /// `self ≥ other`.
    fn ge(self, other: Self) -> Self;
    /// `self ≠ other` (true where either is NaN).
    fn ne(self, other: Self) -> Self;
    /// `self & !other`.
    fn and_not(self, other: Self) -> Self;
    /// One bit per lane: bit `i` set where lane `i` is true.
    fn bits(self) -> u32;
    /// The lanes' values.
    fn to_array(self) -> [f32; 4];
}

/// Eight `f32` lanes, one per child of a BVH node.
pub(crate) trait Lanes8: Copy {
    /// `self · b − c` (one rounding where the set has a fused multiply-add).
    fn mul_sub(self, b: Self, c: Self) -> Self;
    /// The larger of each pair; `other` where either is NaN.
    fn max(self, other: Self) -> Self;
    /// The smaller of each pair; `other` where either is NaN.
    fn min(self, other: Self) -> Self;
    /// One bit per lane: bit `i` set where `self ≤ other` (false where either is NaN).
    fn le_bits(self, other: Self) -> u32;
    /// The lanes' values.
    fn to_array(self) -> [f32; 8];
}

/// A set of vector instructions: makes the vectors the kernels compute with.
pub(crate) trait Isa: Copy {
    /// Four lanes.
    type F4: Lanes4;
    /// Eight lanes.
    type F8: Lanes8;
    /// Every lane `x`.
    fn splat4(self, x: f32) -> Self::F4;
    /// Four values.
    fn load4(self, values: &[f32; 4]) -> Self::F4;
    /// Every lane `x`.
    fn splat8(self, x: f32) -> Self::F8;
    /// Eight values.
    fn load8(self, values: &[f32; 8]) -> Self::F8;
}

/// A kernel to run with whichever [`Isa`] the processor has.
pub(crate) trait Kernel {
    /// What it returns.
    type Output;
    /// Runs it. Implementations are `#[inline(always)]`, and so is everything they call that
    /// computes with the set's vectors: that code must be compiled inside [`dispatch`]'s copy
    /// for the set, or its instructions become calls.
    fn run<I: Isa>(self, isa: I) -> Self::Output;
}

/// Runs `kernel` with the best set the processor has.
#[inline(always)]
pub(crate) fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(isa) = Avx2::detect() {
        // SAFETY: `detect` found AVX2, FMA, BMI1 and BMI2, which are all `run_avx2` enables.
        return unsafe { run_avx2(kernel, isa) };
    }
    kernel.run(Portable)
}

/// The kernel compiled for AVX2 and FMA (and the bit instructions that came with them, which
/// the walk's child masks use).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2")]
unsafe fn run_avx2<K: Kernel>(kernel: K, isa: Avx2) -> K::Output {
    kernel.run(isa)
}

/// The `wide` crate's types: SSE2 on any x86-64 (or whatever the program was built for),
/// NEON on ARM, plain arrays elsewhere.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Portable;

impl Isa for Portable {
    type F4 = f32x4;
    type F8 = f32x8;
    #[inline(always)]
    fn splat4(self, x: f32) -> f32x4 {
        f32x4::splat(x)
    }
    #[inline(always)]
    fn load4(self, values: &[f32; 4]) -> f32x4 {
        f32x4::new(*values)
    }
    #[inline(always)]
    fn splat8(self, x: f32) -> f32x8 {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn load8(self, values: &[f32; 8]) -> f32x8 {
        f32x8::new(*values)
    }
}

impl Lanes4 for f32x4 {
    #[inline(always)]
    fn mul_neg_add(self, b: Self, c: Self) -> Self {
        f32x4::mul_neg_add(self, b, c)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        self.simd_lt(other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        self.simd_gt(other)
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        self.simd_ge(other)
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        self.simd_ne(other)
    }
    #[inline(always)]
    fn and_not(self, other: Self) -> Self {
        self & !other
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        self.to_bitmask()
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 4] {
        f32x4::to_array(self)
    }
}

impl Lanes8 for f32x8 {
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        f32x8::mul_sub(self, b, c)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        self.fast_max(other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        self.fast_min(other)
    }
    #[inline(always)]
    fn le_bits(self, other: Self) -> u32 {
        self.simd_le(other).to_bitmask()
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        f32x8::to_array(self)
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2;

/// The AVX2 + FMA set. Every intrinsic below is `unsafe` only because it needs those
/// instructions, which an [`Avx2`] token (and so any of its vectors) proves.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Isa, Lanes4, Lanes8};
    use std::arch::x86_64::*;
    use std::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

    /// Proof that the processor has AVX2, FMA, BMI1 and BMI2.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct Avx2(());

    impl Avx2 {
        /// The token, when the processor has the instructions (the answer is cached by the
        /// standard library after the first call).
        #[inline(always)]
        pub(crate) fn detect() -> Option<Self> {
            let has = is_x86_feature_detected!("avx2")
                && is_x86_feature_detected!("fma")
                && is_x86_feature_detected!("bmi1")
                && is_x86_feature_detected!("bmi2");
            has.then_some(Self(()))
        }
    }

    /// Four lanes in an SSE register, computed with VEX-encoded and fused instructions.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct V4(__m128);

    /// Eight lanes in an AVX register.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct V8(__m256);

    impl Isa for Avx2 {
        type F4 = V4;
        type F8 = V8;
        #[inline(always)]
        fn splat4(self, x: f32) -> V4 {
            V4(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        fn load4(self, values: &[f32; 4]) -> V4 {
            V4(unsafe { _mm_loadu_ps(values.as_ptr()) })
        }
        #[inline(always)]
        fn splat8(self, x: f32) -> V8 {
            V8(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        fn load8(self, values: &[f32; 8]) -> V8 {
            V8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
        }
    }

    /// Implements a binary operator of [`V4`] with one intrinsic.
    macro_rules! v4_operator {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for V4 {
                type Output = V4;
                #[inline(always)]
                fn $method(self, other: V4) -> V4 {
                    V4(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    v4_operator!(Add, add, _mm_add_ps);
    v4_operator!(Sub, sub, _mm_sub_ps);
    v4_operator!(Mul, mul, _mm_mul_ps);
    v4_operator!(Div, div, _mm_div_ps);
    v4_operator!(BitAnd, bitand, _mm_and_ps);
    v4_operator!(BitOr, bitor, _mm_or_ps);

    impl Lanes4 for V4 {
        #[inline(always)]
        fn mul_neg_add(self, b: Self, c: Self) -> Self {
            V4(unsafe { _mm_fnmadd_ps(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn lt(self, other: Self) -> Self {
            V4(unsafe { _mm_cmplt_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn gt(self, other: Self) -> Self {
            V4(unsafe { _mm_cmpgt_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn ge(self, other: Self) -> Self {
            V4(unsafe { _mm_cmpge_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn ne(self, other: Self) -> Self {
            V4(unsafe { _mm_cmpneq_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn and_not(self, other: Self) -> Self {
            // The instruction complements its first operand.
            V4(unsafe { _mm_andnot_ps(other.0, self.0) })
        }
        #[inline(always)]
        fn bits(self) -> u32 {
            unsafe { _mm_movemask_ps(self.0) as u32 }
        }
        #[inline(always)]
        fn to_array(self) -> [f32; 4] {
            let mut out = [0.0; 4];
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }

    impl Lanes8 for V8 {
        #[inline(always)]
        fn mul_sub(self, b: Self, c: Self) -> Self {
            V8(unsafe { _mm256_fmsub_ps(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            V8(unsafe { _mm256_max_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn min(self, other: Self) -> Self {
            V8(unsafe { _mm256_min_ps(self.0, other.0) })
        }
        #[inline(always)]
        fn le_bits(self, other: Self) -> u32 {
            unsafe { _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(self.0, other.0)) as u32 }
        }
        #[inline(always)]
        fn to_array(self) -> [f32; 8] {
            let mut out = [0.0; 8];
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation of a set, applied to the same awkward lanes (NaN, infinities, zeros of
    /// both signs), as one list of bit patterns, so two sets can be compared lane for lane.
    fn results<I: Isa>(isa: I) -> Vec<u32> {
        let a4 = [1.5, -0.0, f32::NAN, f32::INFINITY];
        let b4 = [-2.0, 0.0, 3.0, 1.0];
        let c4 = [0.25, 7.0, -1.0, f32::NEG_INFINITY];
        let (a, b, c) = (isa.load4(&a4), isa.load4(&b4), isa.load4(&c4));
        let four = [
            a + b,
            a - b,
            a * b,
            a / b,
            a.lt(b),
            a.gt(b),
            a.ge(b),
            a.ne(b),
            a.lt(b) | a.gt(b),
            a.ge(b) & a.ne(b),
            a.ne(b).and_not(a.lt(b)),
            isa.splat4(2.0) * c,
        ];
        let a8 = [1.0, -1.0, f32::NAN, 0.0, f32::INFINITY, -3.5, 2.0, 1e30];
        let b8 = [0.5, f32::NAN, 1.0, -0.0, 1.0, -4.0, 2.0, -1e30];
        let (x, y) = (isa.load8(&a8), isa.load8(&b8));
        let eight = [x.max(y), x.min(y), x.mul_sub(isa.splat8(2.0), y)];
        // A NaN's sign and payload may differ between the instructions and a result the
        // compiler folded at build time: any NaN is compared as one.
        let bits = |v: f32| {
            if v.is_nan() {
                f32::NAN.to_bits()
            } else {
                v.to_bits()
            }
        };
        let mut out: Vec<u32> = four.iter().flat_map(|v| v.to_array()).map(bits).collect();
        out.extend(four[4..11].iter().map(|v| v.bits()));
        out.extend(eight.iter().flat_map(|v| v.to_array()).map(bits));
        out.push(x.le_bits(y));
        out
    }

    #[test]
    fn the_processors_set_computes_what_the_portable_one_does() {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = Avx2::detect() {
            // SAFETY: the token proves the instructions are there.
            let fast = unsafe { with_avx2(avx2) };
            assert_eq!(fast, results(Portable));
        }
        // The portable lanes follow their definitions (a few spot checks: the list holds
        // the twelve four-lane results, the masks of the seven comparisons among them, the
        // three eight-lane results and the eight-lane comparison).
        let r = results(Portable);
        assert_eq!(f32::from_bits(r[0]), -0.5); // 1.5 + -2
        assert_eq!(r[48], 0b0000); // a < b nowhere (NaN compares false)
        assert_eq!(r[48 + 1], 0b1001); // a > b: 1.5 > -2, ∞ > 1
        assert_eq!(r[48 + 3], 0b1101); // a ≠ b: everywhere but -0 ≠ 0, NaN included
        assert_eq!(r[r.len() - 1], 0b0100_1000); // x ≤ y: 0 ≤ -0 and 2 ≤ 2
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2")]
    unsafe fn with_avx2(isa: Avx2) -> Vec<u32> {
        results(isa)
    }
}
