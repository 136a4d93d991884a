//! Hermite radial basis functions (HRBF) with `φ(r) = r³` (thesis eq.
//! 3.17; forward-inclusion paper eq. 9 and §7).
//!
//! # The field
//!
//! ```text
//! f(p) = Σᵢ αᵢ φ(|p − cᵢ|) + βᵢ · ∇φ(p − cᵢ) + a · p + b
//!      = Σᵢ rᵢ (αᵢ rᵢ² + 3 βᵢ · xᵢ) + a · p + b,     xᵢ = p − cᵢ, rᵢ = |xᵢ|
//! ```
//!
//! since `∇φ(x) = 3|x| x`. The term is `C¹` at its center (`β·∇φ` is not
//! twice differentiable there): at a center exactly it contributes `0` to
//! the value and the gradient, and a [`Jet`](boundtrace_inclusion::Jet)'s
//! second derivative there omits it. Evaluation is generic over [`FieldNum`]: `rᵢ` is
//! `√(Σ xᵢ²)` and the term is `rᵢ·(αᵢ rᵢ² + 3 βᵢ·xᵢ)`, so every number type
//! (intervals, affine forms, forward bounds) encloses it soundly.
//!
//! # Fitting
//!
//! [`Hrbf::fit`] (feature `alloc`) interpolates points `pⱼ` with normals
//! `nⱼ`: `f(pⱼ) = 0` and `∇f(pⱼ) = nⱼ/|nⱼ|`, with the side conditions
//! `Σ αᵢ = 0`, `Σ (αᵢ cᵢ + βᵢ) = 0` that make the `(4n + 4)`-square system
//! symmetric. The Hessian of `φ` is `H(x) = 3(|x| I + x xᵀ/|x|)` (`0` at
//! `x = 0`). The system is assembled in `f64` in centered, scaled
//! coordinates and solved by Gaussian elimination with partial pivoting;
//! a tiny pivot or a large residual reports [`FieldError::Singular`]. With
//! **outward** normals the field is negative inside and positive outside
//! near the samples (the tracer's convention), and `|∇f| = 1` there.
//!
//! ```
//! # #[cfg(feature = "alloc")] {
//! use boundtrace_fields::hrbf::Hrbf;
//! use boundtrace_inclusion::Field;
//!
//! // Six points of the unit sphere with outward normals.
//! let pts = [
//!     [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
//!     [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0],
//! ];
//! let h = Hrbf::<f64, _>::fit(&pts, &pts).unwrap();
//! assert!(h.eval([1.0f64, 0.0, 0.0]).abs() < 1e-9);
//! assert!(h.eval([0.0f64, 0.0, 0.0]) < 0.0);
//! assert!(h.eval([1.3f64, 0.0, 0.0]) > 0.0);
//! # }
//! ```

use crate::FieldError;
use crate::error::finite3;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum};

#[cfg(feature = "alloc")]
use alloc::{vec, vec::Vec};

/// The largest number of points [`Hrbf::fit`] accepts (the dense system has
/// `(4n + 4)²` entries and costs `O(n³)`).
pub const MAX_FIT_POINTS: usize = 512;

/// One HRBF center with its weights.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct HrbfCenter<T> {
    /// The center `cᵢ`.
    pub center: [T; 3],
    /// The scalar weight `αᵢ`.
    pub alpha: T,
    /// The vector weight `βᵢ`.
    pub beta: [T; 3],
}

/// The number of `T` words of one [`HrbfCenter`] in flat storage
/// ([`FlatCenters`]): the center, `α`, then `β`.
pub const CENTER_WORDS: usize = 7;

/// Storage of HRBF centers that the field reads one by one
/// ([`Hrbf`]'s `S`): every `AsRef<[HrbfCenter<T>]>` (an array, a slice, a
/// `Vec`) and [`FlatCenters`], the centers as plain words (the GPU's
/// buffers).
pub trait HrbfCenters<T> {
    /// The number of centers.
    fn count(&self) -> usize;
    /// Center `i` (`i < count()`).
    fn center(&self, i: usize) -> HrbfCenter<T>;
}

