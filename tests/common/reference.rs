//! The rigorous reference: exact reals and enclosures of exact results, in
//! arbitrary precision with `astro-float`.
//!
//! A sample point is an exact real (a [`BigFloat`], often not a float of the
//! type under test). For it, each function here returns an [`Enc`]: a pair
//! `lo ≤ f(x) ≤ hi` that is **proven**, not approximate:
//!
//! - `+ − ×` (and `sqr`, `abs`, `min`, `max`) are exact: no rounding at all.
//! - `÷ √` are computed by `astro-float` with directed rounding
//!   (`RoundingMode::Down` for `lo`, `Up` for `hi`), i.e. correct rounding
//!   of the exact result. At a precision of at least 53 bits every float is
//!   representable, so `float ≤ f(x) ⇔ float ≤ round_down(f(x))`: for an
//!   interval bound the check loses nothing. (An affine form's bounds are
//!   exact reals, not floats; if a check fails at [`P`] bits it is redone at
//!   more bits, see `check::verify`.)
//! - `exp`, `ln`, `sin`, `cos` are rounded down by `astro-float` (correctly
//!   rounded with Ziv's strategy; its `Down`/`Up` results were checked
//!   against `mpmath` at 1400 bits on 50 000 values, including arguments up
//!   to `1e308`, while writing these tests), giving `[d, d + ulp]`. Their
//!   only exact cases (`exp 0`, `ln 1`, `sin 0`, `cos 0`; all other values at
//!   rational points are transcendental) are returned exactly. No extra
//!   widening: an exact result may lie within `2^-3000` of a float (at the
//!   sample `x = 2^-3000`, `exp x = 1 + 2^-3000`), and widening would demand
//!   more than the truth.
//! - `x^n` (`powi`, and `pow` with an integer exponent) is binary powering
//!   on `|x|` with every product rounded down, resp. up; `pow` with another
//!   exponent is `exp(e · ln x)`, from an enclosure of `e · ln x` and the
//!   monotonicity of `exp` (exact for `x = 1` and `x = 0`).
//! - Results beyond any float range are replaced by bounds that are equivalent
//!   for float comparisons: above `2^5000` the enclosure is `[2^5000, +∞]`,
//!   a positive value below `2^-5000` is `[0, 2^-5000]`. This also keeps
//!   `astro-float` away from its own exponent limits (where an `Up`-rounded
//!   underflow would return 0, which is not an upper bound).
//! - `astro-float`'s `from_f64` halves subnormals and its `add_full_prec`
//!   returns garbage when an operand is zero (astro-float 0.9.6 /
//!   astro-float-num 0.3.7), so floats are converted here, exactly, from
//!   their bit patterns, and exact sums use an explicit precision.
//!
//! The checks first use [`P`] bits and, only if the code under test seems to
//! violate containment, recompute at higher precisions (`check::verify`)
//! before reporting.

use std::cell::RefCell;
use std::cmp::Ordering;

pub use astro_float::BigFloat;
use astro_float::{Consts, INF_NEG, INF_POS, Radix, RoundingMode as Rm};

use super::Flt;

/// Working precision of the first pass, in bits.
pub const P: usize = 128;
/// Least precision of the confirming passes, in bits.
pub const P_RETRY: usize = 512;
/// Precision of derived sample points (they are exact reals of this width).
pub const P_SAMPLE: usize = 128;
/// `log2` of the "beyond every float" thresholds.
const HUGE_EXP: i32 = 5000;
/// Arguments of `exp` beyond which the result is beyond `2^±5000`
/// (`e^3500 > 2^5049`).
const EXP_GUARD: f64 = 3500.0;

thread_local! {
    static CC: RefCell<Consts> =
        RefCell::new(Consts::new().expect("astro-float constants cache"));
}

/// Runs `f` with this thread's `astro-float` constants cache.
pub fn with_cc<R>(f: impl FnOnce(&mut Consts) -> R) -> R {
    CC.with(|cc| f(&mut cc.borrow_mut()))
}

