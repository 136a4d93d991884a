//! Sample points and containment assertions.
//!
//! An operation passes a case when, for every sample point in its operands'
//! domain, the proven enclosure of the exact result lies inside the output:
//! `out.lo ≤ r_lo` and `r_hi ≤ out.hi` (compared exactly, as reals).

use astro_float::{BigFloat, INF_NEG, INF_POS, RoundingMode as Rm};
use boundtrace::ia_core::{Affine, Interval};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

use super::reference::{
    Enc, P, P_SAMPLE, add_exact, big, far, floor_two_over_pi, from_f64, half_pi_times, int, le,
    mul_exact, pow2, retry_bits, show, sub_exact, tiny,
};
use super::{Flt, show_af, show_f, show_iv};

/// The result of one property case.
pub type Res = Result<(), TestCaseError>;

/// Random words that pick the interior sample points (part of the case, so
/// failures replay and shrink).
#[derive(Clone, Copy, Debug)]
pub struct Picks(pub [u64; 4]);

/// Any [`Picks`].
pub fn picks() -> BoxedStrategy<Picks> {
    any::<[u64; 4]>().prop_map(Picks).boxed()
}

impl Picks {
    /// Fixed picks for the plain `#[test]`s.
    pub const FIXED: [Picks; 3] = [
        Picks([0, 0, 0, 0]),
        Picks([
            0x9e37_79b9_7f4a_7c15,
            0xbf58_476d_1ce4_e5b9,
            0x94d0_49bb_1331_11eb,
            7,
        ]),
        Picks([
            u64::MAX,
            0x0123_4567_89ab_cdef,
            0xfedc_ba98_7654_3210,
            1 << 40,
        ]),
    ];

    /// A dyadic fraction in `(0, 1)`.
    fn frac(&self, i: usize) -> BigFloat {
        let k = 2 * (self.0[i % 4] & 0x7fff) + 1;
        let mut b = int(k as i64);
        let e = b.exponent().expect("finite");
        b.set_exponent(e - 16);
        b
    }

    /// A dyadic fraction in `(−1, 1)`.
    pub fn signed_frac(&self, i: usize) -> BigFloat {
        let k = 2 * (self.0[i % 4] & 0xffff) as i64 + 1 - (1 << 16);
        let mut b = int(k);
        let e = b.exponent().expect("finite");
        b.set_exponent(e - 16);
        b
    }

    /// An exponent `j ∈ [1, 1100]` for points `2^-j` of a width from an end.
    fn near(&self, i: usize) -> i32 {
        1 + ((self.0[i % 4] >> 16) % 1100) as i32
    }

    /// An exponent in `[−1100, 1100)` for offsets into unbounded intervals.
    fn spread(&self, i: usize) -> i32 {
        ((self.0[i % 4] >> 32) % 2200) as i32 - 1100
    }

    /// Different picks for a second operand.
    pub fn rotate(&self) -> Picks {
        let [a, b, c, d] = self.0;
        Picks([
            b.rotate_left(17),
            c.rotate_left(29),
            d.rotate_left(41),
            a.rotate_left(53),
        ])
    }
}

/// Which extra sample points an operation needs.
#[derive(Clone, Copy, Debug)]
pub struct Opts {
    /// Reals beyond the float range (`±2^3000`) in unbounded intervals.
    pub far: bool,
    /// The critical points `kπ/2` of `sin` and `cos` inside the interval.
    pub critical: bool,
}

/// The default: far points, no critical points.
pub const PLAIN: Opts = Opts {
    far: true,
    critical: false,
};

/// For `sin`/`cos`: critical points, no far points (the unbounded side gets
/// critical points instead).
pub const TRIG: Opts = Opts {
    far: false,
    critical: true,
};

/// Exact value of a float bound (`±∞` included).
fn bound<T: Flt>(x: T) -> BigFloat {
    big(x)
}

