//! The [`Real`] trait: the float types (`f32`, `f64`) the bounds are built on.

use crate::math::Math;

/// A binary floating-point type that intervals and affine forms are built on.
///
/// Implemented for `f32` and `f64`. It adds to [`num_traits::Float`] what
/// sound arithmetic needs: **portable** [`next_up`](Real::next_up) /
/// [`next_down`](Real::next_down) (bit manipulation only, so they work on
/// SPIR-V and WASM, where the rounding mode cannot be changed) and a few
/// constants usable in `const` context.
pub trait Real: num_traits::Float + Math + 'static {
    /// `0`.
    const ZERO: Self;
    /// `1`.
    const ONE: Self;
    /// `2`.
    const TWO: Self;
    /// `0.5`.
    const HALF: Self;
    /// `+∞`.
    const INFINITY: Self;
    /// `−∞`.
    const NEG_INFINITY: Self;
    /// Largest finite value.
    const MAX: Self;
    /// Smallest positive subnormal value.
    const MIN_SUBNORMAL: Self;
    /// Machine epsilon: the distance from 1 to the next larger float (`2^(1−p)`).
    const EPSILON: Self;
    /// π rounded to nearest.
    const PI: Self;
    /// 2/π rounded to nearest.
    const FRAC_2_PI: Self;
    /// Number of significand bits `p`, including the implicit one (24 or 53).
    const MANTISSA_DIGITS: u32;

    /// The least float greater than `self`.
    ///
    /// `next_up(±0) = MIN_SUBNORMAL`, `next_up(MAX) = +∞`, `next_up(+∞) = +∞`,
    /// `next_up(−∞) = −MAX`, `next_up(NaN) = NaN`.
    fn next_up(self) -> Self;

    /// The greatest float less than `self` (`-(-self).next_up()`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn next_down(self) -> Self {
        -(-self).next_up()
    }

    /// `self` stepped `n` floats up (saturating at `+∞`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn next_up_n(self, n: u32) -> Self {
        let mut x = self;
        let mut i = 0;
        while i < n {
            x = x.next_up();
            i += 1;
        }
        x
    }

    /// `self` stepped `n` floats down (saturating at `−∞`).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn next_down_n(self, n: u32) -> Self {
        -(-self).next_up_n(n)
    }

    /// Width in bits of the significand's non-zero span: `0` for zero, `1`
    /// for powers of two, `p` for a value whose lowest significand bit is
    /// set. Two finite values whose widths sum to at most `p` multiply
    /// exactly unless the product leaves the normal range.
    fn significant_bits(self) -> u32;

    /// A lower bound of `self · b` (`0 · x = 0`, also for infinite `x`):
    /// [`round::mul_down`](crate::round::mul_down), which calls it. For
    /// `f32` the rounded product is compared with the exact one, computed
    /// in `f64` (a product of two 24-bit significands is exact there), so
    /// the bound is the rounded product itself whenever that is not above
    /// the exact one; for `f64` the product is stepped down unless a cheap
    /// test proves it exact. (The `f32` test is also a quarter of the
    /// other's size in a shader, where every call is inlined: BENCHMARKS.md
    /// "GPU".)
    fn mul_down(self, b: Self) -> Self;

    /// Converts from `f64`, rounding to nearest.
    fn from_f64(x: f64) -> Self;

    /// Converts to `f64` (exact for both implementations).
    fn as_f64(self) -> f64;

    /// `e^self` as `ia-core` computes it for its bounds, before they are
    /// widened: for `f32` `ia-core`'s own exponential on every target
    /// (within one float step of `e^x`, correctly rounded except within
    /// `10⁻¹⁴` of a midpoint, and the same bits on CPUs and on GPUs with
    /// IEEE `f64` arithmetic), for `f64` the platform's or `libm`'s
    /// (`< 1` ulp). Plain-float field evaluations use it, so that a field
    /// traced on the GPU sees the CPU's values.
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn exp_ia(self) -> Self {
        self.m_exp()
    }

    /// `ln self` as `ia-core` computes it for its bounds, before they are
    /// widened: for `f32` `ia-core`'s own logarithm on every target (within
    /// one float step of `ln x`, the same bits on CPUs and on GPUs with IEEE
    /// `f64` arithmetic, where the driver's `Log` is only required to 3 ulp),
    /// for `f64` the platform's or `libm`'s (`< 1` ulp). Plain-float field
    /// evaluations and jets use it, like [`exp_ia`](Self::exp_ia).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn ln_ia(self) -> Self {
        self.m_ln()
    }

    /// `self^p` as `ia-core` computes it for its bounds, before they are
    /// widened: for `f32` `ia-core`'s own power for a positive finite
    /// `self` and a finite `p` on every target (within one float step, the
    /// same bits on CPUs and on GPUs with IEEE `f64` arithmetic, where the
    /// driver's `Pow` has no ulp bound), `libm`'s or the platform's
    /// `powf` for other arguments; for `f64` the platform's or `libm`'s
    /// (`< 1` ulp). Plain-float field evaluations and jets use it, like
    /// [`exp_ia`](Self::exp_ia).
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powf_ia(self, p: Self) -> Self {
        self.m_pow(p)
    }

    /// `selfⁿ` as the standard library's `powi` computes it: binary
    /// powering from the lowest bit of `|n|` (the same products in the
    /// same order), then `1 / p` for `n < 0`. Plain-float and jet field
    /// evaluations use it.
    ///
    /// It is [`round::powi_unrolled`](crate::round::powi_unrolled) on
    /// every target, so CPUs with or without `std` and GPUs agree bit for
    /// bit; without a loop for `|n| < 16`: llvmpipe runs every loop of a
    /// shader at least once, taken or not, and caps an invocation's loop
    /// iterations at 65,535 in all, so a power loop in a blobtree's
    /// operator code costs iterations at every node (BENCHMARKS.md "GPU",
    /// session 24).
    ///
    /// ```
    /// use boundtrace_ia_core::Real;
    /// assert_eq!(1.5f32.powi_std(3), 3.375);
    /// assert_eq!(2.0f64.powi_std(-2), 0.25);
    /// ```
    #[cfg_attr(not(target_arch = "spirv"), inline)]
    fn powi_std(self, n: i32) -> Self {
        crate::round::powi_unrolled(self, n)
    }
}