/// The exact value of a finite `f64`, or `±∞`.
///
/// # Panics
///
/// On NaN (no real number).
pub fn from_f64(x: f64) -> BigFloat {
    assert!(!x.is_nan(), "NaN is not a real number");
    if x.is_infinite() {
        return if x > 0.0 { INF_POS } else { INF_NEG };
    }
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    // x = ±m · 2^e with an integer m < 2^53.
    let (m, e) = if biased == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), biased - 1075)
    };
    let mut b = BigFloat::from_u64(m, 64);
    if m != 0 {
        let eb = b.exponent().expect("finite");
        b.set_exponent(eb + e);
    }
    if x < 0.0 {
        b = b.neg();
    }
    b
}

/// The exact value of a float of the type under test (`f32 → f64` is exact).
pub fn big<T: Flt>(x: T) -> BigFloat {
    from_f64(x.as_f64())
}

/// The exact value of an integer.
pub fn int(i: i64) -> BigFloat {
    BigFloat::from_i64(i, 64)
}

/// `2^k`, exactly.
pub fn pow2(k: i32) -> BigFloat {
    let mut b = BigFloat::from_u64(1, 64);
    b.set_exponent(k + 1);
    b
}

/// A real beyond every float: `2^3000`.
pub fn far() -> BigFloat {
    pow2(3000)
}

/// A positive real below every positive float: `2^-3000`.
pub fn tiny() -> BigFloat {
    pow2(-3000)
}

/// Total order on non-NaN values (`±∞` included).
pub fn cmp(a: &BigFloat, b: &BigFloat) -> Ordering {
    let c = a.cmp(b).expect("no NaN in the reference");
    c.cmp(&0)
}

/// `a ≤ b`.
pub fn le(a: &BigFloat, b: &BigFloat) -> bool {
    cmp(a, b) != Ordering::Greater
}

/// `a < b`.
pub fn lt(a: &BigFloat, b: &BigFloat) -> bool {
    cmp(a, b) == Ordering::Less
}

/// Sign of a non-NaN value.
pub fn sign(a: &BigFloat) -> Ordering {
    if a.is_zero() {
        Ordering::Equal
    } else if a.is_negative() {
        Ordering::Less
    } else {
        Ordering::Greater
    }
}

/// The smaller of two values.
pub fn min(a: BigFloat, b: BigFloat) -> BigFloat {
    if le(&a, &b) { a } else { b }
}

/// The larger of two values.
pub fn max(a: BigFloat, b: BigFloat) -> BigFloat {
    if le(&a, &b) { b } else { a }
}

/// Bits that hold `a + b` exactly (both non-zero and finite).
fn sum_bits(a: &BigFloat, b: &BigFloat) -> usize {
    let e = |x: &BigFloat| i64::from(x.exponent().expect("finite"));
    let m = |x: &BigFloat| x.mantissa_max_bit_len().expect("finite") as i64;
    let top = e(a).max(e(b)) + 1;
    let bottom = (e(a) - m(a)).min(e(b) - m(b));
    ((top - bottom) as usize).div_ceil(64) * 64 + 64
}

/// Exact sum of finite values (no rounding).
///
/// (`astro-float`'s `add_full_prec` returns a corrupt value when an operand is
/// zero, so the precision is chosen here.)
pub fn add_exact(a: &BigFloat, b: &BigFloat) -> BigFloat {
    if a.is_zero() {
        return b.clone();
    }
    if b.is_zero() {
        return a.clone();
    }
    a.add(b, sum_bits(a, b), Rm::ToEven)
}

/// Exact difference of finite values.
pub fn sub_exact(a: &BigFloat, b: &BigFloat) -> BigFloat {
    add_exact(a, &b.neg())
}

/// Exact product of finite values.
pub fn mul_exact(a: &BigFloat, b: &BigFloat) -> BigFloat {
    if a.is_zero() || b.is_zero() {
        return int(0);
    }
    let m = |x: &BigFloat| x.mantissa_max_bit_len().expect("finite");
    a.mul(b, m(a) + m(b), Rm::ToEven)
}

