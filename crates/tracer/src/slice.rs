//! Slicing SCALIS skeletons for additive manufacturing (thesis Part III
//! ch. 2 §2.2, Table 2.1): orthographic rays along the print axis `z`, one
//! per pixel of a `W × H` grid over the box; per-bucket (`64²` pixels)
//! candidate primitives and per-ray primitive lists ([`crate::scalis`]);
//! **all roots** per ray (`scalis-quadratic`, transparent mode); then the
//! inside/outside state of every voxel centre of `N` slices follows from
//! the roots, so adding slices costs no field evaluation.
//!
//! [`sample_scalis`] computes the same stack by evaluating the field at
//! every voxel centre with the same lists (the comparison of Table 2.1).
//!
//! Voxel `(x, y, k)` has its centre at `lo + ((x, y, k) + ½)·(hi − lo)/(W, H,
//! N)`; it is inside when the field is negative there. The roots are within
//! `eps` of the true surface, so the state of a voxel centre can only differ
//! from the field's sign within `eps` of the surface along the ray.

use crate::image::{Image, ImageError};
use crate::method::{Method, Mode, Params};
use crate::scalis::{RayPrimitives, trace_scalis};
use crate::trace::{RayStats, Root, Side, Status};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_inclusion::{Field, Ray};
use std::fmt;
use std::vec::Vec;

/// The bucket side in pixels (§2.2: primitive lists per 64² pixels).
pub const BUCKET: u32 = 64;

/// A slicing grid: `width × height` pixels, `slices` slices along `z`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SliceSettings {
    /// Pixels along `x`.
    pub width: u32,
    /// Pixels along `y`.
    pub height: u32,
    /// Slices along `z`.
    pub slices: u32,
}

/// Why a stack cannot be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum SliceError {
    /// A zero or too large grid (more than `2³²` voxels).
    Grid,
    /// The box is empty or not finite.
    Bounds,
    /// The skeleton has a Cauchy segment (no compact support).
    Skeleton(crate::scalis::ListError),
    /// A ray could not be traced to the end (`max_steps` ran out).
    Unfinished {
        /// The pixel.
        pixel: (u32, u32),
        /// Why.
        status: Status,
    },
}

impl fmt::Display for SliceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SliceError::Grid => {
                f.write_str("slicing grid: every size must be >= 1 and W·H·N < 2^32")
            }
            SliceError::Bounds => f.write_str("slicing box: lo <= hi, finite, on every axis"),
            SliceError::Skeleton(e) => write!(f, "slicing: {e}"),
            SliceError::Unfinished { pixel, status } => write!(
                f,
                "slicing: the ray of pixel {pixel:?} stopped with {status:?} (raise max_steps)"
            ),
        }
    }
}

impl std::error::Error for SliceError {}

/// A stack of inside/outside slices, with the cost of computing it.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceStack {
    settings: SliceSettings,
    /// One byte per voxel (1 inside), `x` fastest, then `y`, then slice.
    inside: Vec<u8>,
    /// Summed per-ray statistics (tracing) or point evaluations (sampling).
    pub stats: RayStats,
}

