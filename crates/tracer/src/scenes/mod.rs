//! The standard procedural scenes of the papers, built by name and seed,
//! shared by the tests, the benches and the CLI (feature `std`).
//!
//! ```
//! use boundtrace_inclusion::{Field, Ray, value_at};
//! use boundtrace_tracer::scenes::{DEFAULT_SEED, NAMES, Scene};
//!
//! let scene = Scene::<f64>::build("blobs", DEFAULT_SEED)?;
//! let [lo, hi] = scene.bounds();
//! assert!(lo.iter().chain(&hi).all(|x| x.abs() <= 1.0)); // every scene fits [−1, 1]³
//! let field = scene.field();
//! assert!(field.eval(lo) > 0.0); // outside on the box
//! assert!(field.eval(scene.inside_point()) < 0.0); // the surface exists
//! // A ray from a face of the box, with the field's Taylor bound.
//! let ray = Ray::new([lo[0], 0.0, 0.0], [1.0, 0.0, 0.0]);
//! let bound = field.taylor_quadratic(&ray, 0.0, 0.1).unwrap();
//! assert!(bound.bounds_at(0.05).contains(value_at(field, &ray, 0.05)));
//! assert!(Scene::<f32>::build("no-such-scene", 1).is_err());
//! assert_eq!(NAMES.len(), 16);
//! # Ok::<(), boundtrace_tracer::scenes::SceneError>(())
//! ```
//!
//! # The scenes
//!
//! Every scene is generated in `f64` from a tiny local PRNG (splitmix64)
//! seeded by `seed`, so the same name and seed give the same scene on every
//! platform; the data is then converted to `T` (`f32` or `f64`). Each is
//! scaled uniformly so that the box enclosing its surface has its largest
//! half-extent `0.95`; [`bounds`](Scene::bounds) is that box (plus a 2 %
//! margin for the scenes with compact supports) and fits `[−1, 1]³`, so
//! one `ε` (the tracer's default `10⁻⁴`) means the same everywhere. The bounds enclose the whole surface (`f > 0` outside
//! them) — proven from the primitives' supports except for the HRBF scenes,
//! where it is checked by sampling (see below).
//!
//! | name | field | primitives | source |
//! | --- | --- | --- | --- |
//! | `blobs` | `f = minₙ (iso − Σₘ blobₙₘ)`: 4 groups of 8 compact (degree 6) point blobs, sharp union of the groups | 32 | forward-inclusion paper eq. 20, Fig. 1, 10 |
//! | `blobs-sum` | the same 32 blobs blended by one sum (for transparency) | 32 | forward-inclusion paper §7.2, Fig. 16 |
//! | `molecule` | `iso − Σ` of ~500 Gaussian atoms on a compact random-walk chain | 500 | forward-inclusion paper §7.1, Fig. 14–15 (after Blinn 1982, Bruckner 2019) |
//! | `hrbf-8`, `hrbf-17` | HRBF (`φ = r³`) through 8 / 17 points with normals on an ellipsoid | 8, 17 | forward-inclusion paper Fig. 13; thesis eq. 3.17 |
//! | `scalis-tree` | SCALIS sum over a branching tree of segments with decreasing radii | 200 | thesis Part III ch. 1 §1.8, Fig. 1.9 left |
//! | `scalis-foam` | SCALIS sum over the edges of a Voronoi diagram, constant radius | ~1,000 | thesis Part III ch. 1 §1.8, Fig. 1.10 |
//! | `scalis-random` | SCALIS sum over random polyline skeletons, varying radii | 60 | thesis Part III ch. 1 §1.8, Fig. 1.9 right |
//! | `aggregate-N` (`N = 1‥4`) | recursive aggregate, CSG union, flat blobtree | 10, 110, 1,110, 11,110 | synchronized-tracing paper Fig. 16 |
//! | `aggregate-N-smooth` | the same with the compact smooth union `G∪` | as above | synchronized-tracing paper Fig. 16, eq. 12 |
//!
//! Details:
//!
//! - **blobs**: each group has a random center in a ball; its 8 blobs are
//!   spread around it, with support radius `σ ∈ [0.3, 0.45]`, weight 1 and
//!   `iso = 0.5`. The field is [`UnionAll`] of [`Blobs`]: Taylor bounds
//!   are the `min` of the groups' (App. A), the Lipschitz bound the largest
//!   group's `Σ |w|·max|k'|`. Bounds: the box of the support spheres (the
//!   density is exactly 0 outside, `f = iso` there).
//! - **molecule**: a self-avoiding random walk with bond length 1.5 (Å),
//!   pulled towards its start so it folds into a compact "protein-like"
//!   cluster; atom radii from C, N, O, S (1.7, 1.55, 1.52, 1.8); Gaussian
//!   kernel `e^{−s(d/r)²}` with `s = 2`, weight `e^s` and `iso = 1` (an
//!   isolated atom has its surface at its radius). Bounds: the atoms' box
//!   grown by `m` with `N·w·e^{−m²/σ²} ≤ iso/4` (so `f ≥ 3·iso/4` on and
//!   beyond the box). Lipschitz: see below.
//! - **hrbf-8 / hrbf-17**: the points are a Fibonacci spiral on an
//!   ellipsoid with radii `(1, 0.75, 0.55)` (randomly rotated, slightly
//!   jittered), with the ellipsoid's outward normals, fitted by
//!   [`Hrbf::fit`](boundtrace_fields::hrbf::Hrbf::fit). An HRBF with
//!   `φ = r³` has no compact support and no global Lipschitz bound; the
//!   bounds are the box of the ellipsoid's bounding ball (radius 1) grown
//!   by 50 %, and `f > 0` on the box
//!   faces is **checked by sampling** at build time (a 33 × 33 grid per
//!   face; the point set is shrunk until it holds), not proven.
//! - **scalis-tree**: a trunk and breadth-first branching (2 children, 3
//!   with probability 0.3, random spread angles), length × 0.78 and radius
//!   × 0.72 per generation, radius varying linearly along each segment;
//!   compact SCALIS kernel of degree 6 with `σ = 2`, `iso = 1`
//!   ([`ScalisSkeleton`]). Bounds: the box of the segments' supports.
//! - **scalis-foam**: the Voronoi diagram of a jittered `7³` grid of seeds,
//!   computed exactly (Delaunay tetrahedra by the empty-circumsphere test
//!   among neighbours within distance 2.6 — tetrahedra with a circumradius
//!   above 1.3, which that neighbourhood cannot certify, are dropped, which
//!   in practice happens only at the hull), clipped to the box `[0.6,
//!   5.4]³` of the `[0, 6]³` grid: its edges are the segments (edges
//!   shorter than 0.02 are dropped; their neighbours' blend covers them),
//!   all of radius 0.06 (in units of the seed spacing).
//! - **scalis-random**: 12 random polylines of 5 segments each, random
//!   directions, lengths and radii.
//! - **aggregate-N**: a base aggregate of 10 primitives (spheres, boxes,
//!   rounded boxes, capsules, cylinders, tori, ellipsoids with random
//!   rotations) clustered in a ball; around it, 10 sub-objects on a
//!   Fibonacci sphere, each the same construction at scale 0.4, recursively
//!   (`N` levels: 10, 110, 1,110, 11,110 primitives). The tree is built
//!   **from largest to smallest** (the paper's Fig. 16 text): the
//!   primitives of each scale form a balanced union, and these groups are
//!   added to a left comb from the largest scale to the smallest, so the
//!   operators nearest the root have the smallest blend range and details
//!   modify the coarse shapes, not the other way round (§8.1). The smooth
//!   variant uses [`Operator::compact_union`](boundtrace_fields::Operator::compact_union)
//!   with `β = 0.1 × scale` of the group it adds and `r_o = 2β`
//!   (Lipschitz factor 12/11 per operator). Bounds: the primitives'
//!   ABVs offset by the largest blend `Σ β/6` along their root path (the
//!   compact union lowers the field by at most `β/6`); the sharp variant
//!   uses the same frame and bounds, so both variants are the same shapes
//!   at the same place.
//!
//! # Lipschitz bounds
//!
//! `molecule` and the SCALIS scenes sum hundreds of primitives, so the
//! plain `Σ Lᵢ` would make sphere tracing useless. Their
//! [`WithLipschitz`] carries a tighter, still global, bound computed once:
//! a `16³` grid over the bounds; per cell, the sum over primitives of
//! their slope bound on the cell (SCALIS: `Lᵢ` when the support box meets
//! the cell; Gaussian: `w·max |k'(d)|` over `d ≥` the distance from the
//! cell to the center); the maximum over the cells and, for the molecule,
//! over the outside of the box (every center is inside, so a point outside
//! is at least the center's distance to the box's boundary away).

