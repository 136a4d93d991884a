//! Forward-bound checks on random expression trees over the ray parameter,
//! shared by the `forward_bounds` property tests and the `forward_bounds`
//! fuzz target (`fuzz/`): a tree and a ray interval are drawn from an
//! [`Rng`] (a seeded PRNG, or the fuzzer's bytes), and [`check_rng`] checks
//! exactness at `t0`, containment, validity, the safe step and tightness
//! against a 192-bit reference. See `tests/forward_bounds.rs` for details.

use std::cell::RefCell;

use astro_float::{BigFloat, RoundingMode as Rm};
use boundtrace::ia_core::{Affine, Interval};
use boundtrace::inclusion::{Composition, FieldNum, ForwardLinear, ForwardQuadratic, Jet};
use proptest::test_runner::TestCaseError;

use super::Flt;
use super::reference::{self as r, big, with_cc};

/// Working precision of the reference.
pub const PREC: usize = 192;
/// Grid points per interval.
pub const GRID: usize = 32;

#[derive(Clone, Copy, Debug)]
pub enum Op {
    T,
    C(f32),
    Neg(usize),
    Sqr(usize),
    Powi(usize, i32),
    Powf(usize, f32),
    Sqrt(usize),
    Recip(usize),
    Exp(usize),
    Ln(usize),
    Sin(usize),
    Cos(usize),
    Abs(usize),
    OneMinus(usize),
    AddC(usize, f32),
    MulC(usize, f32),
    DivC(usize, f32),
    Add(usize, usize),
    Sub(usize, usize),
    Mul(usize, usize),
    Div(usize, usize),
    Min(usize, usize),
    Max(usize, usize),
}

/// The source of a case's random choices: a small deterministic PRNG
/// (xorshift64*) seeded by proptest, or the bytes of a fuzzer input (8 per
/// draw, little-endian), continued by the PRNG seeded from the bytes when
/// they run out.
pub struct Rng {
    state: u64,
    bytes: Vec<u8>,
    pos: usize,
}
impl Rng {
    /// The PRNG from `seed`.
    pub fn seeded(seed: u64) -> Self {
        Rng {
            state: seed | 1,
            bytes: Vec::new(),
            pos: 0,
        }
    }
    /// Draws from `data` first (a fuzzer input).
    pub fn from_bytes(data: &[u8]) -> Self {
        // FNV-1a of the bytes seeds the continuation.
        let seed = data.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        Rng {
            state: seed | 1,
            bytes: data.to_vec(),
            pos: 0,
        }
    }
    fn next(&mut self) -> u64 {
        if let Some(chunk) = self.bytes.get(self.pos..self.pos + 8) {
            self.pos += 8;
            return u64::from_le_bytes(chunk.try_into().expect("8 bytes"));
        }
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        self.state.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn range(&mut self, a: f64, b: f64) -> f32 {
        (a + (b - a) * self.unit()) as f32
    }
    fn log_range(&mut self, a: f64, b: f64) -> f32 {
        (a.ln() + (b.ln() - a.ln()) * self.unit()).exp() as f32
    }
}

/// An expression tree in post-order (children before parents; root last).
#[derive(Clone, Debug)]
pub struct Tree(Vec<Op>);

impl From<Vec<Op>> for Tree {
    /// A tree from its operations in post-order (arguments before uses).
    fn from(ops: Vec<Op>) -> Self {
        Self(ops)
    }
}

impl Tree {
    /// A tree of the given depth that uses the ray parameter.
    fn generate(rng: &mut Rng, depth: u32) -> Self {
        loop {
            let mut t = Tree(Vec::new());
            t.node(rng, depth);
            if t.0.iter().any(|op| matches!(op, Op::T)) {
                return t;
            }
        }
    }

    fn push(&mut self, op: Op) -> usize {
        self.0.push(op);
        self.0.len() - 1
    }

    /// `x² + c`, `c ∈ [1e-6, 1]` (log-uniform): a guarded, near-singular
    /// argument.
    fn guard(&mut self, rng: &mut Rng, x: usize) -> usize {
        let s = self.push(Op::Sqr(x));
        let c = rng.log_range(1e-6, 1.0);
        self.push(Op::AddC(s, c))
    }