impl SliceStack {
    /// The grid.
    pub fn settings(&self) -> SliceSettings {
        self.settings
    }
    /// Whether voxel `(x, y, k)` is inside (`false` out of range).
    pub fn inside(&self, x: u32, y: u32, k: u32) -> bool {
        let s = self.settings;
        x < s.width
            && y < s.height
            && k < s.slices
            && self.inside
                [((k as usize * s.height as usize) + y as usize) * s.width as usize + x as usize]
                != 0
    }
    /// Slice `k` as an 8-bit image (inside white), `y` up.
    ///
    /// # Errors
    /// As [`Image::from_fn`].
    pub fn slice_image(&self, k: u32) -> Result<Image, ImageError> {
        let h = self.settings.height;
        Image::from_fn(self.settings.width, h, |x, y| {
            if self.inside(x, h - 1 - y, k) {
                [255; 3]
            } else {
                [0; 3]
            }
        })
    }
    /// Slice `k` as a 1-bit bitmap: rows of `⌈W/8⌉` bytes, most
    /// significant bit first, row `y = 0` first.
    pub fn slice_bits(&self, k: u32) -> Vec<u8> {
        let s = self.settings;
        let stride = s.width.div_ceil(8) as usize;
        let mut out = vec![0u8; stride * s.height as usize];
        for y in 0..s.height {
            for x in 0..s.width {
                if self.inside(x, y, k) {
                    out[y as usize * stride + x as usize / 8] |= 0x80 >> (x % 8);
                }
            }
        }
        out
    }
    /// Writes every slice as `dir/{stem}-{k:05}.png` (8-bit).
    ///
    /// # Errors
    /// I/O errors.
    pub fn write_png_stack(&self, dir: &std::path::Path, stem: &str) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        for k in 0..self.settings.slices {
            let img = self
                .slice_image(k)
                .map_err(|e| std::io::Error::other(e.to_string()))?;
            img.write_png(dir.join(format!("{stem}-{k:05}.png")))?;
        }
        Ok(())
    }
}

fn check(bounds: &[[f64; 3]; 2], s: &SliceSettings) -> Result<usize, SliceError> {
    let n = u64::from(s.width) * u64::from(s.height) * u64::from(s.slices);
    if n == 0 || n >= 1 << 32 {
        return Err(SliceError::Grid);
    }
    if !(0..3).all(|i| {
        bounds[0][i].is_finite() && bounds[1][i].is_finite() && bounds[0][i] < bounds[1][i]
    }) {
        return Err(SliceError::Bounds);
    }
    Ok(n as usize)
}

/// The segments whose support box meets the column of a bucket.
fn bucket_segments(
    segs: &[ScalisSegment<f64>],
    x: [f64; 2],
    y: [f64; 2],
) -> Vec<ScalisSegment<f64>> {
    segs.iter()
        .filter(|s| match s.support_box() {
            Some([lo, hi]) => lo[0] <= x[1] && hi[0] >= x[0] && lo[1] <= y[1] && hi[1] >= y[0],
            None => true,
        })
        .copied()
        .collect()
}

/// What one ray of the grid fills.
struct Column<'a> {
    settings: SliceSettings,
    z: [f64; 2],
    inside: &'a mut [u8],
}

/// Slices `skeleton` inside `bounds` (module docs) with `params` (`eps`:
/// the root accuracy).
///
/// # Errors
/// [`SliceError`] for a bad grid or box, a Cauchy skeleton, or a ray that
/// did not finish.
pub fn slice_scalis<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
) -> Result<SliceStack, SliceError> {
    run(skeleton, bounds, settings, params, true)
}

/// The same stack by evaluating the field at every voxel centre with the
/// same per-ray lists (the baseline of Table 2.1).
///
/// # Errors
/// As [`slice_scalis`].
pub fn sample_scalis<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
) -> Result<SliceStack, SliceError> {
    run(skeleton, bounds, settings, params, false)
}