mod aggregate;
mod blobs;
mod hrbf;
mod rng;
pub use rng::rotate;
mod scalis;

use boundtrace_fields::blobtree::FlatBlobtree;
use boundtrace_fields::density::UnionAll;
use boundtrace_fields::homothetic::Segment;
use boundtrace_fields::homothetic_skeleton::HomotheticSkeleton;
use boundtrace_fields::hrbf::{Hrbf, HrbfCenter};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_fields::{Blobs, FieldError, PointBlob};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};
use std::fmt;

/// Every scene name, in the order of the module table.
pub const NAMES: &[&str] = &[
    "blobs",
    "blobs-sum",
    "molecule",
    "hrbf-8",
    "hrbf-17",
    "scalis-tree",
    "scalis-foam",
    "scalis-random",
    "aggregate-1",
    "aggregate-1-smooth",
    "aggregate-2",
    "aggregate-2-smooth",
    "aggregate-3",
    "aggregate-3-smooth",
    "aggregate-4",
    "aggregate-4-smooth",
];

/// The seed used when none is given.
pub const DEFAULT_SEED: u64 = 2023;

/// The half-extent the scenes are scaled to (inside `[−1, 1]³`).
const TARGET_HALF: f64 = 0.95;

/// A scene that cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// No scene has this name.
    UnknownName(String),
    /// The generated data was rejected by a field constructor (a bug of
    /// the generator for this seed; reported rather than panicking).
    Field {
        /// The scene.
        scene: &'static str,
        /// The constructor's error.
        error: FieldError,
    },
    /// The generated scene failed a build-time check.
    Check {
        /// The scene.
        scene: &'static str,
        /// What failed.
        reason: &'static str,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::UnknownName(name) => {
                write!(f, "unknown scene `{name}`; expected one of:")?;
                for n in NAMES {
                    write!(f, " {n}")?;
                }
                Ok(())
            }
            SceneError::Field { scene, error } => {
                write!(f, "scene `{scene}`: invalid generated data: {error}")
            }
            SceneError::Check { scene, reason } => write!(f, "scene `{scene}`: {reason}"),
        }
    }
}