macro_rules! impl_real {
    ($t:ident, $bits:ident, $mul_down:path) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const INFINITY: Self = $t::INFINITY;
            const NEG_INFINITY: Self = $t::NEG_INFINITY;
            const MAX: Self = $t::MAX;
            const MIN_SUBNORMAL: Self = $t::from_bits(1);
            const EPSILON: Self = $t::EPSILON;
            const PI: Self = core::$t::consts::PI;
            const FRAC_2_PI: Self = core::$t::consts::FRAC_2_PI;
            const MANTISSA_DIGITS: u32 = $t::MANTISSA_DIGITS;

            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn next_up(self) -> Self {
                // Branch-free (a GPU driver inlines every call, and there
                // are thousands of calls: BENCHMARKS.md "GPU", session 28).
                // ±0 becomes +0, whose successor pattern is the least
                // subnormal; a positive pattern steps up by one, a negative
                // one down by one (its magnitude shrinks); NaN and +∞ are
                // fixed points (a step of 0).
                let sign: $bits = 1 << ($bits::BITS - 1);
                let bits = self.to_bits();
                let zero = <$bits>::from(bits & !sign == 0);
                let bits = bits & !(zero * sign);
                let negative = bits >> ($bits::BITS - 1);
                let keep = <$bits>::from(self.is_nan() | (self == $t::INFINITY));
                // +1, −1 (wrapping) or 0.
                let step = (1 - keep).wrapping_mul((1 as $bits).wrapping_sub(negative << 1));
                $t::from_bits(bits.wrapping_add(step))
            }

            /// Loop-free (llvmpipe caps the loop iterations of a shader
            /// invocation: BENCHMARKS.md "GPU"): `n` steps at once along the
            /// order of the floats, the same value as `n` calls of
            /// [`next_up`](Real::next_up).
            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn next_up_n(self, n: u32) -> Self {
                if n == 0 || self.is_nan() || self == $t::INFINITY {
                    return self;
                }
                let n = <$bits>::from(n);
                let sign = 1 << ($bits::BITS - 1);
                let inf = $t::INFINITY.to_bits();
                let mag = self.to_bits() & !sign;
                if self >= 0.0 {
                    // ±0 or positive: the magnitude grows (from ±0 to the
                    // least subnormal), saturating at +∞.
                    return if n >= inf - mag {
                        $t::INFINITY
                    } else {
                        $t::from_bits(mag + n)
                    };
                }
                // Negative: the magnitude shrinks to −0, then grows past it.
                if n < mag {
                    $t::from_bits(sign | (mag - n))
                } else if n == mag {
                    -0.0
                } else if n - mag >= inf {
                    $t::INFINITY
                } else {
                    $t::from_bits(n - mag)
                }
            }

            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn mul_down(self, b: Self) -> Self {
                $mul_down(self, b)
            }

            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn significant_bits(self) -> u32 {
                const FRAC: u32 = $t::MANTISSA_DIGITS - 1;
                let bits = self.to_bits();
                let frac = bits & ((1 << FRAC) - 1);
                let biased_exp = (bits >> FRAC) & ((1 << ($bits::BITS - 1 - FRAC)) - 1);
                // Normal numbers carry the implicit leading one.
                let m = if biased_exp == 0 {
                    frac
                } else {
                    frac | (1 << FRAC)
                };
                if m == 0 {
                    0
                } else {
                    $bits::BITS - m.leading_zeros() - m.trailing_zeros()
                }
            }

            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }

            #[cfg_attr(not(target_arch = "spirv"), inline)]
            fn as_f64(self) -> f64 {
                self as f64
            }
        }
    };
}

