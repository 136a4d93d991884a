//! Cameras (perspective look-at and orthographic) and the ray–box span.
//!
//! A [`Camera`] is plain `#[repr(C)]` data (eye, orthonormal basis, image
//! plane scale, [`Projection`]) so the GPU receives the same bytes and runs
//! the same [`Camera::ray`]. Image space has `x` to the right and `y` **down**
//! (row 0 is the top of the image); pixel rays go through pixel centres.
//!
//! Every ray is traced on the span where it crosses the scene's bounding box,
//! [`ray_box_span`]; the papers trace "rays around the bounding box"
//! (forward-inclusion paper §7, Table 1).
//!
//! ```
//! use boundtrace_tracer::camera::{Camera, ray_box_span};
//!
//! let cam = Camera::<f64>::perspective([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0, 1.0)?;
//! let ray = cam.ray(32, 32, 64, 64); // near the image centre
//! let span = ray_box_span(&ray, &[[-1.0; 3], [1.0; 3]]).unwrap();
//! assert!((span[0] - 4.0).abs() < 0.01 && (span[1] - 6.0).abs() < 0.01);
//! # Ok::<(), boundtrace_tracer::camera::CameraError>(())
//! ```
//!
//! Allocation-free and panic-free: degenerate inputs give a
//! [`CameraError`] at construction; afterwards only arithmetic runs.

use boundtrace_ia_core::Real;
use boundtrace_inclusion::Ray;
use core::fmt;

/// How a [`Camera`] projects: the kind of its pixel rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Projection {
    /// Rays from the eye through the image plane (look-at pinhole camera).
    #[default]
    Perspective = 0,
    /// Parallel rays along the view direction from points of the image
    /// plane through the eye.
    Orthographic = 1,
}

/// A camera: plain data, ready to upload as GPU constants.
///
/// Invariant (established by the constructors): `right`, `up` and `forward`
/// are an orthonormal, right-handed basis (`right × up = −forward`, i.e. the
/// camera looks along `forward` with `right` to the right of the image and
/// `up` to its top), and `scale` is finite and positive.
///
/// For [`Projection::Perspective`] `scale` is the half extent of the image
/// plane at unit distance from the eye (`tan` of the half field of view in
/// `x` and `y`); for [`Projection::Orthographic`] it is the half extent of
/// the view in world units.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Camera<T> {
    /// The eye (perspective) or the centre of the view rectangle
    /// (orthographic).
    pub eye: [T; 3],
    /// Unit vector to the right of the image.
    pub right: [T; 3],
    /// Unit vector to the top of the image.
    pub up: [T; 3],
    /// Unit view direction.
    pub forward: [T; 3],
    /// Half extents of the image plane `[x, y]` (see the type's docs).
    pub scale: [T; 2],
    /// The projection.
    pub projection: Projection,
}

/// A degenerate camera or bounding box.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CameraError {
    /// A coordinate or parameter is NaN or infinite.
    NotFinite,
    /// The eye and the target coincide: no view direction.
    EyeAtTarget,
    /// The view direction is the zero vector.
    ZeroViewDirection,
    /// The up vector is zero or parallel to the view direction.
    DegenerateUp,
    /// The vertical field of view is not in `(0°, 180°)`.
    BadFieldOfView,
    /// The aspect ratio (width / height) is not finite and `> 0`.
    BadAspect,
    /// The orthographic view height is not finite and `> 0`.
    BadViewHeight,
    /// The bounding box has `min > max` on an axis, or is a single point.
    BadBounds,
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CameraError::NotFinite => "camera: a coordinate or parameter is not finite",
            CameraError::EyeAtTarget => "camera: the eye and the target coincide",
            CameraError::ZeroViewDirection => "camera: the view direction is zero",
            CameraError::DegenerateUp => {
                "camera: the up vector is zero or parallel to the view direction"
            }
            CameraError::BadFieldOfView => {
                "camera: the vertical field of view must be in (0, 180) degrees"
            }
            CameraError::BadAspect => "camera: the aspect ratio must be finite and > 0",
            CameraError::BadViewHeight => "camera: the view height must be finite and > 0",
            CameraError::BadBounds => {
                "camera: the bounding box must have min <= max on every axis and not be a point"
            }
        })
    }
}

impl core::error::Error for CameraError {}

fn sub<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn finite3<T: Real>(a: [T; 3]) -> bool {
    a[0].is_finite() && a[1].is_finite() && a[2].is_finite()
}

