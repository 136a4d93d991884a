//! Approximate signed distance primitives (A-SDF) with rigid transforms:
//! the leaves of a blobtree (synchronized-tracing paper §3–4, §7).
//!
//! Every primitive is a field `f: ℝ³ → ℝ` with **`f > 0` outside and
//! `f < 0` inside** whose Lipschitz constant is at most 1 ([`lipschitz`]),
//! so `|f(p)| ≤ dist(p, {f = 0})`: sphere tracing steps of `|f|` are safe
//! (paper §4: "well-behaved A-SDF primitives (Lipschitz bound ≤ 1)").
//! Each primitive is written once, generic over
//! [`FieldNum`], and evaluated in world space
//! through its [`Rigid`] transform: `f(p) = f_local(Rᵀ(p − t))` ("space
//! deformations are moved to leaf nodes", §5).
//!
//! | kind | local field | exact SDF? |
//! | --- | --- | --- |
//! | [`Sphere`](PrimitiveKind::Sphere) | `|p| − r` | yes |
//! | [`Box`](PrimitiveKind::Box) | `|max(q, 0)| + min(maxᵢ qᵢ, 0)`, `q = |p| − h` | yes |
//! | [`RoundedBox`](PrimitiveKind::RoundedBox) | box with half extents `h − ρ`, minus `ρ` | yes |
//! | [`Capsule`](PrimitiveKind::Capsule) | `|(x, y, max(|z| − h, 0))| − r` | yes |
//! | [`Cylinder`](PrimitiveKind::Cylinder) | capped: 2-D box SDF of `(√(x²+y²) − r, |z| − h)` | yes |
//! | [`Torus`](PrimitiveKind::Torus) | `|(√(x²+y²) − R, z)| − r` | yes |
//! | [`Plane`](PrimitiveKind::Plane) | `z` (half-space `z ≤ 0` inside) | yes |
//! | [`Cone`](PrimitiveKind::Cone) | capped cone (frustum): `max(lateral, |z| − h)` | no, underestimates near the rims |
//! | [`Ellipsoid`](PrimitiveKind::Ellipsoid) | `r_min (|p / r| − 1)` | no (exact for a sphere) |
//! | [`Gyroid`](PrimitiveKind::Gyroid) | `|g(kp)| / (√3 k) − w/2` | no (infinite sheet) |
//! | [`Blob`](PrimitiveKind::Blob) | `R √(1 − ρ^{2/n}) − d₀`, `ρ = (1 − |p|²/R²)₊^{n/2}` ([`crate::kernel`]) | yes for an isolated blob (clamped at `R − d₀`) |
//!
//! Branches (the box corner formula) are decided with
//! [`FieldNum::enclosure`]; when a
//! bound type cannot decide, the general (branch-free) formula is used, so
//! every bound stays sound. Points where a Euclidean norm vanishes (the center
//! of a sphere, the axis of a cylinder, …) have a kink: the value is right,
//! the derivative of a [`Jet`](boundtrace_inclusion::Jet) there is NaN
//! (a set of measure zero that a tracer never lands on exactly).
//!
//! Flat parameters: a primitive is stored as [`PrimitiveKind::param_vec4s`]
//! groups of four `f32` (128-bit slots, paper §7): `[qx, qy, qz, qw]`
//! (rotation), `[tx, ty, tz, 0]` (translation), then the shape parameters
//! (table in [`Primitive::write_params`]).
//!
//! [`lipschitz`]: Primitive::lipschitz

use crate::FieldError;
use crate::bounding::{Aabb, Bounding, Sphere, SphereCone};
use crate::transform::Rigid;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum};

/// The primitive types of the blobtree (the 8-bit `type` field of a leaf,
/// paper §7).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PrimitiveKind {
    /// Ball of radius `r` ([`Primitive::sphere`]).
    Sphere = 0,
    /// Box with half extents `h` ([`Primitive::cuboid`]).
    Box = 1,
    /// Box with rounded edges ([`Primitive::rounded_box`]).
    RoundedBox = 2,
    /// Segment swept by a ball ([`Primitive::capsule`]).
    Capsule = 3,
    /// Capped cylinder ([`Primitive::cylinder`]).
    Cylinder = 4,
    /// Torus ([`Primitive::torus`]).
    Torus = 5,
    /// Half-space ([`Primitive::plane`]).
    Plane = 6,
    /// Capped cone / frustum ([`Primitive::cone`]).
    Cone = 7,
    /// Ellipsoid, approximate ([`Primitive::ellipsoid`]).
    Ellipsoid = 8,
    /// Gyroid sheet for infills ([`Primitive::gyroid`]).
    Gyroid = 9,
    /// Normalized compact point-blob density ([`Primitive::blob`]).
    Blob = 10,
}

impl PrimitiveKind {
    /// Every kind, in code order.
    pub const ALL: [PrimitiveKind; 11] = [
        PrimitiveKind::Sphere,
        PrimitiveKind::Box,
        PrimitiveKind::RoundedBox,
        PrimitiveKind::Capsule,
        PrimitiveKind::Cylinder,
        PrimitiveKind::Torus,
        PrimitiveKind::Plane,
        PrimitiveKind::Cone,
        PrimitiveKind::Ellipsoid,
        PrimitiveKind::Gyroid,
        PrimitiveKind::Blob,
    ];

