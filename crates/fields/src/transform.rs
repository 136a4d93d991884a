//! [`Rigid`]: the rigid transform (rotation + translation) every blobtree
//! leaf carries.
//!
//! The synchronized-tracing paper moves all space deformations to the
//! leaves (§5, "Space deformations are moved to leaf nodes (i.e.,
//! primitives) and stored in `D_i`; our implementation only supports
//! rotation and translation"). A primitive is defined in its own *local*
//! frame; its world-space field is `f_world(p) = f_local(Rᵀ (p − t))`.
//!
//! The rotation is stored as a unit quaternion `[x, y, z, w]` together with
//! its 3×3 matrix `R` (computed once at construction, so evaluation costs
//! nine products and no trigonometry). A rigid map preserves distances, so
//! it preserves the Lipschitz constant of the field it is applied to (up to
//! the rounding of `R`, whose columns are orthonormal to a few ulps).

use crate::FieldError;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::FieldNum;

/// A rigid transform `p_world = R · p_local + t`: a rotation (unit
/// quaternion `[x, y, z, w]`, with its matrix `R`) and a translation `t`.
///
/// Invariant: the quaternion is finite and of unit length (to rounding);
/// `matrix` is the rotation matrix of `rotation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid<T> {
    rotation: [T; 4],
    translation: [T; 3],
    /// Row-major `R` (local → world).
    matrix: [[T; 3]; 3],
}

impl<T: Real> Default for Rigid<T> {
    fn default() -> Self {
        Self::identity()
    }
}

impl<T: Real> Rigid<T> {
    /// The identity transform (the local frame is the world frame).
    pub fn identity() -> Self {
        let (o, z) = (T::ONE, T::ZERO);
        Self {
            rotation: [z, z, z, o],
            translation: [z; 3],
            matrix: [[o, z, z], [z, o, z], [z, z, o]],
        }
    }

    /// A pure translation by `t`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `t` has a NaN or infinite
    /// coordinate.
    pub fn translation(t: [T; 3]) -> Result<Self, FieldError> {
        let t = crate::error::finite3("translation", t)?;
        Ok(Self {
            translation: t,
            ..Self::identity()
        })
    }

    /// A rotation given as a quaternion `[x, y, z, w]` (normalized here)
    /// followed by a translation.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a NaN/infinite component, a
    /// zero (or underflowing) quaternion, or a non-finite translation.
    ///
    /// ```
    /// use boundtrace_fields::transform::Rigid;
    /// // 90° about z, then move by (1, 0, 0).
    /// let s = core::f64::consts::FRAC_1_SQRT_2;
    /// let r = Rigid::new([0.0, 0.0, s, s], [1.0, 0.0, 0.0]).unwrap();
    /// let w = r.to_world_point([1.0, 0.0, 0.0]);
    /// assert!((w[0] - 1.0).abs() < 1e-12 && (w[1] - 1.0).abs() < 1e-12);
    /// let l = r.to_local::<f64>(w);
    /// assert!((l[0] - 1.0).abs() < 1e-12 && l[1].abs() < 1e-12);
    /// assert!(Rigid::new([0.0; 4], [0.0; 3]).is_err());
    /// ```
    pub fn new(rotation_xyzw: [T; 4], translation: [T; 3]) -> Result<Self, FieldError> {
        let t = crate::error::finite3("translation", translation)?;
        let q = Self::normalize_quat(rotation_xyzw)?;
        Ok(Self::from_unit(q, t))
    }

    /// Like [`new`](Self::new), but keeps a quaternion whose squared norm is
    /// within `2⁻²⁰` (a few `f32` ulps) of 1 bit-for-bit, so that parameters
    /// read back from the `f32` array reproduce the same transform (the
    /// matrix is orthonormal for any non-zero quaternion, see `from_unit`).
    pub(crate) fn new_keep_unit(rotation_xyzw: [T; 4], translation: [T; 3]) -> Option<Self> {
        crate::error::finite3("translation", translation).ok()?;
        if !rotation_xyzw.iter().all(|x| x.is_finite()) {
            return None;
        }
        if !Self::is_unit_to_rounding(rotation_xyzw) {
            Self::normalize_quat(rotation_xyzw).ok()?;
        }
        Some(Self::decode(rotation_xyzw, translation))
    }

