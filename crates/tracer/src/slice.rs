//! Slicing SCALIS skeletons for additive manufacturing (thesis Part III
//! ch. 2 §2.2, Table 2.1): orthographic rays along the print axis `z`, one
//! per pixel of a `W × H` grid over the box; per-bucket (`64²` pixels)
//! candidate primitives and per-ray primitive lists ([`crate::scalis`]);
//! then the inside/outside state of every voxel centre of `N` slices.
//!
//! Voxel `(x, y, k)` has its centre at `lo + ((x, y, k) + ½)·(hi − lo)/(W, H,
//! N)`; it is inside when the field is negative there (`Σ fᵢ > iso`).
//! Three ways to fill a stack, with the same lists:
//!
//! - [`slice_scalis`]: the **column classifier** below — the field is
//!   evaluated at a few voxel centres per ray, next to the roots; every
//!   other centre gets the sign of an interval whose per-primitive ranges
//!   exclude the iso-value.
//! - [`slice_scalis_traced`]: all roots of each ray with `scalis-quadratic`
//!   (transparent mode, roots within `eps`, interval enclosures of the
//!   closed form throughout), then the state between the roots. Sound
//!   without assumptions on the `f64` closed form, but milliseconds per ray.
//! - [`sample_scalis`]: the field at every voxel centre (the baseline of
//!   Table 2.1).
//!
//! # Classifying a column
//!
//! Only the voxel centres matter, so the classifier never locates a root
//! more finely than the centres around it. Each covered region of the ray
//! (a union of overlapping supports; empty space is outside) starts as one
//! interval whose ends are outside every support (`fᵢ = fᵢ' = 0` there).
//! An interval `[a, b]` whose ends are evaluated is
//!
//! 1. done when no voxel centre lies strictly inside it;
//! 2. outside (resp. inside) on all its centres when the sum of the
//!    per-primitive upper (resp. lower) bounds below is `< iso` (`> iso`);
//! 3. otherwise split at **a voxel centre**, which is evaluated (so it is
//!    classified by the sign of the field there, exactly as the sampling
//!    does — same closed form, same summation order): the one nearest to
//!    the first root of the *line model* in the interval (where the ray's
//!    distance to a segment's line equals its radius: the surface of an
//!    isolated long segment) that can still be crossed there, else the
//!    secant's root of the normalized field `g(Σf) − 1` (≈ `D² − 1`,
//!    thesis Part III §1.2) on a bracketed interval (a bisection after a
//!    secant that moved the same end twice), else the middle. A correct
//!    guess brackets a root between two adjacent centres in two
//!    evaluations.
//!
//! Intervals that are probably root-free (same sign at both ends, no model
//! root) but not proven are put aside until the region's other intervals
//! are done, then get the derivatives `fᵢ'` at their ends (forward-mode
//! [`Jet`]s) before they are split. Points are evaluated without
//! derivatives otherwise.
//!
//! Per-primitive bounds on `[a, b]` (constant radius, compact kernel — the
//! SCALIS segments of `scalis-foam`):
//!
//! - **Log-concavity.** `fᵢ` is log-concave along every line: with
//!   `K(u) = (1 − u/σ²)₊^m`, `ln K` is concave and non-increasing in `u`,
//!   `u = |p − q(s)|²/τ²` is convex in `(t, s)` for a constant `τ`, so
//!   `K(u(t, s))·1_{[0, L]}(s)` is log-concave in `(t, s)` and its integral
//!   over `s` is log-concave in `t` (Prékopa–Leindler). Hence `fᵢ` is
//!   unimodal: `min(fᵢ(a), fᵢ(b))` is a lower bound; `fᵢ` is monotone on
//!   `[a, b]` when two values or a derivative's sign place the mode outside
//!   it (`fᵢ(x₁) > fᵢ(x₂)`, `x₁ < x₂` ⇒ non-increasing from `x₂`); and
//!   `ln fᵢ` lies below its tangents at `a` and `b`.
//! - **The segment's line.** `fᵢ ≤ 1/(Nτ R^{2m}) ∫ (w² − v²)^m dv` with
//!   `R = στ`, `w² = R² − d²`, over `|v| ≥ δ` (one side) or the whole chord,
//!   and over a centred `|v| ≤ L/2`: `d` is the ray piece's smallest
//!   distance to the line and `δ` its smallest axial overshoot beyond the
//!   segment's ends (the integrand decreases in `d` and `|v|`).
//!
//! Segments with varying radii use the sound cell sums of
//! [`crate::scalis::bounds::density_bounds`] instead (no log-concavity
//! proof for them), slower but correct.
//!
//! # Accuracy
//!
//! The classifier's bounds take the `f64` closed form's values and
//! derivatives as exact up to a relative [`CLOSED_FORM_REL`] (`10⁻⁷`, 100 ×
//! the largest relative error measured against adaptive quadrature in
//! `tests/fields_scalis.rs`); they do not use interval enclosures of the
//! closed form (about 13 µs per primitive on `scalis-foam` instead of
//! 0.5 µs, which would make slicing slower than sampling). Evaluated centres are classified by the
//! `f64` sign, like the sampling. So the stack equals [`sample_scalis`]'s
//! except where a proven interval contains a centre whose `|Σf − iso|` is
//! below that accuracy; [`slice_scalis_traced`] makes no such assumption.
//! Adding slices adds centres to the intervals (a few more splits near the
//! roots), not root-finding work proportional to `N`.