fn run<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
    by_roots: bool,
) -> Result<SliceStack, SliceError> {
    let n = check(&bounds, &settings)?;
    crate::scalis::check_segments(skeleton.segments()).map_err(SliceError::Skeleton)?;
    params.validate().map_err(|_| SliceError::Grid)?;
    let (w, h) = (settings.width, settings.height);
    let [lo, hi] = bounds;
    let dx = (hi[0] - lo[0]) / f64::from(w);
    let dy = (hi[1] - lo[1]) / f64::from(h);
    let mut voxels = vec![0u8; n];
    // one column of voxels per ray, gathered per pixel then scattered
    let mut column = vec![0u8; settings.slices as usize];
    let mut stats = RayStats::default();
    for by in (0..h).step_by(BUCKET as usize) {
        for bx in (0..w).step_by(BUCKET as usize) {
            let (ex, ey) = ((bx + BUCKET).min(w), (by + BUCKET).min(h));
            let xs = [lo[0] + f64::from(bx) * dx, lo[0] + f64::from(ex) * dx];
            let ys = [lo[1] + f64::from(by) * dy, lo[1] + f64::from(ey) * dy];
            let segs = bucket_segments(skeleton.segments(), xs, ys);
            if segs.is_empty() {
                continue; // every voxel outside (already 0)
            }
            let sk = ScalisSkeleton::new(segs).map_err(|_| SliceError::Grid)?;
            let mut storage = vec![crate::scalis::PrimitiveHit::empty(); sk.segments().len()];
            for y in by..ey {
                for x in bx..ex {
                    let px = lo[0] + (f64::from(x) + 0.5) * dx;
                    let py = lo[1] + (f64::from(y) + 0.5) * dy;
                    let ray = Ray::new([px, py, lo[2]], [0.0, 0.0, 1.0]);
                    let span = [0.0, hi[2] - lo[2]];
                    let list = RayPrimitives::build(sk.segments(), &ray, span, &mut storage);
                    let mut col = Column {
                        settings,
                        z: span,
                        inside: &mut column,
                    };
                    col.inside.fill(0);
                    if list.hits().is_empty() {
                        continue;
                    }
                    if by_roots {
                        let st = fill_by_roots(&sk, list.hits(), &ray, &mut col, params).map_err(
                            |status| SliceError::Unfinished {
                                pixel: (x, y),
                                status,
                            },
                        )?;
                        stats = stats + st;
                    } else {
                        stats.field_evals = stats.field_evals.saturating_add(fill_by_sampling(
                            &sk,
                            list.hits(),
                            &ray,
                            &mut col,
                        ));
                    }
                    let plane = (w as usize) * (h as usize);
                    for (k, &v) in column.iter().enumerate() {
                        voxels[k * plane + y as usize * w as usize + x as usize] = v;
                    }
                }
            }
        }
    }
    Ok(SliceStack {
        settings,
        inside: voxels,
        stats,
    })
}

/// The voxel centres of a column: `t_k = (k + ½)·dz` along the ray.
#[inline]
fn centre(col: &Column<'_>, k: usize) -> f64 {
    (col.z[1] - col.z[0]) * (k as f64 + 0.5) / f64::from(col.settings.slices)
}

/// All roots (resuming after a full buffer), then the state between them.
fn fill_by_roots<S: AsRef<[ScalisSegment<f64>]>>(
    sk: &ScalisSkeleton<f64, S>,
    hits: &[crate::scalis::PrimitiveHit<f64>],
    ray: &Ray<f64>,
    col: &mut Column<'_>,
    params: &Params<f64>,
) -> Result<RayStats, Status> {
    let mut buf = [Root {
        t: 0.0,
        side: Side::Touch,
    }; 64];
    let mut stats = RayStats::default();
    let mut t0 = col.z[0];
    // the span starts on the box's face, outside the surface
    let mut inside = sk.eval(ray.at::<f64>(t0, t0)) < 0.0;
    let mut k = 0usize;
    let n = col.inside.len();
    loop {
        let tr = trace_scalis(
            sk,
            hits,
            ray,
            [t0, col.z[1]],
            Method::ScalisQuadratic,
            Mode::Transparent,
            params,
            &mut buf,
        );
        stats = stats + tr.stats;
        for r in &buf[..tr.roots as usize] {
            while k < n && centre(col, k) < r.t {
                col.inside[k] = u8::from(inside);
                k += 1;
            }
            match r.side {
                Side::Entering => inside = true,
                Side::Leaving => inside = false,
                Side::Touch => {}
            }
        }
        match tr.status {
            Status::Finished => break,
            Status::BufferFull if tr.t_reached > t0 => t0 = tr.t_reached,
            s => return Err(s),
        }
    }
    while k < n {
        col.inside[k] = u8::from(inside);
        k += 1;
    }
    Ok(stats)
}