/// Decimal rendering for failure messages.
pub fn show(b: &BigFloat) -> String {
    if b.is_inf_pos() {
        return "+inf".into();
    }
    if b.is_inf_neg() {
        return "-inf".into();
    }
    let mut r = b.clone();
    if r.mantissa_max_bit_len().unwrap_or(0) > 128 {
        // Only for display: 128 bits are 38 decimal digits.
        r.set_precision(128, Rm::ToEven).expect("precision");
    }
    with_cc(|cc| r.format(Radix::Dec, Rm::ToEven, cc)).unwrap_or_else(|e| format!("<{e:?}>"))
}

/// A proven enclosure `lo ≤ value ≤ hi` of an exact real result.
#[derive(Clone, Debug)]
pub struct Enc {
    /// Lower bound (never `+∞`).
    pub lo: BigFloat,
    /// Upper bound (never `−∞`).
    pub hi: BigFloat,
}

impl Enc {
    /// The exact value `v`.
    pub fn exact(v: BigFloat) -> Self {
        Self {
            lo: v.clone(),
            hi: v,
        }
    }

    /// `−self`.
    pub fn neg(&self) -> Self {
        Self {
            lo: self.hi.neg(),
            hi: self.lo.neg(),
        }
    }

    /// Intersection with `[−1, 1]` (for `sin`, `cos`, whose values lie there).
    fn clamp_unit(self) -> Self {
        let one = int(1);
        Self {
            lo: max(self.lo, one.neg()),
            hi: min(self.hi, one),
        }
    }
}

impl std::fmt::Display for Enc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{}, {}]", show(&self.lo), show(&self.hi))
    }
}

/// `x + y` (exact; `p` is unused).
pub fn add(x: &BigFloat, y: &BigFloat, _p: usize) -> Enc {
    Enc::exact(add_exact(x, y))
}

/// `x − y` (exact).
pub fn sub(x: &BigFloat, y: &BigFloat, _p: usize) -> Enc {
    Enc::exact(sub_exact(x, y))
}

/// `x · y` (exact).
pub fn mul(x: &BigFloat, y: &BigFloat, _p: usize) -> Enc {
    Enc::exact(mul_exact(x, y))
}

/// `x / y`; `None` for `y = 0` (no quotient).
pub fn div(x: &BigFloat, y: &BigFloat, p: usize) -> Option<Enc> {
    if y.is_zero() {
        return None;
    }
    Some(Enc {
        lo: x.div(y, p, Rm::Down),
        hi: x.div(y, p, Rm::Up),
    })
}

/// `1 / x`; `None` for `x = 0`.
pub fn recip(x: &BigFloat, p: usize) -> Option<Enc> {
    div(&int(1), x, p)
}

/// `x²` (exact).
pub fn sqr(x: &BigFloat, _p: usize) -> Enc {
    Enc::exact(mul_exact(x, x))
}

/// Bits to redo a check with so that a result of `inputs` that is exactly
/// representable comes out exact: their total precision plus 128, at least
/// [`P_RETRY`].
pub fn retry_bits(inputs: &[&BigFloat]) -> usize {
    let total: usize = inputs
        .iter()
        .map(|x| x.mantissa_max_bit_len().unwrap_or(0))
        .sum();
    (total + 128).div_ceil(64).max(P_RETRY / 64) * 64
}

/// `√x`; `None` for `x < 0`.
pub fn sqrt(x: &BigFloat, p: usize) -> Option<Enc> {
    match sign(x) {
        Ordering::Less => None,
        Ordering::Equal => Some(Enc::exact(int(0))),
        Ordering::Greater => Some(Enc {
            lo: x.sqrt(p, Rm::Down),
            hi: x.sqrt(p, Rm::Up),
        }),
    }
}

/// `|x|`.
pub fn abs(x: &BigFloat) -> Enc {
    Enc::exact(x.abs())
}

/// Encloses a transcendental value from its `Down`-rounded `p`-bit result
/// `d`: `[d, d + ulp]` (one evaluation instead of a `Down` and an `Up` one).
fn widen(d: BigFloat, p: usize) -> Enc {
    assert!(
        !d.is_zero() && !d.is_inf() && !d.is_nan(),
        "transcendental reference left its range: {d:?}"
    );
    let e = d.exponent().expect("finite");
    // |d| < 2^e, so the next p-bit number above d is at most 2^(e − p) away.
    let ulp = pow2(e - p as i32);
    Enc {
        hi: add_exact(&d, &ulp),
        lo: d,
    }
}