    /// Number of 128-bit slots (4 × `f32`) of the flat parameters, the two
    /// transform slots included.
    pub const fn param_vec4s(self) -> u32 {
        match self {
            PrimitiveKind::Plane => 2,
            _ => 3,
        }
    }

    /// The kind with code `x`, if any.
    pub fn from_u32(x: u32) -> Option<Self> {
        // A `match`, not an index into `ALL`: rust-gpu cannot take a
        // slice of a constant array.
        Some(match x {
            0 => PrimitiveKind::Sphere,
            1 => PrimitiveKind::Box,
            2 => PrimitiveKind::RoundedBox,
            3 => PrimitiveKind::Capsule,
            4 => PrimitiveKind::Cylinder,
            5 => PrimitiveKind::Torus,
            6 => PrimitiveKind::Plane,
            7 => PrimitiveKind::Cone,
            8 => PrimitiveKind::Ellipsoid,
            9 => PrimitiveKind::Gyroid,
            10 => PrimitiveKind::Blob,
            _ => return None,
        })
    }
}

/// A set of [`PrimitiveKind`]s, as a type ([`Primitive::eval_among`]):
/// every kind but the two whose evaluation needs transcendental functions
/// (and so the most code in a GPU shader) is always in.
pub trait PrimitiveKinds {
    /// Whether [`PrimitiveKind::Gyroid`] (sines and cosines) is in.
    const GYROID: bool;
    /// Whether [`PrimitiveKind::Blob`] (a power of the kernel) is in.
    const BLOB: bool;

    /// Whether `kind` is in the set.
    fn contains(kind: PrimitiveKind) -> bool {
        match kind {
            PrimitiveKind::Gyroid => Self::GYROID,
            PrimitiveKind::Blob => Self::BLOB,
            _ => true,
        }
    }
}

/// Every [`PrimitiveKind`] ([`PrimitiveKinds`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct AllPrimitives;

impl PrimitiveKinds for AllPrimitives {
    const GYROID: bool = true;
    const BLOB: bool = true;
}

/// The [`PrimitiveKind`]s evaluated with `+ − × ÷`, square roots, `min`
/// and `max` alone: all but [`PrimitiveKind::Gyroid`] and
/// [`PrimitiveKind::Blob`] ([`PrimitiveKinds`]; the GPU shader's blobtree
/// entry point).
#[derive(Clone, Copy, Debug, Default)]
pub struct AlgebraicPrimitives;

impl PrimitiveKinds for AlgebraicPrimitives {
    const GYROID: bool = false;
    const BLOB: bool = false;
}

/// An A-SDF primitive: a [`PrimitiveKind`], its shape parameters in the
/// local frame and its [`Rigid`] transform.
///
/// Built only by the validated constructors, so every field is finite and
/// its parameters are in their domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primitive<T> {
    kind: PrimitiveKind,
    /// Shape parameters (meaning per kind, see [`Primitive::write_params`]).
    shape: [T; 4],
    rigid: Rigid<T>,
}

fn invalid(name: &'static str, reason: &'static str) -> FieldError {
    FieldError::InvalidParameter { name, reason }
}