use crate::image::{Image, ImageError};
use crate::method::{Method, Mode, Params};
use crate::scalis::{RayPrimitives, trace_scalis};
use crate::trace::{RayStats, Root, Side, Status};
use boundtrace_fields::homothetic::SegmentKernel;
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_inclusion::{Field, Jet, Ray};
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
            self.write_png_slice(dir, stem, k)?;
        }
        Ok(())
    }
    /// Writes slice `k` as `dir/{stem}-{k:05}.png` (8-bit), the file
    /// [`write_png_stack`](Self::write_png_stack) writes for it (`dir`
    /// must exist).
    ///
    /// # Errors
    /// I/O errors, or `k` out of range.
    pub fn write_png_slice(
        &self,
        dir: &std::path::Path,
        stem: &str,
        k: u32,
    ) -> std::io::Result<()> {
        if k >= self.settings.slices {
            return Err(std::io::Error::other(format!(
                "slice {k} out of range ({} slices)",
                self.settings.slices
            )));
        }
        let img = self
            .slice_image(k)
            .map_err(|e| std::io::Error::other(e.to_string()))?;
        img.write_png(dir.join(format!("{stem}-{k:05}.png")))
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

/// The side in pixels of the tiles of a bucket whose rays share a
/// candidate list ([`tile_candidates`]).
const TILE: u32 = 4;

/// Per [`TILE`]² tile of the bucket `[b0, b1)` (row-major), the indices of
/// the bucket's segments whose support box contains the `(x, y)` of some
/// pixel centre of the tile: the only supports its `z` rays can cross
/// (the box test of [`RayPrimitives::build_among`] compares those coordinates
/// exactly), so the per-ray lists built from them equal the full ones.
fn tile_candidates(
    segs: &[ScalisSegment<f64>],
    b0: [u32; 2],
    b1: [u32; 2],
    lo: [f64; 3],
    d: [f64; 2],
) -> Vec<Vec<u32>> {
    let centre = |i: usize, p: u32| lo[i] + (f64::from(p) + 0.5) * d[i];
    let mut tiles = Vec::new();
    for ty in (b0[1]..b1[1]).step_by(TILE as usize) {
        let ys = [centre(1, ty), centre(1, (ty + TILE).min(b1[1]) - 1)];
        for tx in (b0[0]..b1[0]).step_by(TILE as usize) {
            let xs = [centre(0, tx), centre(0, (tx + TILE).min(b1[0]) - 1)];
            let c = segs
                .iter()
                .enumerate()
                .filter(|(_, s)| match s.support_box() {
                    Some([l, h]) => {
                        l[0] <= xs[1] && h[0] >= xs[0] && l[1] <= ys[1] && h[1] >= ys[0]
                    }
                    None => true,
                })
                .map(|(i, _)| i as u32)
                .collect();
            tiles.push(c);
        }
    }
    tiles
}

/// How [`run`] fills a column of voxels.
#[derive(Clone, Copy, PartialEq, Eq)]
enum How {
    /// The column classifier (module docs, "Classifying a column").
    Classify,
    /// All roots with `scalis-quadratic` (interval enclosures throughout).
    Traced,
    /// The field at every voxel centre.
    Sample,
}

/// Slices `skeleton` inside `bounds` (module docs) with the column
/// classifier: the state of every voxel centre is the sign of the field
/// there, evaluated only where the per-primitive ranges cannot decide.
/// `params.eps` is not used (the classifier works at voxel resolution).
///
/// # Errors
/// [`SliceError`] for a bad grid or box, or a Cauchy skeleton.
pub fn slice_scalis<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
) -> Result<SliceStack, SliceError> {
    run(skeleton, bounds, settings, params, How::Classify, &|_| {})
}

/// [`slice_scalis`], calling `on_columns(n)` each time `n` more of the
/// `width × height` voxel columns are done, for progress bars; the stack
/// is the same.
///
/// # Errors
/// As [`slice_scalis`].
pub fn slice_scalis_with_progress<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
    on_columns: &dyn Fn(u64),
) -> Result<SliceStack, SliceError> {
    run(
        skeleton,
        bounds,
        settings,
        params,
        How::Classify,
        on_columns,
    )
}

/// Slices `skeleton` by tracing all roots of every column with
/// `scalis-quadratic` ([`trace_scalis`], transparent mode, roots within
/// `params.eps`; interval enclosures throughout, no reliance on the `f64`
/// accuracy of the closed form), then filling the voxels between them.
/// Much slower than [`slice_scalis`] (BENCHMARKS.md).
///
/// # Errors
/// [`SliceError`], including a ray that did not finish.
pub fn slice_scalis_traced<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
) -> Result<SliceStack, SliceError> {
    run(skeleton, bounds, settings, params, How::Traced, &|_| {})
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
    run(skeleton, bounds, settings, params, How::Sample, &|_| {})
}

/// The voxels of one ray: `buf[k·stride]` is voxel `k` of the column.
struct Column<'a> {
    slices: usize,
    /// The span `[0, z1 − z0]` along the ray.
    len: f64,
    buf: &'a mut [u8],
    stride: usize,
    /// The voxels set so far lie in `set[0]..set[1]` (empty: `set[0] ≥
    /// set[1]`).
    set: [usize; 2],
}

impl Column<'_> {
    /// The parameter of voxel centre `k` along the ray.
    #[inline]
    fn centre(&self, k: usize) -> f64 {
        self.len * (k as f64 + 0.5) / self.slices as f64
    }
    #[inline]
    fn set(&mut self, k: usize) {
        self.buf[k * self.stride] = 1;
        self.set = [self.set[0].min(k), self.set[1].max(k + 1)];
    }
    /// The first centre `≥ t` (may be `slices`).
    fn first_at_or_after(&self, t: f64) -> usize {
        let g = (t / self.len * self.slices as f64 - 0.5).ceil();
        let mut k = if g > 0.0 {
            (g as usize).min(self.slices)
        } else {
            0
        };
        // exact against `centre`, whatever the rounding of the guess
        while k > 0 && self.centre(k - 1) >= t {
            k -= 1;
        }
        while k < self.slices && self.centre(k) < t {
            k += 1;
        }
        k
    }
}