fn exp_lo(t: &BigFloat, p: usize) -> BigFloat {
    if t.is_zero() {
        return int(1);
    }
    if le(&from_f64(EXP_GUARD), t) {
        return pow2(HUGE_EXP);
    }
    if le(t, &from_f64(-EXP_GUARD)) {
        return int(0);
    }
    let d = with_cc(|cc| t.exp(p, Rm::Down, cc));
    widen(d, p).lo
}

fn exp_hi(t: &BigFloat, p: usize) -> BigFloat {
    if t.is_zero() {
        return int(1);
    }
    if le(&from_f64(EXP_GUARD), t) {
        return INF_POS;
    }
    if le(t, &from_f64(-EXP_GUARD)) {
        return pow2(-HUGE_EXP);
    }
    let d = with_cc(|cc| t.exp(p, Rm::Down, cc));
    widen(d, p).hi
}

/// `e^x`.
pub fn exp(x: &BigFloat, p: usize) -> Enc {
    Enc {
        lo: exp_lo(x, p),
        hi: exp_hi(x, p),
    }
}

/// `ln x`; `None` for `x ≤ 0`.
pub fn ln(x: &BigFloat, p: usize) -> Option<Enc> {
    if sign(x) != Ordering::Greater {
        return None;
    }
    if cmp(x, &int(1)) == Ordering::Equal {
        return Some(Enc::exact(int(0)));
    }
    let d = with_cc(|cc| x.ln(p, Rm::Down, cc));
    Some(widen(d, p))
}

/// `sin x`.
pub fn sin(x: &BigFloat, p: usize) -> Enc {
    if x.is_zero() {
        return Enc::exact(int(0));
    }
    let d = with_cc(|cc| x.sin(p, Rm::Down, cc));
    widen(d, p).clamp_unit()
}

/// `cos x`.
pub fn cos(x: &BigFloat, p: usize) -> Enc {
    if x.is_zero() {
        return Enc::exact(int(1));
    }
    let d = with_cc(|cc| x.cos(p, Rm::Down, cc));
    widen(d, p).clamp_unit()
}

/// `m^k` for a real `m > 0` and an integer `k ≥ 1`, by binary powering on
/// two tracks (all products rounded down, resp. up). Values beyond
/// `2^±5000` are clamped as described in the module docs.
fn pow_mag(m: &BigFloat, k: u64, p: usize) -> Enc {
    debug_assert!(sign(m) == Ordering::Greater && k >= 1);
    let huge = pow2(HUGE_EXP);
    let small = pow2(-HUGE_EXP);
    let grows = le(&int(1), m);
    let (mut base_lo, mut base_hi) = (m.clone(), m.clone());
    let (mut acc_lo, mut acc_hi): (Option<BigFloat>, Option<BigFloat>) = (None, None);
    let mut k = k;
    loop {
        if k & 1 == 1 {
            acc_lo = Some(match acc_lo {
                None => base_lo.clone(),
                Some(a) => a.mul(&base_lo, p, Rm::Down),
            });
            acc_hi = Some(match acc_hi {
                None => base_hi.clone(),
                Some(a) => a.mul(&base_hi, p, Rm::Up),
            });
        }
        k >>= 1;
        if k == 0 {
            break;
        }
        base_lo = base_lo.mul(&base_lo, p, Rm::Down);
        base_hi = base_hi.mul(&base_hi, p, Rm::Up);
        // Every partial power is a power m^j with j ≤ k_original: for m ≥ 1 it
        // is at most the result, for m < 1 at least the result.
        if grows {
            if lt(&huge, &base_lo) || acc_lo.as_ref().is_some_and(|a| lt(&huge, a)) {
                return Enc {
                    lo: huge,
                    hi: INF_POS,
                };
            }
            if lt(&huge, &base_hi) {
                base_hi = INF_POS;
            }
            if acc_hi.as_ref().is_some_and(|a| lt(&huge, a)) {
                acc_hi = Some(INF_POS);
            }
        } else {
            if lt(&base_hi, &small) || acc_hi.as_ref().is_some_and(|a| lt(a, &small)) {
                return Enc {
                    lo: int(0),
                    hi: small,
                };
            }
            if lt(&base_lo, &small) {
                base_lo = int(0);
            }
            if acc_lo.as_ref().is_some_and(|a| lt(a, &small)) {
                acc_lo = Some(int(0));
            }
        }
    }
    let (lo, hi) = (acc_lo.expect("k ≥ 1"), acc_hi.expect("k ≥ 1"));
    // Clamp the final values the same way.
    if lt(&huge, &lo) {
        return Enc {
            lo: huge,
            hi: INF_POS,
        };
    }
    if lt(&hi, &small) {
        return Enc {
            lo: int(0),
            hi: small,
        };
    }
    Enc { lo, hi }
}