impl<T: Copy, S: AsRef<[HrbfCenter<T>]>> HrbfCenters<T> for S {
    fn count(&self) -> usize {
        self.as_ref().len()
    }
    fn center(&self, i: usize) -> HrbfCenter<T> {
        self.as_ref()[i]
    }
}

/// HRBF centers stored as plain words, [`CENTER_WORDS`] per center in
/// [`HrbfCenter`]'s field order (`cₓ c_y c_z α βₓ β_y β_z`): the flat data
/// that the GPU kernel reads from a `f32` buffer, where a typed view of the
/// words is not available. The field over it is the field over the same
/// centers as structs, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatCenters<'a, T> {
    words: &'a [T],
    count: usize,
}

impl<'a, T> FlatCenters<'a, T> {
    /// The first `count` centers of `words`; `None` when `words` holds
    /// fewer than `count ·` [`CENTER_WORDS`] words. Extra words are left
    /// out.
    pub fn new(words: &'a [T], count: usize) -> Option<Self> {
        let needed = count.checked_mul(CENTER_WORDS)?;
        (needed <= words.len()).then_some(Self { words, count })
    }

    /// [`new`](Self::new) without the length check, for the GPU kernel
    /// (no `Option` to move): `count ·` [`CENTER_WORDS`] `≤ words.len()`
    /// is the caller's to check, else the field's evaluation indexes past
    /// the words (a panic on the CPU).
    pub const fn new_unchecked(words: &'a [T], count: usize) -> Self {
        Self { words, count }
    }
}

impl<T: Copy> HrbfCenters<T> for FlatCenters<'_, T> {
    fn count(&self) -> usize {
        self.count
    }
    fn center(&self, i: usize) -> HrbfCenter<T> {
        let w = &self.words;
        let k = i * CENTER_WORDS;
        HrbfCenter {
            center: [w[k], w[k + 1], w[k + 2]],
            alpha: w[k + 3],
            beta: [w[k + 4], w[k + 5], w[k + 6]],
        }
    }
}

/// An HRBF field: centers with weights and the linear polynomial
/// `a·p + b` (stored as `[a₀, a₁, a₂, b]`).
///
/// `S` is any storage of centers ([`HrbfCenters`]): `[HrbfCenter<T>; K]`,
/// a slice, a `Vec`, or [`FlatCenters`].
#[derive(Clone, Debug, PartialEq)]
pub struct Hrbf<T, S> {
    centers: S,
    poly: [T; 4],
}

impl<T, S> Hrbf<T, S> {
    /// An HRBF from centers and polynomial without the finiteness checks
    /// of [`from_parts`](Hrbf::from_parts) (for the GPU kernel, which
    /// cannot build its error values: the host validated the data). A
    /// non-finite weight, center or coefficient gives non-finite values,
    /// never a panic.
    pub const fn from_parts_unchecked(centers: S, poly: [T; 4]) -> Self {
        Self { centers, poly }
    }
}

impl<T: Real, S: AsRef<[HrbfCenter<T>]>> Hrbf<T, S> {
    /// An HRBF from given centers and polynomial.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite weight, center or
    /// polynomial coefficient.
    pub fn from_parts(centers: S, poly: [T; 4]) -> Result<Self, FieldError> {
        for c in centers.as_ref() {
            finite3("center", c.center)?;
            finite3("beta", c.beta)?;
            if !c.alpha.is_finite() {
                return Err(FieldError::InvalidParameter {
                    name: "alpha",
                    reason: "must be finite",
                });
            }
        }
        if !poly.iter().all(|x| x.is_finite()) {
            return Err(FieldError::InvalidParameter {
                name: "poly",
                reason: "must be finite",
            });
        }
        Ok(Self { centers, poly })
    }

    /// The centers and weights.
    pub fn centers(&self) -> &[HrbfCenter<T>] {
        self.centers.as_ref()
    }

    /// The polynomial `[a₀, a₁, a₂, b]`.
    pub fn poly(&self) -> [T; 4] {
        self.poly
    }