    /// Whether `|q|²` is within `2⁻²⁰` of 1 ([`new_keep_unit`](Self::new_keep_unit)
    /// keeps such a quaternion bit-for-bit).
    #[inline]
    fn is_unit_to_rounding(q: [T; 4]) -> bool {
        (dot4(q, q) - T::ONE).abs() <= T::from_f64(9.5367431640625e-7)
    }

    /// [`new_keep_unit`](Self::new_keep_unit) without its checks, for
    /// parameters it accepted before (a validated blobtree, on the CPU or
    /// in a GPU shader, which cannot build error values): the same
    /// transform, bit for bit. Parameters it would reject give an
    /// unspecified transform (NaN or infinite entries, or finite ones
    /// from a tiny non-unit quaternion), never a panic.
    #[inline]
    pub(crate) fn decode(rotation_xyzw: [T; 4], translation: [T; 3]) -> Self {
        let q = rotation_xyzw;
        if Self::is_unit_to_rounding(q) {
            Self::from_unit(q, translation)
        } else {
            // `normalize_quat`'s arithmetic, without its error values.
            let n = dot4(q, q).sqrt();
            Self::from_unit([q[0] / n, q[1] / n, q[2] / n, q[3] / n], translation)
        }
    }

    /// The rotation taking the local `z` axis to the direction of `axis`,
    /// followed by the translation to `center`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] when `axis` is zero, NaN or
    /// infinite, or `center` is not finite.
    pub fn from_z_axis(center: [T; 3], axis: [T; 3]) -> Result<Self, FieldError> {
        let c = crate::error::finite3("center", center)?;
        let a = crate::error::finite3("axis", axis)?;
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if !n.is_finite() || n <= T::ZERO {
            return Err(FieldError::InvalidParameter {
                name: "axis",
                reason: "must be a non-zero finite vector",
            });
        }
        let u = [a[0] / n, a[1] / n, a[2] / n];
        // Half-way quaternion between e_z and u: (e_z × u, 1 + e_z·u).
        let w = T::ONE + u[2];
        let q = if w <= T::EPSILON * T::from_f64(16.0) {
            // u ≈ −e_z: half a turn about x.
            [T::ONE, T::ZERO, T::ZERO, T::ZERO]
        } else {
            [-u[1], u[0], T::ZERO, w]
        };
        Self::new(q, c)
    }

    fn normalize_quat(q: [T; 4]) -> Result<[T; 4], FieldError> {
        if !q.iter().all(|x| x.is_finite()) {
            return Err(FieldError::InvalidParameter {
                name: "rotation",
                reason: "has a NaN or infinite component",
            });
        }
        let n = dot4(q, q).sqrt();
        if !n.is_finite() || n <= T::ZERO {
            return Err(FieldError::InvalidParameter {
                name: "rotation",
                reason: "quaternion must be non-zero",
            });
        }
        let u = [q[0] / n, q[1] / n, q[2] / n, q[3] / n];
        if dot4(u, u) < T::HALF {
            return Err(FieldError::InvalidParameter {
                name: "rotation",
                reason: "quaternion must be non-zero",
            });
        }
        Ok(u)
    }

    fn from_unit(q: [T; 4], t: [T; 3]) -> Self {
        let [x, y, z, w] = q;
        // s = 2/|q|² makes the matrix orthonormal even for a quaternion that
        // is unit only to rounding.
        let s = T::TWO / dot4(q, q);
        let (xx, yy, zz) = (x * x * s, y * y * s, z * z * s);
        let (xy, xz, yz) = (x * y * s, x * z * s, y * z * s);
        let (wx, wy, wz) = (w * x * s, w * y * s, w * z * s);
        let o = T::ONE;
        Self {
            rotation: q,
            translation: t,
            matrix: [
                [o - (yy + zz), xy - wz, xz + wy],
                [xy + wz, o - (xx + zz), yz - wx],
                [xz - wy, yz + wx, o - (xx + yy)],
            ],
        }
    }