    fn node(&mut self, rng: &mut Rng, depth: u32) -> usize {
        if depth == 0 {
            return if rng.below(10) < 7 {
                self.push(Op::T)
            } else {
                let c = rng.range(-2.0, 2.0);
                self.push(Op::C(c))
            };
        }
        let k = rng.below(22);
        if k < 15 {
            let x = self.node(rng, depth - 1);
            let guarded = rng.below(2) == 0;
            let op = match k {
                0 => Op::Neg(x),
                1 => Op::Sqr(x),
                2 => Op::Powi(x, [-2, -1, 3, 4][rng.below(4) as usize]),
                3 => {
                    let x = if guarded { self.guard(rng, x) } else { x };
                    Op::Powf(x, [0.5, 1.5, 2.5, -0.5][rng.below(4) as usize])
                }
                4 => Op::Sqrt(if guarded { self.guard(rng, x) } else { x }),
                5 => Op::Recip(if guarded { self.guard(rng, x) } else { x }),
                6 => {
                    // Half of the time a Gaussian e^{−x²}.
                    if guarded {
                        let s = self.push(Op::Sqr(x));
                        let n = self.push(Op::Neg(s));
                        Op::Exp(n)
                    } else {
                        Op::Exp(x)
                    }
                }
                7 => Op::Ln(if guarded { self.guard(rng, x) } else { x }),
                8 => Op::Abs(x),
                9 => Op::OneMinus(x),
                10 => Op::AddC(x, rng.range(-2.0, 2.0)),
                11 => Op::MulC(x, rng.range(-3.0, 3.0)),
                13 => Op::Sin(x),
                14 => Op::Cos(x),
                _ => {
                    let mut c = rng.range(-3.0, 3.0);
                    if c.abs() < 0.1 {
                        c = 0.5;
                    }
                    Op::DivC(x, c)
                }
            };
            self.push(op)
        } else {
            let other_depth = rng.below(u64::from(depth)) as u32;
            let (a, b) = if rng.below(2) == 0 {
                let a = self.node(rng, depth - 1);
                (a, self.node(rng, other_depth))
            } else {
                let a = self.node(rng, other_depth);
                (a, self.node(rng, depth - 1))
            };
            let op = match k {
                15 | 16 => Op::Add(a, b),
                17 => Op::Sub(a, b),
                18 => Op::Mul(a, b),
                19 => {
                    let b = if rng.below(2) == 0 {
                        self.guard(rng, b)
                    } else {
                        b
                    };
                    Op::Div(a, b)
                }
                20 => Op::Min(a, b),
                _ => Op::Max(a, b),
            };
            self.push(op)
        }
    }

    /// Evaluates the tree in any number type.
    fn eval<T: Flt, N: FieldNum<T>>(&self, t: N) -> N {
        *self.eval_all(t).last().expect("non-empty tree")
    }

    /// The values of all nodes, in post-order.
    fn eval_all<T: Flt, N: FieldNum<T>>(&self, t: N) -> Vec<N> {
        let mut v: Vec<N> = Vec::with_capacity(self.0.len());
        for op in &self.0 {
            let y = Self::apply(*op, t, &v);
            v.push(y);
        }
        v
    }

    /// One operation on the values `v` of the nodes before it (`t` for
    /// [`Op::T`]).
    fn apply<T: Flt, N: FieldNum<T>>(op: Op, t: N, v: &[N]) -> N {
        let c = |x: f32| T::from_f64(f64::from(x));
        match op {
            Op::T => t,
            Op::C(x) => N::constant(c(x)),
            Op::Neg(a) => -v[a],
            Op::Sqr(a) => v[a].sqr(),
            Op::Powi(a, n) => v[a].powi(n),
            Op::Powf(a, p) => v[a].powf(c(p)),
            Op::Sqrt(a) => v[a].sqrt(),
            Op::Recip(a) => v[a].recip(),
            Op::Exp(a) => v[a].exp(),
            Op::Ln(a) => v[a].ln(),
            Op::Sin(a) => v[a].sin(),
            Op::Cos(a) => v[a].cos(),
            Op::Abs(a) => v[a].abs(),
            Op::OneMinus(a) => v[a].one_minus_clamped(),
            Op::AddC(a, x) => v[a] + c(x),
            Op::MulC(a, x) => v[a] * c(x),
            Op::DivC(a, x) => v[a] / c(x),
            Op::Add(a, b) => v[a] + v[b],
            Op::Sub(a, b) => v[a] - v[b],
            Op::Mul(a, b) => v[a] * v[b],
            Op::Div(a, b) => v[a] / v[b],
            Op::Min(a, b) => v[a].min(v[b]),
            Op::Max(a, b) => v[a].max(v[b]),
        }
    }