/// Whether the real `s` lies in `x`.
pub fn in_interval<T: Flt>(x: Interval<T>, s: &BigFloat) -> bool {
    !x.is_empty() && le(&bound(x.lo()), s) && le(s, &bound(x.hi()))
}

/// The critical points `kπ/2` inside `x` near the finite bound `v`
/// (`|v| < 2^64`; beyond that the code under test gives `[−1, 1]` anyway).
fn critical_near<T: Flt>(
    x: Interval<T>,
    v: T,
    ks: std::ops::RangeInclusive<i64>,
    out: &mut Vec<BigFloat>,
) {
    if v.abs().as_f64() >= 1.8e19 {
        return;
    }
    let k0 = floor_two_over_pi(&big(v));
    for d in ks {
        let c = half_pi_times(&add_exact(&k0, &int(d)));
        if in_interval(x, &c) {
            out.push(c);
        }
    }
}

/// Sample reals of `x`: the finite endpoints, an interior point, reals
/// `2^-j` of the width from each end (not floats for large `j`), `0` and
/// `±2^-3000` when `x` reaches zero, `±MAX`, offsets `2^e` and (with
/// `o.far`) `±2^3000` on unbounded sides, and (with `o.critical`) the points
/// `kπ/2` inside `x`.
pub fn samples<T: Flt>(x: Interval<T>, pk: &Picks, o: Opts) -> Vec<BigFloat> {
    let mut v = Vec::new();
    if x.is_empty() {
        return v;
    }
    let (a, b) = (x.lo(), x.hi());
    let (la, lb) = (bound(a), bound(b));
    let max = big(T::MAX);
    match (a.is_finite(), b.is_finite()) {
        (true, true) => {
            v.push(la.clone());
            if a < b {
                v.push(lb.clone());
                let w = sub_exact(&lb, &la);
                v.push(la.add(&mul_exact(&w, &pk.frac(0)), P_SAMPLE, Rm::ToEven));
                v.push(la.add(&mul_exact(&w, &pow2(-pk.near(1))), P_SAMPLE, Rm::Up));
                v.push(lb.sub(&mul_exact(&w, &pow2(-pk.near(2))), P_SAMPLE, Rm::Down));
            }
        }
        (true, false) => {
            v.push(la.clone());
            v.push(la.add(&pow2(pk.spread(0)), P_SAMPLE, Rm::Down));
            v.push(max.clone());
            if o.far {
                v.push(far());
            }
        }
        (false, true) => {
            v.push(lb.clone());
            v.push(lb.sub(&pow2(pk.spread(0)), P_SAMPLE, Rm::Up));
            v.push(max.neg());
            if o.far {
                v.push(far().neg());
            }
        }
        (false, false) => {
            v.extend([int(1), int(-1), max.clone(), max.neg()]);
            let r = T::from_bits64(pk.0[3]);
            if r.is_finite() {
                v.push(big(r));
            }
            if o.far {
                v.extend([far(), far().neg()]);
            }
        }
    }
    let zero = T::ZERO;
    if a <= zero && zero <= b {
        v.push(int(0));
    }
    if a <= zero && zero < b {
        v.push(tiny());
    }
    if a < zero && zero <= b {
        v.push(tiny().neg());
    }
    if o.critical {
        if a.is_finite() {
            critical_near(x, a, -1..=5, &mut v);
        }
        if b.is_finite() {
            critical_near(x, b, -5..=1, &mut v);
        }
        if !a.is_finite() && !b.is_finite() {
            critical_near(x, zero, -2..=2, &mut v);
        }
    }
    v
}