    /// The unit quaternion `[x, y, z, w]`.
    pub fn rotation(&self) -> [T; 4] {
        self.rotation
    }

    /// The translation `t`.
    pub fn translation_vector(&self) -> [T; 3] {
        self.translation
    }

    /// The rotation matrix `R` (row-major, local → world).
    pub fn matrix(&self) -> [[T; 3]; 3] {
        self.matrix
    }

    /// `self ∘ inner`: first `inner`, then `self` (`p ↦ R_s (R_i p + t_i) + t_s`).
    pub fn then_after(&self, inner: &Self) -> Self {
        let [ax, ay, az, aw] = self.rotation;
        let [bx, by, bz, bw] = inner.rotation;
        // Hamilton product self.rotation ⊗ inner.rotation.
        let q = [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ];
        let t = self.to_world_point(inner.translation);
        let q = Self::normalize_quat(q).unwrap_or([T::ZERO, T::ZERO, T::ZERO, T::ONE]);
        Self::from_unit(q, t)
    }

    /// World → local: `Rᵀ (p − t)`, in any number type.
    #[inline]
    pub fn to_local<N: FieldNum<T>>(&self, p: [N; 3]) -> [N; 3] {
        let d = [
            p[0] - self.translation[0],
            p[1] - self.translation[1],
            p[2] - self.translation[2],
        ];
        let m = &self.matrix;
        [
            d[0] * m[0][0] + d[1] * m[1][0] + d[2] * m[2][0],
            d[0] * m[0][1] + d[1] * m[1][1] + d[2] * m[2][1],
            d[0] * m[0][2] + d[1] * m[1][2] + d[2] * m[2][2],
        ]
    }

    /// Local → world for a point: `R q + t` (plain floats, rounded to
    /// nearest).
    #[inline]
    pub fn to_world_point(&self, q: [T; 3]) -> [T; 3] {
        let m = &self.matrix;
        let t = &self.translation;
        [
            m[0][0] * q[0] + m[0][1] * q[1] + m[0][2] * q[2] + t[0],
            m[1][0] * q[0] + m[1][1] * q[1] + m[1][2] * q[2] + t[1],
            m[2][0] * q[0] + m[2][1] * q[1] + m[2][2] * q[2] + t[2],
        ]
    }

    /// Local → world for a vector (rotation only): `R v`.
    #[inline]
    pub fn to_world_vector(&self, v: [T; 3]) -> [T; 3] {
        let m = &self.matrix;
        [
            m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
        ]
    }
}

#[inline]
fn dot4<T: Real>(a: [T; 4], b: [T; 4]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_composition() {
        let r = Rigid::new([0.3, -0.2, 0.5, 0.7], [1.0, 2.0, -3.0]).unwrap();
        let p = [0.4, -1.5, 2.25];
        let w = r.to_world_point(p);
        let l = r.to_local::<f64>(w);
        for k in 0..3 {
            assert!((l[k] - p[k]).abs() < 1e-12);
        }
        let s = Rigid::new([-0.1, 0.9, 0.2, 0.3], [0.5, 0.0, 1.0]).unwrap();
        let c = s.then_after(&r);
        let a = c.to_world_point(p);
        let b = s.to_world_point(r.to_world_point(p));
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-12);
        }
    }

    #[test]
    fn z_axis() {
        for axis in [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -2.0],
            [1.0, 1.0, 0.0],
            [0.3, -0.4, 0.1],
        ] {
            let r = Rigid::from_z_axis([1.0, 2.0, 3.0], axis).unwrap();
            let v = r.to_world_vector([0.0, 0.0, 1.0]);
            let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            for k in 0..3 {
                assert!((v[k] - axis[k] / n).abs() < 1e-12, "{axis:?} {v:?}");
            }
        }
        assert!(Rigid::from_z_axis([0.0; 3], [0.0; 3]).is_err());
        assert!(Rigid::<f64>::new([f64::NAN, 0.0, 0.0, 1.0], [0.0; 3]).is_err());
    }
}