    /// The per-operation form of the margin at `t0` (crate docs of
    /// `inclusion`: each start is the outward-rounded interval rule applied
    /// to its arguments' starts, up to a few float steps): the first node
    /// whose start `starts[i]` is wider than the [`Interval`] operation on
    /// its arguments' starts plus `8·ε·M + 8·MIN_SUBNORMAL` (`M` that
    /// result's largest magnitude), as `(node, start width, allowed)`.
    ///
    /// The whole-tree margin `4·w + 2·n·ε·M` against the point evaluation
    /// cannot hold when the point enclosure is already wide and a later
    /// operation amplifies a one-ulp difference exponentially (seed
    /// `0x7392ce0ebae9277a`: a division one ulp wider than `Interval`'s,
    /// then `cos` of `≈ 9·10⁵`, then `exp` of a width-100 argument); this
    /// check still bounds every step. `sqrt`/`powf` of an argument whose
    /// start reaches `0` are the documented relaxation and are skipped.
    pub fn local_start_excess<T: Flt>(&self, starts: &[Interval<T>]) -> Option<(usize, f64, f64)> {
        for (i, op) in self.0.iter().enumerate() {
            if matches!(op, Op::T | Op::C(_)) {
                continue;
            }
            if let Op::Sqrt(a) | Op::Powf(a, _) = *op {
                if starts[a].lo() <= T::ZERO {
                    continue;
                }
            }
            let local: Interval<T> = Self::apply(*op, starts[i], &starts[..i]);
            let s = starts[i];
            if s.is_empty() || local.is_empty() {
                continue;
            }
            let (sl, sh) = (s.lo().as_f64(), s.hi().as_f64());
            let (ll, lh) = (local.lo().as_f64(), local.hi().as_f64());
            if !(sl.is_finite() && sh.is_finite() && ll.is_finite() && lh.is_finite()) {
                continue;
            }
            let m = ll.abs().max(lh.abs());
            let allowed =
                (lh - ll) + 8.0 * T::EPSILON.as_f64() * m + 8.0 * T::MIN_SUBNORMAL.as_f64();
            if sh - sl > allowed {
                return Some((i, sh - sl, allowed));
            }
        }
        None
    }

    /// Whether a `sqrt`/`powf` argument's point enclosure at `t0` touches 0
    /// (the documented relaxed-start case) or `RelaxStart`-like effects can
    /// occur.
    fn root_arg_touches_zero<T: Flt>(&self, t0: T) -> bool {
        let v: Vec<Interval<T>> = self.eval_all(Interval::point(t0));
        self.0.iter().any(|op| match *op {
            Op::Sqrt(a) | Op::Powf(a, _) => v[a].lo() <= T::ZERO,
            _ => false,
        })
    }

    /// Whether some node's forward bound has a non-finite coefficient or
    /// start (a float overflow, e.g. `f32` values beyond `10³⁸`).
    fn overflows<T: Flt>(&self, t0: T, t1: T, mode: Composition) -> bool {
        let v: Vec<ForwardQuadratic<T>> =
            self.eval_all(ForwardQuadratic::ray_param_with(t0, t1, mode));
        let l: Vec<ForwardLinear<T>> = self.eval_all(ForwardLinear::ray_param(t0, t1));
        let bad = |x: T| !x.is_finite();
        v.iter().any(|b| {
            b.lower_coeffs()
                .into_iter()
                .chain(b.upper_coeffs())
                .any(bad)
                || bad(b.start().lo())
                || bad(b.start().hi())
        }) || l.iter().any(|b| b.slopes().into_iter().any(bad))
    }

