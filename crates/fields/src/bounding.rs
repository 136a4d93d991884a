//! Bounding volumes: the support of a primitive (sphere for point blobs,
//! sphere-cone for segments) and the augmented bounding volumes (ABVs) of
//! blobtree primitives (synchronized-tracing paper §4.3: sphere, box,
//! sphere-cone).
//!
//! All shapes are closed and convex; every query is conservative (a shape
//! may report an intersection that the exact shape does not have, never the
//! reverse).

/// A ball `|p − center| ≤ radius`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Sphere<T> {
    /// Center.
    pub center: [T; 3],
    /// Radius (≥ 0).
    pub radius: T,
}

/// An axis-aligned box `min ≤ p ≤ max` (per coordinate).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Aabb<T> {
    /// Lower corner.
    pub min: [T; 3],
    /// Upper corner.
    pub max: [T; 3],
}

/// A sphere-cone: the convex hull of the balls `(a, ra)` and `(b, rb)`
/// (the support of a segment primitive with linearly varying radius).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct SphereCone<T> {
    /// First end-point.
    pub a: [T; 3],
    /// Radius at `a` (≥ 0).
    pub ra: T,
    /// Second end-point.
    pub b: [T; 3],
    /// Radius at `b` (≥ 0).
    pub rb: T,
}

/// One of the bounding shapes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bounding<T> {
    /// A ball.
    Sphere(Sphere<T>),
    /// An axis-aligned box.
    Aabb(Aabb<T>),
    /// A sphere-cone.
    SphereCone(SphereCone<T>),
}

use boundtrace_ia_core::Real;

/// A relative slack `k·ε·(|scale| + 1)` added to radii and box sides so that
/// the floating-point queries below stay conservative (rounding can only
/// make a shape look larger).
#[inline]
fn slack<T: Real>(scale: T) -> T {
    T::from_f64(16.0) * T::EPSILON * (scale.abs() + T::ONE)
}

#[inline]
fn max_abs3<T: Real>(p: [T; 3]) -> T {
    p[0].abs().max(p[1].abs()).max(p[2].abs())
}