/// Checks `ok` against the reference at [`P`] bits and, if that fails, at
/// [`retry_bits`] of `spans` (the sample inputs and the exact bounds compared
/// against), then at four times that; `Err` holds the last enclosure. `None`
/// from `f` means the point is outside the operation's domain.
///
/// The second precision makes a result that is exactly representable come
/// out exact; the third resolves results that are not, but lie extremely close
/// to an exact bound of an affine form (at `x = 2^-1090`, `exp x` exceeds the
/// bound `1 + x` of a tight linearisation by only `x²/2`).
pub fn verify(
    spans: &[&BigFloat],
    f: impl Fn(usize) -> Option<Enc>,
    ok: impl Fn(&Enc) -> bool,
) -> Result<(), Enc> {
    let Some(mut r) = f(P) else {
        return Ok(());
    };
    if ok(&r) {
        return Ok(());
    }
    let bits = retry_bits(spans);
    for p in [bits, (4 * bits).min(1 << 15)] {
        r = f(p).expect("the domain does not depend on the precision");
        if ok(&r) {
            return Ok(());
        }
    }
    Err(r)
}

/// Whether the interval `out` contains the enclosure `r`.
pub fn iv_contains<T: Flt>(out: Interval<T>, r: &Enc) -> bool {
    !out.is_empty() && le(&bound(out.lo()), &r.lo) && le(&r.hi, &bound(out.hi()))
}

/// Containment for a unary interval operation `out = op(x)` with reference `f`.
pub fn unary<T: Flt>(
    op: &str,
    x: Interval<T>,
    out: Interval<T>,
    pk: &Picks,
    o: Opts,
    f: impl Fn(&BigFloat, usize) -> Option<Enc>,
) -> Res {
    for s in samples(x, pk, o) {
        if let Err(r) = verify(&[&s], |p| f(&s, p), |r| iv_contains(out, r)) {
            return Err(TestCaseError::fail(format!(
                "containment violated: {op} on {t}\n  x      = {x}\n  sample = {s}\n  \
                 exact  ∈ {r}\n  got    = {out}",
                t = T::NAME,
                x = show_iv(x),
                s = show(&s),
                out = show_iv(out),
            )));
        }
    }
    Ok(())
}

/// Containment for a binary interval operation `out = op(x, y)`.
pub fn binary<T: Flt>(
    op: &str,
    x: Interval<T>,
    y: Interval<T>,
    out: Interval<T>,
    pk: &Picks,
    f: impl Fn(&BigFloat, &BigFloat, usize) -> Option<Enc>,
) -> Res {
    let ys = samples(y, &pk.rotate(), PLAIN);
    for s in samples(x, pk, PLAIN) {
        for t in &ys {
            if let Err(r) = verify(&[&s, t], |p| f(&s, t, p), |r| iv_contains(out, r)) {
                return Err(TestCaseError::fail(format!(
                    "containment violated: {op} on {ty}\n  x      = {x}\n  y      = {y}\n  \
                     sample = ({s}, {t})\n  exact  ∈ {r}\n  got    = {out}",
                    ty = T::NAME,
                    x = show_iv(x),
                    y = show_iv(y),
                    s = show(&s),
                    t = show(t),
                    out = show_iv(out),
                )));
            }
        }
    }
    Ok(())
}

/// `x₀ + Σ xᵢ·εᵢ`, exactly, for a bounded form.
pub fn center_at<T: Flt, const N: usize>(x: &Affine<T, N>, eps: &[T; N]) -> BigFloat {
    let mut c = big(x.center());
    for (xi, ei) in x.coeffs().iter().zip(eps) {
        c = add_exact(&c, &mul_exact(&big(*xi), &big(*ei)));
    }
    c
}

/// Reals an `ENTIRE` form stands for (a few of them).
fn entire_samples() -> Vec<BigFloat> {
    vec![
        int(0),
        int(1),
        int(-1),
        from_f64(0.75),
        far(),
        far().neg(),
        tiny(),
        tiny().neg(),
    ]
}