impl std::error::Error for SceneError {}

/// A field with a tighter global Lipschitz bound than its own (computed
/// once by the scene generator, see the module docs); everything else is
/// delegated.
#[derive(Clone, Debug, PartialEq)]
pub struct WithLipschitz<F, T> {
    field: F,
    lipschitz: T,
}

impl<F, T: Copy> WithLipschitz<F, T> {
    /// `field` with the global Lipschitz bound `lipschitz`, which the caller
    /// vouches for (a bound that is too small makes sphere tracing miss
    /// roots); it is not checked here.
    pub fn new(field: F, lipschitz: T) -> Self {
        Self { field, lipschitz }
    }
    /// The wrapped field.
    pub fn field(&self) -> &F {
        &self.field
    }
    /// The bound.
    pub fn bound(&self) -> T {
        self.lipschitz
    }
}

impl<T: Real, F: Field<T>> Field<T> for WithLipschitz<F, T> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        self.field.eval(p)
    }
    fn lipschitz(&self) -> Option<T> {
        Some(self.lipschitz)
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        self.field.taylor_linear(ray, t0, t1)
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        self.field.taylor_quadratic(ray, t0, t1)
    }
}

/// A blob set stored in a `Vec`.
pub type BlobSet<T> = Blobs<T, Vec<PointBlob<T>>>;