fn sub3<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm3<T: Real>(a: [T; 3]) -> T {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn nonneg<T: Real>(name: &'static str, x: T) -> Result<T, FieldError> {
    if x.is_finite() && x >= T::ZERO {
        Ok(x)
    } else {
        Err(invalid(name, "must be finite and ≥ 0"))
    }
}

impl<T: Real> Primitive<T> {
    fn make(kind: PrimitiveKind, shape: [T; 4], rigid: Rigid<T>) -> Self {
        Self { kind, shape, rigid }
    }

    /// A ball of `radius` around `center`: `f = |p − c| − r` (exact).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center or a radius
    /// that is NaN, infinite or ≤ 0.
    ///
    /// ```
    /// use boundtrace_fields::sdf::Primitive;
    /// let s = Primitive::sphere([1.0, 0.0, 0.0], 0.5).unwrap();
    /// assert!((s.eval([3.0f64, 0.0, 0.0]) - 1.5).abs() < 1e-15);
    /// assert!(Primitive::sphere([0.0; 3], -1.0).is_err());
    /// ```
    pub fn sphere(center: [T; 3], radius: T) -> Result<Self, FieldError> {
        let r = crate::error::positive("radius", radius)?;
        let z = T::ZERO;
        Ok(Self::make(
            PrimitiveKind::Sphere,
            [r, z, z, z],
            Rigid::translation(crate::error::finite3("center", center)?)?,
        ))
    }

    /// An axis-aligned (in its frame) box `|p − c|ᵢ ≤ hᵢ` (exact SDF).
    /// Named `cuboid` because `box` is a Rust keyword.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center or a half
    /// extent that is NaN, infinite or ≤ 0.
    pub fn cuboid(center: [T; 3], half_extents: [T; 3]) -> Result<Self, FieldError> {
        let h = half_extents;
        for x in h {
            crate::error::positive("half_extents", x)?;
        }
        Ok(Self::make(
            PrimitiveKind::Box,
            [h[0], h[1], h[2], T::ZERO],
            Rigid::translation(crate::error::finite3("center", center)?)?,
        ))
    }

    /// A box of outer half extents `h` whose edges and corners are rounded
    /// with radius `rounding` (`0 < rounding ≤ minᵢ hᵢ`): the box of half
    /// extents `h − rounding`, offset by `rounding` (exact SDF).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center, a half
    /// extent ≤ 0 or a rounding radius ≤ 0 or larger than a half extent.
    pub fn rounded_box(
        center: [T; 3],
        half_extents: [T; 3],
        rounding: T,
    ) -> Result<Self, FieldError> {
        let h = half_extents;
        for x in h {
            crate::error::positive("half_extents", x)?;
        }
        let r = crate::error::positive("rounding", rounding)?;
        if r > h[0] || r > h[1] || r > h[2] {
            return Err(invalid("rounding", "must be ≤ every half extent"));
        }
        Ok(Self::make(
            PrimitiveKind::RoundedBox,
            [h[0], h[1], h[2], r],
            Rigid::translation(crate::error::finite3("center", center)?)?,
        ))
    }

    /// The set of points within `radius` of the segment `[a, b]` (exact
    /// SDF). Stored along the local `z` axis with half length `|b − a|/2`.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for non-finite end-points, a
    /// zero-length segment, or a radius that is NaN, infinite or ≤ 0.
    pub fn capsule(a: [T; 3], b: [T; 3], radius: T) -> Result<Self, FieldError> {
        let (rigid, h) = segment_frame(a, b)?;
        let r = crate::error::positive("radius", radius)?;
        Ok(Self::make(
            PrimitiveKind::Capsule,
            [h, r, T::ZERO, T::ZERO],
            rigid,
        ))
    }

    /// The capped cylinder of `radius` whose axis is the segment `[a, b]`
    /// (exact SDF, flat caps at `a` and `b`).
    ///
    /// # Errors
    /// As [`capsule`](Self::capsule).
    pub fn cylinder(a: [T; 3], b: [T; 3], radius: T) -> Result<Self, FieldError> {
        let (rigid, h) = segment_frame(a, b)?;
        let r = crate::error::positive("radius", radius)?;
        Ok(Self::make(
            PrimitiveKind::Cylinder,
            [h, r, T::ZERO, T::ZERO],
            rigid,
        ))
    }

    /// A torus around `center` in the plane normal to `axis`: the points at
    /// distance `minor` of the circle of radius `major` (exact SDF).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center, a zero or
    /// non-finite axis, or radii that are NaN, infinite or ≤ 0.
    pub fn torus(center: [T; 3], axis: [T; 3], major: T, minor: T) -> Result<Self, FieldError> {
        let rigid = Rigid::from_z_axis(center, axis)?;
        let big = crate::error::positive("major", major)?;
        let small = crate::error::positive("minor", minor)?;
        Ok(Self::make(
            PrimitiveKind::Torus,
            [big, small, T::ZERO, T::ZERO],
            rigid,
        ))
    }

    /// The half-space below the plane through `point` with outward
    /// `normal`: `f = n̂ · (p − point)` (exact SDF, unbounded).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite point or a zero or
    /// non-finite normal.
    pub fn plane(point: [T; 3], normal: [T; 3]) -> Result<Self, FieldError> {
        let rigid = Rigid::from_z_axis(point, normal)?;
        Ok(Self::make(PrimitiveKind::Plane, [T::ZERO; 4], rigid))
    }

    /// The **capped** cone (frustum) with base disk of radius `ra` centered
    /// at `a` and top disk of radius `rb` centered at `b` (`rb = 0`: a
    /// pointed cone). The field is `max(lateral, |z| − h)` in the local
    /// frame, with `lateral` the signed distance to the slanted side line in
    /// the meridian half-plane `(√(x²+y²), z)`: a maximum of two
    /// 1-Lipschitz lower bounds of the distance, exact on the lateral
    /// surface and caps, an underestimate near the rims (outside corners).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for non-finite end-points, a
    /// zero-length axis, a negative or non-finite radius, or both radii 0.
    pub fn cone(a: [T; 3], ra: T, b: [T; 3], rb: T) -> Result<Self, FieldError> {
        let (rigid, h) = segment_frame(a, b)?;
        let ra = nonneg("ra", ra)?;
        let rb = nonneg("rb", rb)?;
        if !(ra > T::ZERO || rb > T::ZERO) {
            return Err(invalid("ra", "ra and rb must not both be 0"));
        }
        Ok(Self::make(PrimitiveKind::Cone, [h, ra, rb, T::ZERO], rigid))
    }

    /// An axis-aligned (in its frame) ellipsoid with semi-axes `radii`,
    /// approximated by `f = r_min (|p / r| − 1)` (`r_min = minᵢ rᵢ`).
    ///
    /// Its gradient is `r_min (p/r²)/|p/r|`, of norm at most
    /// `r_min · maxᵢ(1/rᵢ) = 1`: **Lipschitz bound 1** (tested), so it
    /// underestimates the distance (exact for a sphere, and exactly `0` on
    /// the ellipsoid).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center or a radius
    /// that is NaN, infinite or ≤ 0.
    pub fn ellipsoid(center: [T; 3], radii: [T; 3]) -> Result<Self, FieldError> {
        for x in radii {
            crate::error::positive("radii", x)?;
        }
        Ok(Self::make(
            PrimitiveKind::Ellipsoid,
            [radii[0], radii[1], radii[2], T::ZERO],
            Rigid::translation(crate::error::finite3("center", center)?)?,
        ))
    }

    /// A gyroid sheet of the given `period` and `thickness` (for infills;
    /// intersect it with a bounded shape). With `k = 2π / period` and
    /// `g(p) = sin kx cos ky + sin ky cos kz + sin kz cos kx`,
    /// `f = |g(p)| / (√3 k) − thickness / 2`.
    ///
    /// `|∇g| ≤ √3 k` (Cauchy–Schwarz on each component:
    /// `(cos x cos y − sin z sin x)² ≤ cos²y + sin²z`, and the three bounds
    /// sum to 3), so the factor `1/(√3 k)` makes the field **1-Lipschitz**.
    /// The sheet is the set where `|g| ≤ √3 k · thickness / 2`, roughly
    /// `thickness` thick.
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a period or thickness that is
    /// NaN, infinite or ≤ 0.
    pub fn gyroid(period: T, thickness: T) -> Result<Self, FieldError> {
        let p = crate::error::positive("period", period)?;
        let w = crate::error::positive("thickness", thickness)?;
        Ok(Self::make(
            PrimitiveKind::Gyroid,
            [p, w, T::ZERO, T::ZERO],
            Rigid::identity(),
        ))
    }

    /// A compact point blob normalized to a distance, with the compact
    /// polynomial kernel of degree 6 ([`blob_with_degree`](Self::blob_with_degree)
    /// with `n = 6`: density `ρ = (1 − |p − c|²/R²)₊³`, a `C²` kernel).
    ///
    /// # Errors
    /// As [`blob_with_degree`](Self::blob_with_degree).
    pub fn blob(center: [T; 3], radius: T, iso: T) -> Result<Self, FieldError> {
        Self::blob_with_degree(center, radius, iso, 6)
    }

    /// A compact point blob normalized to a distance: the density
    /// `ρ(p) = K(|p − c|²/R²)` of the compact polynomial kernel
    /// [`Kernel::compact`](crate::kernel::Kernel::compact)`(n, R)`,
    /// `K(u) = (1 − u)₊^{n/2}`, with iso-value `iso ∈ (0, 1)`, is mapped back
    /// through the inverse of the kernel profile, `g(ρ) = R √(1 − ρ^{2/n})`,
    /// giving `f = g(ρ) − d₀` with `d₀ = R √(1 − iso^{2/n})` the radius of
    /// the iso-surface. For an isolated blob this is exactly
    /// `min(|p − c|, R) − d₀`: an SDF inside the support, the constant
    /// `R − d₀` outside (Lipschitz 1, up to the rounding of the round
    /// trip through the density).
    ///
    /// # Errors
    /// [`FieldError::InvalidParameter`] for a non-finite center, a radius
    /// that is NaN, infinite or ≤ 0, an iso-value outside `(0, 1)`, or a
    /// degree outside `[2, 64]`.
    pub fn blob_with_degree(
        center: [T; 3],
        radius: T,
        iso: T,
        degree: u32,
    ) -> Result<Self, FieldError> {
        let r = crate::error::positive("radius", radius)?;
        if iso.is_nan() || iso <= T::ZERO || iso >= T::ONE {
            return Err(invalid("iso", "must be in (0, 1)"));
        }
        crate::kernel::Kernel::compact(degree, r)?;
        Ok(Self::make(
            PrimitiveKind::Blob,
            [r, iso, T::from_f64(f64::from(degree)), T::ZERO],
            Rigid::translation(crate::error::finite3("center", center)?)?,
        ))
    }

    /// The same primitive moved by `rigid` **after** its current placement
    /// (the constructors already place it: a sphere at its center, a capsule
    /// along its segment), i.e. the new world transform is
    /// `rigid ∘ current`.
    pub fn with_transform(self, rigid: Rigid<T>) -> Self {
        Self {
            rigid: rigid.then_after(&self.rigid),
            ..self
        }
    }

    /// The primitive's kind.
    pub fn kind(&self) -> PrimitiveKind {
        self.kind
    }

    /// The world transform of the primitive's local frame.
    pub fn rigid(&self) -> &Rigid<T> {
        &self.rigid
    }

    /// The shape parameters in the local frame (see
    /// [`write_params`](Self::write_params) for their meaning).
    pub fn shape_params(&self) -> [T; 4] {
        self.shape
    }

    /// Writes the flat parameters, exactly `kind().param_vec4s() * 4`
    /// floats at the start of `out`:
    ///
    /// | slot | contents |
    /// | --- | --- |
    /// | 0 | rotation quaternion `[x, y, z, w]` |
    /// | 1 | translation `[x, y, z]`, `0` |
    /// | 2 | shape: sphere `[r]`; box `[hx, hy, hz]`; rounded box `[hx, hy, hz, ρ]`; capsule, cylinder `[h, r]` (half length, radius); torus `[R, r]`; cone `[h, ra, rb]`; ellipsoid `[rx, ry, rz]`; gyroid `[period, thickness]`; blob `[R, iso, n]` (kernel degree); unused entries `0` |
    ///
    /// (the plane has no shape slot).
    ///
    /// # Errors
    /// [`FieldError::TooLarge`] when `out` is too short,
    /// [`FieldError::InvalidParameter`] when a value overflows `f32`.
    pub fn write_params(&self, out: &mut [f32]) -> Result<(), FieldError> {
        let n = self.kind.param_vec4s() as usize * 4;
        if out.len() < n {
            return Err(FieldError::TooLarge {
                what: "parameter floats",
                count: n,
                max: out.len(),
            });
        }
        let q = self.rigid.rotation();
        let t = self.rigid.translation_vector();
        let s = self.shape;
        let all = [
            q[0],
            q[1],
            q[2],
            q[3],
            t[0],
            t[1],
            t[2],
            T::ZERO,
            s[0],
            s[1],
            s[2],
            s[3],
        ];
        let mut i = 0;
        while i < n {
            let v = all[i].as_f64() as f32;
            if !v.is_finite() {
                return Err(invalid("params", "value overflows f32"));
            }
            out[i] = v;
            i += 1;
        }
        Ok(())
    }

    /// Reads parameters written by [`write_params`](Self::write_params).
    /// `None` when `d` is shorter than `kind.param_vec4s() * 4` or the
    /// values are invalid for the kind (the constructors' checks); never
    /// panics. A quaternion already unit to rounding is kept as is, so a
    /// write/read round trip is exact for `f32`.
    pub fn read_params(kind: PrimitiveKind, d: &[f32]) -> Option<Self> {
        let n = kind.param_vec4s() as usize * 4;
        if d.len() < n {
            return None;
        }
        let g = |i: usize| T::from_f64(f64::from(d[i]));
        Rigid::new_keep_unit([g(0), g(1), g(2), g(3)], [g(4), g(5), g(6)])?;
        let decoded = Self::decode_with(kind, |i| d[i]);
        let z = T::ZERO;
        let o = [z; 3];
        let s = decoded.shape;
        // Validate through the constructors (in the local frame), then keep
        // the stored transform and shape bit-for-bit.
        let ok = match kind {
            PrimitiveKind::Sphere => Self::sphere(o, s[0]).is_ok(),
            PrimitiveKind::Box => Self::cuboid(o, [s[0], s[1], s[2]]).is_ok(),
            PrimitiveKind::RoundedBox => Self::rounded_box(o, [s[0], s[1], s[2]], s[3]).is_ok(),
            PrimitiveKind::Capsule | PrimitiveKind::Cylinder | PrimitiveKind::Torus => {
                crate::error::positive("h", s[0]).is_ok()
                    && crate::error::positive("r", s[1]).is_ok()
            }
            PrimitiveKind::Plane => true,
            PrimitiveKind::Cone => {
                crate::error::positive("h", s[0]).is_ok()
                    && Self::cone([z, z, -s[0]], s[1], [z, z, s[0]], s[2]).is_ok()
            }
            PrimitiveKind::Ellipsoid => Self::ellipsoid(o, [s[0], s[1], s[2]]).is_ok(),
            PrimitiveKind::Gyroid => Self::gyroid(s[0], s[1]).is_ok(),
            PrimitiveKind::Blob => {
                let n = s[2];
                n == n.round()
                    && n >= T::TWO
                    && n <= T::from_f64(64.0)
                    && Self::blob_with_degree(o, s[0], s[1], n.as_f64() as u32).is_ok()
            }
        };
        ok.then_some(decoded)
    }

    /// [`read_params`](Self::read_params) without its checks, the `i`-th
    /// parameter float given by `param(i)` (`i < kind.param_vec4s() * 4`):
    /// for parameters that `read_params` accepted before (a validated
    /// blobtree), the same primitive bit for bit. This is the decoding the
    /// blobtree interpreters run per evaluation, on the CPU and in the GPU
    /// shader (which can neither build the checks' error values nor take
    /// sub-slices of a buffer). Parameters `read_params` rejects give some
    /// primitive (NaN values for NaN parameters), never a panic.
    #[inline]
    pub(crate) fn decode_with(kind: PrimitiveKind, param: impl Fn(usize) -> f32) -> Self {
        let g = |i: usize| T::from_f64(f64::from(param(i)));
        let rigid = Rigid::decode([g(0), g(1), g(2), g(3)], [g(4), g(5), g(6)]);
        let shape = if kind.param_vec4s() > 2 {
            [g(8), g(9), g(10), g(11)]
        } else {
            [T::ZERO; 4]
        };
        Self::make(kind, shape, rigid)
    }

    /// The field at the world-space point `p`, in any number type.
    #[inline]
    pub fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.eval_among::<N, AllPrimitives>(p)
    }

    /// [`eval`](Self::eval) compiled for the kinds of `K` only: a
    /// primitive of another kind evaluates to NaN. The kinds left out are
    /// not even compiled (`K`'s flags are constants, so their branches are
    /// dropped when the code is instantiated): a GPU shader for scenes
    /// without them is smaller.
    #[inline]
    pub fn eval_among<N: FieldNum<T>, K: PrimitiveKinds>(&self, p: [N; 3]) -> N {
        let q = self.rigid.to_local(p);
        let s = self.shape;
        match self.kind {
            PrimitiveKind::Gyroid if !K::GYROID => N::constant(T::nan()),
            PrimitiveKind::Blob if !K::BLOB => N::constant(T::nan()),
            PrimitiveKind::Sphere => length3(q) - s[0],
            PrimitiveKind::Box => {
                box_sdf([q[0].abs() - s[0], q[1].abs() - s[1], q[2].abs() - s[2]])
            }
            PrimitiveKind::RoundedBox => {
                let r = s[3];
                box_sdf([
                    q[0].abs() - (s[0] - r),
                    q[1].abs() - (s[1] - r),
                    q[2].abs() - (s[2] - r),
                ]) - r
            }
            PrimitiveKind::Capsule => {
                let w = (q[2].abs() - s[0]).max(N::constant(T::ZERO));
                (q[0].sqr() + q[1].sqr() + w.sqr()).sqrt() - s[1]
            }
            PrimitiveKind::Cylinder => {
                let rho = (q[0].sqr() + q[1].sqr()).sqrt();
                box2_sdf(rho - s[1], q[2].abs() - s[0])
            }
            PrimitiveKind::Torus => {
                let rho = (q[0].sqr() + q[1].sqr()).sqrt();
                ((rho - s[0]).sqr() + q[2].sqr()).sqrt() - s[1]
            }
            PrimitiveKind::Plane => q[2],
            PrimitiveKind::Cone => {
                let (h, ra, rb) = (s[0], s[1], s[2]);
                let (nr, nz) = cone_normal(h, ra, rb);
                let rho = (q[0].sqr() + q[1].sqr()).sqrt();
                let lateral = (rho - ra) * nr + (q[2] + h) * nz;
                lateral.max(q[2].abs() - h)
            }
            PrimitiveKind::Ellipsoid => {
                let rmin = s[0].min(s[1]).min(s[2]);
                length3([q[0] / s[0], q[1] / s[1], q[2] / s[2]]) * rmin - rmin
            }
            PrimitiveKind::Gyroid => gyroid(q, s[0], s[1]),
            PrimitiveKind::Blob => {
                let (big_r, iso, n) = (s[0], s[1], s[2]);
                let d0 = blob_d0(big_r, iso, n);
                // Validated at construction: the checked constructor would
                // accept these parameters.
                let kernel = crate::kernel::Kernel::compact_trusted(n.as_f64() as u32, big_r);
                let rho = kernel.eval_sq(q[0].sqr() + q[1].sqr() + q[2].sqr());
                let e = rho.enclosure();
                if e.hi() <= T::ZERO {
                    // Outside the support: g(0) = R.
                    N::constant(big_r - d0)
                } else {
                    let c = rho.powf(T::TWO / n);
                    (-c + T::ONE).max(N::constant(T::ZERO)).sqrt() * big_r - d0
                }
            }
        }
    }

    /// The Lipschitz bound of the field: `1` for every kind (the
    /// constructors' docs give the argument for the approximate ones); a
    /// float evaluation may exceed it by a few ulps of rounding.
    pub fn lipschitz(&self) -> T {
        T::ONE
    }

    /// A world-space volume outside which `f(p) > r` (`r ≥ 0`; a negative
    /// `r` is treated as `0`), i.e. the primitive's bounding volume offset
    /// by `r` (the ABV building block, paper §4.3). `None` when no bounded
    /// volume exists: the plane and the gyroid (unbounded), a blob whose
    /// field never exceeds `r` (`r ≥ R − d₀`), or a NaN/infinite `r`.
    ///
    /// The volume is enlarged by a small relative margin so that the
    /// property holds for the rounded float evaluation as well.
    pub fn abv(&self, r: T) -> Option<Bounding<T>> {
        if !r.is_finite() {
            return None;
        }
        let r = r.max(T::ZERO);
        let s = self.shape;
        let rig = &self.rigid;
        let t = rig.translation_vector();
        let scale = t[0].abs().max(t[1].abs()).max(t[2].abs())
            + s[0].abs()
            + s[1].abs()
            + s[2].abs()
            + s[3].abs()
            + r;
        let slack = scale * T::EPSILON * T::from_f64(64.0) + T::from_f64(1e-30);
        let z = T::ZERO;
        let sphere = |radius: T| {
            Some(Bounding::Sphere(Sphere {
                center: t,
                radius: radius + slack,
            }))
        };
        match self.kind {
            PrimitiveKind::Sphere => sphere(s[0] + r),
            PrimitiveKind::Box => Some(local_box_to_world(
                rig,
                [s[0] + r, s[1] + r, s[2] + r],
                slack,
            )),
            PrimitiveKind::RoundedBox => Some(local_box_to_world(
                rig,
                [s[0] + r, s[1] + r, s[2] + r],
                slack,
            )),
            PrimitiveKind::Capsule | PrimitiveKind::Cylinder => {
                let a = rig.to_world_point([z, z, -s[0]]);
                let b = rig.to_world_point([z, z, s[0]]);
                let rr = s[1] + r + slack;
                Some(Bounding::SphereCone(SphereCone {
                    a,
                    ra: rr,
                    b,
                    rb: rr,
                }))
            }
            PrimitiveKind::Torus => {
                let e = s[0] + s[1] + r;
                Some(local_box_to_world(rig, [e, e, s[1] + r], slack))
            }
            PrimitiveKind::Plane | PrimitiveKind::Gyroid => None,
            PrimitiveKind::Cone => {
                // f ≥ |z| − h and f ≥ nr(ρ − ra) + nz(z + h); with
                // |z| ≤ h + r, f > r once ρ > ra + (r + |nz|(2h + r))/nr.
                let (h, ra, rb) = (s[0], s[1], s[2]);
                let (nr, nz) = cone_normal(h, ra, rb);
                let rho = ra + (r + nz.abs() * (h + h + r)) / nr;
                let rho = rho.max(ra.max(rb) + r);
                Some(local_box_to_world(rig, [rho, rho, h + r], slack))
            }
            PrimitiveKind::Ellipsoid => {
                let rmin = s[0].min(s[1]).min(s[2]);
                let k = T::ONE + r / rmin;
                Some(local_box_to_world(
                    rig,
                    [s[0] * k, s[1] * k, s[2] * k],
                    slack,
                ))
            }
            PrimitiveKind::Blob => {
                let big_r = s[0];
                let d0 = blob_d0(big_r, s[1], s[2]);
                if d0 + r + slack >= big_r {
                    None
                } else {
                    sphere(d0 + r)
                }
            }
        }
    }
}

