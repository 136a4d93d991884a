//! proptest strategies for floats, intervals, exponents and affine forms.
//!
//! Floats mix: arbitrary bit patterns (every exponent, subnormals, `±∞`,
//! NaN), anchors stepped a few ulps (`±0`, `±1`, `MAX`, `MIN_POSITIVE`,
//! `MIN_SUBNORMAL`, `ln MAX` and `ln MIN_SUBNORMAL` for `exp` overflow and
//! underflow, `kπ/2`, `2^(p−3)` where `sin`/`cos` stop locating extrema,
//! `2^31`, `1e300`), uniform moderate values, small halves, subnormals and
//! `m·2^e` over the whole exponent range.

use boundtrace::ia_core::{Affine, Interval};
use proptest::prelude::*;

use super::Flt;

/// `2^e` as an `f64` (exact, also subnormal), `e ∈ [−1074, 1023]`.
pub fn pow2f(e: i32) -> f64 {
    assert!((-1074..=1023).contains(&e));
    if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (e + 1074))
    }
}

/// `x` stepped `k` floats up (`k > 0`) or down.
pub fn step<T: Flt>(x: T, k: i32) -> T {
    if k >= 0 {
        x.next_up_n(k as u32)
    } else {
        x.next_down_n(k.unsigned_abs())
    }
}

/// Smallest and largest binary exponent `e` of `2^e` in the type.
fn exp_range<T: Flt>() -> (i32, i32) {
    if T::MANTISSA_DIGITS == 24 {
        (-149, 127)
    } else {
        (-1074, 1023)
    }
}

/// Half the spacing of the floats at `MAX` (`2^(emax − p)`).
pub fn half_ulp_of_max<T: Flt>() -> T {
    (T::MAX - T::MAX.next_down()) * T::HALF
}

/// Interesting values of the type (non-negative; a sign is added).
pub fn anchors<T: Flt>() -> Vec<T> {
    let f = T::from_f64;
    let half_pi = std::f64::consts::FRAC_PI_2;
    let trig_limit = f(2f64.powi(T::MANTISSA_DIGITS as i32 - 3));
    let mut v = vec![
        T::ZERO,
        T::ONE,
        T::TWO,
        T::HALF,
        f(3.0),
        f(10.0),
        T::MAX,
        T::MAX.sqrt(),
        T::min_positive_value(),
        T::MIN_SUBNORMAL,
        T::EPSILON,
        T::MAX.ln(),
        -T::MIN_SUBNORMAL.ln(),
        -T::min_positive_value().ln(),
        trig_limit,
        f(2147483648.0),
        f(1e300),
        f(1e30),
        f(1e-30),
        f(1e6),
        T::PI,
    ];
    for k in [1.0, 3.0, 4.0, 5.0, 7.0, 1000.0, 1e6] {
        v.push(f(half_pi * k));
    }
    v
}

/// Any float: finite or not, NaN included.
pub fn float<T: Flt>() -> BoxedStrategy<T> {
    let anchors = anchors::<T>();
    let (emin, emax) = exp_range::<T>();
    let sub_bits = 1u64 << (T::MANTISSA_DIGITS - 1);
    let half_ulp_max = half_ulp_of_max::<T>();
    prop_oneof![
        4 => (0..anchors.len(), any::<bool>(), -3i32..=3).prop_map(move |(i, neg, k)| {
            let a = if neg { -anchors[i] } else { anchors[i] };
            step(a, k)
        }),
        3 => any::<u64>().prop_map(T::from_bits64),
        3 => (-1e3..1e3f64).prop_map(T::from_f64),
        2 => (-10.0..10.0f64).prop_map(T::from_f64),
        2 => (-40i32..=40).prop_map(|k| T::from_f64(f64::from(k) * 0.5)),
        1 => (1..sub_bits, any::<bool>()).prop_map(|(b, neg)| {
            let x = T::from_bits64(b);
            if neg { -x } else { x }
        }),
        1 => (1i32..64, any::<bool>()).prop_map(move |(k, neg)| {
            // Small multiples of half an ulp of MAX: their sums with values
            // near ±MAX are ties at the overflow threshold.
            let x = T::from_f64(f64::from(k)) * half_ulp_max;
            if neg { -x } else { x }
        }),
        3 => (1.0..2.0f64, emin..=emax, any::<bool>()).prop_map(|(m, e, neg)| {
            // m · 2^e, in two steps below the normal range.
            let v = if e >= -1022 {
                m * pow2f(e)
            } else {
                m * pow2f(-1022) * pow2f(e + 1022)
            };
            let x = T::from_f64(v);
            if neg { -x } else { x }
        }),
    ]
    .boxed()
}

/// A finite float (infinities become `±MAX`, NaN `0`).
pub fn finite<T: Flt>() -> BoxedStrategy<T> {
    float::<T>().prop_map(finite_or_max).boxed()
}

fn finite_or_max<T: Flt>(x: T) -> T {
    if x.is_nan() {
        T::ZERO
    } else if x.is_infinite() {
        x.signum() * T::MAX
    } else {
        x
    }
}