    /// The reference value at the exact real `t` and the largest magnitude
    /// of an intermediate result, or `None` where the expression is
    /// undefined.
    fn reference(&self, t: &BigFloat) -> Option<(BigFloat, BigFloat)> {
        let mut v: Vec<BigFloat> = Vec::with_capacity(self.0.len());
        let mut mag = BigFloat::from_u64(0, 64);
        let c = |x: f32| r::from_f64(f64::from(x));
        let zero = BigFloat::from_u64(0, 64);
        let one = BigFloat::from_u64(1, 64);
        for op in &self.0 {
            let y = match *op {
                Op::T => t.clone(),
                Op::C(x) => c(x),
                Op::Neg(a) => v[a].neg(),
                Op::Sqr(a) => v[a].mul(&v[a], PREC, Rm::ToEven),
                Op::Powi(a, n) => {
                    let x = &v[a];
                    if n < 0 && x.is_zero() {
                        return None;
                    }
                    let mut p = one.clone();
                    for _ in 0..n.unsigned_abs() {
                        p = p.mul(x, PREC, Rm::ToEven);
                    }
                    if n < 0 {
                        one.div(&p, PREC, Rm::ToEven)
                    } else {
                        p
                    }
                }
                Op::Powf(a, p) => {
                    let x = &v[a];
                    if x.is_negative() || (x.is_zero() && p < 0.0) {
                        return None;
                    }
                    if x.is_zero() {
                        zero.clone()
                    } else {
                        let l = with_cc(|cc| x.ln(PREC, Rm::ToEven, cc));
                        let e = l.mul(&c(p), PREC, Rm::ToEven);
                        with_cc(|cc| e.exp(PREC, Rm::ToEven, cc))
                    }
                }
                Op::Sqrt(a) => {
                    if v[a].is_negative() {
                        return None;
                    }
                    v[a].sqrt(PREC, Rm::ToEven)
                }
                Op::Recip(a) => {
                    if v[a].is_zero() {
                        return None;
                    }
                    one.div(&v[a], PREC, Rm::ToEven)
                }
                Op::Exp(a) => {
                    let x = &v[a];
                    // Beyond every float range: the bounds are then ±∞ or
                    // 0-ish; skip such samples (no float can be checked).
                    if r::lt(&r::from_f64(800.0), x) {
                        return None;
                    }
                    if r::lt(x, &r::from_f64(-800.0)) {
                        zero.clone()
                    } else {
                        with_cc(|cc| x.exp(PREC, Rm::ToEven, cc))
                    }
                }
                Op::Ln(a) => {
                    if !v[a].is_positive() || v[a].is_zero() {
                        return None;
                    }
                    with_cc(|cc| v[a].ln(PREC, Rm::ToEven, cc))
                }
                Op::Sin(a) | Op::Cos(a) => {
                    // Huge arguments need more precision for the reduction
                    // than PREC gives; no tree of this test reaches them
                    // with a meaningful bound.
                    if r::lt(&r::from_f64(1e6), &v[a].abs()) {
                        return None;
                    }
                    if matches!(*op, Op::Sin(_)) {
                        with_cc(|cc| v[a].sin(PREC, Rm::ToEven, cc))
                    } else {
                        with_cc(|cc| v[a].cos(PREC, Rm::ToEven, cc))
                    }
                }
                Op::Abs(a) => v[a].abs(),
                Op::OneMinus(a) => r::max(one.sub(&v[a], PREC, Rm::ToEven), zero.clone()),
                Op::AddC(a, x) => v[a].add(&c(x), PREC, Rm::ToEven),
                Op::MulC(a, x) => v[a].mul(&c(x), PREC, Rm::ToEven),
                Op::DivC(a, x) => v[a].div(&c(x), PREC, Rm::ToEven),
                Op::Add(a, b) => v[a].add(&v[b], PREC, Rm::ToEven),
                Op::Sub(a, b) => v[a].sub(&v[b], PREC, Rm::ToEven),
                Op::Mul(a, b) => v[a].mul(&v[b], PREC, Rm::ToEven),
                Op::Div(a, b) => {
                    if v[b].is_zero() {
                        return None;
                    }
                    v[a].div(&v[b], PREC, Rm::ToEven)
                }
                Op::Min(a, b) => r::min(v[a].clone(), v[b].clone()),
                Op::Max(a, b) => r::max(v[a].clone(), v[b].clone()),
            };
            if y.is_nan() || y.is_inf() {
                return None;
            }
            let m = y.abs();
            if r::lt(&mag, &m) {
                mag = m;
            }
            v.push(y);
        }
        let last = v.pop().expect("non-empty tree");
        Some((last, mag))
    }
}

/// The exact value of `s + τ(a + bτ)` (an undefined `∞ − ∞` counts as the
/// bound's own infinity: `−∞` for a lower, `+∞` for an upper side).
pub fn side_at(s: f64, a: f64, b: f64, tau: &BigFloat, upper: bool) -> BigFloat {
    if tau.is_zero() {
        return r::from_f64(s);
    }
    let p = 1024;
    let bt = r::from_f64(b).mul(tau, p, Rm::ToEven);
    let inner = r::from_f64(a).add(&bt, p, Rm::ToEven);
    let v = r::from_f64(s).add(&tau.mul(&inner, p, Rm::ToEven), p, Rm::ToEven);
    if v.is_nan() {
        r::from_f64(if upper {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        })
    } else {
        v
    }
}

/// Slack of the comparisons: `2^-150 ·` the largest intermediate magnitude.
pub fn slack(mag: &BigFloat) -> BigFloat {
    mag.mul(&r::pow2(-150), PREC, Rm::ToEven)
}

/// `lo − slack ≤ y ≤ hi + slack`; an infinite bound always holds.
pub fn within(lo: f64, hi: f64, y: &BigFloat, mag: &BigFloat) -> bool {
    let sl = slack(mag);
    let lo_ok = lo == f64::NEG_INFINITY || r::le(&r::from_f64(lo).sub(&sl, PREC, Rm::ToEven), y);
    let hi_ok = hi == f64::INFINITY || r::le(y, &r::from_f64(hi).add(&sl, PREC, Rm::ToEven));
    lo_ok && hi_ok
}

/// A forward bound of either degree, seen through its parts.
pub struct Parts {
    name: &'static str,
    start: (f64, f64),
    lo: (f64, f64),
    hi: (f64, f64),
    h: f64,
    valid: bool,
    step: f64,
    relax_start: bool,
}

impl Parts {
    fn linear<T: Flt>(b: ForwardLinear<T>) -> Self {
        let [l, u] = b.slopes();
        Self {
            name: "linear",
            start: (b.start().lo().as_f64(), b.start().hi().as_f64()),
            lo: (l.as_f64(), 0.0),
            hi: (u.as_f64(), 0.0),
            h: b.validity().as_f64(),
            valid: b.is_valid(),
            step: b.safe_step().as_f64(),
            relax_start: false,
        }
    }