/// The field of a [`Scene`]: one variant per kind of field. It implements
/// [`Field`] by delegating `eval`, `lipschitz`, `taylor_linear` and
/// `taylor_quadratic` to the variant.
#[derive(Clone, Debug)]
pub enum SceneField<T> {
    /// Sharp union of blob groups (`blobs`).
    BlobGroups(UnionAll<BlobSet<T>, Vec<BlobSet<T>>>),
    /// One summed blob set (`blobs-sum`).
    Blobs(BlobSet<T>),
    /// One summed blob set with a grid Lipschitz bound (`molecule`).
    Molecule(WithLipschitz<BlobSet<T>, T>),
    /// A fitted HRBF (no Taylor or Lipschitz bound).
    Hrbf(Hrbf<T, Vec<HrbfCenter<T>>>),
    /// A SCALIS skeleton with a grid Lipschitz bound.
    Scalis(WithLipschitz<ScalisSkeleton<T, Vec<ScalisSegment<T>>>, T>),
    /// A skeleton of homothetic-distance primitives (scene files only)
    /// with its global Lipschitz bound (computed or given by the file).
    Homothetic(WithLipschitz<HomotheticSkeleton<T, Vec<Segment<T>>>, T>),
    /// A flat blobtree, evaluated in full (`f32` parameters).
    Blobtree(FlatBlobtree),
}

macro_rules! delegate {
    ($self:ident, $f:ident => $e:expr) => {
        match $self {
            SceneField::BlobGroups($f) => $e,
            SceneField::Blobs($f) => $e,
            SceneField::Molecule($f) => $e,
            SceneField::Hrbf($f) => $e,
            SceneField::Scalis($f) => $e,
            SceneField::Homothetic($f) => $e,
            SceneField::Blobtree(tree) => {
                let $f = &tree.as_ref();
                $e
            }
        }
    };
}

impl<T: Real> Field<T> for SceneField<T> {
    #[inline]
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        delegate!(self, f => f.eval(p))
    }
    fn lipschitz(&self) -> Option<T> {
        delegate!(self, f => f.lipschitz())
    }
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        delegate!(self, f => f.taylor_linear(ray, t0, t1))
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        delegate!(self, f => f.taylor_quadratic(ray, t0, t1))
    }
}

/// A standard scene: its field, a box enclosing its surface, and a
/// description. Build with [`Scene::build`].
#[derive(Clone, Debug)]
pub struct Scene<T> {
    name: String,
    description: String,
    bounds: [[T; 3]; 2],
    inside: [T; 3],
    field: SceneField<T>,
    primitives: usize,
}

/// What a generator returns, in `f64`, already scaled into `[−1, 1]³`.
pub(crate) struct Built<T> {
    pub(crate) field: SceneField<T>,
    pub(crate) bounds: [[f64; 3]; 2],
    pub(crate) inside: [f64; 3],
    pub(crate) primitives: usize,
    pub(crate) description: String,
}

impl<T: Real> Scene<T> {
    /// The scene `name` (one of [`NAMES`]) generated from `seed`.
    ///
    /// # Errors
    /// [`SceneError::UnknownName`] (its message lists [`NAMES`]); the other
    /// variants only if the generator produced invalid data for this seed.
    pub fn build(name: &str, seed: u64) -> Result<Self, SceneError> {
        let Some(&name) = NAMES.iter().find(|n| **n == name) else {
            return Err(SceneError::UnknownName(name.to_string()));
        };
        let built: Built<T> = match name {
            "blobs" => blobs::groups(seed, false),
            "blobs-sum" => blobs::groups(seed, true),
            "molecule" => blobs::molecule(seed),
            "hrbf-8" => hrbf::build(seed, 8),
            "hrbf-17" => hrbf::build(seed, 17),
            "scalis-tree" => scalis::tree(seed),
            "scalis-foam" => scalis::foam(seed),
            "scalis-random" => scalis::random(seed),
            _ => {
                let smooth = name.ends_with("-smooth");
                let level = name
                    .trim_start_matches("aggregate-")
                    .trim_end_matches("-smooth")
                    .parse::<u32>()
                    .map_err(|_| SceneError::UnknownName(name.to_string()))?;
                aggregate::build(seed, level, smooth)
            }
        }
        .map_err(|e| e.named(name))?;
        let [lo, hi] = built.bounds;
        Ok(Self {
            name: name.to_string(),
            description: built.description,
            bounds: [lo.map(T::from_f64), hi.map(T::from_f64)],
            inside: built.inside.map(T::from_f64),
            field: built.field,
            primitives: built.primitives,
        })
    }

