//! The tile A-buffer of synchronized tracing (synchronized-tracing paper
//! §6.1): for a camera and a tile size (8×8 by default), per screen tile
//! the list of `(primitive post-order index, entry depth, exit depth)` of
//! every augmented bounding volume (ABV, [`Abv`]) that one of the tile's
//! pixel rays meets inside the scene box, sorted by entry depth.
//!
//! # Depth
//!
//! Depths are **camera depths** `z = t·(d·forward)`: the distance of a
//! point along the view direction (for a perspective camera measured from
//! the eye, for an orthographic one from the view plane). Every pixel ray
//! of the tile maps a depth to its own ray parameter by
//! `t = z / (d·forward)` ([`depth_factor`]), so one depth range
//! `[z_b, z_e]` cuts the whole tile frustum at the same planes — the
//! paper's NDC depth range shared by the workgroup (§6.2), in a linear
//! coordinate.
//!
//! # Conservativeness
//!
//! For a tile and an ABV the builder intersects **every pixel ray of the
//! tile** with the ABV (sphere, box or sphere-cone; the shapes'
//! `ray_entry_exit` are widened by a few ulps), clips the hit to the ray's
//! span in the scene box ([`ray_box_span`], the span that is traced) and
//! keeps the smallest entry and the largest exit depth over the tile's
//! rays (§6.1: "conservatively aggregating depth (min for entry, max for
//! exit)"). The stored depths are then widened by [`DEPTH_ULPS`] float
//! steps so that the depth ↔ ray-parameter conversions of the tracer
//! (one rounding each) cannot move a boundary across an ABV. A primitive
//! whose ABV is unbounded is listed in every tile over the rays' spans.
//!
//! Which tiles are examined comes from a screen footprint of the ABV's
//! bounding box (its 8 corners projected, with a one-pixel margin; the
//! whole screen when the box reaches behind the eye plane): a tile outside
//! the footprint has no pixel ray through the box. The unit tests check,
//! independently of the builder, that every point of a pixel ray lying in
//! an ABV is covered by an entry of its tile.
//!
//! # Layout
//!
//! Flat arrays ready for GPU upload: `offsets` (`u32`, one more than the
//! number of tiles; tile `i`'s entries are `entries[offsets[i]..offsets[i + 1]]`)
//! and `entries` ([`TileEntry`], `#[repr(C)]`: a `u32` and two `T`). Tiles
//! are numbered row by row from the top-left, as pixels.
//!
//! With the `parallel` feature the per-ABV work and the final sort run on
//! rayon's pool; the result is identical to the serial build (entries are
//! sorted by a total key: tile, entry depth, primitive index).

use crate::camera::Camera;
#[cfg(feature = "alloc")]
use crate::camera::{Projection, ray_box_span};
#[cfg(feature = "alloc")]
use alloc::vec::Vec;
#[cfg(feature = "alloc")]
use boundtrace_fields::blobtree::Abv;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Ray;
use core::fmt;

/// The default tile size in pixels (paper §6: 8×8 tiles, one workgroup
/// each).
pub const DEFAULT_TILE_SIZE: u32 = 8;

/// The largest tile size accepted (a tile's rays are processed together).
pub const MAX_TILE_SIZE: u32 = 64;

/// Float steps each stored depth is widened by (outward), covering the
/// roundings of `z = t·c` and `t = z / c`.
pub const DEPTH_ULPS: u32 = 16;

/// One A-buffer fragment: a primitive whose ABV meets the tile's frustum
/// between two camera depths.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct TileEntry<T> {
    /// The primitive's post-order index in the blobtree.
    pub node: u32,
    /// The smallest camera depth at which a pixel ray of the tile is in
    /// the ABV (widened).
    pub z_entry: T,
    /// The largest such depth (widened).
    pub z_exit: T,
}

/// The tiling of a `width × height` image into `tile_size²` tiles (the
/// last column and row of tiles may be partial). Plain data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct TileGrid {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Tile side in pixels.
    pub tile_size: u32,
    /// Tiles per row, `⌈width / tile_size⌉`.
    pub tiles_x: u32,
    /// Tile rows, `⌈height / tile_size⌉`.
    pub tiles_y: u32,
}