impl<T: Real> Field<T> for Primitive<T> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        Primitive::eval(self, p)
    }
    fn lipschitz(&self) -> Option<T> {
        Some(Primitive::lipschitz(self))
    }
}

/// The iso-surface radius of a normalized blob: `R √(1 − iso^{2/n})`.
fn blob_d0<T: Real>(big_r: T, iso: T, n: T) -> T {
    big_r * (T::ONE - iso.powf(T::TWO / n)).sqrt()
}

/// The local frame of a segment `[a, b]`: center at the midpoint, `z` along
/// `b − a`; returns the half length.
fn segment_frame<T: Real>(a: [T; 3], b: [T; 3]) -> Result<(Rigid<T>, T), FieldError> {
    let a = crate::error::finite3("a", a)?;
    let b = crate::error::finite3("b", b)?;
    let d = sub3(b, a);
    let len = norm3(d);
    if !len.is_finite() || len <= T::ZERO {
        return Err(invalid("b", "zero-length (or overflowing) segment"));
    }
    let c = [
        (a[0] + b[0]) * T::HALF,
        (a[1] + b[1]) * T::HALF,
        (a[2] + b[2]) * T::HALF,
    ];
    Ok((Rigid::from_z_axis(c, d)?, len * T::HALF))
}

/// Outward unit normal `(n_ρ, n_z)` of the slanted side of a frustum from
/// `(ra, −h)` to `(rb, h)` in the meridian half-plane.
fn cone_normal<T: Real>(h: T, ra: T, rb: T) -> (T, T) {
    let dr = ra - rb;
    let l = (T::from_f64(4.0) * h * h + dr * dr).sqrt();
    (T::TWO * h / l, dr / l)
}