fn sorted<T: Flt>(a: T, b: T) -> Interval<T> {
    // NaN stays in and gives EMPTY.
    if b < a {
        Interval::new(b, a)
    } else {
        Interval::new(a, b)
    }
}

/// Any interval: general, narrow, points, `EMPTY`, `ENTIRE`, half-unbounded,
/// touching zero with either sign of zero, symmetric.
pub fn interval<T: Flt>() -> BoxedStrategy<Interval<T>> {
    prop_oneof![
        8 => (float::<T>(), float::<T>()).prop_map(|(a, b)| sorted(a, b)),
        2 => (finite::<T>(), 1u32..6).prop_map(|(x, k)| Interval::new(x, x.next_up_n(k))),
        2 => (finite::<T>(), 0u32..12).prop_map(|(x, k)| {
            let w = x.abs() * T::from_f64(10f64.powi(-(k as i32)));
            sorted(x, x + w)
        }),
        1 => finite::<T>().prop_map(Interval::point),
        1 => Just(Interval::EMPTY),
        1 => Just(Interval::ENTIRE),
        1 => float::<T>().prop_map(|x| Interval::new(T::NEG_INFINITY, x)),
        1 => float::<T>().prop_map(|x| Interval::new(x, T::INFINITY)),
        2 => (finite::<T>(), 0u8..4).prop_map(|(x, kind)| {
            let a = x.abs();
            match kind {
                0 => Interval::new(T::ZERO, a),
                1 => Interval::new(-T::ZERO, a),
                2 => Interval::new(-a, T::ZERO),
                _ => Interval::new(-a, -T::ZERO),
            }
        }),
        1 => finite::<T>().prop_map(|x| Interval::new(-x.abs(), x.abs())),
    ]
    .boxed()
}

/// A bounded, non-empty interval.
pub fn bounded<T: Flt>() -> BoxedStrategy<Interval<T>> {
    interval::<T>()
        .prop_map(|x| {
            if x.is_bounded() {
                x
            } else {
                let a = finite_or_max(x.lo());
                let b = finite_or_max(x.hi());
                if a <= b {
                    Interval::new(a, b)
                } else {
                    Interval::new(T::ZERO, T::ONE)
                }
            }
        })
        .boxed()
}

/// Multiples of π/2: small, and large up to beyond `2^(p−3)`.
fn half_pi_multiple() -> BoxedStrategy<f64> {
    prop_oneof![
        4 => -40i64..=40,
        1 => (0u32..5, -3i64..=3, any::<bool>()).prop_map(|(i, d, neg)| {
            let k = [1i64 << 18, 1 << 21, 1 << 30, 1 << 40, 1 << 49][i as usize] + d;
            if neg { -k } else { k }
        }),
    ]
    .prop_map(|k| k as f64 * std::f64::consts::FRAC_PI_2)
    .boxed()
}

/// An offset from a critical point: a few ulps or an absolute distance.
#[derive(Clone, Copy, Debug)]
enum Off {
    Ulps(i32),
    Abs(f64),
}

fn offset() -> BoxedStrategy<Off> {
    prop_oneof![
        2 => (-4i32..=4).prop_map(Off::Ulps),
        1 => (-1e-3..1e-3f64).prop_map(Off::Abs),
        2 => (-2.0..2.0f64).prop_map(Off::Abs),
        1 => (-8.0..8.0f64).prop_map(Off::Abs),
    ]
    .boxed()
}

fn apply<T: Flt>(c: T, o: Off) -> T {
    match o {
        Off::Ulps(k) => step(c, k),
        Off::Abs(d) => T::from_f64(c.as_f64() + d),
    }
}

/// Intervals for `sin`/`cos`: general ones, and ones around `kπ/2`, wide,
/// beyond `2^(p−3)`, or points there.
pub fn trig_interval<T: Flt>() -> BoxedStrategy<Interval<T>> {
    prop_oneof![
        3 => interval::<T>(),
        4 => (half_pi_multiple(), offset(), offset()).prop_map(|(c, a, b)| {
            let c = T::from_f64(c);
            sorted(apply(c, a), apply(c, b))
        }),
        1 => (half_pi_multiple(), offset())
            .prop_map(|(c, a)| Interval::point(apply(T::from_f64(c), a))),
        1 => (finite::<T>(), 0u32..4).prop_map(|(x, i)| {
            let w = T::from_f64([3.0, 6.3, 12.0, 1e3][i as usize]);
            sorted(x, x + w)
        }),
    ]
    .boxed()
}

/// `powi` exponents: small, large, `i32::MIN`, `i32::MAX`.
pub fn powi_exponent() -> BoxedStrategy<i32> {
    prop_oneof![
        6 => -10i32..=10,
        2 => any::<i32>(),
        1 => prop_oneof![
            Just(i32::MIN),
            Just(i32::MIN + 1),
            Just(i32::MAX),
            Just(i32::MAX - 1)
        ],
        2 => (11i32..100_000, any::<bool>()).prop_map(|(n, neg)| if neg { -n } else { n }),
    ]
    .boxed()
}