    /// A scene from given parts (used by scene files, see the
    /// `boundtrace-cli` crate's `scene_format`): `bounds` must contain the
    /// whole surface (`f > 0` on and outside its faces) — the renderers and
    /// the statistics clip every ray to it; `inside` is a point where the
    /// field is negative, if known.
    ///
    /// # Errors
    /// [`SceneError::Check`] when `bounds` is not a finite box with
    /// `min < max` on every axis or `inside` is not finite.
    pub fn from_parts(
        name: &str,
        description: String,
        bounds: [[T; 3]; 2],
        inside: [T; 3],
        field: SceneField<T>,
        primitives: usize,
    ) -> Result<Self, SceneError> {
        let [lo, hi] = bounds;
        if !(0..3).all(|k| lo[k].is_finite() && hi[k].is_finite() && lo[k] < hi[k]) {
            return Err(SceneError::Check {
                scene: "from_parts",
                reason: "bounds must be finite with min < max on every axis",
            });
        }
        if !inside.iter().all(|x| x.is_finite()) {
            return Err(SceneError::Check {
                scene: "from_parts",
                reason: "the inside point must be finite",
            });
        }
        Ok(Self {
            name: name.to_string(),
            description,
            bounds,
            inside,
            field,
            primitives,
        })
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One line: what it is, primitive count, source.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// An axis-aligned box `[min, max]` inside `[−1, 1]³` containing the
    /// whole surface (`f > 0` on and outside its faces).
    pub fn bounds(&self) -> [[T; 3]; 2] {
        self.bounds
    }

    /// A point where the field is negative (inside; checked at build).
    pub fn inside_point(&self) -> [T; 3] {
        self.inside
    }

    /// The field.
    pub fn field(&self) -> &SceneField<T> {
        &self.field
    }

    /// The number of primitives (blobs, HRBF centers, segments, blobtree
    /// leaves).
    pub fn primitive_count(&self) -> usize {
        self.primitives
    }
}

/// An error of a generator, before the scene name is attached.
pub(crate) enum GenError {
    Field(FieldError),
    Check(&'static str),
}

impl From<FieldError> for GenError {
    fn from(e: FieldError) -> Self {
        GenError::Field(e)
    }
}

impl GenError {
    fn named(self, scene: &'static str) -> SceneError {
        match self {
            GenError::Field(error) => SceneError::Field { scene, error },
            GenError::Check(reason) => SceneError::Check { scene, reason },
        }
    }
}

/// A uniform map `p ↦ (p − c)·s` taking a box into `[−TARGET_HALF,
/// TARGET_HALF]³` (centered).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    pub(crate) center: [f64; 3],
    pub(crate) scale: f64,
}

impl Frame {
    /// The frame fitting `[lo, hi]` (its largest half-extent becomes
    /// `TARGET_HALF`).
    pub(crate) fn fit(lo: [f64; 3], hi: [f64; 3]) -> Self {
        let center = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let half = (0..3).map(|k| 0.5 * (hi[k] - lo[k])).fold(0.0, f64::max);
        Self {
            center,
            scale: TARGET_HALF / half.max(1e-300),
        }
    }
    pub(crate) fn point(&self, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| (p[k] - self.center[k]) * self.scale)
    }
    pub(crate) fn length(&self, l: f64) -> f64 {
        l * self.scale
    }
    /// The mapped box, grown by a relative margin `rel` of its largest
    /// half-extent and clamped to `[−1, 1]`.
    pub(crate) fn bounds(&self, lo: [f64; 3], hi: [f64; 3], rel: f64) -> [[f64; 3]; 2] {
        let m = rel * TARGET_HALF;
        let (a, b) = (self.point(lo), self.point(hi));
        [a.map(|x| (x - m).max(-1.0)), b.map(|x| (x + m).min(1.0))]
    }
}