impl_real!(f32, u32, crate::round::mul_down_f32);
impl_real!(f64, u64, crate::round::mul_down_tested);

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference: `n` single steps.
    fn stepped<T: Real>(x: T, n: u32) -> T {
        let mut y = x;
        for _ in 0..n {
            y = y.next_up();
        }
        y
    }

    #[test]
    fn next_up_n_equals_repeated_next_up() {
        let f32s = [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            -f32::from_bits(3),
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1.0,
            -1.0,
            -1.5e-30,
            3.7e12,
            f32::MAX,
            -f32::MAX,
            f32::from_bits(0x7f7f_fffd),
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for x in f32s {
            for n in [0, 1, 2, 3, 4, 5, 8, 9] {
                let (a, b) = (x.next_up_n(n), stepped(x, n));
                assert_eq!(a.to_bits(), b.to_bits(), "{x:e} up {n}: {a:e} vs {b:e}");
                let (a, b) = (x.next_down_n(n), -stepped(-x, n));
                assert_eq!(a.to_bits(), b.to_bits(), "{x:e} down {n}: {a:e} vs {b:e}");
            }
        }
        for x in [
            0.0f64,
            -0.0,
            -f64::from_bits(2),
            1.0,
            -2.5,
            f64::MAX,
            f64::NEG_INFINITY,
        ] {
            for n in [0, 1, 2, 3, 7] {
                let (a, b) = (x.next_up_n(n), stepped(x, n));
                assert_eq!(a.to_bits(), b.to_bits(), "{x:e} up {n}");
            }
        }
        assert!(f32::NAN.next_up_n(3).is_nan());
        assert_eq!(f32::from_bits(1).next_up_n(u32::MAX), f32::INFINITY);
        assert_eq!((-f32::from_bits(1)).next_up_n(u32::MAX), f32::INFINITY);
    }

    #[test]
    fn next_up_down_special_values() {
        assert_eq!(0.0f64.next_up(), f64::from_bits(1));
        assert_eq!((-0.0f64).next_up(), f64::from_bits(1));
        assert_eq!(0.0f64.next_down(), -f64::from_bits(1));
        assert_eq!(f64::MAX.next_up(), f64::INFINITY);
        assert_eq!(f64::INFINITY.next_up(), f64::INFINITY);
        assert_eq!(f64::NEG_INFINITY.next_up(), -f64::MAX);
        assert_eq!(f64::NEG_INFINITY.next_down(), f64::NEG_INFINITY);
        assert!(f64::NAN.next_up().is_nan());
        assert_eq!((-f64::from_bits(1)).next_up(), -0.0);
        assert_eq!(1.0f32.next_up(), 1.0 + f32::EPSILON);
        assert_eq!(1.0f32.next_down(), 1.0 - f32::EPSILON / 2.0);
        assert_eq!(f32::MIN_POSITIVE.next_down(), f32::from_bits(0x007f_ffff));
        assert_eq!(1.0f64.next_up_n(3), 1.0 + 3.0 * f64::EPSILON);
    }

    #[test]
    fn significant_bits() {
        assert_eq!(0.0f64.significant_bits(), 0);
        assert_eq!(1.0f64.significant_bits(), 1);
        assert_eq!(3.0f64.significant_bits(), 2);
        assert_eq!((-5.0f32).significant_bits(), 3);
        assert_eq!(0.1f64.significant_bits(), 52); // 0x1.999999999999Ap-4
        assert_eq!(f64::from_bits(1).significant_bits(), 1);
        assert_eq!(1.0f64.next_up().significant_bits(), 53);
        assert_eq!(f32::MAX.significant_bits(), 24);
    }

    #[test]
    fn next_up_matches_std() {
        let samples = [
            -3.5f64, -1.0, -1e-310, 1e-310, 0.1, 1.0, 2.0, 1e300, -1e300, 123.456,
        ];
        for x in samples {
            assert_eq!(Real::next_up(x), f64::next_up(x));
            assert_eq!(Real::next_down(x), f64::next_down(x));
            let y = x as f32;
            assert_eq!(Real::next_up(y), f32::next_up(y));
            assert_eq!(Real::next_down(y), f32::next_down(y));
        }
    }

    /// The branch-free `next_up`/`next_down` against the standard library's,
    /// bit for bit: the special values and 200,000 pseudo-random bit
    /// patterns of each type (every class: zeros, subnormals, normals,
    /// infinities, NaNs).
    #[test]
    fn next_up_and_down_equal_std_bit_for_bit() {
        fn check32(x: f32) {
            for (ours, std) in [
                (Real::next_up(x), f32::next_up(x)),
                (Real::next_down(x), f32::next_down(x)),
            ] {
                if std.is_nan() {
                    assert!(ours.is_nan(), "{x:e} ({:#x})", x.to_bits());
                } else {
                    assert_eq!(ours.to_bits(), std.to_bits(), "{x:e} ({:#x})", x.to_bits());
                }
            }
        }
        fn check64(x: f64) {
            for (ours, std) in [
                (Real::next_up(x), f64::next_up(x)),
                (Real::next_down(x), f64::next_down(x)),
            ] {
                if std.is_nan() {
                    assert!(ours.is_nan(), "{x:e} ({:#x})", x.to_bits());
                } else {
                    assert_eq!(ours.to_bits(), std.to_bits(), "{x:e} ({:#x})", x.to_bits());
                }
            }
        }
        for x in [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            1.0,
            -1.0,
        ] {
            check32(x);
            check64(f64::from(x));
        }
        check64(f64::from_bits(1));
        check64(-f64::from_bits(1));
        check64(f64::MAX);
        check64(f64::MIN);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            // splitmix64
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            check64(f64::from_bits(z));
            check32(f32::from_bits(z as u32));
            check32(f32::from_bits((z >> 32) as u32));
        }
    }
}