/// The field's sign at every voxel centre, from the hits whose
/// `[entry, exit]` contains it; returns the number of point evaluations.
fn fill_by_sampling<S: AsRef<[ScalisSegment<f64>]>>(
    sk: &ScalisSkeleton<f64, S>,
    hits: &[crate::scalis::PrimitiveHit<f64>],
    ray: &Ray<f64>,
    col: &mut Column<'_>,
) -> u32 {
    let segs = sk.segments();
    let mut evals = 0u32;
    for k in 0..col.inside.len() {
        let t = centre(col, k);
        let p = ray.at::<f64>(t, t);
        let mut f = 0.0;
        for h in hits {
            if h.entry > t {
                break;
            }
            if h.exit >= t {
                f += segs[h.index as usize].density(p);
                evals += 1;
            }
        }
        col.inside[k] = u8::from(f > sk.iso());
    }
    evals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{Scene, SceneField};

    #[test]
    fn voxels_match_the_field_sign_except_next_to_the_surface() {
        let scene = Scene::<f64>::build("scalis-random", 2023).unwrap();
        let SceneField::Scalis(w) = scene.field() else {
            panic!("not a SCALIS scene")
        };
        let sk = w.field();
        let s = SliceSettings {
            width: 24,
            height: 20,
            slices: 40,
        };
        let b = scene.bounds();
        let params = Params::new();
        let stack = slice_scalis(sk, b, s, &params).unwrap();
        let sampled = sample_scalis(sk, b, s, &params).unwrap();
        let d =
            [0, 1, 2].map(|i| (b[1][i] - b[0][i]) / f64::from([s.width, s.height, s.slices][i]));
        let (mut inside, mut differ) = (0, 0);
        for k in 0..s.slices {
            for y in 0..s.height {
                for x in 0..s.width {
                    let c = [x, y, k].map(f64::from);
                    let p = [0, 1, 2].map(|i| b[0][i] + (c[i] + 0.5) * d[i]);
                    let f: f64 = sk.eval(p);
                    let got = stack.inside(x, y, k);
                    inside += usize::from(got);
                    if got != (f < 0.0) {
                        // only within half a voxel of the surface along z
                        let q = |dz: f64| sk.eval([p[0], p[1], p[2] + dz]) < 0.0;
                        assert!(
                            q(-0.5 * d[2]) != q(0.5 * d[2]),
                            "voxel ({x}, {y}, {k}): {got} but f = {f}"
                        );
                        differ += 1;
                    }
                    if sampled.inside(x, y, k) != got {
                        differ += 1;
                    }
                }
            }
        }
        assert!(inside > 50, "{inside}");
        assert!(differ <= 4, "{differ}");
        // 1-bit and 8-bit views agree
        let bits = stack.slice_bits(s.slices / 2);
        let img = stack.slice_image(s.slices / 2).unwrap();
        for y in 0..s.height {
            for x in 0..s.width {
                let bit = bits[y as usize * 3 + x as usize / 8] & (0x80 >> (x % 8)) != 0;
                assert_eq!(bit, img.get(x, s.height - 1 - y).unwrap()[0] == 255);
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let scene = Scene::<f64>::build("scalis-random", 2023).unwrap();
        let SceneField::Scalis(w) = scene.field() else {
            panic!("not a SCALIS scene")
        };
        let p = Params::new();
        let s = SliceSettings {
            width: 0,
            height: 4,
            slices: 4,
        };
        assert_eq!(
            slice_scalis(w.field(), scene.bounds(), s, &p),
            Err(SliceError::Grid)
        );
        let s = SliceSettings { width: 4, ..s };
        let mut b = scene.bounds();
        b[1][2] = f64::NAN;
        assert_eq!(slice_scalis(w.field(), b, s, &p), Err(SliceError::Bounds));
    }
}
