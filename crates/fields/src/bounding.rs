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