fn length3<T: Real, N: FieldNum<T>>(q: [N; 3]) -> N {
    (q[0].sqr() + q[1].sqr() + q[2].sqr()).sqrt()
}

/// Exact box SDF from `q = |p| − h`: `|max(q, 0)| + min(maxᵢ qᵢ, 0)`, with
/// the branch decided by enclosure (inside: `maxᵢ qᵢ`; outside:
/// `|max(q, 0)|`) so that point types never take `√0`'s derivative.
fn box_sdf<T: Real, N: FieldNum<T>>(q: [N; 3]) -> N {
    let zero = N::constant(T::ZERO);
    let m = q[0].max(q[1]).max(q[2]);
    let e = m.enclosure();
    if e.hi() <= T::ZERO {
        m
    } else {
        let out = length3([q[0].max(zero), q[1].max(zero), q[2].max(zero)]);
        if e.lo() > T::ZERO {
            out
        } else {
            out + m.min(zero)
        }
    }
}

/// The 2-D version of [`box_sdf`].
fn box2_sdf<T: Real, N: FieldNum<T>>(a: N, b: N) -> N {
    let zero = N::constant(T::ZERO);
    let m = a.max(b);
    let e = m.enclosure();
    if e.hi() <= T::ZERO {
        m
    } else {
        let out = (a.max(zero).sqr() + b.max(zero).sqr()).sqrt();
        if e.lo() > T::ZERO {
            out
        } else {
            out + m.min(zero)
        }
    }
}