/// Invalid A-buffer input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileError {
    /// Zero image width or height.
    ZeroSize,
    /// The tile size is not in `1 ..= MAX_TILE_SIZE`.
    TileSize,
    /// The bounding box is not finite with `min ≤ max` on every axis.
    Bounds,
    /// More fragments than a `u32` offset can address.
    TooManyEntries,
}

impl fmt::Display for TileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TileError::ZeroSize => f.write_str("tile grid: the image size must be nonzero"),
            TileError::TileSize => {
                write!(f, "tile grid: the tile size must be in 1..={MAX_TILE_SIZE}")
            }
            TileError::Bounds => f.write_str(
                "tile A-buffer: the bounding box must be finite with min <= max on every axis",
            ),
            TileError::TooManyEntries => f.write_str("tile A-buffer: more than u32::MAX fragments"),
        }
    }
}

impl core::error::Error for TileError {}

impl TileGrid {
    /// The grid of `tile_size²` tiles over a `width × height` image.
    ///
    /// # Errors
    /// [`TileError::ZeroSize`], [`TileError::TileSize`].
    pub fn new(width: u32, height: u32, tile_size: u32) -> Result<Self, TileError> {
        if width == 0 || height == 0 {
            return Err(TileError::ZeroSize);
        }
        if tile_size == 0 || tile_size > MAX_TILE_SIZE {
            return Err(TileError::TileSize);
        }
        Ok(Self {
            width,
            height,
            tile_size,
            tiles_x: width.div_ceil(tile_size),
            tiles_y: height.div_ceil(tile_size),
        })
    }

    /// The number of tiles.
    #[inline]
    pub fn tile_count(&self) -> usize {
        self.tiles_x as usize * self.tiles_y as usize
    }

    /// The pixel rectangle `[x0, x1) × [y0, y1)` of tile `i` (row-major
    /// tile index); empty for an index past the grid.
    #[inline]
    pub fn pixels(&self, i: usize) -> ([u32; 2], [u32; 2]) {
        if i >= self.tile_count() {
            return ([0, 0], [0, 0]);
        }
        let tx = (i % self.tiles_x as usize) as u32;
        let ty = (i / self.tiles_x as usize) as u32;
        let x0 = tx * self.tile_size;
        let y0 = ty * self.tile_size;
        (
            [x0, (x0 + self.tile_size).min(self.width)],
            [y0, (y0 + self.tile_size).min(self.height)],
        )
    }
}

/// `c = d·forward` of a pixel ray: the factor with `z = t·c` between the
/// ray parameter and the camera depth (`1` for orthographic rays,
/// `1/√(1 + x² + y²) > 0` for perspective ones).
#[inline]
pub fn depth_factor<T: Real>(camera: &Camera<T>, ray: &Ray<T>) -> T {
    let f = camera.forward;
    ray.dir[0] * f[0] + ray.dir[1] * f[1] + ray.dir[2] * f[2]
}

#[cfg(feature = "alloc")]
/// The tile A-buffer (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct ABuffer<T> {
    grid: TileGrid,
    offsets: Vec<u32>,
    entries: Vec<TileEntry<T>>,
}

#[cfg(feature = "alloc")]
/// A tile index and its fragment (the builder's unsorted output).
type Fragment<T> = (u32, TileEntry<T>);

