//! Bisection methods: interval arithmetic (Mitchell 1990; thesis §2.2.2) and
//! revised affine arithmetic with interval pruning (Fryazinov, Pasko and
//! Comninos 2010), depth-first with an explicit fixed-size stack.
//!
//! Both examine sub-intervals of the span left to right. An interval whose
//! enclosure of `f` excludes `0` is discarded (proven root-free); otherwise
//! it is split in two (affine: first *pruned* to the part where the affine
//! form's linear part can reach zero). An interval no longer than `eps`
//! whose enclosure contains `0` is a *leaf*: the signs of `f` at its ends
//! (as sound enclosures) decide between a crossing (registered at the middle, so within `eps / 2`
//! of a true root, as [`Side::Entering`]/[`Side::Leaving`]) and a
//! [`Side::Touch`] — the latter only after halving the leaf further, down to
//! `eps / 2^TOUCH_DEPTH` ([`TOUCH_DEPTH`]),
//! without excluding `0` or finding a sign change. Signs classify `f` not proven positive as inside, so a root at a shared
//! end point is registered once.
//!
//! One *step* is one enclosure evaluation (the popped interval).
//! [`STACK_CAPACITY`] bounds the depth; intervals that cannot be split
//! further (float resolution, or the stack is full) are leaves.

use crate::march::{TOUCH_DEPTH, Walk, value_enclosure};
use crate::method::{Mode, Params};
use crate::trace::{Root, Side, Status, Trace};
use boundtrace_ia_core::{Affine, Interval, Real};
use boundtrace_inclusion::{Field, ForwardLinear, Ray};

/// The bisection stack depth (enough for `(t1 − t0) / eps` up to `2⁶³`).
pub const STACK_CAPACITY: usize = 64;

/// `true` unless `f` is proven positive (inside, or on the surface within
/// rounding).
#[inline]
fn inside<T: Real>(f: Interval<T>) -> bool {
    !(f.lo() > T::ZERO)
}

/// How an enclosure method narrows `[a, b]`: `None` when it proves it
/// root-free, else the (possibly pruned) sub-interval that may hold roots.
pub(crate) trait Narrow<T: Real> {
    fn narrow<F: Field<T>>(field: &F, ray: &Ray<T>, a: T, b: T) -> Option<(T, T)>;
}

/// Interval arithmetic (Mitchell 1990).
pub(crate) struct ByInterval;
impl<T: Real> Narrow<T> for ByInterval {
    #[inline]
    fn narrow<F: Field<T>>(field: &F, ray: &Ray<T>, a: T, b: T) -> Option<(T, T)> {
        let f: Interval<T> = field.eval(ray.at::<Interval<T>>(a, b));
        f.contains(T::ZERO).then_some((a, b))
    }
}

/// Revised affine arithmetic with interval pruning (Fryazinov et al. 2010).
pub(crate) struct ByAffine;
impl<T: Real> Narrow<T> for ByAffine {
    /// Revised affine form `f ∈ x₀ + x₁·ε₀ ± R` with the ray `t = m + r·ε₀`
    /// (noise symbol 0): roots need `|x₀ + x₁ε₀| ≤ R`, i.e.
    /// `ε₀ ∈ ([−R, R] − x₀) / x₁`, mapped back to `t` with outward rounding.
    fn narrow<F: Field<T>>(field: &F, ray: &Ray<T>, a: T, b: T) -> Option<(T, T)> {
        let f: Affine<T, 1> = field.eval(ray.at::<Affine<T, 1>>(a, b));
        if f.is_empty() {
            return None;
        }
        if !f.to_interval().contains(T::ZERO) {
            return None;
        }
        if !f.is_bounded() {
            return Some((a, b));
        }
        let tv = Affine::<T, 1>::variable(Interval::new(a, b), 0);
        let (x0, x1, r) = (f.center(), f.coeffs()[0], f.err());
        if x1 == T::ZERO {
            return Some((a, b));
        }
        let e = ((Interval::new(-r, r) - x0) / x1).intersection(Interval::new(-T::ONE, T::ONE));
        if e.is_empty() {
            return None;
        }
        let t = Interval::point(tv.center()) + Interval::point(tv.coeffs()[0]) * e;
        let (lo, hi) = (t.lo().max(a), t.hi().min(b));
        if lo > hi { None } else { Some((lo, hi)) }
    }
}