    /// The analytic gradient `Σ 3αᵢ rᵢ xᵢ + 3(rᵢ βᵢ + (βᵢ·xᵢ) xᵢ/rᵢ) + a` in
    /// plain floats.
    pub fn gradient_at(&self, p: [T; 3]) -> [T; 3] {
        let three = T::from_f64(3.0);
        let mut g = [self.poly[0], self.poly[1], self.poly[2]];
        for c in self.centers.as_ref() {
            let x = [p[0] - c.center[0], p[1] - c.center[1], p[2] - c.center[2]];
            let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            let bx = c.beta[0] * x[0] + c.beta[1] * x[1] + c.beta[2] * x[2];
            let q = if r > T::ZERO { bx / r } else { T::ZERO };
            for k in 0..3 {
                g[k] = g[k] + three * (c.alpha * r * x[k] + r * c.beta[k] + q * x[k]);
            }
        }
        g
    }
}

impl<T: Real, S: HrbfCenters<T>> Field<T> for Hrbf<T, S> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let three = T::from_f64(3.0);
        let a = self.poly;
        let mut acc = p[0] * a[0] + p[1] * a[1] + p[2] * a[2] + a[3];
        // By index (no iterator over the storage: the SPIR-V build).
        let mut i = 0;
        while i < self.centers.count() {
            let c = self.centers.center(i);
            i += 1;
            let x = [p[0] - c.center[0], p[1] - c.center[1], p[2] - c.center[2]];
            let r2 = x[0].sqr() + x[1].sqr() + x[2].sqr();
            if r2.enclosure().hi() <= T::ZERO {
                // Exactly at the center: the term and its gradient are 0
                // (and √ has no derivative at 0 for jets).
                continue;
            }
            let r = r2.sqrt();
            let bx = x[0] * c.beta[0] + x[1] * c.beta[1] + x[2] * c.beta[2];
            acc = acc + r * (r2 * c.alpha + bx * three);
        }
        acc
    }
}

#[cfg(feature = "alloc")]
impl<T: Copy, S: HrbfCenters<T>> Hrbf<T, S> {
    /// The centers as flat words, [`CENTER_WORDS`] per center in
    /// [`FlatCenters`]' order: the data of an HRBF over [`FlatCenters`]
    /// (the GPU's buffer).
    pub fn center_words(&self) -> Vec<T> {
        let mut w = Vec::with_capacity(self.centers.count() * CENTER_WORDS);
        for i in 0..self.centers.count() {
            let c = self.centers.center(i);
            w.extend_from_slice(&c.center);
            w.push(c.alpha);
            w.extend_from_slice(&c.beta);
        }
        w
    }
}