#[inline]
fn sub3<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot3<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn lerp3<T: Real>(a: [T; 3], b: [T; 3], t: T) -> [T; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

/// `r ≥ 0` with NaN mapped to `+∞` (an unknown offset can only enlarge a
/// conservative volume).
#[inline]
fn offset<T: Real>(r: T) -> T {
    if r.is_nan() {
        T::INFINITY
    } else {
        r.max(T::ZERO)
    }
}

impl<T: Real> Aabb<T> {
    /// The box `[min, max]`.
    #[inline]
    pub fn new(min: [T; 3], max: [T; 3]) -> Self {
        Self { min, max }
    }

    /// Whether some coordinate has `min > max` (or a NaN): the box is empty.
    #[inline]
    pub fn is_empty(&self) -> bool {
        let mut k = 0;
        while k < 3 {
            if self.min[k].is_nan() || self.max[k].is_nan() || self.min[k] > self.max[k] {
                return true;
            }
            k += 1;
        }
        false
    }

    /// The box grown by `r ≥ 0` on every side (the Minkowski sum with the
    /// cube of half-side `r`, which contains the sum with the ball of radius
    /// `r`). A negative `r` is treated as 0, NaN as `+∞`.
    #[inline]
    pub fn inflate(&self, r: T) -> Self {
        let r = offset(r);
        Self {
            min: [self.min[0] - r, self.min[1] - r, self.min[2] - r],
            max: [self.max[0] + r, self.max[1] + r, self.max[2] + r],
        }
    }

    /// Whether `p` is in the closed box.
    #[inline]
    pub fn contains_point(&self, p: [T; 3]) -> bool {
        let mut k = 0;
        while k < 3 {
            if !(p[k] >= self.min[k] && p[k] <= self.max[k]) {
                return false;
            }
            k += 1;
        }
        true
    }

    /// Whether two closed boxes meet (exact: comparisons only).
    #[inline]
    pub fn overlaps(&self, other: &Aabb<T>) -> bool {
        let mut k = 0;
        while k < 3 {
            if !(self.min[k] <= other.max[k] && other.min[k] <= self.max[k]) {
                return false;
            }
            k += 1;
        }
        true
    }

    /// The union hull of two boxes.
    #[inline]
    pub fn union(&self, other: &Aabb<T>) -> Self {
        Self {
            min: [
                self.min[0].min(other.min[0]),
                self.min[1].min(other.min[1]),
                self.min[2].min(other.min[2]),
            ],
            max: [
                self.max[0].max(other.max[0]),
                self.max[1].max(other.max[1]),
                self.max[2].max(other.max[2]),
            ],
        }
    }

    /// The center `(min + max) / 2`.
    #[inline]
    pub fn center(&self) -> [T; 3] {
        [
            (self.min[0] + self.max[0]) * T::HALF,
            (self.min[1] + self.max[1]) * T::HALF,
            (self.min[2] + self.max[2]) * T::HALF,
        ]
    }

    /// The Euclidean distance from `p` to the box (0 inside), rounded to
    /// nearest (callers add [`slack`]).
    #[inline]
    fn distance(&self, p: [T; 3]) -> T {
        let mut d2 = T::ZERO;
        let mut k = 0;
        while k < 3 {
            let d = (self.min[k] - p[k]).max(p[k] - self.max[k]).max(T::ZERO);
            d2 = d2 + d * d;
            k += 1;
        }
        d2.sqrt()
    }

    /// The largest absolute coordinate of the corners (a scale for slack).
    #[inline]
    fn scale(&self) -> T {
        max_abs3(self.min).max(max_abs3(self.max))
    }

    /// The ray parameters `(t_entry, t_exit)` where `origin + t·dir` enters
    /// and leaves the box (slab method), or `None` when the line misses it.
    /// The whole line is considered, so `t_entry` may be negative. A zero direction component is handled
    /// (the slab is then either everything or nothing). The interval is
    /// widened by a few ulps so rounding cannot lose a hit.
    pub fn ray_entry_exit(&self, origin: [T; 3], dir: [T; 3]) -> Option<(T, T)> {
        let mut t0 = T::NEG_INFINITY;
        let mut t1 = T::INFINITY;
        let mut k = 0;
        while k < 3 {
            if dir[k] == T::ZERO {
                if !(origin[k] >= self.min[k] && origin[k] <= self.max[k]) {
                    return None;
                }
            } else {
                let inv = T::ONE / dir[k];
                let a = (self.min[k] - origin[k]) * inv;
                let b = (self.max[k] - origin[k]) * inv;
                let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
                if lo.is_nan() || hi.is_nan() {
                    return None;
                }
                t0 = t0.max(lo - slack(lo));
                t1 = t1.min(hi + slack(hi));
            }
            k += 1;
        }
        if t0 <= t1 { Some((t0, t1)) } else { None }
    }
}

impl<T: Real> Sphere<T> {
    /// The ball grown by `r ≥ 0` (negative `r` is treated as 0, NaN as `+∞`).
    #[inline]
    pub fn inflate(&self, r: T) -> Self {
        Self {
            center: self.center,
            radius: self.radius + offset(r),
        }
    }

    /// Its axis-aligned bounding box.
    #[inline]
    pub fn aabb(&self) -> Aabb<T> {
        let c = self.center;
        let r = self.radius;
        Aabb {
            min: [c[0] - r, c[1] - r, c[2] - r],
            max: [c[0] + r, c[1] + r, c[2] + r],
        }
    }

    #[inline]
    fn tolerance(&self) -> T {
        slack(max_abs3(self.center).max(self.radius))
    }

    /// Whether `p` is in the ball (conservative: up to a few ulps outside
    /// also counts).
    #[inline]
    pub fn contains_point(&self, p: [T; 3]) -> bool {
        let d = sub3(p, self.center);
        dot3(d, d).sqrt() <= self.radius + self.tolerance()
    }

    /// Whether the ball meets the box (conservative).
    #[inline]
    pub fn overlaps_aabb(&self, b: &Aabb<T>) -> bool {
        b.distance(self.center) <= self.radius + self.tolerance() + slack(b.scale())
    }

    /// The ray parameters where `origin + t·dir` enters and leaves the ball
    /// (whole line, so `t_entry` may be negative), widened by a few ulps;
    /// `None` when the line misses it or `dir` is zero.
    pub fn ray_entry_exit(&self, origin: [T; 3], dir: [T; 3]) -> Option<(T, T)> {
        let a = dot3(dir, dir);
        if a.is_nan() || a <= T::ZERO {
            return None;
        }
        let oc = sub3(origin, self.center);
        // Closest approach: t_m = −(oc·d)/|d|², squared distance h² there.
        let tm = -dot3(oc, dir) / a;
        let closest = [
            oc[0] + dir[0] * tm,
            oc[1] + dir[1] * tm,
            oc[2] + dir[2] * tm,
        ];
        let h2 = dot3(closest, closest);
        let r = self.radius + self.tolerance();
        let w2 = r * r - h2;
        if w2.is_nan() || w2 < T::ZERO {
            return None;
        }
        let half = (w2 / a).sqrt();
        let lo = tm - half;
        let hi = tm + half;
        Some((lo - slack(lo), hi + slack(hi)))
    }
}

impl<T: Real> SphereCone<T> {
    /// The sphere-cone grown by `r ≥ 0` (both radii; negative `r` is
    /// treated as 0, NaN as `+∞`).
    #[inline]
    pub fn inflate(&self, r: T) -> Self {
        let r = offset(r);
        Self {
            a: self.a,
            ra: self.ra + r,
            b: self.b,
            rb: self.rb + r,
        }
    }

    /// Its axis-aligned bounding box (union of the two balls' boxes, exact
    /// for the convex hull).
    #[inline]
    pub fn aabb(&self) -> Aabb<T> {
        Sphere {
            center: self.a,
            radius: self.ra,
        }
        .aabb()
        .union(
            &Sphere {
                center: self.b,
                radius: self.rb,
            }
            .aabb(),
        )
    }

    #[inline]
    fn tolerance(&self) -> T {
        slack(
            max_abs3(self.a)
                .max(max_abs3(self.b))
                .max(self.ra)
                .max(self.rb),
        )
    }

    /// `min over t ∈ [0, 1] of dist(a + t(b − a), X) − (ra + t(rb − ra))`
    /// for a convex distance `dist` (to a point or a box): the hull of two
    /// balls is the union of the linearly interpolated balls, so the shape
    /// meets `X` iff this is ≤ 0. The function is convex in `t` with
    /// Lipschitz constant `L = |b − a| + |rb − ra|`; a ternary search keeps
    /// a bracket of width `w` around the minimizer, so the true minimum is
    /// at least `value(mid) − L·w`, which is what is returned (a lower
    /// bound: conservative).
    fn min_gap<F: Fn([T; 3]) -> T>(&self, dist: F) -> T {
        let g = |t: T| dist(lerp3(self.a, self.b, t)) - (self.ra + (self.rb - self.ra) * t);
        let (mut lo, mut hi) = (T::ZERO, T::ONE);
        let third = T::ONE / T::from_f64(3.0);
        let mut i = 0;
        while i < 48 {
            let m0 = lo + (hi - lo) * third;
            let m1 = hi - (hi - lo) * third;
            if g(m0) <= g(m1) {
                hi = m1;
            } else {
                lo = m0;
            }
            i += 1;
        }
        let d = sub3(self.b, self.a);
        let lip = dot3(d, d).sqrt() + (self.rb - self.ra).abs();
        let mid = (lo + hi) * T::HALF;
        g(mid).min(g(T::ZERO)).min(g(T::ONE)) - lip * (hi - lo)
    }

    /// Whether `p` is in the sphere-cone (conservative).
    pub fn contains_point(&self, p: [T; 3]) -> bool {
        self.min_gap(|q| {
            let d = sub3(p, q);
            dot3(d, d).sqrt()
        }) <= self.tolerance()
    }

    /// Whether the sphere-cone meets the box (conservative, see the private
    /// `min_gap`: a convex 1-D minimization with a proven lower bound).
    pub fn overlaps_aabb(&self, b: &Aabb<T>) -> bool {
        // Cheap rejection by bounding boxes first.
        if !self.aabb().inflate(self.tolerance()).overlaps(b) {
            return false;
        }
        self.min_gap(|q| b.distance(q)) <= self.tolerance() + slack(b.scale())
    }

    /// The ray parameters where `origin + t·dir` enters and leaves the
    /// capsule of radius `max(ra, rb)` around `[a, b]`, a superset of the
    /// sphere-cone (whole line; widened by a few ulps); `None` when the line
    /// misses it or `dir` is zero.
    pub fn ray_entry_exit(&self, origin: [T; 3], dir: [T; 3]) -> Option<(T, T)> {
        let r = self.ra.max(self.rb) + self.tolerance();
        let sa = Sphere {
            center: self.a,
            radius: r,
        }
        .ray_entry_exit(origin, dir);
        let sb = Sphere {
            center: self.b,
            radius: r,
        }
        .ray_entry_exit(origin, dir);
        let mut out = match (sa, sb) {
            (Some(x), Some(y)) => Some((x.0.min(y.0), x.1.max(y.1))),
            (Some(x), None) | (None, Some(x)) => Some(x),
            (None, None) => None,
        };
        // Finite cylinder: |(p − a) − ((p − a)·u)u|² ≤ r², 0 ≤ (p − a)·u ≤ |ab|.
        let axis = sub3(self.b, self.a);
        let len2 = dot3(axis, axis);
        if len2 > T::ZERO {
            let oa = sub3(origin, self.a);
            // Components orthogonal to the axis.
            let dd = dot3(dir, axis) / len2;
            let od = dot3(oa, axis) / len2;
            let dp = [
                dir[0] - axis[0] * dd,
                dir[1] - axis[1] * dd,
                dir[2] - axis[2] * dd,
            ];
            let op = [
                oa[0] - axis[0] * od,
                oa[1] - axis[1] * od,
                oa[2] - axis[2] * od,
            ];
            let qa = dot3(dp, dp);
            let qb = dot3(op, dp);
            let qc = dot3(op, op) - r * r;
            let (mut c0, mut c1) = (T::NEG_INFINITY, T::INFINITY);
            let mut hit = true;
            if qa > T::ZERO {
                let disc = qb * qb - qa * qc;
                if disc >= T::ZERO {
                    let s = disc.sqrt();
                    c0 = (-qb - s) / qa;
                    c1 = (-qb + s) / qa;
                } else {
                    hit = false;
                }
            } else if qc > T::ZERO {
                hit = false;
            }
            // Slab 0 ≤ od + t·dd ≤ 1 along the axis.
            if hit {
                if dd != T::ZERO {
                    let s0 = -od / dd;
                    let s1 = (T::ONE - od) / dd;
                    let (s0, s1) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
                    c0 = c0.max(s0);
                    c1 = c1.min(s1);
                } else if !(od >= T::ZERO && od <= T::ONE) {
                    hit = false;
                }
            }
            if hit && c0 <= c1 && c0.is_finite() && c1.is_finite() {
                let c = (c0 - slack(c0), c1 + slack(c1));
                out = match out {
                    Some(x) => Some((x.0.min(c.0), x.1.max(c.1))),
                    None => Some(c),
                };
            }
        }
        out
    }
}

impl<T: Real> Bounding<T> {
    /// The volume grown by `r ≥ 0` (negative `r` is treated as 0, NaN as
    /// `+∞`): the ABV of a primitive whose bound of its 0-isosurface is
    /// `self` and whose ROI upper limit is `r` (paper §4, Fig. 4d).
    #[inline]
    pub fn inflate(&self, r: T) -> Self {
        match self {
            Bounding::Sphere(s) => Bounding::Sphere(s.inflate(r)),
            Bounding::Aabb(b) => Bounding::Aabb(b.inflate(r)),
            Bounding::SphereCone(c) => Bounding::SphereCone(c.inflate(r)),
        }
    }

    /// Its axis-aligned bounding box.
    #[inline]
    pub fn aabb(&self) -> Aabb<T> {
        match self {
            Bounding::Sphere(s) => s.aabb(),
            Bounding::Aabb(b) => *b,
            Bounding::SphereCone(c) => c.aabb(),
        }
    }

    /// Whether `p` is inside (conservative).
    #[inline]
    pub fn contains_point(&self, p: [T; 3]) -> bool {
        match self {
            Bounding::Sphere(s) => s.contains_point(p),
            Bounding::Aabb(b) => b.contains_point(p),
            Bounding::SphereCone(c) => c.contains_point(p),
        }
    }

    /// Whether the volume meets the box (conservative: a `true` may be a
    /// near miss, a `false` is certain).
    #[inline]
    pub fn overlaps_aabb(&self, b: &Aabb<T>) -> bool {
        match self {
            Bounding::Sphere(s) => s.overlaps_aabb(b),
            Bounding::Aabb(a) => a.overlaps(b),
            Bounding::SphereCone(c) => c.overlaps_aabb(b),
        }
    }

    /// Entry and exit parameters of the line `origin + t·dir` (conservative
    /// superset, see each shape), or `None` when it misses.
    #[inline]
    pub fn ray_entry_exit(&self, origin: [T; 3], dir: [T; 3]) -> Option<(T, T)> {
        match self {
            Bounding::Sphere(s) => s.ray_entry_exit(origin, dir),
            Bounding::Aabb(b) => b.ray_entry_exit(origin, dir),
            Bounding::SphereCone(c) => c.ray_entry_exit(origin, dir),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_queries() {
        let s = Sphere {
            center: [1.0f64, 0.0, 0.0],
            radius: 1.0,
        };
        assert!(s.contains_point([1.5, 0.5, 0.0]));
        assert!(!s.contains_point([3.0, 0.0, 0.0]));
        let b = Aabb::new([2.5, -1.0, -1.0], [3.0, 1.0, 1.0]);
        assert!(!s.overlaps_aabb(&b));
        assert!(s.inflate(0.6).overlaps_aabb(&b));
        let (t0, t1) = s.ray_entry_exit([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!((t0 - 5.0).abs() < 1e-9 && (t1 - 7.0).abs() < 1e-9);
        assert!(
            s.ray_entry_exit([-5.0, 3.0, 0.0], [1.0, 0.0, 0.0])
                .is_none()
        );
    }

    #[test]
    fn box_queries() {
        let b = Aabb::new([0.0f64, 0.0, 0.0], [1.0, 2.0, 3.0]);
        assert!(b.contains_point([0.5, 1.0, 3.0]));
        assert!(!b.contains_point([0.5, 1.0, 3.1]));
        let (t0, t1) = b.ray_entry_exit([-1.0, 1.0, 1.0], [1.0, 0.0, 0.0]).unwrap();
        assert!((t0 - 1.0).abs() < 1e-9 && (t1 - 2.0).abs() < 1e-9);
        assert!(
            b.ray_entry_exit([-1.0, 3.0, 1.0], [1.0, 0.0, 0.0])
                .is_none()
        );
        assert!(b.inflate(0.5).contains_point([-0.4, 2.4, 3.4]));
    }

    #[test]
    fn sphere_cone_queries() {
        let c = SphereCone {
            a: [0.0f64, 0.0, 0.0],
            ra: 1.0,
            b: [4.0, 0.0, 0.0],
            rb: 0.5,
        };
        assert!(c.contains_point([2.0, 0.7, 0.0]));
        assert!(!c.contains_point([2.0, 0.8, 0.0]));
        assert!(!c.contains_point([5.0, 0.0, 0.0]));
        let near = Aabb::new([1.9, 0.74, -0.1], [2.1, 1.0, 0.1]);
        let far = Aabb::new([1.9, 0.8, -0.1], [2.1, 1.0, 0.1]);
        assert!(c.overlaps_aabb(&near));
        assert!(!c.overlaps_aabb(&far));
        // Ray through the middle, orthogonal to the axis.
        let (t0, t1) = c.ray_entry_exit([2.0, -5.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        assert!(t0 <= 5.0 - 0.75 && t1 >= 5.0 + 0.75 && t1 - t0 <= 2.0 + 1e-9);
        // Along the axis: from a − ra to b + rb at least.
        let (t0, t1) = c.ray_entry_exit([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!(t0 <= 2.0 && t1 >= 7.5);
        assert!(c.ray_entry_exit([0.0, 3.0, 0.0], [1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn sphere_cone_overlap_is_conservative() {
        // Random boxes touching sample points of the shape must overlap.
        let c = SphereCone {
            a: [0.3f64, -0.2, 0.1],
            ra: 0.4,
            b: [-1.0, 0.9, 0.5],
            rb: 0.1,
        };
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64)
        };
        for _ in 0..2000 {
            let t = rnd();
            let q = lerp3(c.a, c.b, t);
            let r = c.ra + (c.rb - c.ra) * t;
            let dir = [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5];
            let n = dot3(dir, dir).sqrt();
            let s = rnd() * r / n;
            let p = [q[0] + dir[0] * s, q[1] + dir[1] * s, q[2] + dir[2] * s];
            assert!(c.contains_point(p));
            let e = rnd() * 0.3;
            let b = Aabb::new([p[0], p[1], p[2]], [p[0] + e, p[1] + e, p[2] + e]);
            assert!(c.overlaps_aabb(&b));
        }
    }
}