#[cfg(feature = "alloc")]
impl<T: Real + Send + Sync> ABuffer<T> {
    /// Builds the A-buffer of `abvs` (e.g. from
    /// [`FlatBlobtree::abvs`](boundtrace_fields::blobtree::FlatBlobtree::abvs))
    /// for `camera`'s pixel rays of `grid`, clipped to the scene box
    /// `bounds = [min, max]` (the box the renderer traces in).
    ///
    /// # Errors
    /// [`TileError::Bounds`] for a non-finite or inverted box,
    /// [`TileError::TooManyEntries`] beyond `u32` offsets.
    pub fn build(
        camera: &Camera<T>,
        grid: TileGrid,
        bounds: [[T; 3]; 2],
        abvs: &[Abv<T>],
    ) -> Result<Self, TileError> {
        let ok = (0..3).all(|i| {
            bounds[0][i].is_finite() && bounds[1][i].is_finite() && bounds[0][i] <= bounds[1][i]
        });
        if !ok {
            return Err(TileError::Bounds);
        }
        #[cfg(feature = "parallel")]
        let mut frags: Vec<Fragment<T>> = {
            use rayon::prelude::*;
            abvs.par_iter()
                .fold(Vec::new, |mut out, abv| {
                    fragments(camera, &grid, &bounds, abv, &mut out);
                    out
                })
                .reduce(Vec::new, |mut a, mut b| {
                    a.append(&mut b);
                    a
                })
        };
        #[cfg(not(feature = "parallel"))]
        let mut frags: Vec<Fragment<T>> = {
            let mut out = Vec::new();
            for abv in abvs {
                fragments(camera, &grid, &bounds, abv, &mut out);
            }
            out
        };
        if frags.len() > u32::MAX as usize {
            return Err(TileError::TooManyEntries);
        }
        // A total order (depths are never NaN): the same result whatever
        // order the fragments were produced in.
        let key = |a: &Fragment<T>, b: &Fragment<T>| {
            a.0.cmp(&b.0)
                .then(
                    a.1.z_entry
                        .partial_cmp(&b.1.z_entry)
                        .unwrap_or(core::cmp::Ordering::Equal),
                )
                .then(a.1.node.cmp(&b.1.node))
        };
        #[cfg(feature = "parallel")]
        {
            use rayon::slice::ParallelSliceMut;
            frags.par_sort_unstable_by(key);
        }
        #[cfg(not(feature = "parallel"))]
        frags.sort_unstable_by(key);
        let mut offsets = Vec::with_capacity(grid.tile_count() + 1);
        offsets.push(0u32);
        let mut k = 0usize;
        for tile in 0..grid.tile_count() as u32 {
            while k < frags.len() && frags[k].0 == tile {
                k += 1;
            }
            offsets.push(k as u32);
        }
        let entries = frags.into_iter().map(|(_, e)| e).collect();
        Ok(Self {
            grid,
            offsets,
            entries,
        })
    }
}

#[cfg(feature = "alloc")]
impl<T> ABuffer<T> {
    /// The tiling.
    #[inline]
    pub fn grid(&self) -> &TileGrid {
        &self.grid
    }