/// Values of the form `x` at the noise symbols `eps`: `x₀ + Σ xᵢεᵢ + t·e`
/// for each error fraction `t ∈ [−1, 1]` (exact reals).
pub fn form_values<T: Flt, const N: usize>(
    x: &Affine<T, N>,
    eps: &[T; N],
    fracs: &[BigFloat],
) -> Vec<BigFloat> {
    if x.is_empty() {
        return Vec::new();
    }
    if x.is_entire() {
        return entire_samples();
    }
    let c = center_at(x, eps);
    if x.err() == T::ZERO {
        return vec![c];
    }
    let e = big(x.err());
    fracs
        .iter()
        .map(|t| add_exact(&c, &mul_exact(&e, t)))
        .collect()
}

/// What the output form `z` must satisfy at one noise-symbol assignment.
struct FormAt<T> {
    entire: bool,
    empty: bool,
    /// Exact `[z₀ + Σ zᵢεᵢ − e, z₀ + Σ zᵢεᵢ + e]`.
    lo: BigFloat,
    hi: BigFloat,
    eval: Interval<T>,
    range: Interval<T>,
}

impl<T: Flt> FormAt<T> {
    fn new<const N: usize>(z: &Affine<T, N>, eps: &[T; N]) -> Self {
        let (lo, hi) = if z.is_empty() || z.is_entire() {
            (INF_POS, INF_NEG)
        } else {
            let c = center_at(z, eps);
            let e = big(z.err());
            (sub_exact(&c, &e), add_exact(&c, &e))
        };
        Self {
            entire: z.is_entire(),
            empty: z.is_empty(),
            lo,
            hi,
            eval: z.eval(*eps),
            range: z.to_interval(),
        }
    }

    /// `None` when `r` is contained, otherwise which check failed.
    fn failure(&self, r: &Enc) -> Option<&'static str> {
        if self.entire {
            return None; // ENTIRE contains every real
        }
        if self.empty {
            return Some("the result is EMPTY");
        }
        if !(le(&self.lo, &r.lo) && le(&r.hi, &self.hi)) {
            return Some("the form z₀ + Σzᵢεᵢ ± e (exact) misses the value");
        }
        if !iv_contains(self.eval, r) {
            return Some("z.eval(ε) misses the value");
        }
        if !iv_contains(self.range, r) {
            return Some("z.to_interval() misses the value");
        }
        None
    }
}

/// A form with its range.
fn show_form<T: Flt, const N: usize>(x: &Affine<T, N>) -> String {
    format!("{}, to_interval {}", show_af(x), show_iv(x.to_interval()))
}

fn show_eps<T: Flt, const N: usize>(eps: &[T; N]) -> String {
    let v: Vec<String> = eps.iter().map(|&e| show_f(e)).collect();
    format!("[{}]", v.join(", "))
}

#[allow(clippy::too_many_arguments)]
fn affine_failure<T: Flt, const N: usize>(
    op: &str,
    operands: &str,
    z: &Affine<T, N>,
    eps: &[T; N],
    sample: &str,
    r: &Enc,
    at: &FormAt<T>,
    why: &str,
) -> TestCaseError {
    TestCaseError::fail(format!(
        "containment violated: {op} on Affine<{t}, {N}>: {why}\n{operands}  ε      = {e}\n  \
         sample = {sample}\n  exact  ∈ {r}\n  z      = {z}\n  z at ε = [{lo}, {hi}]\n  \
         eval   = {ev}\n  range  = {rg}",
        t = T::NAME,
        e = show_eps(eps),
        z = show_af(z),
        lo = show(&at.lo),
        hi = show(&at.hi),
        ev = show_iv(at.eval),
        rg = show_iv(at.range),
    ))
}