/// `a / |a|`, or `None` for a zero (or overflowing) vector.
fn normalize<T: Real>(a: [T; 3]) -> Option<[T; 3]> {
    let n = dot(a, a).sqrt();
    if n > T::ZERO && n.is_finite() {
        Some([a[0] / n, a[1] / n, a[2] / n])
    } else {
        None
    }
}

/// The right-handed basis `(right, up, forward)` looking along `dir` with
/// `up_hint` towards the top of the image.
fn basis<T: Real>(dir: [T; 3], up_hint: [T; 3]) -> Result<[[T; 3]; 3], CameraError> {
    let forward = normalize(dir).ok_or(CameraError::ZeroViewDirection)?;
    let up_len = dot(up_hint, up_hint).sqrt();
    let side = cross(forward, up_hint);
    // sin(angle(forward, up)) must not vanish (to within √ε, relative).
    let sin = dot(side, side).sqrt() / up_len;
    if !(up_len > T::ZERO && sin > T::EPSILON.sqrt()) {
        return Err(CameraError::DegenerateUp);
    }
    let right = normalize(side).ok_or(CameraError::DegenerateUp)?;
    let up = cross(right, forward); // unit: right ⟂ forward, both unit
    Ok([right, up, forward])
}

/// `(tan(fov_y / 2), ok)` for a vertical field of view in degrees.
fn half_tan<T: Real>(fov_y_degrees: T) -> Result<T, CameraError> {
    if !(fov_y_degrees > T::ZERO && fov_y_degrees < T::from_f64(180.0)) {
        return Err(CameraError::BadFieldOfView);
    }
    let half = fov_y_degrees * T::PI / T::from_f64(360.0);
    let tan = half.tan();
    if tan > T::ZERO && tan.is_finite() {
        Ok(tan)
    } else {
        Err(CameraError::BadFieldOfView)
    }
}

fn check_aspect<T: Real>(aspect: T) -> Result<(), CameraError> {
    if aspect > T::ZERO && aspect.is_finite() {
        Ok(())
    } else {
        Err(CameraError::BadAspect)
    }
}

/// The checks every constructor starts with: finite points, a valid aspect.
fn check_inputs<T: Real>(
    eye: [T; 3],
    target: [T; 3],
    up: [T; 3],
    aspect: T,
) -> Result<(), CameraError> {
    if !(finite3(eye) && finite3(target) && finite3(up)) {
        return Err(CameraError::NotFinite);
    }
    check_aspect(aspect)
}

/// The orthonormal `[right, up, forward]` of a camera at `eye` looking at
/// `target`.
fn look_at<T: Real>(eye: [T; 3], target: [T; 3], up: [T; 3]) -> Result<[[T; 3]; 3], CameraError> {
    if eye == target {
        return Err(CameraError::EyeAtTarget);
    }
    basis(sub(target, eye), up).map_err(|e| match e {
        CameraError::ZeroViewDirection => CameraError::EyeAtTarget,
        e => e,
    })
}

impl<T: Real> Camera<T> {
    /// A perspective look-at camera at `eye` looking at `target`, with `up`
    /// towards the top of the image (need not be orthogonal to the view
    /// direction), a vertical field of view in degrees and the aspect ratio
    /// `width / height` of the image.
    ///
    /// # Errors
    /// [`CameraError::NotFinite`] for a non-finite input,
    /// [`CameraError::EyeAtTarget`], [`CameraError::DegenerateUp`] (zero or
    /// parallel to the view direction), [`CameraError::BadFieldOfView`]
    /// outside `(0°, 180°)`, [`CameraError::BadAspect`] unless finite `> 0`.
    pub fn perspective(
        eye: [T; 3],
        target: [T; 3],
        up: [T; 3],
        fov_y_degrees: T,
        aspect: T,
    ) -> Result<Self, CameraError> {
        check_inputs(eye, target, up, aspect)?;
        let tan = half_tan(fov_y_degrees)?;
        let [right, up, forward] = look_at(eye, target, up)?;
        let scale = [tan * aspect, tan];
        if !(scale[0].is_finite() && scale[0] > T::ZERO) {
            return Err(CameraError::BadAspect);
        }
        Ok(Self {
            eye,
            right,
            up,
            forward,
            scale,
            projection: Projection::Perspective,
        })
    }