/// `pow` exponents: fractions, integers (also around `2^31`), tiny, huge,
/// and any float (NaN, `±∞` included).
pub fn pow_exponent<T: Flt>() -> BoxedStrategy<T> {
    prop_oneof![
        3 => (-40i32..=40).prop_map(|k| T::from_f64(f64::from(k) / 4.0)),
        2 => (-30i32..=30).prop_map(|k| T::from_f64(f64::from(k) / 3.0)),
        2 => float::<T>(),
        1 => prop_oneof![
            Just(2147483647.0),
            Just(2147483648.0),
            Just(-2147483648.0),
            Just(-2147483649.0),
            Just(1e-3),
            Just(-1e-3),
            Just(1e10),
            Just(-1e10),
            Just(0.5),
            Just(-0.5)
        ]
        .prop_map(T::from_f64),
    ]
    .boxed()
}

/// A coefficient of an affine form: moderate, wild, zero or a small integer,
/// all finite.
fn coefficient<T: Flt>() -> BoxedStrategy<T> {
    prop_oneof![
        3 => (-100.0..100.0f64).prop_map(T::from_f64),
        2 => finite::<T>(),
        1 => Just(T::ZERO),
        1 => (-8i32..=8).prop_map(|k| T::from_f64(f64::from(k))),
    ]
    .boxed()
}

/// An error term: zero, small, moderate or wild (finite, `≥ 0`).
fn error_term<T: Flt>() -> BoxedStrategy<T> {
    prop_oneof![
        2 => Just(T::ZERO),
        2 => (0.0..10.0f64).prop_map(T::from_f64),
        1 => (0.0..1e-6f64).prop_map(T::from_f64),
        1 => finite::<T>().prop_map(|x| x.abs()),
    ]
    .boxed()
}

/// The form `c + Σ coeffs[k]·ε_k ± e`, built exactly: every step adds a zero
/// or negates, which `Affine` does without rounding. (The tests read the
/// components back and never rely on this.)
pub fn raw_form<T: Flt, const N: usize>(c: T, coeffs: [T; N], e: T) -> Affine<T, N> {
    let mut x = Affine::<T, N>::constant(c);
    for (k, &ck) in coeffs.iter().enumerate() {
        if ck != T::ZERO {
            let v = Affine::variable(Interval::new(-ck.abs(), ck.abs()), k);
            x = x + if ck < T::ZERO { -v } else { v };
        }
    }
    if e > T::ZERO {
        x = x + Affine::from_interval(Interval::new(-e, e));
    }
    x
}

/// Any affine form: `ENTIRE`, `EMPTY`, constants, `from_interval`,
/// `variable` (also with a symbol index `≥ N`), and forms with arbitrary
/// components, optionally scaled by a common power of two (huge and tiny
/// coefficients, overflow to `ENTIRE`).
pub fn form<T: Flt, const N: usize>() -> BoxedStrategy<Affine<T, N>> {
    let (emin, emax) = exp_range::<T>();
    prop_oneof![
        1 => Just(Affine::ENTIRE),
        1 => Just(Affine::EMPTY),
        1 => finite::<T>().prop_map(Affine::constant),
        2 => interval::<T>().prop_map(Affine::from_interval),
        2 => (interval::<T>(), 0..=N).prop_map(|(iv, k)| Affine::variable(iv, k)),
        8 => (
            coefficient::<T>(),
            proptest::array::uniform::<_, N>(coefficient::<T>()),
            error_term::<T>()
        )
            .prop_map(|(c, k, e)| raw_form(c, k, e)),
        3 => (
            coefficient::<T>(),
            proptest::array::uniform::<_, N>(coefficient::<T>()),
            error_term::<T>(),
            (emin + 60)..=emax,
        )
            .prop_map(|(c, k, e, s)| {
                let s = T::from_f64(pow2f(s.min(1023)));
                let f = |v: T| finite_or_max(v * s);
                raw_form(f(c), k.map(f), f(e))
            }),
    ]
    .boxed()
}

/// A value of a noise symbol: `±1`, `±0`, dyadic, uniform, subnormal.
fn eps_value<T: Flt>() -> BoxedStrategy<T> {
    prop_oneof![
        2 => Just(T::ONE),
        2 => Just(-T::ONE),
        1 => Just(T::ZERO),
        1 => Just(-T::ZERO),
        2 => (-16i32..=16).prop_map(|k| T::from_f64(f64::from(k) / 16.0)),
        3 => (-1.0..=1.0f64).prop_map(T::from_f64),
        1 => (1..(1u64 << (T::MANTISSA_DIGITS - 1)), any::<bool>()).prop_map(|(b, neg)| {
            let x = T::from_bits64(b);
            if neg { -x } else { x }
        }),
    ]
    .boxed()
}

/// Three noise-symbol assignments in `[−1, 1]^N`.
pub fn eps<T: Flt, const N: usize>() -> BoxedStrategy<[[T; N]; 3]> {
    proptest::array::uniform::<_, 3>(proptest::array::uniform::<_, N>(eps_value::<T>())).boxed()
}