    /// The entries of tile `i`, sorted by entry depth (empty past the
    /// grid).
    #[inline]
    pub fn tile(&self, i: usize) -> &[TileEntry<T>] {
        match (self.offsets.get(i), self.offsets.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.entries[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The offsets array (`tile_count + 1` values).
    #[inline]
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// Every entry, tile after tile.
    #[inline]
    pub fn entries(&self) -> &[TileEntry<T>] {
        &self.entries
    }

    /// The largest number of entries of one tile.
    pub fn max_tile_len(&self) -> usize {
        self.offsets
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0)
    }
}

#[cfg(feature = "alloc")]
/// Camera-space coordinates `[x, y, z]` of `p` (right, up, forward).
#[inline]
fn to_camera<T: Real>(camera: &Camera<T>, p: [T; 3]) -> [T; 3] {
    let d = [
        p[0] - camera.eye[0],
        p[1] - camera.eye[1],
        p[2] - camera.eye[2],
    ];
    let dot = |a: [T; 3]| d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
    [dot(camera.right), dot(camera.up), dot(camera.forward)]
}

#[cfg(feature = "alloc")]
/// The pixel rectangle `[x0, x1] × [y0, y1]` (inclusive, clamped to the
/// image) whose pixel-centre rays may pass through the box `[lo, hi]`;
/// `None` when none can.
fn footprint<T: Real>(
    camera: &Camera<T>,
    grid: &TileGrid,
    lo: [T; 3],
    hi: [T; 3],
) -> Option<([u32; 2], [u32; 2])> {
    let full = Some(([0, grid.width - 1], [0, grid.height - 1]));
    // Camera-space box of the 8 corners.
    let mut cmin = [T::INFINITY; 3];
    let mut cmax = [T::NEG_INFINITY; 3];
    for corner in 0..8 {
        let p = [
            if corner & 1 == 0 { lo[0] } else { hi[0] },
            if corner & 2 == 0 { lo[1] } else { hi[1] },
            if corner & 4 == 0 { lo[2] } else { hi[2] },
        ];
        let c = to_camera(camera, p);
        for k in 0..3 {
            cmin[k] = cmin[k].min(c[k]);
            cmax[k] = cmax[k].max(c[k]);
        }
    }
    if !(cmin.iter().chain(cmax.iter()).all(|v| v.is_finite())) {
        return full;
    }
    // Image-plane ranges (before the division by `scale`).
    let (xr, yr) = match camera.projection {
        Projection::Orthographic => ([cmin[0], cmax[0]], [cmin[1], cmax[1]]),
        Projection::Perspective => {
            if cmax[2] <= T::ZERO {
                return None; // wholly behind the eye
            }
            let scale = cmax[2].abs().max(cmax[0].abs()).max(cmax[1].abs());
            if !(cmin[2] > scale * T::from_f64(1e-6)) {
                return full; // reaches the eye plane: no finite projection
            }
            // x/z over x ∈ [x0, x1], z ∈ [z0, z1] (z > 0) is extreme at corners.
            let ratio = |a: [T; 2]| {
                let q = [
                    a[0] / cmin[2],
                    a[0] / cmax[2],
                    a[1] / cmin[2],
                    a[1] / cmax[2],
                ];
                [
                    q[0].min(q[1]).min(q[2]).min(q[3]),
                    q[0].max(q[1]).max(q[2]).max(q[3]),
                ]
            };
            (ratio([cmin[0], cmax[0]]), ratio([cmin[1], cmax[1]]))
        }
    };
    let w = T::from_f64(f64::from(grid.width));
    let h = T::from_f64(f64::from(grid.height));
    let u = [xr[0] / camera.scale[0], xr[1] / camera.scale[0]];
    let v = [yr[0] / camera.scale[1], yr[1] / camera.scale[1]];
    // Pixel centre px + ½ at u = 2(px + ½)/w − 1: px = (u + 1)·w/2 − ½;
    // py = (1 − v)·h/2 − ½. One pixel of margin each side for rounding.
    let px = [
        (u[0] + T::ONE) * w * T::HALF - T::HALF,
        (u[1] + T::ONE) * w * T::HALF - T::HALF,
    ];
    let py = [
        (T::ONE - v[1]) * h * T::HALF - T::HALF,
        (T::ONE - v[0]) * h * T::HALF - T::HALF,
    ];
    let clamp = |lo: T, hi: T, n: u32| -> Option<[u32; 2]> {
        let a = (lo.floor() - T::ONE).as_f64();
        let b = (hi.ceil() + T::ONE).as_f64();
        let last = f64::from(n - 1);
        if a.is_nan() || b.is_nan() || b < 0.0 || a > last {
            return None;
        }
        Some([a.max(0.0) as u32, b.min(last) as u32])
    };
    Some((
        clamp(px[0], px[1], grid.width)?,
        clamp(py[0], py[1], grid.height)?,
    ))
}

#[cfg(feature = "alloc")]
/// Appends the fragments of one ABV.
fn fragments<T: Real>(
    camera: &Camera<T>,
    grid: &TileGrid,
    bounds: &[[T; 3]; 2],
    abv: &Abv<T>,
    out: &mut Vec<Fragment<T>>,
) {
    let rect = match &abv.volume {
        Some(v) => {
            let b = v.aabb();
            // Clip to the scene box: rays are traced only there.
            let lo = [0, 1, 2].map(|k| b.min[k].max(bounds[0][k]));
            let hi = [0, 1, 2].map(|k| b.max[k].min(bounds[1][k]));
            if !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) {
                return;
            }
            footprint(camera, grid, lo, hi)
        }
        None => Some(([0, grid.width - 1], [0, grid.height - 1])),
    };
    let Some(([x0, x1], [y0, y1])) = rect else {
        return;
    };
    let ts = grid.tile_size;
    for ty in y0 / ts..=y1 / ts {
        for tx in x0 / ts..=x1 / ts {
            let tile = ty * grid.tiles_x + tx;
            let (xs, ys) = grid.pixels(tile as usize);
            let mut z_entry = T::INFINITY;
            let mut z_exit = T::NEG_INFINITY;
            for py in ys[0]..ys[1] {
                for px in xs[0]..xs[1] {
                    let ray = camera.ray(px, py, grid.width, grid.height);
                    let Some(span) = ray_box_span(&ray, bounds) else {
                        continue;
                    };
                    let hit = match &abv.volume {
                        Some(v) => v.ray_entry_exit(ray.origin, ray.dir),
                        None => Some((span[0], span[1])),
                    };
                    let Some((te, tx)) = hit else {
                        continue;
                    };
                    let (te, tx) = (te.max(span[0]), tx.min(span[1]));
                    if !(te <= tx) {
                        continue;
                    }
                    let c = depth_factor(camera, &ray);
                    z_entry = z_entry.min(te * c);
                    z_exit = z_exit.max(tx * c);
                }
            }
            if z_entry <= z_exit {
                out.push((
                    tile,
                    TileEntry {
                        node: abv.node,
                        z_entry: z_entry.next_down_n(DEPTH_ULPS),
                        z_exit: z_exit.next_up_n(DEPTH_ULPS),
                    },
                ));
            }
        }
    }
}

#[cfg(all(test, feature = "alloc"))]
mod tests {
    extern crate std;
    use super::*;
    use boundtrace_fields::bounding::{Aabb, Bounding, Sphere, SphereCone};
    use std::string::ToString;