    /// An orthographic camera: parallel rays along `target − eye`, from a
    /// view rectangle centred at `eye` of height `view_height` (world units)
    /// and width `aspect · view_height`, with `up` towards its top.
    ///
    /// # Errors
    /// As [`Camera::perspective`], with [`CameraError::BadViewHeight`] unless
    /// `view_height` is finite and `> 0`.
    pub fn orthographic(
        eye: [T; 3],
        target: [T; 3],
        up: [T; 3],
        view_height: T,
        aspect: T,
    ) -> Result<Self, CameraError> {
        check_inputs(eye, target, up, aspect)?;
        if !(view_height > T::ZERO && view_height.is_finite()) {
            return Err(CameraError::BadViewHeight);
        }
        let [right, up, forward] = look_at(eye, target, up)?;
        let half = view_height * T::HALF;
        let scale = [half * aspect, half];
        if !(scale[0].is_finite() && scale[0] > T::ZERO && scale[1] > T::ZERO) {
            return Err(CameraError::BadAspect);
        }
        Ok(Self {
            eye,
            right,
            up,
            forward,
            scale,
            projection: Projection::Orthographic,
        })
    }

    /// A perspective camera that frames the box `bounds = [min, max]`:
    /// looking along `view_dir` at the box centre, from 1.05 times the
    /// nearest distance at which every corner of the box projects into the
    /// image (so the whole box is in the picture, with a small margin).
    ///
    /// The top of the image is `+y`, or `+z` when `view_dir` is (nearly)
    /// parallel to the `y` axis.
    ///
    /// # Errors
    /// [`CameraError::NotFinite`], [`CameraError::BadBounds`] (`min > max`
    /// on an axis, or a single point), [`CameraError::ZeroViewDirection`],
    /// [`CameraError::BadFieldOfView`], [`CameraError::BadAspect`].
    pub fn framing(
        bounds: [[T; 3]; 2],
        view_dir: [T; 3],
        fov_y_degrees: T,
        aspect: T,
    ) -> Result<Self, CameraError> {
        let [lo, hi] = bounds;
        if !(finite3(lo) && finite3(hi) && finite3(view_dir)) {
            return Err(CameraError::NotFinite);
        }
        if !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) {
            return Err(CameraError::BadBounds);
        }
        check_aspect(aspect)?;
        let tan_y = half_tan(fov_y_degrees)?;
        let forward = normalize(view_dir).ok_or(CameraError::ZeroViewDirection)?;
        let centre = [
            (lo[0] + hi[0]) * T::HALF,
            (lo[1] + hi[1]) * T::HALF,
            (lo[2] + hi[2]) * T::HALF,
        ];
        let half_diag = sub(hi, centre);
        let radius = dot(half_diag, half_diag).sqrt();
        if !(radius > T::ZERO && radius.is_finite()) {
            return Err(CameraError::BadBounds);
        }
        let y_up = [T::ZERO, T::ONE, T::ZERO];
        let up = if basis(forward, y_up).is_ok() {
            y_up
        } else {
            [T::ZERO, T::ZERO, T::ONE]
        };
        let [right, up_cam, _] = basis(forward, up)?;
        let scale = [tan_y * aspect, tan_y];
        // The nearest eye distance at which every corner q (relative to the
        // centre, camera coordinates x, y, z) projects into the image:
        // |x| ≤ sx·(dist + z) and |y| ≤ sy·(dist + z).
        let mut dist = T::ZERO;
        let mut corner = 0;
        while corner < 8 {
            let q = [
                if corner & 1 == 0 { lo[0] } else { hi[0] } - centre[0],
                if corner & 2 == 0 { lo[1] } else { hi[1] } - centre[1],
                if corner & 4 == 0 { lo[2] } else { hi[2] } - centre[2],
            ];
            let z = dot(q, forward);
            let need_x = dot(q, right).abs() / scale[0] - z;
            let need_y = dot(q, up_cam).abs() / scale[1] - z;
            dist = dist
                .max(need_x)
                .max(need_y)
                .max(radius * T::from_f64(1e-3) - z);
            corner += 1;
        }
        // A 5 % margin (a farther eye only shrinks the projection).
        let dist = dist * T::from_f64(1.05);
        let eye = [
            centre[0] - forward[0] * dist,
            centre[1] - forward[1] * dist,
            centre[2] - forward[2] * dist,
        ];
        Self::perspective(eye, centre, up, fov_y_degrees, aspect)
    }

    /// The ray through the point `(u, v)` of the image plane in normalized
    /// coordinates: `u, v ∈ [−1, 1]`, `u = 1` at the right edge, `v = 1` at
    /// the top edge. Perspective rays start at the eye, orthographic rays on
    /// the view rectangle; the direction has unit length (up to rounding), so
    /// the ray parameter `t` is a distance.
    pub fn ray_ndc(&self, u: T, v: T) -> Ray<T> {
        let x = u * self.scale[0];
        let y = v * self.scale[1];
        let (r, up, f) = (self.right, self.up, self.forward);
        match self.projection {
            Projection::Perspective => {
                let d = [
                    f[0] + x * r[0] + y * up[0],
                    f[1] + x * r[1] + y * up[1],
                    f[2] + x * r[2] + y * up[2],
                ];
                // |d|² = 1 + x² + y² ≥ 1 for a valid camera: never zero.
                let n = (T::ONE + x * x + y * y).sqrt();
                Ray::new(self.eye, [d[0] / n, d[1] / n, d[2] / n])
            }
            Projection::Orthographic => Ray::new(
                [
                    self.eye[0] + x * r[0] + y * up[0],
                    self.eye[1] + x * r[1] + y * up[1],
                    self.eye[2] + x * r[2] + y * up[2],
                ],
                f,
            ),
        }
    }

    /// The ray through the centre of pixel `(px, py)` of a `width × height`
    /// image (`py = 0` is the top row). A pixel outside the image gives the
    /// ray through the extended image plane; a zero `width` or `height`
    /// gives non-finite components (no panic).
    pub fn ray(&self, px: u32, py: u32, width: u32, height: u32) -> Ray<T> {
        let (w, h) = (T::from_f64(width as f64), T::from_f64(height as f64));
        let u = T::TWO * (T::from_f64(px as f64) + T::HALF) / w - T::ONE;
        let v = T::ONE - T::TWO * (T::from_f64(py as f64) + T::HALF) / h;
        self.ray_ndc(u, v)
    }
}