/// The box of `[lo, hi]` boxes.
pub(crate) fn box_union(boxes: impl IntoIterator<Item = [[f64; 3]; 2]>) -> [[f64; 3]; 2] {
    let mut out = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for [lo, hi] in boxes {
        for k in 0..3 {
            out[0][k] = out[0][k].min(lo[k]);
            out[1][k] = out[1][k].max(hi[k]);
        }
    }
    out
}

/// A global Lipschitz bound on a `G³` grid over `bounds` (module docs):
/// `per_cell(lo, hi)` bounds the gradient norm on the closed cell;
/// `outside` bounds it outside the box. Rounded up by a relative `10⁻⁶`.
pub(crate) fn grid_lipschitz(
    bounds: [[f64; 3]; 2],
    g: usize,
    outside: f64,
    mut per_cell: impl FnMut([f64; 3], [f64; 3]) -> f64,
) -> f64 {
    let [lo, hi] = bounds;
    let step = [0, 1, 2].map(|k| (hi[k] - lo[k]) / g as f64);
    let mut best = outside;
    for i in 0..g {
        for j in 0..g {
            for l in 0..g {
                let idx = [i, j, l];
                let a = [0, 1, 2].map(|k| lo[k] + step[k] * idx[k] as f64);
                let b = [0, 1, 2].map(|k| lo[k] + step[k] * (idx[k] + 1) as f64);
                best = best.max(per_cell(a, b));
            }
        }
    }
    best * (1.0 + 1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_unknown_fails() {
        let e = Scene::<f64>::build("nope", 1).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("nope") && msg.contains("scalis-foam") && msg.contains("aggregate-4"));
        assert!(Scene::<f64>::build("aggregate-9", 1).is_err());
        assert_eq!(NAMES.len(), 16);
    }

    #[test]
    fn from_parts_checks_the_box() {
        let s = Scene::<f64>::build("hrbf-8", DEFAULT_SEED).unwrap();
        let parts = |b: [[f64; 3]; 2], inside: [f64; 3]| {
            Scene::from_parts("x", "d".into(), b, inside, s.field().clone(), 8)
        };
        let ok = parts(s.bounds(), s.inside_point()).unwrap();
        assert_eq!((ok.name(), ok.bounds()), ("x", s.bounds()));
        let [lo, hi] = s.bounds();
        assert!(parts([hi, lo], s.inside_point()).is_err());
        assert!(parts([lo, [hi[0], f64::NAN, hi[2]]], s.inside_point()).is_err());
        assert!(parts(s.bounds(), [0.0, f64::INFINITY, 0.0]).is_err());
    }

    #[test]
    fn frame_maps_into_the_unit_box() {
        let f = Frame::fit([1.0, 2.0, 3.0], [5.0, 4.0, 3.5]);
        let b = f.bounds([1.0, 2.0, 3.0], [5.0, 4.0, 3.5], 0.0);
        assert!((b[0][0] + TARGET_HALF).abs() < 1e-12 && (b[1][0] - TARGET_HALF).abs() < 1e-12);
        assert!(b[0][1] > -TARGET_HALF && b[1][2] < TARGET_HALF);
        assert_eq!(f.length(2.0), 2.0 * f.scale);
    }

    #[test]
    fn grid_lipschitz_takes_the_largest_cell() {
        // one "primitive" with bound 3 in the cell touching the origin's corner
        let l = grid_lipschitz([[0.0; 3], [1.0; 3]], 4, 0.5, |a, _| {
            if a == [0.0; 3] { 3.0 } else { 1.0 }
        });
        assert!((3.0..3.0001).contains(&l));
    }
}