/// The gyroid sheet (see [`Primitive::gyroid`]).
fn gyroid<T: Real, N: FieldNum<T>>(q: [N; 3], period: T, thickness: T) -> N {
    let k = T::TWO * T::PI / period;
    let (x, y, z) = (q[0] * k, q[1] * k, q[2] * k);
    let (sx, sy, sz) = (x.sin(), y.sin(), z.sin());
    let (cx, cy, cz) = (x.cos(), y.cos(), z.cos());
    let g = sx * cy + sy * cz + sz * cx;
    g.abs() / (T::from_f64(3.0).sqrt() * k) - thickness * T::HALF
}

/// Axis-aligned world box of the local box `|q|ᵢ ≤ halfᵢ`.
fn local_box_to_world<T: Real>(rig: &Rigid<T>, half: [T; 3], slack: T) -> Bounding<T> {
    let m = rig.matrix();
    let c = rig.translation_vector();
    let mut min = [T::ZERO; 3];
    let mut max = [T::ZERO; 3];
    let mut i = 0;
    while i < 3 {
        let e = m[i][0].abs() * half[0] + m[i][1].abs() * half[1] + m[i][2].abs() * half[2];
        let e = e + e * T::EPSILON * T::from_f64(8.0) + slack;
        min[i] = c[i] - e;
        max[i] = c[i] + e;
        i += 1;
    }
    Bounding::Aabb(Aabb { min, max })
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_ia_core::Interval;
    use boundtrace_inclusion::gradient;

    #[test]
    fn kinds_round_trip() {
        for (i, k) in PrimitiveKind::ALL.iter().enumerate() {
            assert_eq!(PrimitiveKind::from_u32(i as u32), Some(*k));
            assert_eq!(*k as u32, i as u32);
        }
        assert_eq!(PrimitiveKind::from_u32(11), None);
    }

    #[test]
    fn box_branches_agree() {
        // Inside, outside and straddling the box: the interval evaluation
        // encloses the point values and the jet gradient is finite inside.
        let b = Primitive::cuboid([0.0; 3], [1.0, 0.5, 0.25]).unwrap();
        for x in [-2.0, -0.9, 0.0, 0.3, 0.99, 1.0, 1.5] {
            let p = [x, 0.1, -0.1];
            let v: f64 = b.eval(p);
            let i: Interval<f64> = b.eval([
                Interval::new(x - 0.2, x + 0.2),
                Interval::point(0.1),
                Interval::point(-0.1),
            ]);
            assert!(i.contains(v), "{x}: {v} ∉ {i:?}");
            let g = gradient(&b, p);
            assert!(g.iter().all(|c| c.is_finite()), "{x}: {g:?}");
        }
    }

    #[test]
    fn gyroid_and_blob_values() {
        let g = Primitive::gyroid(2.0f64, 0.2).unwrap();
        assert!((g.eval([0.0f64; 3]) + 0.1).abs() < 1e-15);
        let b = Primitive::blob([0.0; 3], 1.0f64, 0.5).unwrap();
        let d0 = (1.0 - 0.5f64.cbrt()).sqrt();
        assert!((b.eval([0.5f64, 0.0, 0.0]) - (0.5 - d0)).abs() < 1e-12);
        assert!((b.eval([5.0f64, 0.0, 0.0]) - (1.0 - d0)).abs() < 1e-15);
        // ABV: none once r reaches the exterior constant R − d₀.
        assert!(b.abv(0.1).is_some());
        assert!(b.abv(1.0 - d0).is_none());
    }

    #[test]
    fn abv_and_params() {
        let s = Primitive::sphere([1.0, 2.0, 3.0], 0.5f64).unwrap();
        match s.abv(0.25) {
            Some(Bounding::Sphere(b)) => {
                assert_eq!(b.center, [1.0, 2.0, 3.0]);
                assert!(b.radius >= 0.75 && b.radius < 0.75 + 1e-9);
            }
            other => panic!("{other:?}"),
        }
        assert!(
            Primitive::plane([0.0; 3], [0.0, 0.0, 1.0f64])
                .unwrap()
                .abv(1.0)
                .is_none()
        );
        let mut buf = [0.0f32; 12];
        s.write_params(&mut buf).unwrap();
        assert_eq!(&buf[4..9], &[1.0, 2.0, 3.0, 0.0, 0.5]);
        assert!(s.write_params(&mut buf[..11]).is_err());
        assert_eq!(
            Primitive::<f64>::read_params(PrimitiveKind::Sphere, &buf),
            Some(s)
        );
        assert_eq!(
            Primitive::<f64>::read_params(PrimitiveKind::Sphere, &buf[..11]),
            None
        );
    }
}