/// Containment for a unary affine operation `z = op(x)`: at each noise
/// assignment `ε` and error fractions `t ∈ {−1, 1, random}`, the exact
/// `f(x₀ + Σxᵢεᵢ + t·eₓ)` lies in `z` at `ε` (exactly), in `z.eval(ε)` and
/// in `z.to_interval()`.
pub fn affine_unary<T: Flt, const N: usize>(
    op: &str,
    x: &Affine<T, N>,
    z: &Affine<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
    f: impl Fn(&BigFloat, usize) -> Option<Enc>,
) -> Res {
    let fracs = [int(-1), int(1), pk.signed_frac(0)];
    for e in eps {
        let at = FormAt::new(z, e);
        for v in form_values(x, e, &fracs) {
            if let Err(r) = verify(
                &[&v, &at.lo, &at.hi],
                |p| f(&v, p),
                |r| at.failure(r).is_none(),
            ) {
                let why = at.failure(&r).unwrap_or("?");
                let operands = format!("  x      = {}\n", show_form(x));
                return Err(affine_failure(op, &operands, z, e, &show(&v), &r, &at, why));
            }
        }
    }
    Ok(())
}

/// Containment for a binary affine operation `z = op(x, y)` (`x`, `y` share
/// the noise symbols; their error terms are independent).
pub fn affine_binary<T: Flt, const N: usize>(
    op: &str,
    x: &Affine<T, N>,
    y: &Affine<T, N>,
    z: &Affine<T, N>,
    eps: &[[T; N]; 3],
    pk: &Picks,
    f: impl Fn(&BigFloat, &BigFloat, usize) -> Option<Enc>,
) -> Res {
    let fx = [int(-1), int(1), pk.signed_frac(0)];
    let fy = [int(-1), int(1), pk.signed_frac(1)];
    for e in eps {
        let at = FormAt::new(z, e);
        let ys = form_values(y, e, &fy);
        for v in form_values(x, e, &fx) {
            for w in &ys {
                if let Err(r) = verify(
                    &[&v, w, &at.lo, &at.hi],
                    |p| f(&v, w, p),
                    |r| at.failure(r).is_none(),
                ) {
                    let why = at.failure(&r).unwrap_or("?");
                    let operands =
                        format!("  x      = {}\n  y      = {}\n", show_form(x), show_form(y));
                    let sample = format!("({}, {})", show(&v), show(w));
                    return Err(affine_failure(op, &operands, z, e, &sample, &r, &at, why));
                }
            }
        }
    }
    Ok(())
}

/// Containment of given reals in a form `z` at every noise assignment in
/// `eps` (for the constructors: `z` must stand for each of `values`).
pub fn affine_values<T: Flt, const N: usize>(
    op: &str,
    inputs: &str,
    z: &Affine<T, N>,
    eps: &[[T; N]; 3],
    values: &[BigFloat],
) -> Res {
    for e in eps {
        let at = FormAt::new(z, e);
        for v in values {
            let r = Enc::exact(v.clone());
            if let Some(why) = at.failure(&r) {
                let operands = format!("  input  = {inputs}\n");
                return Err(affine_failure(op, &operands, z, e, &show(v), &r, &at, why));
            }
        }
    }
    Ok(())
}

/// Runs property bodies on fixed inputs (the plain `#[test]`s) and reports
/// every failing one, not just the first.
#[derive(Default)]
pub struct Fixed {
    cases: usize,
    failures: Vec<String>,
}

impl Fixed {
    /// Records the outcome of one fixed case.
    pub fn check(&mut self, res: Res) {
        self.cases += 1;
        if let Err(e) = res {
            self.failures.push(e.to_string());
        }
    }

    /// Panics if any case failed: the number of failures per kind (first
    /// line of the message: operation and type) and one example of each.
    pub fn finish(self) {
        if self.failures.is_empty() {
            return;
        }
        let mut kinds: Vec<(&str, usize, &str)> = Vec::new();
        for f in &self.failures {
            let head = f.lines().next().unwrap_or("");
            match kinds.iter_mut().find(|k| k.0 == head) {
                Some(k) => k.1 += 1,
                None => kinds.push((head, 1, f)),
            }
        }
        let report: Vec<String> = kinds
            .iter()
            .map(|(_, n, example)| format!("{n} case(s) like:\n{example}"))
            .collect();
        panic!(
            "{} of {} fixed cases failed:\n\n{}",
            self.failures.len(),
            self.cases,
            report.join("\n\n")
        );
    }
}