/// Float steps each end of [`ray_box_span`]'s result is widened by.
const SPAN_ULPS: u32 = 4;

/// The span `[t0, t1]` (with `0 ≤ t0 ≤ t1`) of the ray parameter for which
/// `o + t·d` lies in the box `bounds = [min, max]`, by the slab test; `None`
/// when the ray misses the box (or the box is behind the origin).
///
/// - A ray starting inside the box gets `t0 = 0`.
/// - A zero direction component constrains nothing when the origin lies
///   within that slab (`min ≤ o ≤ max`, faces included) and misses the box
///   otherwise, so axis-parallel rays never divide `0/0`. A zero direction
///   vector gives `[0, ∞]` from inside the box.
/// - Each end is widened outward by a few float steps (`t0` down, not below
///   `0`; `t1` up), so that the rounding of the slab divisions never cuts
///   off a root lying on a face of the box.
/// - NaN anywhere in the ray or the box, or `min > max` on an axis, gives
///   `None`.
///
/// Allocation-free and panic-free; the span of every pixel ray is computed
/// here before it is traced.
pub fn ray_box_span<T: Real>(ray: &Ray<T>, bounds: &[[T; 3]; 2]) -> Option<[T; 2]> {
    let mut t0 = T::ZERO;
    let mut t1 = T::INFINITY;
    let mut axis = 0;
    while axis < 3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        let (lo, hi) = (bounds[0][axis], bounds[1][axis]);
        // `min > max` or NaN: no span.
        if lo.partial_cmp(&hi).is_none_or(|c| c.is_gt()) || o.is_nan() || d.is_nan() {
            return None;
        }
        if d == T::ZERO {
            // Parallel to the slab: inside it for every t, or never.
            if !(lo <= o && o <= hi) {
                return None;
            }
        } else {
            let a = (lo - o) / d;
            let b = (hi - o) / d;
            // NaN only from infinite operands (∞ − ∞, ∞/∞): no span.
            if a.is_nan() || b.is_nan() {
                return None;
            }
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            if near > t0 {
                t0 = near;
            }
            if far < t1 {
                t1 = far;
            }
        }
        axis += 1;
    }
    // t0, t1 are not NaN here (NaN quotients return above).
    if t0 > t1 {
        return None;
    }
    let t0 = t0.next_down_n(SPAN_ULPS);
    Some([
        if t0 > T::ZERO { t0 } else { T::ZERO },
        t1.next_up_n(SPAN_ULPS),
    ])
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() <= tol)
    }

    #[test]
    fn basis_is_orthonormal_and_right_handed() {
        let cam = Camera::<f64>::perspective(
            [1.0, 2.0, 3.0],
            [-1.0, 0.5, 0.0],
            [0.1, 1.0, 0.2],
            60.0,
            1.5,
        )
        .unwrap();
        for v in [cam.right, cam.up, cam.forward] {
            assert!((dot(v, v) - 1.0).abs() < 1e-12);
        }
        assert!(dot(cam.right, cam.up).abs() < 1e-12);
        assert!(dot(cam.right, cam.forward).abs() < 1e-12);
        assert!(dot(cam.up, cam.forward).abs() < 1e-12);
        let rxu = cross(cam.right, cam.up);
        assert!(close(
            rxu,
            [-cam.forward[0], -cam.forward[1], -cam.forward[2]],
            1e-12
        ));
        // up keeps the hint's side
        assert!(dot(cam.up, [0.1, 1.0, 0.2]) > 0.0);
        let tan = (30.0f64).to_radians().tan();
        assert!((cam.scale[1] - tan).abs() < 1e-12);
        assert!((cam.scale[0] - 1.5 * tan).abs() < 1e-12);
    }

    #[test]
    fn image_orientation() {
        // Looking down −z with +y up: +x is to the right, row 0 at the top.
        let cam =
            Camera::perspective([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 90.0, 1.0).unwrap();
        assert!(close(cam.right, [1.0, 0.0, 0.0], 1e-15));
        let top_left = cam.ray(0, 0, 10, 10);
        assert!(top_left.dir[0] < 0.0 && top_left.dir[1] > 0.0 && top_left.dir[2] < 0.0);
        let bottom_right = cam.ray(9, 9, 10, 10);
        assert!(bottom_right.dir[0] > 0.0 && bottom_right.dir[1] < 0.0);
        // 90° field of view: the edge of the image plane is at 45°.
        let edge = cam.ray_ndc(1.0, 0.0);
        assert!(close(
            edge.dir,
            [0.5f64.sqrt(), 0.0, -(0.5f64.sqrt())],
            1e-15
        ));
    }

    #[test]
    fn orthographic_rays_are_parallel_and_cover_the_view() {
        let cam =
            Camera::orthographic([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 4.0, 2.0).unwrap();
        let a = cam.ray(0, 0, 8, 4);
        let b = cam.ray(7, 3, 8, 4);
        assert_eq!(a.dir, b.dir);
        assert!(close(a.dir, [0.0, 0.0, -1.0], 0.0));
        // pixel centres: x = ±(1 − 1/8)·4, y = ±(1 − 1/4)·2
        assert!(close(a.origin, [-3.5, 1.5, 5.0], 1e-12));
        assert!(close(b.origin, [3.5, -1.5, 5.0], 1e-12));
    }

    #[test]
    fn errors() {
        let (e, t, u) = ([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0]);
        type C = Camera<f64>;
        assert_eq!(
            C::perspective(e, e, u, 45.0, 1.0),
            Err(CameraError::EyeAtTarget)
        );
        assert_eq!(
            C::perspective(e, t, [0.0; 3], 45.0, 1.0),
            Err(CameraError::DegenerateUp)
        );
        assert_eq!(
            C::perspective(e, t, [0.0, 0.0, 2.0], 45.0, 1.0),
            Err(CameraError::DegenerateUp)
        );
        for fov in [0.0, -1.0, 180.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                C::perspective(e, t, u, fov, 1.0),
                Err(CameraError::BadFieldOfView)
            );
        }
        for aspect in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                C::perspective(e, t, u, 45.0, aspect),
                Err(CameraError::BadAspect)
            );
            assert_eq!(
                C::orthographic(e, t, u, 1.0, aspect),
                Err(CameraError::BadAspect)
            );
        }
        assert_eq!(
            C::perspective([f64::NAN, 0.0, 0.0], t, u, 45.0, 1.0),
            Err(CameraError::NotFinite)
        );
        assert_eq!(
            C::orthographic(e, t, u, 0.0, 1.0),
            Err(CameraError::BadViewHeight)
        );
        assert_eq!(
            C::orthographic(e, t, u, f64::NAN, 1.0),
            Err(CameraError::BadViewHeight)
        );
        assert_eq!(
            C::orthographic(e, e, u, 1.0, 1.0),
            Err(CameraError::EyeAtTarget)
        );
        let b = [[-1.0; 3], [1.0; 3]];
        assert_eq!(
            C::framing([[1.0; 3], [-1.0; 3]], [0.0, 0.0, -1.0], 45.0, 1.0),
            Err(CameraError::BadBounds)
        );
        assert_eq!(
            C::framing([[1.0; 3], [1.0; 3]], [0.0, 0.0, -1.0], 45.0, 1.0),
            Err(CameraError::BadBounds)
        );
        assert_eq!(
            C::framing(b, [0.0; 3], 45.0, 1.0),
            Err(CameraError::ZeroViewDirection)
        );
        assert_eq!(
            C::framing(b, [0.0, 0.0, -1.0], 190.0, 1.0),
            Err(CameraError::BadFieldOfView)
        );
        // every error has a message
        assert!(CameraError::DegenerateUp.to_string().contains("up vector"));
    }

    #[test]
    fn framing_sees_the_whole_box() {
        let b = [[-1.0, -2.0, 0.0], [3.0, 2.0, 1.0]];
        for (dir, aspect) in [
            ([0.0, 0.0, -1.0], 1.0),
            ([1.0, -1.0, 0.5], 0.5),
            ([0.0, -1.0, 0.0], 2.0),
        ] {
            let cam = Camera::<f64>::framing(b, dir, 40.0, aspect).unwrap();
            // every corner projects inside the image and in front of the eye
            for c in 0..8 {
                let p = [b[c & 1][0], b[(c >> 1) & 1][1], b[(c >> 2) & 1][2]];
                let q = sub(p, cam.eye);
                let z = dot(q, cam.forward);
                assert!(z > 0.0);
                assert!(dot(q, cam.right).abs() / z <= cam.scale[0]);
                assert!(dot(q, cam.up).abs() / z <= cam.scale[1]);
            }
            // the centre ray hits the box centre
            let r = cam.ray_ndc(0.0, 0.0);
            let span = ray_box_span(&r, &b).unwrap();
            let mid = (span[0] + span[1]) * 0.5;
            let p = [0, 1, 2].map(|i| r.origin[i] + mid * r.dir[i]);
            assert!(close(p, [1.0, 0.0, 0.5], 1e-9), "{p:?}");
        }
    }

    #[test]
    fn span_cases() {
        let b: [[f64; 3]; 2] = [[-1.0; 3], [1.0; 3]];
        // through the box along x
        let s = ray_box_span(&Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]), &b).unwrap();
        assert!((s[0] - 2.0).abs() < 1e-14 && (s[1] - 4.0).abs() < 1e-14);
        assert!(s[0] <= 2.0 && s[1] >= 4.0); // widened outward
        // starting inside
        let s = ray_box_span(&Ray::new([0.5, 0.0, 0.0], [0.0, 0.0, -2.0]), &b).unwrap();
        assert_eq!(s[0], 0.0);
        assert!((s[1] - 0.5).abs() < 1e-14);
        // pointing away: behind the origin
        assert_eq!(
            ray_box_span(&Ray::new([-3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]), &b),
            None
        );
        // axis-parallel miss (zero components, origin outside a slab)
        assert_eq!(
            ray_box_span(&Ray::new([-3.0, 2.0, 0.0], [1.0, 0.0, 0.0]), &b),
            None
        );
        // axis-parallel ray on a face: hits
        assert!(ray_box_span(&Ray::new([-3.0, 1.0, -1.0], [1.0, 0.0, 0.0]), &b).is_some());
        // diagonal miss
        assert_eq!(
            ray_box_span(&Ray::new([-3.0, 0.0, 0.0], [1.0, 2.0, 0.0]), &b),
            None
        );
        // zero direction: inside gives [0, ∞], outside None
        assert_eq!(
            ray_box_span(&Ray::new([0.0; 3], [0.0; 3]), &b),
            Some([0.0, f64::INFINITY])
        );
        assert_eq!(ray_box_span(&Ray::new([2.0, 0.0, 0.0], [0.0; 3]), &b), None);
        // NaN and inverted boxes
        assert_eq!(
            ray_box_span(&Ray::new([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0]), &b),
            None
        );
        assert_eq!(
            ray_box_span(
                &Ray::new([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
                &[[1.0; 3], [-1.0; 3]]
            ),
            None
        );
        // f32
        let s = ray_box_span(
            &Ray::new([0.0f32, 0.0, -5.0], [0.0, 0.0, 1.0]),
            &[[-1.0; 3], [1.0; 3]],
        )
        .unwrap();
        assert!((s[0] - 4.0).abs() < 1e-5 && (s[1] - 6.0).abs() < 1e-5);
    }
}