/// `1/v` for an enclosure of a positive value (bounds may be `0`, `+∞`).
fn recip_pos(e: &Enc, p: usize) -> Enc {
    let one = int(1);
    Enc {
        lo: if e.hi.is_inf_pos() {
            int(0)
        } else {
            one.div(&e.hi, p, Rm::Down)
        },
        hi: if e.lo.is_zero() {
            INF_POS
        } else {
            one.div(&e.lo, p, Rm::Up)
        },
    }
}

/// `x^n` for an integer `n` (`x^0 = 1`, also for `x = 0`); `None` for
/// `x = 0`, `n < 0`.
pub fn powi(x: &BigFloat, n: i64, p: usize) -> Option<Enc> {
    if n == 0 {
        return Some(Enc::exact(int(1)));
    }
    if x.is_zero() {
        return (n > 0).then(|| Enc::exact(int(0)));
    }
    let k = n.unsigned_abs();
    let mut r = pow_mag(&x.abs(), k, p);
    if n < 0 {
        r = recip_pos(&r, p);
    }
    if x.is_negative() && k % 2 == 1 {
        r = r.neg();
    }
    Some(r)
}

/// `x^e` for a real exponent given as an `f64` (IEEE 1788 `pow`): domain
/// `x ≥ 0`, and `x > 0` for `e ≤ 0`; `None` outside it or for a NaN or
/// infinite `e`.
pub fn pow(x: &BigFloat, e: f64, p: usize) -> Option<Enc> {
    if !e.is_finite() || x.is_negative() {
        return None;
    }
    if x.is_zero() {
        return (e > 0.0).then(|| Enc::exact(int(0)));
    }
    if e == 0.0 || cmp(x, &int(1)) == Ordering::Equal {
        return Some(Enc::exact(int(1)));
    }
    if e.fract() == 0.0 && e.abs() < 9.0e18 {
        // An integer exponent: exact binary powering (covers exact results).
        return powi(x, e as i64, p);
    }
    // x^e = exp(e · ln x): an enclosure of the exponent, then monotonicity.
    let l = ln(x, p).expect("x > 0");
    let eb = from_f64(e);
    let (a, b) = (l.lo.mul(&eb, p, Rm::Down), l.hi.mul(&eb, p, Rm::Down));
    let t_lo = min(a, b);
    let (a, b) = (l.lo.mul(&eb, p, Rm::Up), l.hi.mul(&eb, p, Rm::Up));
    let t_hi = max(a, b);
    Some(Enc {
        lo: exp_lo(&t_lo, p),
        hi: exp_hi(&t_hi, p),
    })
}

/// `π/2 · k` rounded to [`P_SAMPLE`] bits, for an integer `k` with
/// `|k| < 2^70` (π taken to 256 bits: the point is within `2^-120` of the
/// critical point `kπ/2`).
pub fn half_pi_times(k: &BigFloat) -> BigFloat {
    let half_pi = with_cc(|cc| cc.pi(256, Rm::ToEven)).div(&int(2), 256, Rm::ToEven);
    k.mul(&half_pi, P_SAMPLE, Rm::ToEven)
}

/// `⌊x · 2/π⌋` for `|x| < 2^66` (up to one off near an integer, which the
/// callers tolerate).
pub fn floor_two_over_pi(x: &BigFloat) -> BigFloat {
    let pi = with_cc(|cc| cc.pi(256, Rm::ToEven));
    x.mul(&int(2), 256, Rm::ToEven)
        .div(&pi, 256, Rm::ToEven)
        .floor()
}