/// Bisection of `ray` on `span`, narrowing with `M` ([`ByInterval`] or
/// [`ByAffine`]).
pub(crate) fn bisect<T: Real, F: Field<T>, M: Narrow<T>>(
    field: &F,
    ray: &Ray<T>,
    span: [T; 2],
    mode: Mode,
    params: &Params<T>,
    roots: crate::march::RootSlots<'_, T>,
) -> Trace<T> {
    let mut w = Walk::new(roots, mode, params.eps);
    let mut stack = [(T::ZERO, T::ZERO); STACK_CAPACITY];
    stack[0] = (span[0], span[1]);
    let mut sp = 1usize;
    // Leaves without a sign change are halved further, down to this width.
    let fine = params.eps / T::from_f64(f64::from(1u32 << TOUCH_DEPTH));
    while sp > 0 {
        sp -= 1;
        let (a, b) = stack[sp];
        if w.stats.steps >= params.max_steps {
            return w.done(Status::MaxSteps, a);
        }
        w.stats.steps += 1;
        w.stats.bound_evals += 1;
        let Some((a2, b2)) = M::narrow(field, ray, a, b) else {
            continue;
        };
        let mid = a2 + (b2 - a2) * T::HALF;
        let splittable = mid > a2 && mid < b2 && sp + 2 <= STACK_CAPACITY;
        if b2 - a2 > params.eps && splittable {
            stack[sp] = (mid, b2);
            stack[sp + 1] = (a2, mid);
            sp += 2;
            continue;
        }
        // A leaf: a crossing, or (after further halving below eps, see
        // `march::resolve`) a touch.
        let fa = value_enclosure(field, ray, a2);
        let fb = value_enclosure(field, ray, b2);
        w.stats.field_evals += 2;
        let side = match (inside(fa), inside(fb)) {
            (false, true) => Side::Entering,
            (true, false) => Side::Leaving,
            _ if splittable && b2 - a2 > fine => {
                // Same sign at both ends. On a near-tangent stretch (the
                // field within ~10⁻⁶ of 0 over a long span) the interval
                // extension's dependency overestimation would only exclude
                // 0 on pieces ~100× shorter than `eps`; a first-order
                // enclosure (the range of the forward linear bound, sound
                // like every bound of `boundtrace-inclusion`) usually proves
                // the whole leaf root-free at once.
                w.stats.bound_evals += 1;
                let lin: ForwardLinear<T> = field.eval(ray.at(a2, b2));
                let r = lin.range();
                if lin.is_valid()
                    && lin.validity() >= b2 - a2
                    && !r.is_empty()
                    && !r.contains(T::ZERO)
                {
                    continue;
                }
                stack[sp] = (mid, b2);
                stack[sp + 1] = (a2, mid);
                sp += 2;
                continue;
            }
            _ => Side::Touch,
        };
        let t = if fa.contains(T::ZERO) { a2 } else { mid };
        let next = w.register(Root { t, side }, a);
        if next.stop {
            return next.trace;
        }
        if side == Side::Touch {
            // The rest of this contact, up to t + eps, is the same root:
            // drop or trim the pending intervals there (a near-zero stretch
            // would otherwise be explored down to the finest level
            // everywhere).
            let end = (t + params.eps).min(span[1]);
            while sp > 0 && stack[sp - 1].1 <= end {
                sp -= 1;
            }
            if sp > 0 && stack[sp - 1].0 < end {
                stack[sp - 1].0 = end;
            }
            // A sign change across the dropped part is a crossing next to
            // the touch: it replaces the touch (see `Walk::register`).
            let fe = value_enclosure(field, ray, end);
            w.stats.field_evals += 1;
            let side = match (inside(fa), inside(fe)) {
                (false, true) => Some(Side::Entering),
                (true, false) => Some(Side::Leaving),
                _ => None,
            };
            if let Some(side) = side {
                let tc = t + (end - t) * T::HALF;
                let next = w.register(Root { t: tc, side }, a);
                if next.stop {
                    return next.trace;
                }
            }
        }
    }
    w.done(Status::Finished, span[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Method;
    use crate::trace::trace;
    use boundtrace_inclusion::FieldNum;

    struct Ball;
    impl Field<f64> for Ball {
        fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
            (p[0].sqr() + p[1].sqr() + p[2].sqr()).sqrt() - 1.0
        }
    }

    const NONE: Root<f64> = Root {
        t: f64::NAN,
        side: Side::Touch,
    };

    #[test]
    fn both_bisections_find_both_roots() {
        let p = Params::new();
        let ray = Ray::new([-3.0, 0.3, 0.0], [1.0, 0.0, 0.0]);
        let h = (1.0f64 - 0.09).sqrt();
        for m in [Method::Interval, Method::Affine] {
            let mut buf = [NONE; 4];
            let tr = trace(&Ball, &ray, [0.0, 6.0], m, Mode::Transparent, &p, &mut buf);
            assert_eq!((tr.status, tr.roots), (Status::Finished, 2), "{m}");
            assert!((buf[0].t - (3.0 - h)).abs() <= p.eps / 2.0 + 1e-12, "{m}");
            assert!((buf[1].t - (3.0 + h)).abs() <= p.eps / 2.0 + 1e-12, "{m}");
            assert_eq!((buf[0].side, buf[1].side), (Side::Entering, Side::Leaving));
            let tr = trace(&Ball, &ray, [0.0, 6.0], m, Mode::Opaque, &p, &mut buf);
            assert_eq!(
                (tr.status, tr.roots, tr.t_reached),
                (Status::Finished, 1, buf[0].t)
            );
        }
    }

    #[test]
    fn roots_on_bisection_boundaries_are_reported_once_with_their_side() {
        // Through the centre: the roots t = 2 and t = 4 fall exactly on
        // (pruned) interval ends, next to leaves that cannot decide.
        let p = Params::new();
        let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        for m in [Method::Interval, Method::Affine] {
            let mut buf = [NONE; 8];
            let tr = trace(&Ball, &ray, [0.0, 6.0], m, Mode::Transparent, &p, &mut buf);
            let got = &buf[..tr.roots as usize];
            assert_eq!(got.len(), 2, "{m}: {got:?}");
            assert_eq!(
                (got[0].side, got[1].side),
                (Side::Entering, Side::Leaving),
                "{m}"
            );
            assert!((got[0].t - 2.0).abs() <= p.eps && (got[1].t - 4.0).abs() <= p.eps);
        }
    }

    #[test]
    fn affine_pruning_takes_fewer_steps() {
        let p = Params::new();
        let ray = Ray::new([-3.0, 0.3, 0.1], [1.0, 0.0, 0.0]);
        let mut buf = [NONE; 4];
        let ia = trace(
            &Ball,
            &ray,
            [0.0, 6.0],
            Method::Interval,
            Mode::Opaque,
            &p,
            &mut buf,
        );
        let aa = trace(
            &Ball,
            &ray,
            [0.0, 6.0],
            Method::Affine,
            Mode::Opaque,
            &p,
            &mut buf,
        );
        assert!(aa.stats.steps < ia.stats.steps, "{aa:?} vs {ia:?}");
    }

    #[test]
    fn misses_and_gives_up() {
        let p = Params::new();
        let ray = Ray::new([-3.0, 1.2, 0.0], [1.0, 0.0, 0.0]);
        let mut buf = [NONE; 2];
        for m in [Method::Interval, Method::Affine] {
            let tr = trace(&Ball, &ray, [0.0, 6.0], m, Mode::Opaque, &p, &mut buf);
            assert_eq!((tr.status, tr.roots), (Status::Finished, 0), "{m}");
        }
        let p3 = p.with_max_steps(3).unwrap();
        let ray = Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let tr = trace(
            &Ball,
            &ray,
            [0.0, 6.0],
            Method::Interval,
            Mode::Opaque,
            &p3,
            &mut buf,
        );
        assert_eq!((tr.status, tr.roots), (Status::MaxSteps, 0));
        assert!(tr.t_reached <= 2.0);
    }
}