    fn abv(node: u32, volume: Option<Bounding<f64>>) -> Abv<f64> {
        Abv {
            node,
            r_plus: 0.0,
            volume,
        }
    }

    /// Spheres, boxes and sphere-cones scattered around (and partly out
    /// of) the view, one unbounded ABV.
    fn volumes() -> Vec<Abv<f64>> {
        let mut out = Vec::new();
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.4 - 1.2
        };
        for i in 0..60u32 {
            let c = [rnd(), rnd(), rnd()];
            let r = 0.02 + 0.1 * (rnd() + 1.2);
            let v = match i % 3 {
                0 => Bounding::Sphere(Sphere {
                    center: c,
                    radius: r,
                }),
                1 => Bounding::Aabb(Aabb::new(
                    [c[0] - r, c[1] - 0.5 * r, c[2] - 0.3 * r],
                    [c[0] + 0.4 * r, c[1] + r, c[2] + r],
                )),
                _ => Bounding::SphereCone(SphereCone {
                    a: c,
                    ra: 0.5 * r,
                    b: [c[0] + rnd() * 0.5, c[1] + rnd() * 0.5, c[2]],
                    rb: 0.2 * r,
                }),
            };
            out.push(abv(2 * i, Some(v)));
        }
        out.push(abv(999, None));
        out
    }