    fn quadratic<T: Flt>(b: ForwardQuadratic<T>) -> Self {
        let [la, lb] = b.lower_coeffs();
        let [ua, ub] = b.upper_coeffs();
        Self {
            name: "quadratic",
            start: (b.start().lo().as_f64(), b.start().hi().as_f64()),
            lo: (la.as_f64(), lb.as_f64()),
            hi: (ua.as_f64(), ub.as_f64()),
            h: b.validity().as_f64(),
            valid: b.is_valid(),
            step: b.safe_step().as_f64(),
            relax_start: b.composition() == Composition::RelaxStart,
        }
    }

    fn lower(&self, tau: &BigFloat) -> f64 {
        side_at(self.start.0, self.lo.0, self.lo.1, tau, false).to_f64_lossy_down()
    }

    fn bounds(&self, tau: &BigFloat) -> (BigFloat, BigFloat) {
        (
            side_at(self.start.0, self.lo.0, self.lo.1, tau, false),
            side_at(self.start.1, self.hi.0, self.hi.1, tau, true),
        )
    }
}

/// Conversions used only for reporting.
trait Lossy {
    fn to_f64_lossy_down(&self) -> f64;
}
impl Lossy for BigFloat {
    fn to_f64_lossy_down(&self) -> f64 {
        let s = r::show(self);
        s.parse().unwrap_or(f64::NAN)
    }
}

/// Statistics over a run.
#[derive(Default)]
pub struct Stats {
    pub cases: u64,
    pub valid: [u64; 2],
    pub checked_samples: u64,
    pub step_checks: u64,
    pub quad_tighter: u64,
    pub compared: u64,
    pub shortened: [u64; 2],
    /// Starts past the whole-tree margin that passed the per-operation one.
    pub start_local: u64,
}

thread_local! {
    pub static STATS: RefCell<Stats> = RefCell::new(Stats::default());
}

pub fn fail(msg: String) -> Result<(), TestCaseError> {
    Err(TestCaseError::fail(msg))
}

/// One case from a proptest seed: a tree, an interval and a composition
/// variant.
pub fn check_case<T: Flt + FieldNum<T>>(seed: u64) -> Result<(), TestCaseError> {
    check_rng::<T>(Rng::seeded(seed), &format!("seed={seed:#x}"))
}

/// One case drawn from a fuzzer input's bytes.
pub fn check_bytes<T: Flt + FieldNum<T>>(data: &[u8]) -> Result<(), TestCaseError> {
    check_rng::<T>(Rng::from_bytes(data), &format!("bytes={data:02x?}"))
}

/// One case drawn from `rng`; `label` names it in failure messages.
pub fn check_rng<T: Flt + FieldNum<T>>(mut rng: Rng, label: &str) -> Result<(), TestCaseError> {
    let depth = 6 + rng.below(3) as u32;
    let tree = Tree::generate(&mut rng, depth);
    let t0f = rng.range(-3.0, 3.0);
    let len = rng.log_range(1e-4, 8.0);
    let t1f = t0f + len;
    let mode = [
        Composition::ValidityInterval,
        Composition::RelaxStart,
        Composition::RelaxMax,
    ][rng.below(3) as usize];
    let (t0, t1) = (T::from_f64(f64::from(t0f)), T::from_f64(f64::from(t1f)));
    if t1 <= t0 {
        return Ok(());
    }
    // Every node's bound: the roots are checked, the nodes' starts feed the
    // per-operation start check.
    let lin_all: Vec<ForwardLinear<T>> = tree.eval_all(ForwardLinear::ray_param(t0, t1));
    let quad_all: Vec<ForwardQuadratic<T>> =
        tree.eval_all(ForwardQuadratic::ray_param_with(t0, t1, mode));
    let (lin, quad) = (
        *lin_all.last().expect("non-empty tree"),
        *quad_all.last().expect("non-empty tree"),
    );
    let point: Interval<T> = tree.eval(Interval::point(t0));
    let bounds = [Parts::linear(lin), Parts::quadratic(quad)];
    let starts: [Vec<Interval<T>>; 2] = [
        lin_all.iter().map(|b| b.start()).collect(),
        quad_all.iter().map(|b| b.start()).collect(),
    ];
    let ctx = || {
        format!(
            "{} {label} t0={t0:e} t1={t1:e} mode={mode:?} tree={:?}",
            T::NAME,
            tree.0
        )
    };

    let bt0 = big(t0);
    let len_exact = big(t1).sub(&bt0, 1024, Rm::ToEven);
    let f_t0 = tree.reference(&bt0);
    STATS.with(|s| s.borrow_mut().cases += 1);

    // Shared grid over [t0, t1]: τ_k = len·k/GRID.
    let grid: Vec<(BigFloat, Option<(BigFloat, BigFloat)>)> = (0..=GRID)
        .map(|k| {
            let tau = if k == GRID {
                len_exact.clone()
            } else {
                len_exact.mul(&r::int(k as i64), 1024, Rm::ToEven).div(
                    &r::int(GRID as i64),
                    PREC,
                    Rm::Down,
                )
            };
            let t = bt0.add(&tau, 1024, Rm::ToEven);
            let v = tree.reference(&t);
            (tau, v)
        })
        .collect();

    // The other number types through the same trait: Interval and Affine
    // enclose the reference on the whole grid; a Jet's value is the plain
    // float evaluation.
    let iv: Interval<T> = tree.eval(Interval::new(t0, t1));
    let af: Affine<T, 1> = tree.eval(FieldNum::ray_param(t0, t1));
    let afi = af.to_interval();
    for (tau, v) in &grid {
        let Some((y, mag)) = v else { continue };
        for (name, e) in [("interval", iv), ("affine", afi)] {
            if !e.is_empty() && !within(e.lo().as_f64(), e.hi().as_f64(), y, mag) {
                return fail(format!(
                    "{name}: f(t0+τ) = {} not in {e:?} at τ = {}; {}",
                    r::show(y),
                    r::show(tau),
                    ctx()
                ));
            }
            if e.is_empty() {
                return fail(format!(
                    "{name}: EMPTY although f is defined at τ = {}; {}",
                    r::show(tau),
                    ctx()
                ));
            }
        }
    }
    let plain: T = tree.eval(t0);
    let jet: Jet<T> = tree.eval(Jet::variable(t0));
    if !(plain.is_nan() && jet.v.is_nan()) && plain != jet.v {
        return fail(format!(
            "jet value {:e} != plain {:e}; {}",
            jet.v,
            plain,
            ctx()
        ));
    }

    for (i, b) in bounds.iter().enumerate() {
        if !b.valid {
            continue;
        }
        STATS.with(|s| s.borrow_mut().valid[i] += 1);
        let h = b.h;
        // 3. validity
        if h.is_nan() || h < 0.0 || r::lt(&len_exact, &r::from_f64(h)) {
            return fail(format!(
                "{}: validity h={h:e} not in [0, t1−t0]; {}",
                b.name,
                ctx()
            ));
        }
        let start_finite = b.start.0.is_finite() && b.start.1.is_finite();
        if start_finite && h == 0.0 && f_t0.is_some() && !tree.overflows(t0, t1, mode) {
            return fail(format!(
                "{}: validity h = 0 at a finite start; {}",
                b.name,
                ctx()
            ));
        }
        if h < len as f64 * 0.999 {
            STATS.with(|s| s.borrow_mut().shortened[i] += 1);
        }
        // 1. exact at t0 within the margin
        if let Some((v, mag)) = &f_t0 {
            if !within(b.start.0, b.start.1, v, mag) {
                return fail(format!(
                    "{}: f(t0) = {} not in start [{:e}, {:e}]; {}",
                    b.name,
                    r::show(v),
                    b.start.0,
                    b.start.1,
                    ctx()
                ));
            }
            let relaxed = b.relax_start || tree.root_arg_touches_zero(t0);
            if !relaxed && start_finite && !point.is_empty() {
                // The documented margin: 4× the point-interval width plus
                // 2·n·ε·M (n operations, M the largest intermediate |value|).
                let pw = (point.hi().as_f64() - point.lo().as_f64()).abs();
                let w = b.start.1 - b.start.0;
                let n = tree.0.len() as f64;
                let m = r::show(mag).parse::<f64>().unwrap_or(f64::INFINITY);
                let margin =
                    4.0 * pw + 2.0 * n * T::EPSILON.as_f64() * m + 8.0 * T::MIN_SUBNORMAL.as_f64();
                if w > margin {
                    // Past the whole-tree margin: every operation must still
                    // be within a few float steps of the interval rule on
                    // its arguments' starts.
                    if let Some((node, ws, allowed)) = tree.local_start_excess(&starts[i]) {
                        return fail(format!(
                            "{}: start width {w:e} > margin (point interval width {pw:e}), and node {node} \
                             start width {ws:e} > {allowed:e} (interval rule on its arguments' starts); {}",
                            b.name,
                            ctx()
                        ));
                    }
                    STATS.with(|s| s.borrow_mut().start_local += 1);
                }
            }
        }
        // 2. containment on the grid within [0, h], plus τ = h.
        let bh = r::from_f64(h);
        let mut end_sample = None;
        if h.is_finite() {
            let te = bt0.add(&bh, 1024, Rm::ToEven);
            end_sample = Some((bh.clone(), tree.reference(&te)));
        }
        for (tau, v) in grid.iter().chain(end_sample.iter()) {
            if r::lt(&bh, tau) {
                continue;
            }
            let Some((y, mag)) = v else { continue };
            let (lo, hi) = b.bounds(tau);
            let sl = slack(mag);
            let ok = r::le(&lo.sub(&sl, PREC, Rm::ToEven), y)
                && r::le(y, &hi.add(&sl, PREC, Rm::ToEven));
            STATS.with(|s| s.borrow_mut().checked_samples += 1);
            if !ok {
                return fail(format!(
                    "{}: f(t0+τ) = {} not in [{}, {}] at τ = {}; start=({:e},{:e}) lo={:?} hi={:?} h={h:e}; {}",
                    b.name,
                    r::show(y),
                    r::show(&lo),
                    r::show(&hi),
                    r::show(tau),
                    b.start.0,
                    b.start.1,
                    b.lo,
                    b.hi,
                    ctx()
                ));
            }
        }
        // 4. the safe step never passes the first root.
        if let Some((v0, _)) = &f_t0 {
            let outside = b.start.0 > 0.0;
            let inside = b.start.1 < 0.0;
            if (outside || inside) && b.step > 0.0 {
                let step = r::from_f64(b.step);
                let mut points: Vec<(BigFloat, Option<(BigFloat, BigFloat)>)> = (0..GRID)
                    .map(|k| {
                        let tau = step.mul(&r::int(k as i64), 1024, Rm::ToEven).div(
                            &r::int(GRID as i64),
                            PREC,
                            Rm::Down,
                        );
                        let t = bt0.add(&tau, 1024, Rm::ToEven);
                        (tau.clone(), tree.reference(&t))
                    })
                    .collect();
                points.extend(grid.iter().filter(|(tau, _)| r::lt(tau, &step)).cloned());
                let _ = v0;
                for (tau, v) in &points {
                    let Some((y, mag)) = v else { continue };
                    let sl = slack(mag);
                    let bad = if outside {
                        r::lt(y, &sl.neg())
                    } else {
                        r::lt(&sl, y)
                    };
                    STATS.with(|s| s.borrow_mut().step_checks += 1);
                    if bad {
                        return fail(format!(
                            "{}: the step {:e} passes a root: f(t0+τ) = {} at τ = {} (lower there {:e}); {}",
                            b.name,
                            b.step,
                            r::show(y),
                            r::show(tau),
                            b.lower(tau),
                            ctx()
                        ));
                    }
                }
            }
        }
    }
    // 5. tightness at the end of the common validity interval.
    let (l, q) = (&bounds[0], &bounds[1]);
    if l.valid && q.valid && !q.relax_start {
        let h = l.h.min(q.h);
        if h.is_finite() && h > 0.0 {
            let tau = r::from_f64(h);
            let (ll, lh) = l.bounds(&tau);
            let (ql, qh) = q.bounds(&tau);
            let wl = lh.sub(&ll, PREC, Rm::ToEven);
            let wq = qh.sub(&ql, PREC, Rm::ToEven);
            if !wl.is_nan() && !wq.is_nan() && !wl.is_inf() {
                let tol = wl.abs().mul(&r::pow2(-20), PREC, Rm::ToEven);
                let tighter = r::le(&wq, &wl.add(&tol, PREC, Rm::ToEven));
                STATS.with(|s| {
                    let mut s = s.borrow_mut();
                    s.compared += 1;
                    s.quad_tighter += u64::from(tighter);
                });
            }
        }
    }
    Ok(())
}

/// Prints every node's bounds for one case: set `BOUNDTRACE_TRACE_SEED`
/// (hex or decimal) to debug a failure.
pub fn trace_case<T: Flt>(seed: u64) {
    let mut rng = Rng::seeded(seed);
    let depth = 6 + rng.below(3) as u32;
    let tree = Tree::generate(&mut rng, depth);
    let t0f = rng.range(-3.0, 3.0);
    let len = rng.log_range(1e-4, 8.0);
    let mode = [
        Composition::ValidityInterval,
        Composition::RelaxStart,
        Composition::RelaxMax,
    ][rng.below(3) as usize];
    let (t0, t1) = (
        T::from_f64(f64::from(t0f)),
        T::from_f64(f64::from(t0f + len)),
    );
    for i in 0..tree.0.len() {
        let sub = Tree(tree.0[..=i].to_vec());
        let l: ForwardLinear<T> = sub.eval(ForwardLinear::ray_param(t0, t1));
        let q: ForwardQuadratic<T> = sub.eval(ForwardQuadratic::ray_param_with(t0, t1, mode));
        let p: Interval<T> = sub.eval(Interval::point(t0));
        println!(
            "{i}: {:?}\n   point {:?}\n   lin {:?} {:?} h={:e}\n   quad {:?} {:?} {:?} h={:e}",
            tree.0[i],
            p,
            l.start(),
            l.slopes(),
            l.validity(),
            q.start(),
            q.lower_coeffs(),
            q.upper_coeffs(),
            q.validity()
        );
    }
}