#[allow(clippy::too_many_lines)]
fn run<S: AsRef<[ScalisSegment<f64>]>>(
    skeleton: &ScalisSkeleton<f64, S>,
    bounds: [[f64; 3]; 2],
    settings: SliceSettings,
    params: &Params<f64>,
    how: How,
    on_columns: &dyn Fn(u64),
) -> Result<SliceStack, SliceError> {
    let n = check(&bounds, &settings)?;
    crate::scalis::check_segments(skeleton.segments()).map_err(SliceError::Skeleton)?;
    params.validate().map_err(|_| SliceError::Grid)?;
    let (w, h) = (settings.width, settings.height);
    let [lo, hi] = bounds;
    let dx = (hi[0] - lo[0]) / f64::from(w);
    let dy = (hi[1] - lo[1]) / f64::from(h);
    let slices = settings.slices as usize;
    let plane = (w as usize) * (h as usize);
    let mut voxels = vec![0u8; n];
    let mut stats = RayStats::default();
    let mut scratch = Scratch::default();
    for by in (0..h).step_by(BUCKET as usize) {
        for bx in (0..w).step_by(BUCKET as usize) {
            let (ex, ey) = ((bx + BUCKET).min(w), (by + BUCKET).min(h));
            let xs = [lo[0] + f64::from(bx) * dx, lo[0] + f64::from(ex) * dx];
            let ys = [lo[1] + f64::from(by) * dy, lo[1] + f64::from(ey) * dy];
            let segs = bucket_segments(skeleton.segments(), xs, ys);
            let columns = u64::from(ex - bx) * u64::from(ey - by);
            if segs.is_empty() {
                on_columns(columns);
                continue; // every voxel outside (already 0)
            }
            let sk = ScalisSkeleton::new(segs).map_err(|_| SliceError::Grid)?;
            let prims: Vec<Prim> = sk.segments().iter().map(Prim::new).collect();
            let mut storage = vec![crate::scalis::PrimitiveHit::empty(); sk.segments().len()];
            let tiles = tile_candidates(sk.segments(), [bx, by], [ex, ey], lo, [dx, dy]);
            let tiles_x = (ex - bx).div_ceil(TILE) as usize;
            // one row of the bucket at a time: `row[k·bw + x − bx]`, copied
            // slice by slice into the stack (contiguous writes)
            let bw = (ex - bx) as usize;
            let mut row = vec![0u8; bw * slices];
            // the slices of `row` that hold a set voxel (the rest is 0),
            // so that only those are cleared and copied: the stack is
            // zeroed already, and most of it stays so (pages never written)
            let mut filled = [slices, 0];
            for y in by..ey {
                if filled[0] < filled[1] {
                    row[filled[0] * bw..filled[1] * bw].fill(0);
                }
                filled = [slices, 0];
                for x in bx..ex {
                    let px = lo[0] + (f64::from(x) + 0.5) * dx;
                    let py = lo[1] + (f64::from(y) + 0.5) * dy;
                    let ray = Ray::new([px, py, lo[2]], [0.0, 0.0, 1.0]);
                    let span = [0.0, hi[2] - lo[2]];
                    let tile = ((y - by) / TILE) as usize * tiles_x + ((x - bx) / TILE) as usize;
                    let list = RayPrimitives::build_among(
                        sk.segments(),
                        &tiles[tile],
                        &ray,
                        span,
                        &mut storage,
                    );
                    if list.hits().is_empty() {
                        continue;
                    }
                    let mut col = Column {
                        slices,
                        len: span[1],
                        buf: &mut row[(x - bx) as usize..],
                        stride: bw,
                        set: [slices, 0],
                    };
                    match how {
                        How::Classify => {
                            let cx = ColumnCtx {
                                sk: &sk,
                                prims: &prims,
                                ray: &ray,
                            };
                            let st = classify(&cx, list.hits(), &mut col, &mut scratch);
                            stats = stats + st;
                        }
                        How::Traced => {
                            let st = fill_by_roots(&sk, list.hits(), &ray, &mut col, params)
                                .map_err(|status| SliceError::Unfinished {
                                    pixel: (x, y),
                                    status,
                                })?;
                            stats = stats + st;
                        }
                        How::Sample => {
                            stats.field_evals = stats.field_evals.saturating_add(fill_by_sampling(
                                &sk,
                                list.hits(),
                                &ray,
                                &mut col,
                            ));
                        }
                    }
                    filled = [filled[0].min(col.set[0]), filled[1].max(col.set[1])];
                }
                let base = y as usize * w as usize + bx as usize;
                for k in filled[0]..filled[1] {
                    let dst = k * plane + base;
                    voxels[dst..dst + bw].copy_from_slice(&row[k * bw..(k + 1) * bw]);
                }
                on_columns(bw as u64);
            }
        }
    }
    Ok(SliceStack {
        settings,
        inside: voxels,
        stats,
    })
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
    let mut t0 = 0.0;
    // the span starts on the box's face, outside the surface
    let mut inside = sk.eval(ray.at::<f64>(t0, t0)) < 0.0;
    let mut k = 0usize;
    let n = col.slices;
    loop {
        let tr = trace_scalis(
            sk,
            hits,
            ray,
            [t0, col.len],
            Method::ScalisQuadratic,
            Mode::Transparent,
            params,
            &mut buf,
        );
        stats = stats + tr.stats;
        for r in &buf[..tr.roots as usize] {
            while k < n && col.centre(k) < r.t {
                if inside {
                    col.set(k);
                }
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
        if inside {
            col.set(k);
        }
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
    // only the centres inside some support can be inside
    let (first, last) = (
        hits[0].entry,
        hits.iter().fold(hits[0].exit, |m, h| m.max(h.exit)),
    );
    let mut k = col.first_at_or_after(first);
    while k < col.slices {
        let t = col.centre(k);
        if t > last {
            break;
        }
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
        if f > sk.iso() {
            col.set(k);
        }
        k += 1;
    }
    evals
}

// ---------------------------------------------------------------------
// Classifying a column
// ---------------------------------------------------------------------

/// The relative accuracy assumed of the `f64` closed form's values and
/// derivatives (module docs, "Accuracy"): 100 × the largest relative error
/// measured against adaptive quadrature (`tests/fields_scalis.rs`).
pub const CLOSED_FORM_REL: f64 = 1e-7;

/// Skeleton cells of the per-primitive ranges of varying-radius segments
/// ([`crate::scalis::bounds::density_bounds`]).
pub const CLASSIFY_CELLS: u32 = 16;

/// What the classifier needs of one segment of a bucket.
#[derive(Clone, Copy, Debug)]
struct Prim {
    /// Constant radius (`r_a = r_b`) and a compact kernel: the density is
    /// log-concave along every line and bounded by the infinite line's.
    constant: bool,
    /// A point of the skeleton line and its unit direction.
    a: [f64; 3],
    u: [f64; 3],
    /// The radius, `σ`, and `m` (degree `2m`).
    tau: f64,
    sigma: f64,
    m: i32,
    /// `(1 + ε_rel)/(N τ R^{2m})`, `c_m` and the length `L`.
    scale: f64,
    cm: f64,
    len: f64,
}

impl Prim {
    fn new(s: &ScalisSegment<f64>) -> Self {
        let sk = s.segment();
        let (sigma, m) = match s.kernel() {
            SegmentKernel::CompactPolynomial { degree, sigma } => (sigma, (degree / 2) as i32),
            SegmentKernel::Cauchy { .. } => (0.0, 0),
        };
        // c_m = ∫₋₁¹ (1 − v²)^m dv = 2^{2m+1} (m!)² / (2m + 1)!
        let mut cm = 2.0;
        let mut i = 1;
        while i <= m {
            cm *= 2.0 * f64::from(i) / (2.0 * f64::from(i) + 1.0);
            i += 1;
        }
        let constant = m > 0 && sk.ra() == sk.rb() && sk.length() > 0.0 && sk.ra() > 0.0;
        Self {
            constant,
            a: sk.a(),
            u: sk.axis(),
            tau: sk.ra().min(sk.rb()),
            sigma,
            m,
            scale: s.inv_normalization() / (sk.ra() * (sigma * sk.ra()).powi(2 * m))
                * (1.0 + CLOSED_FORM_REL),
            cm,
            len: sk.length(),
        }
    }

    /// The ray's distance to the line: `d²(t) = d2 + ee·(t − ts)²`.
    fn geometry(&self, ray: &Ray<f64>, span: f64) -> Geo {
        let nan = Geo {
            ts: f64::NAN,
            d2: f64::NAN,
            ee: f64::NAN,
            slack: f64::NAN,
            x0: f64::NAN,
            dx: f64::NAN,
        };
        if !self.constant {
            return nan;
        }
        let w0 = sub(ray.origin, self.a);
        let c = cross(w0, self.u);
        let e = cross(ray.dir, self.u);
        let ee = dot(e, e);
        let ts = if ee > 0.0 { -dot(c, e) / ee } else { 0.0 };
        let q = [c[0] + ts * e[0], c[1] + ts * e[1], c[2] + ts * e[2]];
        // rounding of the cross products and of the identity: a few ulps
        // of |w0| + |t|·|d| (|u| = 1)
        let slack = 1e-12 * (dot(w0, w0).sqrt() + (span + ts.abs()) * dot(ray.dir, ray.dir).sqrt());
        Geo {
            ts,
            d2: dot(q, q),
            ee,
            slack,
            x0: dot(w0, self.u),
            dx: dot(ray.dir, self.u),
        }
    }

    /// An upper bound of the density on the ray piece `[t0, t1]`
    /// (constant radius `τ`, `R = στ`). With `x` the axial coordinate of
    /// a point from `a` and `d` its distance to the line,
    /// `f = 1/(N τ R^{2m}) ∫ (w² − v²)^m dv` over `v ∈ [−x, L − x] ∩
    /// [−w, w]`, `w² = R² − d²`. The integrand decreases in `d` and `|v|`:
    /// with `d_min` the piece's smallest distance to the line and `δ ≥ 0`
    /// its smallest axial overshoot beyond the segment's ends, `f` is at
    /// most the integral over `|v| ≥ δ` on one side (`δ > 0`) or over the
    /// whole chord, and at most the integral over the centred `|v| ≤ L/2`.
    fn line_bound(&self, g: &Geo, t0: f64, t1: f64) -> f64 {
        let t = g.ts.clamp(t0, t1);
        let dt = t - g.ts;
        let d = ((g.d2 + g.ee * dt * dt).sqrt() - g.slack).max(0.0);
        let r = self.sigma * self.tau;
        let w2 = r * r - d * d;
        if !(w2 > 0.0) {
            return 0.0;
        }
        let w = w2.sqrt();
        let (x0, x1) = (g.x0 + g.dx * t0, g.x0 + g.dx * t1);
        let delta = if x0.min(x1) > self.len {
            x0.min(x1) - self.len
        } else if x0.max(x1) < 0.0 {
            -x0.max(x1)
        } else {
            0.0
        };
        let delta = (delta - g.slack).max(0.0);
        // ∫_0^w (w² − v²)^m dv = c_m w^{2m+1} / 2
        let half = 0.5 * self.cm * w * w2.powi(self.m);
        let mut i = if delta > 0.0 {
            if delta >= w {
                0.0
            } else {
                self.power_integral(w, delta, w)
            }
        } else {
            2.0 * half
        };
        if 0.5 * self.len < w {
            i = i.min(2.0 * self.power_integral(w, 0.0, 0.5 * self.len));
        }
        // the alternating sum cancels: an absolute slack of its scale
        let i = i + half * 1e-12;
        let v = self.scale * i;
        if v.is_nan() { f64::INFINITY } else { v }
    }

    /// `∫_a^b (w² − v²)^m dv` for `0 ≤ a ≤ b ≤ w` (binomial expansion).
    fn power_integral(&self, w: f64, a: f64, b: f64) -> f64 {
        let w2 = w * w;
        let (a2, b2) = (a * a, b * b);
        // Σ_k C(m,k) (−1)^k w^{2(m−k)} (b^{2k+1} − a^{2k+1})/(2k+1)
        // Horner in w²: Σ_k C(m,k) (−1)^k w^{2(m−k)} (b^{2k+1} − a^{2k+1})/(2k+1)
        let mut pows = [0.0f64; 9];
        let (mut pa, mut pb) = (a, b);
        let mut k = 0;
        while k <= self.m as usize && k < pows.len() {
            pows[k] = pb - pa;
            pa *= a2;
            pb *= b2;
            k += 1;
        }
        let mut sum = 0.0;
        let mut c = 1.0; // C(m, k)
        let mut wk = 1.0; // w^{2k}, from k = m down
        let mut k = self.m;
        // C(m, m) = 1; walk k downwards with C(m, k−1) = C(m, k)·k/(m − k + 1)
        while k >= 0 {
            let term = c * wk * pows[k as usize] / f64::from(2 * k + 1);
            sum += if k % 2 == 0 { term } else { -term };
            c = c * f64::from(k) / f64::from(self.m - k + 1);
            wk *= w2;
            k -= 1;
        }
        sum.max(0.0)
    }

    /// Where the ray's distance to the line equals the radius (the
    /// surface of an isolated long segment), or NaN.
    fn model_roots(&self, g: &Geo) -> (f64, f64) {
        let r = self.tau * self.tau - g.d2;
        if !(r > 0.0 && g.ee > 0.0) {
            return (f64::NAN, f64::NAN);
        }
        let hw = (r / g.ee).sqrt();
        (g.ts - hw, g.ts + hw)
    }
}

/// The ray's distance to a segment's line (see [`Prim::geometry`]); NaN
/// for varying radii.
#[derive(Clone, Copy, Debug)]
struct Geo {
    ts: f64,
    d2: f64,
    ee: f64,
    slack: f64,
    /// The axial coordinate from `a`: `x(t) = x0 + dx·t`.
    x0: f64,
    dx: f64,
}

#[inline]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The supremum on `[a, b]` of a log-concave `f ≥ 0` with value `fa` and
/// derivative `da` at `a`, `fb` and `db` at `b` (a zero value or a NaN
/// derivative carries no information): below each tangent of `ln f`
/// (module docs). `tau` scales the derivative's accuracy margin.
fn log_concave_sup(a: f64, fa: f64, da: f64, b: f64, fb: f64, db: f64, tau: f64) -> f64 {
    let r = CLOSED_FORM_REL;
    let len = b - a;
    // ln f(t) ≤ ln f(x) + (f'(x)/f(x))·(t − x), with the slopes widened
    // outward (larger to the right of a, smaller to the left of b)
    let ta = (fa > 0.0 && !da.is_nan())
        .then(|| (fa * (1.0 + r), (da + 2.0 * r * (da.abs() + fa / tau)) / fa));
    let tb = (fb > 0.0 && !db.is_nan())
        .then(|| (fb * (1.0 + r), (db - 2.0 * r * (db.abs() + fb / tau)) / fb));
    let sup_a = ta.map_or(f64::INFINITY, |(f, s)| {
        if s <= 0.0 { f } else { f * (s * len).exp() }
    });
    let sup_b = tb.map_or(f64::INFINITY, |(f, s)| {
        if s >= 0.0 { f } else { f * (-s * len).exp() }
    });
    let mut v = sup_a.min(sup_b);
    if let (Some((fa, al)), Some((fb, be))) = (ta, tb) {
        if al > 0.0 && be < 0.0 {
            let t = ((fb.ln() - fa.ln() + al * a - be * b) / (al - be)).clamp(a, b);
            let at = (fa * (al * (t - a)).exp()).min(fb * (be * (t - b)).exp());
            v = v.min(at);
        }
    }
    let v = v * (1.0 + r);
    if v.is_nan() { f64::INFINITY } else { v }
}

/// The last secant split of a bracket made its left end.
const SECANT_LEFT: u8 = 1;
/// The last secant split of a bracket made its right end.
const SECANT_RIGHT: u8 = 2;
/// The secant moved the same end twice: bisect next.
const SECANT_STUCK: u8 = 3;

/// An evaluated point of a column.
#[derive(Clone, Copy, Debug)]
struct Pt {
    t: f64,
    /// The first voxel centre `≥ t` and the first `> t`.
    kge: usize,
    kgt: usize,
    /// `Σ f_i`.
    f: f64,
    /// Whether the derivatives `f_i'` are known at this point.
    deriv: bool,
}

/// Reused buffers of the classifier.
#[derive(Default)]
struct Scratch {
    /// Evaluated points.
    pts: Vec<Pt>,
    /// Per point and per hit of the region: `(f_i, f_i')` (`f_i'` NaN until
    /// computed).
    vals: Vec<(f64, f64)>,
    /// Per hit of the region: the ray's distance to its line.
    geo: Vec<Geo>,
    /// Per hit of the region: `f_i` is non-decreasing up to `.0` and
    /// non-increasing from `.1` (log-concavity: certified by two values
    /// or a derivative's sign).
    mono: Vec<(f64, f64)>,
    /// Per hit of the region: the line model's entering and leaving roots.
    model: Vec<(f64, f64)>,
    /// Intervals put aside until the rest of the region has been examined
    /// (more monotony certificates by then).
    deferred: Vec<(usize, usize, u8)>,
    /// Intervals to examine, as point indices, with the secant's state
    /// ([`SECANT_LEFT`], [`SECANT_RIGHT`], [`SECANT_STUCK`] or 0).
    stack: Vec<(usize, usize, u8)>,
}

/// One column's context for the classifier.
struct ColumnCtx<'a, S> {
    sk: &'a ScalisSkeleton<f64, S>,
    prims: &'a [Prim],
    ray: &'a Ray<f64>,
}

impl<S: AsRef<[ScalisSegment<f64>]>> ColumnCtx<'_, S> {
    /// The range of `Σ f_i` on `[pa, pb]` over the hits `rh` (module docs).
    ///
    /// For constant radii the cheap lower sum comes first and the upper
    /// sum stops as soon as it reaches `iso` (the interval is then
    /// undecided either way: the returned `hi` is only a partial sum).
    fn range(
        &self,
        rh: &[crate::scalis::PrimitiveHit<f64>],
        sc: &Scratch,
        ia: usize,
        ib: usize,
        iso: f64,
    ) -> (f64, f64) {
        let nh = rh.len();
        let (ta, tb) = (sc.pts[ia].t, sc.pts[ib].t);
        if rh.iter().all(|h| self.prims[h.index as usize].constant) {
            let mut lo = 0.0;
            for (q, h) in rh.iter().enumerate() {
                if h.entry <= tb && h.exit >= ta {
                    lo += sc.vals[ia * nh + q].0.min(sc.vals[ib * nh + q].0);
                }
            }
            let lo = lo * (1.0 - CLOSED_FORM_REL);
            if lo > iso {
                return (lo, f64::INFINITY);
            }
            let mut hi = 0.0;
            for (q, h) in rh.iter().enumerate() {
                if h.entry > tb || h.exit < ta {
                    continue;
                }
                let p = &self.prims[h.index as usize];
                let (fa, da) = sc.vals[ia * nh + q];
                let (fb, db) = sc.vals[ib * nh + q];
                hi += if tb <= sc.mono[q].0 {
                    fb * (1.0 + CLOSED_FORM_REL)
                } else if ta >= sc.mono[q].1 {
                    fa * (1.0 + CLOSED_FORM_REL)
                } else {
                    let mut up = f64::INFINITY;
                    if !da.is_nan() || !db.is_nan() {
                        up = log_concave_sup(ta, fa, da, tb, fb, db, p.tau);
                    }
                    if up > fa.max(fb) * (1.0 + 4.0 * CLOSED_FORM_REL) {
                        up = up.min(p.line_bound(&sc.geo[q], ta.max(h.entry), tb.min(h.exit)));
                    }
                    up
                };
                if !(hi < iso) {
                    break;
                }
            }
            return (lo, hi);
        }
        let (mut lo, mut hi) = (0.0, 0.0);
        for (q, h) in rh.iter().enumerate() {
            if h.entry > tb || h.exit < ta {
                continue;
            }
            let p = &self.prims[h.index as usize];
            let (fa, da) = sc.vals[ia * nh + q];
            let (fb, db) = sc.vals[ib * nh + q];
            let (u, v) = (ta.max(h.entry), tb.min(h.exit));
            let (l, up) = if p.constant && tb <= sc.mono[q].0 {
                (fa * (1.0 - CLOSED_FORM_REL), fb * (1.0 + CLOSED_FORM_REL))
            } else if p.constant && ta >= sc.mono[q].1 {
                (fb * (1.0 - CLOSED_FORM_REL), fa * (1.0 + CLOSED_FORM_REL))
            } else if p.constant {
                let mut up = p.line_bound(&sc.geo[q], u, v);
                if !da.is_nan() || !db.is_nan() {
                    up = up.min(log_concave_sup(ta, fa, da, tb, fb, db, p.tau));
                }
                (fa.min(fb) * (1.0 - CLOSED_FORM_REL), up)
            } else {
                let r = crate::scalis::bounds::density_bounds(
                    &self.sk.segments()[h.index as usize],
                    self.ray,
                    u,
                    v,
                    CLASSIFY_CELLS,
                );
                let partial = u > ta || v < tb;
                (if partial { 0.0 } else { r.lo() }, r.hi())
            };
            lo += l;
            hi += up;
        }
        (lo, hi)
    }

    /// Evaluates `Σ f_i` at `t` (the hits whose support contains `t`,
    /// summed in hit order as the sampling does), with the derivatives
    /// when `deriv`; appends the per-hit values to `vals`.
    fn eval(
        &self,
        rh: &[crate::scalis::PrimitiveHit<f64>],
        t: f64,
        deriv: bool,
        vals: &mut Vec<(f64, f64)>,
        stats: &mut RayStats,
    ) -> f64 {
        let mut f = 0.0;
        let segs = self.sk.segments();
        if deriv {
            let p = self.ray.at::<Jet<f64>>(t, t);
            for h in rh {
                let v = if h.entry <= t && h.exit >= t {
                    stats.field_evals += 1;
                    let j: Jet<f64> = segs[h.index as usize].density(p);
                    (j.v, j.d1)
                } else {
                    (0.0, 0.0)
                };
                f += v.0;
                vals.push(v);
            }
        } else {
            let p = self.ray.at::<f64>(t, t);
            for h in rh {
                let v = if h.entry <= t && h.exit >= t {
                    stats.field_evals += 1;
                    (segs[h.index as usize].density(p), f64::NAN)
                } else {
                    (0.0, 0.0)
                };
                f += v.0;
                vals.push(v);
            }
        }
        f
    }
}

/// Classifies the voxel centres of one column (module docs, "Classifying a
/// column"); returns the cost (`steps`: intervals examined,
/// `field_evals`: point evaluations of a primitive, `bound_evals`: interval
/// ranges).
#[allow(clippy::too_many_lines)]
fn classify<S: AsRef<[ScalisSegment<f64>]>>(
    cx: &ColumnCtx<'_, S>,
    hits: &[crate::scalis::PrimitiveHit<f64>],
    col: &mut Column<'_>,
    sc: &mut Scratch,
) -> RayStats {
    let mut stats = RayStats::default();
    let iso = cx.sk.iso();
    crate::scalis::for_each_region(hits, |r0, r1, i, j| {
        let rh = &hits[i..j];
        let nh = rh.len();
        let end = |t: f64| {
            let kge = col.first_at_or_after(t);
            let kgt = if kge < col.slices && col.centre(kge) == t {
                kge + 1
            } else {
                kge
            };
            Pt {
                t,
                kge,
                kgt,
                f: 0.0,
                deriv: true,
            }
        };
        let (p0, p1) = (end(r0), end(r1));
        if p0.kge >= p1.kgt {
            return true; // no voxel centre in the region
        }
        sc.pts.clear();
        sc.vals.clear();
        sc.stack.clear();
        sc.geo.clear();
        sc.mono.clear();
        sc.model.clear();
        sc.deferred.clear();
        sc.mono
            .extend(core::iter::repeat_n((f64::NEG_INFINITY, f64::INFINITY), nh));
        // the region's ends: outside every support, f = f' = 0 exactly
        for p in [p0, p1] {
            sc.pts.push(p);
            sc.vals.extend(core::iter::repeat_n((0.0, 0.0), nh));
        }
        sc.geo.extend(
            rh.iter()
                .map(|h| cx.prims[h.index as usize].geometry(cx.ray, col.len)),
        );
        sc.model.extend(
            rh.iter()
                .zip(&sc.geo)
                .map(|(h, g)| cx.prims[h.index as usize].model_roots(g)),
        );
        sc.stack.push((0, 1, 0));
        let mut second_pass = false;
        loop {
            let Some((ia, ib, secant)) = sc.stack.pop() else {
                if second_pass || sc.deferred.is_empty() {
                    break;
                }
                second_pass = true;
                sc.stack.append(&mut sc.deferred);
                continue;
            };
            // the centres strictly inside (ta, tb)
            let (ka, kb) = (sc.pts[ia].kgt, sc.pts[ib].kge);
            if ka >= kb {
                continue; // no centre to decide inside
            }
            stats.steps += 1;
            stats.bound_evals += 1;
            let (ta, tb) = (sc.pts[ia].t, sc.pts[ib].t);
            let (mut lo, mut hi) = cx.range(rh, sc, ia, ib, iso);
            // the line model's roots in (ta, tb) that can still be crossed
            // there (an entering root after an outside `ta`, a leaving root
            // before an outside `tb`): the split guesses
            let (fa, fb) = (sc.pts[ia].f, sc.pts[ib].f);
            let (out_a, out_b) = (!(fa > iso), !(fb > iso));
            let mut model = f64::NAN;
            for (q, h) in rh.iter().enumerate() {
                if h.entry > tb || h.exit < ta {
                    continue;
                }
                let (u, v) = sc.model[q];
                for (m, ok) in [(u, out_a), (v, out_b)] {
                    if ok && m > ta && m < tb && !(m >= model) {
                        model = m;
                    }
                }
            }
            let bracketed = out_a != out_b;
            let decided = hi < iso || lo > iso;
            // probably root-free: same sign at both ends, no model root
            let both_jets = sc.pts[ia].deriv && sc.pts[ib].deriv;
            let probably_free = !(decided || bracketed || both_jets) && model.is_nan();
            if probably_free && !second_pass {
                // probably root-free: look again once the rest of the
                // region has added monotony certificates
                sc.deferred.push((ia, ib, secant));
                continue;
            }
            if probably_free {
                // the tangents of the derivatives may prove it
                for ip in [ia, ib] {
                    if !sc.pts[ip].deriv {
                        let t = sc.pts[ip].t;
                        let base = sc.vals.len();
                        let _ = cx.eval(rh, t, true, &mut sc.vals, &mut stats);
                        sc.vals.copy_within(base..base + nh, ip * nh);
                        sc.vals.truncate(base);
                        sc.pts[ip].deriv = true;
                        for (q, h) in rh.iter().enumerate() {
                            let (f, d) = sc.vals[ip * nh + q];
                            let margin = 2.0
                                * CLOSED_FORM_REL
                                * (d.abs() + f / cx.prims[h.index as usize].tau);
                            if f > 0.0 && d > margin {
                                sc.mono[q].0 = sc.mono[q].0.max(t);
                            } else if f > 0.0 && d < -margin {
                                sc.mono[q].1 = sc.mono[q].1.min(t);
                            }
                        }
                    }
                }
                stats.bound_evals += 1;
                (lo, hi) = cx.range(rh, sc, ia, ib, iso);
            }
            if hi < iso {
                continue; // outside on [ta, tb]
            }
            if lo > iso {
                for k in ka..kb {
                    col.set(k);
                }
                continue;
            }
            // Split at the centre nearest that model root, else at the
            // secant's root of the normalized field g(Σf) − 1 (≈ D² − 1 of
            // the nearest line: nearly quadratic along the ray, thesis
            // §1.2) on a bracketed interval, else at the middle.
            let by_secant = model.is_nan() && bracketed && secant != SECANT_STUCK;
            let guess = if !model.is_nan() {
                model
            } else if by_secant {
                let ga = cx.sk.segments()[0].g(fa) - 1.0;
                let gb = cx.sk.segments()[0].g(fb) - 1.0;
                let g = ta + (tb - ta) * ga / (ga - gb);
                if g > ta && g < tb { g } else { 0.5 * (ta + tb) }
            } else {
                0.5 * (ta + tb)
            };
            let g = (guess / col.len * col.slices as f64 - 0.5).round();
            let k = if g > ka as f64 {
                (g as usize).min(kb - 1)
            } else {
                ka
            };
            let t = col.centre(k);
            let f = cx.eval(rh, t, false, &mut sc.vals, &mut stats);
            if f > iso {
                col.set(k);
            }
            let ic = sc.pts.len();
            sc.pts.push(Pt {
                t,
                kge: k,
                kgt: k + 1,
                f,
                deriv: false,
            });
            // monotony certificates from the new pairs of values
            for q in 0..nh {
                let (fa_, fc, fb_) = (
                    sc.vals[ia * nh + q].0,
                    sc.vals[ic * nh + q].0,
                    sc.vals[ib * nh + q].0,
                );
                for (x1, f1, x2, f2) in [(ta, fa_, t, fc), (t, fc, tb, fb_)] {
                    if f1 > 0.0 && f2 > 0.0 {
                        if f1 > f2 * (1.0 + 4.0 * CLOSED_FORM_REL) {
                            sc.mono[q].1 = sc.mono[q].1.min(x2);
                        } else if f2 > f1 * (1.0 + 4.0 * CLOSED_FORM_REL) {
                            sc.mono[q].0 = sc.mono[q].0.max(x1);
                        }
                    }
                }
            }
            // a secant that moves the same end twice in a row is stuck
            // (regula falsi): the next split of that bracket is a bisection
            let (mut sl, mut sr) = (0, 0);
            if by_secant {
                let left_bracketed = out_a == (f > iso);
                sl = if left_bracketed && secant == SECANT_RIGHT {
                    SECANT_STUCK
                } else {
                    SECANT_RIGHT
                };
                sr = if !left_bracketed && secant == SECANT_LEFT {
                    SECANT_STUCK
                } else {
                    SECANT_LEFT
                };
            }
            sc.stack.push((ic, ib, sr));
            sc.stack.push((ia, ic, sl));
        }
        true
    });
    stats
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{Scene, SceneField};

    /// Checks `stack` against the field's sign at every voxel centre and
    /// against `sampled`; returns (inside voxels, voxels that differ).
    fn compare<S: AsRef<[ScalisSegment<f64>]>>(
        sk: &ScalisSkeleton<f64, S>,
        b: [[f64; 3]; 2],
        stack: &SliceStack,
        sampled: &SliceStack,
    ) -> (usize, usize) {
        let s = stack.settings();
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
        (inside, differ)
    }

    #[test]
    fn voxels_match_the_field_sign_except_next_to_the_surface() {
        // varying radii: the classifier's cell sums, and the traced path
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
        let sampled = sample_scalis(sk, b, s, &params).unwrap();
        for stack in [
            slice_scalis(sk, b, s, &params).unwrap(),
            slice_scalis_traced(sk, b, s, &params).unwrap(),
        ] {
            let (inside, differ) = compare(sk, b, &stack, &sampled);
            assert!(inside > 50, "{inside}");
            assert!(differ <= 4, "{differ}");
        }
        let stack = slice_scalis(sk, b, s, &params).unwrap();
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
    fn foam_classifier_equals_sampling_with_few_evaluations() {
        // constant radii: log-concave ranges and line bounds
        let scene = Scene::<f64>::build("scalis-foam", 2023).unwrap();
        let SceneField::Scalis(w) = scene.field() else {
            panic!("not a SCALIS scene")
        };
        let sk = w.field();
        let s = SliceSettings {
            width: 14,
            height: 12,
            slices: 512,
        };
        let b = scene.bounds();
        let params = Params::new();
        let stack = slice_scalis(sk, b, s, &params).unwrap();
        let sampled = sample_scalis(sk, b, s, &params).unwrap();
        let (inside, differ) = compare(sk, b, &stack, &sampled);
        assert!(inside > 1000, "{inside}");
        assert_eq!(differ, 0);
        // the point of it: far fewer evaluations than one per voxel centre
        assert!(
            u64::from(stack.stats.field_evals) * 3 < u64::from(sampled.stats.field_evals),
            "{:?} vs {:?}",
            stack.stats,
            sampled.stats
        );
    }

    #[test]
    fn line_bound_and_log_concave_sup_bound_the_density() {
        let scene = Scene::<f64>::build("scalis-foam", 2023).unwrap();
        let SceneField::Scalis(w) = scene.field() else {
            panic!("not a SCALIS scene")
        };
        let segs = w.field().segments();
        let mut checked = 0;
        for (i, seg) in segs.iter().enumerate().step_by(37) {
            let p = Prim::new(seg);
            assert!(p.constant);
            let a = seg.segment().a();
            let u = seg.segment().axis();
            // rays near the segment, some beyond its ends
            for (j, off) in [(0.3, 0.5), (-0.2, 0.9), (1.1, 0.2), (0.5, 1.2)]
                .iter()
                .enumerate()
            {
                let l = seg.segment().length();
                let c = [0, 1, 2].map(|k| a[k] + u[k] * l * off.0);
                let dir = [0.0, 0.0, 1.0];
                let r = p.tau * p.sigma * off.1 * (j as f64 * 0.3 + 0.2);
                let o = [c[0] + r, c[1] - 0.5 * r, c[2] - 1.0];
                let ray = Ray::new(o, dir);
                let g = p.geometry(&ray, 2.0);
                for (t0, t1) in [(0.0, 2.0), (0.9, 1.0), (0.97, 1.03), (1.0, 1.1)] {
                    let bound = p.line_bound(&g, t0, t1);
                    let ts: Vec<f64> = (0..=200)
                        .map(|n| t0 + (t1 - t0) * f64::from(n) / 200.0)
                        .collect();
                    let fs: Vec<f64> = ts
                        .iter()
                        .map(|&t| seg.density(ray.at::<f64>(t, t)))
                        .collect();
                    let fmax = fs.iter().copied().fold(0.0, f64::max);
                    assert!(
                        fmax <= bound,
                        "segment {i}: {fmax} > {bound} on [{t0}, {t1}]"
                    );
                    // the tangent bound from the end-points' jets
                    let jet = |t: f64| -> (f64, f64) {
                        let v: Jet<f64> = seg.density(ray.at::<Jet<f64>>(t, t));
                        (v.v, v.d1)
                    };
                    let ((fa, da), (fb, db)) = (jet(t0), jet(t1));
                    let sup = log_concave_sup(t0, fa, da, t1, fb, db, p.tau);
                    assert!(fmax <= sup, "segment {i}: {fmax} > {sup} on [{t0}, {t1}]");
                    // and the unimodal lower bound
                    let fmin = fs.iter().copied().fold(f64::INFINITY, f64::min);
                    assert!(
                        fmin >= fa.min(fb) * (1.0 - 1e-9),
                        "{fmin} < min({fa}, {fb})"
                    );
                    checked += usize::from(fmax > 0.0);
                }
            }
        }
        assert!(checked > 20, "{checked}");
    }

    #[test]
    fn power_integral_matches_quadrature() {
        let scene = Scene::<f64>::build("scalis-foam", 2023).unwrap();
        let SceneField::Scalis(w) = scene.field() else {
            panic!("not a SCALIS scene")
        };
        let p = Prim::new(&w.field().segments()[0]);
        let w = 0.7;
        for (a, b) in [(0.0, 0.7), (0.2, 0.7), (0.0, 0.3), (0.65, 0.7)] {
            let n = 20_000;
            let h = (b - a) / f64::from(n);
            let mut q = 0.0;
            for i in 0..n {
                let v: f64 = a + (f64::from(i) + 0.5) * h;
                q += (w * w - v * v).powi(p.m) * h;
            }
            let got = p.power_integral(w, a, b);
            assert!(
                (got - q).abs() <= 1e-6 * q.max(1e-12),
                "[{a}, {b}]: {got} vs {q}"
            );
        }
        // the half chord in closed form: c_m w^{2m+1} / 2
        let half = 0.5 * p.cm * w * (w * w).powi(p.m);
        assert!((p.power_integral(w, 0.0, w) - half).abs() < 1e-14);
    }

    #[test]
    fn centres_are_found_exactly() {
        let mut buf = vec![0u8; 7];
        let col = Column {
            slices: 7,
            len: 1.3,
            buf: &mut buf,
            stride: 1,
            set: [7, 0],
        };
        for k in 0..7 {
            let c = col.centre(k);
            assert_eq!(col.first_at_or_after(c), k);
            assert_eq!(col.first_at_or_after(c + 1e-12), k + 1);
            assert_eq!(col.first_at_or_after(c - 1e-12), k);
        }
        assert_eq!(col.first_at_or_after(-1.0), 0);
        assert_eq!(col.first_at_or_after(2.0), 7);
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