    /// Every point of every pixel ray (sampled densely on its box span)
    /// that lies in an ABV is covered by an entry of its tile for that
    /// primitive. Independent of the builder's ray intersections: uses
    /// `contains_point` only.
    fn check_cover(camera: &Camera<f64>, grid: TileGrid) {
        let bounds = [[-1.0; 3], [1.0; 3]];
        let abvs = volumes();
        let ab = ABuffer::build(camera, grid, bounds, &abvs).unwrap();
        assert_eq!(ab.offsets().len(), grid.tile_count() + 1);
        let mut checked = 0;
        for py in 0..grid.height {
            for px in 0..grid.width {
                let tile = (py / grid.tile_size * grid.tiles_x + px / grid.tile_size) as usize;
                let list = ab.tile(tile);
                let ray = camera.ray(px, py, grid.width, grid.height);
                let Some(span) = ray_box_span(&ray, &bounds) else {
                    continue;
                };
                let c = depth_factor(camera, &ray);
                for k in 0..=200 {
                    let t = span[0] + (span[1] - span[0]) * (k as f64 / 200.0);
                    let p = [0, 1, 2].map(|i| ray.origin[i] + t * ray.dir[i]);
                    for a in &abvs {
                        let inside = a.volume.is_none_or(|v| v.contains_point(p));
                        if !inside {
                            continue;
                        }
                        checked += 1;
                        let z = t * c;
                        assert!(
                            list.iter()
                                .any(|e| e.node == a.node && e.z_entry <= z && z <= e.z_exit),
                            "pixel ({px}, {py}) at t = {t}: ABV {} missing from tile {tile}",
                            a.node
                        );
                    }
                }
            }
        }
        assert!(checked > 1000, "too few covered samples: {checked}");
        // Sorted by entry depth within each tile.
        for i in 0..grid.tile_count() {
            assert!(ab.tile(i).windows(2).all(|w| w[0].z_entry <= w[1].z_entry));
        }
    }

    #[test]
    fn covers_every_pixel_ray_perspective() {
        let cam =
            Camera::perspective([0.3, 0.4, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 50.0, 1.25).unwrap();
        check_cover(&cam, TileGrid::new(30, 24, 8).unwrap());
    }

    #[test]
    fn covers_every_pixel_ray_close_perspective_and_orthographic() {
        // The eye inside the scene box: volumes behind the eye plane.
        let cam =
            Camera::perspective([0.1, 0.0, 0.6], [0.0; 3], [0.0, 1.0, 0.0], 70.0, 1.0).unwrap();
        check_cover(&cam, TileGrid::new(20, 20, 4).unwrap());
        let ortho =
            Camera::orthographic([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 2.6, 1.0).unwrap();
        check_cover(&ortho, TileGrid::new(24, 24, 8).unwrap());
    }

    #[test]
    fn footprints_prune_tiles() {
        // A small sphere in the image centre is listed in few tiles.
        let cam =
            Camera::perspective([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0, 1.0).unwrap();
        let grid = TileGrid::new(64, 64, 8).unwrap();
        let s = abv(
            0,
            Some(Bounding::Sphere(Sphere {
                center: [0.0; 3],
                radius: 0.1,
            })),
        );
        let ab = ABuffer::build(&cam, grid, [[-1.0; 3], [1.0; 3]], &[s]).unwrap();
        assert!(!ab.entries().is_empty() && ab.entries().len() <= 4);
        let e = ab.entries()[0];
        assert!((e.z_entry - 2.9).abs() < 0.01 && (e.z_exit - 3.1).abs() < 0.01);
        // Outside the box: nothing.
        let far = abv(
            1,
            Some(Bounding::Sphere(Sphere {
                center: [5.0, 0.0, 0.0],
                radius: 0.1,
            })),
        );
        let ab = ABuffer::build(&cam, grid, [[-1.0; 3], [1.0; 3]], &[far]).unwrap();
        assert!(ab.entries().is_empty());
    }

    #[test]
    fn bad_input_is_refused() {
        assert_eq!(TileGrid::new(0, 4, 8), Err(TileError::ZeroSize));
        assert_eq!(TileGrid::new(4, 4, 0), Err(TileError::TileSize));
        assert_eq!(TileGrid::new(4, 4, 65), Err(TileError::TileSize));
        let cam =
            Camera::perspective([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 45.0, 1.0).unwrap();
        let grid = TileGrid::new(4, 4, 8).unwrap();
        assert_eq!(grid.tile_count(), 1);
        assert_eq!(
            ABuffer::<f64>::build(&cam, grid, [[1.0; 3], [-1.0; 3]], &[]),
            Err(TileError::Bounds)
        );
        assert!(TileError::TileSize.to_string().contains("64"));
    }
}