#[cfg(feature = "alloc")]
impl<T: Real> Hrbf<T, Vec<HrbfCenter<T>>> {
    /// Fits an HRBF to points with normals (module docs): the result is
    /// `0` at every point with gradient `nⱼ/|nⱼ|` (up to the solver's
    /// rounding, then rounding to `T`).
    ///
    /// # Errors
    /// - [`FieldError::InvalidParameter`]: `points` and `normals` differ in
    ///   length, or a coordinate is NaN/infinite, or a normal is zero;
    /// - [`FieldError::TooLarge`]: more than [`MAX_FIT_POINTS`] points;
    /// - [`FieldError::Singular`]: fewer than 2 points, duplicate points
    ///   (closer than `10⁻⁹` of the point set's extent), or a numerically
    ///   singular system (tiny pivot or residual above `10⁻⁸` relative).
    pub fn fit(points: &[[T; 3]], normals: &[[T; 3]]) -> Result<Self, FieldError> {
        if points.len() != normals.len() {
            return Err(FieldError::InvalidParameter {
                name: "normals",
                reason: "must have one normal per point",
            });
        }
        let n = points.len();
        if n < 2 {
            return Err(FieldError::Singular {
                reason: "HRBF fitting needs at least 2 points",
            });
        }
        if n > MAX_FIT_POINTS {
            return Err(FieldError::TooLarge {
                what: "HRBF points",
                count: n,
                max: MAX_FIT_POINTS,
            });
        }
        let mut pts = Vec::with_capacity(n);
        let mut nrm = Vec::with_capacity(n);
        for (p, q) in points.iter().zip(normals) {
            finite3("points", *p)?;
            finite3("normals", *q)?;
            let p = p.map(|x| x.as_f64());
            let q = q.map(|x| x.as_f64());
            let len = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            if len.is_nan() || len <= 0.0 || !len.is_finite() {
                return Err(FieldError::InvalidParameter {
                    name: "normals",
                    reason: "a normal has zero (or overflowing) length",
                });
            }
            pts.push(p);
            nrm.push(q.map(|x| x / len));
        }
        // Center and scale: x' = (x − m)/s.
        let mut lo = pts[0];
        let mut hi = pts[0];
        for p in &pts {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let m = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let s = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        if s.is_nan() || s <= 0.0 || !s.is_finite() {
            return Err(FieldError::Singular {
                reason: "HRBF points are all equal",
            });
        }
        let c: Vec<[f64; 3]> = pts
            .iter()
            .map(|p| [0, 1, 2].map(|k| (p[k] - m[k]) / s))
            .collect();
        for i in 0..n {
            for j in 0..i {
                let d = dist(c[i], c[j]);
                if d <= 1e-9 {
                    return Err(FieldError::Singular {
                        reason: "duplicate HRBF points",
                    });
                }
            }
        }
        let (a, rhs) = assemble(&c, &nrm);
        let x = solve(a.clone(), rhs.clone(), 4 * n + 4)?;
        check_residual(&a, &x, &rhs, 4 * n + 4)?;
        // Back to original coordinates: f(p) = s·g((p − m)/s).
        let mut centers = Vec::with_capacity(n);
        for (i, p) in points.iter().enumerate() {
            let alpha = x[4 * i] / (s * s);
            let beta = [0, 1, 2].map(|k| T::from_f64(x[4 * i + 1 + k] / s));
            centers.push(HrbfCenter {
                center: *p,
                alpha: T::from_f64(alpha),
                beta,
            });
        }
        let pa = [x[4 * n], x[4 * n + 1], x[4 * n + 2]];
        let b = s * x[4 * n + 3] - (pa[0] * m[0] + pa[1] * m[1] + pa[2] * m[2]);
        let poly = [
            T::from_f64(pa[0]),
            T::from_f64(pa[1]),
            T::from_f64(pa[2]),
            T::from_f64(b),
        ];
        // Rounding to T may overflow for huge coordinates.
        Self::from_parts(centers, poly).map_err(|_| FieldError::Singular {
            reason: "HRBF weights overflow the float type",
        })
    }
}

#[cfg(feature = "alloc")]
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The symmetric HRBF system (row-major, `(4n+4)²`) and its right side.
#[cfg(feature = "alloc")]
fn assemble(c: &[[f64; 3]], nrm: &[[f64; 3]]) -> (Vec<f64>, Vec<f64>) {
    let n = c.len();
    let m = 4 * n + 4;
    let mut a = vec![0.0; m * m];
    let mut rhs = vec![0.0; m];
    for j in 0..n {
        let (rv, rg) = (4 * j, 4 * j + 1);
        for i in 0..n {
            let x = [c[j][0] - c[i][0], c[j][1] - c[i][1], c[j][2] - c[i][2]];
            let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            let ci = 4 * i;
            // value row: α φ(r) + β·∇φ(x), ∇φ(x) = 3 r x
            a[rv * m + ci] = r * r * r;
            for k in 0..3 {
                a[rv * m + ci + 1 + k] = 3.0 * r * x[k];
                // gradient rows: α ∇φ(x) + H(x) β
                a[(rg + k) * m + ci] = 3.0 * r * x[k];
                for l in 0..3 {
                    let h = if r > 0.0 {
                        3.0 * (if k == l { r } else { 0.0 } + x[k] * x[l] / r)
                    } else {
                        0.0
                    };
                    a[(rg + k) * m + ci + 1 + l] = h;
                }
            }
        }
        // polynomial columns
        let pc = 4 * n;
        for k in 0..3 {
            a[rv * m + pc + k] = c[j][k];
            a[(rg + k) * m + pc + k] = 1.0;
            rhs[rg + k] = nrm[j][k];
        }
        a[rv * m + pc + 3] = 1.0;
        // side conditions (transposed polynomial columns)
        for k in 0..3 {
            a[(pc + k) * m + rv] = c[j][k];
            a[(pc + k) * m + rg + k] = 1.0;
        }
        a[(pc + 3) * m + rv] = 1.0;
    }
    (a, rhs)
}

/// Gaussian elimination with partial pivoting; `Singular` for a pivot below
/// `10⁻¹³·max|A|`.
#[cfg(feature = "alloc")]
fn solve(mut a: Vec<f64>, mut b: Vec<f64>, m: usize) -> Result<Vec<f64>, FieldError> {
    let scale = a.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    let tiny = 1e-13 * scale;
    for col in 0..m {
        let mut piv = col;
        for row in col + 1..m {
            if a[row * m + col].abs() > a[piv * m + col].abs() {
                piv = row;
            }
        }
        let pv = a[piv * m + col];
        if pv.is_nan() || pv.abs() <= tiny {
            return Err(FieldError::Singular {
                reason: "HRBF system is singular (degenerate points)",
            });
        }
        if piv != col {
            for k in 0..m {
                a.swap(piv * m + k, col * m + k);
            }
            b.swap(piv, col);
        }
        for row in col + 1..m {
            let f = a[row * m + col] / pv;
            if f != 0.0 {
                for k in col..m {
                    a[row * m + k] -= f * a[col * m + k];
                }
                b[row] -= f * b[col];
            }
        }
    }
    let mut x = vec![0.0; m];
    for row in (0..m).rev() {
        let mut s = b[row];
        for k in row + 1..m {
            s -= a[row * m + k] * x[k];
        }
        x[row] = s / a[row * m + row];
    }
    Ok(x)
}

/// `‖Ax − b‖∞ ≤ 10⁻⁸ (‖A‖∞‖x‖∞ + ‖b‖∞)`, else `Singular`.
#[cfg(feature = "alloc")]
fn check_residual(a: &[f64], x: &[f64], b: &[f64], m: usize) -> Result<(), FieldError> {
    let (mut res, mut an) = (0.0f64, 0.0f64);
    for row in 0..m {
        let r = &a[row * m..(row + 1) * m];
        let s: f64 = r.iter().zip(x).map(|(p, q)| p * q).sum();
        res = res.max((s - b[row]).abs());
        an = an.max(r.iter().map(|v| v.abs()).sum());
    }
    let xn = x.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let bn = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if res.is_finite() && res <= 1e-8 * (an * xn + bn) {
        Ok(())
    } else {
        Err(FieldError::Singular {
            reason: "HRBF system is ill-conditioned (large residual)",
        })
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    use super::*;
    use boundtrace_ia_core::Interval;
    use boundtrace_inclusion::gradient;

    fn sphere_samples(n: usize, r: f64, c: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        // Fibonacci sphere
        let mut p = Vec::new();
        let mut q = Vec::new();
        let ga = core::f64::consts::PI * (3.0 - 5f64.sqrt());
        for i in 0..n {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let rr = (1.0 - z * z).sqrt();
            let th = ga * i as f64;
            let d = [rr * th.cos(), rr * th.sin(), z];
            p.push([c[0] + r * d[0], c[1] + r * d[1], c[2] + r * d[2]]);
            q.push(d);
        }
        (p, q)
    }

    #[test]
    fn interpolates_points_and_normals() {
        let (p, q) = sphere_samples(40, 2.5, [10.0, -3.0, 1.0]);
        let h = Hrbf::<f64, _>::fit(&p, &q).unwrap();
        for (pj, nj) in p.iter().zip(&q) {
            assert!(h.eval(*pj).abs() <= 1e-6 * 2.5, "{}", h.eval(*pj));
            let g = h.gradient_at(*pj);
            let gj = gradient(&h, *pj);
            let gl = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
            let cos = (g[0] * nj[0] + g[1] * nj[1] + g[2] * nj[2]) / gl;
            assert!(cos > 0.99, "{cos}");
            for k in 0..3 {
                assert!((g[k] - gj[k]).abs() < 1e-6 * (1.0 + gl));
            }
        }
        assert!(h.eval([10.0f64, -3.0, 1.0]) < 0.0);
        assert!(h.eval([14.0f64, -3.0, 1.0]) > 0.0);
    }

    #[test]
    fn degenerate_input_is_an_error() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let q = [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        assert!(Hrbf::<f64, _>::fit(&p, &q).is_ok());
        assert!(matches!(
            Hrbf::<f64, _>::fit(&p[..1], &q[..1]),
            Err(FieldError::Singular { .. })
        ));
        assert!(Hrbf::<f64, _>::fit(&[], &[]).is_err());
        let dup = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
        let qd = [[1.0, 0.0, 0.0]; 3];
        assert!(matches!(
            Hrbf::<f64, _>::fit(&dup, &qd),
            Err(FieldError::Singular { .. })
        ));
        let nan = [[0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0]];
        assert!(Hrbf::<f64, _>::fit(&nan, &q).is_err());
        assert!(Hrbf::<f64, _>::fit(&p, &[[0.0; 3], [1.0, 0.0, 0.0]]).is_err());
        assert!(Hrbf::<f64, _>::fit(&p, &q[..1]).is_err());
        let same = [[1.0, 1.0, 1.0]; 2];
        assert!(Hrbf::<f32, _>::fit(&same, &[[1.0f32, 0.0, 0.0]; 2]).is_err());
    }

    #[test]
    fn interval_eval_contains_points() {
        let (p, q) = sphere_samples(12, 1.0, [0.0; 3]);
        let h = Hrbf::<f64, _>::fit(&p, &q).unwrap();
        let b: Interval<f64> = h.eval([
            Interval::new(0.2, 0.4),
            Interval::new(-0.1, 0.3),
            Interval::point(0.5),
        ]);
        for &(x, y) in &[(0.2, -0.1), (0.4, 0.3), (0.3, 0.0), (0.25, 0.2)] {
            assert!(b.contains(h.eval([x, y, 0.5])));
        }
        let c = Hrbf::from_parts(h.centers().to_vec(), h.poly()).unwrap();
        assert_eq!(c.eval([0.1f64, 0.2, 0.3]), h.eval([0.1, 0.2, 0.3]));
        let flat: Vec<f64> = h
            .centers()
            .iter()
            .flat_map(|c| [c.center[0], c.center[1], c.center[2], c.alpha])
            .collect();
        // (too few words: the β words are missing)
        assert!(FlatCenters::new(&flat, h.centers().len()).is_none());
        let bad = [HrbfCenter {
            center: [0.0; 3],
            alpha: f64::NAN,
            beta: [0.0; 3],
        }];
        assert!(Hrbf::from_parts(bad, [0.0; 4]).is_err());
    }

    /// The field over [`FlatCenters`] (the GPU's flat words) is the field
    /// over the same centers as structs, bit for bit, in every number type
    /// (intervals, jets: the tracer's bounds); a short buffer is refused.
    #[test]
    fn flat_centers_are_the_same_field() {
        let (p, q) = sphere_samples(17, 1.3, [0.2, -0.1, 0.4]);
        let h = Hrbf::<f64, _>::fit(&p, &q).unwrap();
        let mut words = h.center_words();
        let n = h.centers().len();
        assert_eq!(words.len(), n * CENTER_WORDS);
        assert_eq!(words[CENTER_WORDS + 3], h.centers()[1].alpha);
        words.push(99.0); // a word past the last center, left out
        assert!(FlatCenters::new(&words, n + 1).is_none());
        assert!(FlatCenters::new(&words, usize::MAX).is_none());
        let flat = Hrbf::from_parts_unchecked(FlatCenters::new(&words, n).unwrap(), h.poly());
        assert_eq!(flat.center_words(), words[..n * CENTER_WORDS]);
        for k in 0..50 {
            let t = k as f64 * 0.07 - 1.7;
            let x = [t, 0.3 * t - 0.2, 1.1 - 0.5 * t];
            assert_eq!(flat.eval(x).to_bits(), h.eval(x).to_bits(), "{x:?}");
            let b = [
                Interval::new(x[0], x[0] + 0.1),
                Interval::new(x[1] - 0.05, x[1]),
                Interval::point(x[2]),
            ];
            let (fi, hi): (Interval<f64>, Interval<f64>) = (flat.eval(b), h.eval(b));
            assert_eq!(
                (fi.lo().to_bits(), fi.hi().to_bits()),
                (hi.lo().to_bits(), hi.hi().to_bits())
            );
            assert_eq!(gradient(&flat, x), gradient(&h, x));
        }
    }
}
