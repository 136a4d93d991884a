//! Synchronized ray processing with pruned blobtree views
//! (synchronized-tracing paper §6.2, Alg. 3): the per-tile loop, `no_std`
//! and allocation-free (the caller provides every buffer), so the GPU can
//! run the same code with one workgroup per tile.
//!
//! For one tile of the [A-buffer](crate::tiles) (its entries sorted by
//! entry depth) a [`RangeCursor`] cuts the tile frustum into camera-depth
//! ranges `[z_b, z_e]` with a fixed set of active primitives 𝒜
//! (`fetchPrimitives` of Alg. 3, eqs. 21–22):
//!
//! 1. drop from 𝒜 the entries with `z_exit ≤ z_b`; if 𝒜 is empty, skip the
//!    empty space to the next entry's `z_entry`;
//! 2. fetch every entry with `z_entry ≤ z_b` (they overlap the range
//!    start: mandatory);
//! 3. fetch more while `z_entry < max z_exit` of 𝒜 (no empty space),
//!    `|𝒜| < M_overlap` and fewer than `max_fetch` optional fetches (the
//!    paper's heuristic, 8 by default);
//! 4. `z_e = min(z_entry of the next unfetched entry, max z_exit of 𝒜)`
//!    (eq. 22).
//!
//! Every entry overlapping `[z_b, z_e]` is then in 𝒜: unfetched entries
//! start at or after `z_e`, dropped ones end at or before `z_b`, and the
//! A-buffer widens its depths beyond the rounding of the depth ↔ ray
//! parameter conversions, so such an entry's ABV does not reach the
//! range. Hence on every point of a pixel ray in the range, every
//! primitive whose ABV contains the point is active, and the pruned field
//! `f_𝒜` has the sign of the full field there (local equivalence,
//! [`boundtrace_fields::blobtree`] module docs). Outside every ABV the
//! field is positive (no surface), so depths without entries are skipped.
//!
//! Per range, the [`PrunedView`](boundtrace_fields::blobtree::PrunedView) is built **once** (sparse traversal of
//! the active primitives, sorted by post-order index), and every unfinished
//! ray of the tile traces its part `[z_b/c, z_e/c] ∩ span` (`c` from
//! [`depth_factor`]) with **any** [`Method`] through
//! [`trace`] on the pruned field. Consecutive ranges
//! share the exact boundary value, so nothing is left untraced between
//! them; a root registered at a shared boundary is kept once.
//!
//! # Overflows (counted, never wrong output)
//!
//! - More than `M_overlap` entries overlap the range start: the range is
//!   traced with the **full tree** up to the end of every entry fetched so
//!   far (extended while further entries start inside it), then the set is
//!   rebuilt from scratch ([`SyncCounters::overflow_ranges`]).
//! - The view refuses the set (its evaluation stack or node capacity would
//!   overflow): the range is traced with the full tree
//!   ([`SyncCounters::view_failures`]).
//! - `D_cache` is full: the view reads the remaining nodes' parameters
//!   from the tree (paper §6.2; [`SyncCounters::uncached_nodes`]).

use crate::camera::{Camera, ray_box_span};
use crate::method::{Method, Mode, Params};
use crate::tiles::{TileEntry, depth_factor};
use crate::trace::{RayStats, Root, Side, Status, Trace, normal, trace};
use boundtrace_fields::blobtree::{BlobtreeRef, DefaultPrunedView, M_OVERLAP};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, Ray};
use core::fmt;

/// The default number of optional fetches per range (paper §6.2: "less
/// than 8 primitive fetches").
pub const DEFAULT_MAX_FETCH: u32 = 8;

/// Settings of synchronized ray processing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct SyncConfig {
    /// `M_overlap`: the largest active set (`1 ..= M_OVERLAP`, default
    /// [`M_OVERLAP`] = 128, paper §7).
    pub m_overlap: u32,
    /// Optional fetches per range beyond the mandatory ones (default
    /// [`DEFAULT_MAX_FETCH`]).
    pub max_fetch: u32,
}

/// An invalid [`SyncConfig`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidSyncConfig;

impl fmt::Display for InvalidSyncConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "synchronized tracing: m_overlap must be in 1..={M_OVERLAP}"
        )
    }
}

impl core::error::Error for InvalidSyncConfig {}

impl Default for SyncConfig {
    fn default() -> Self {
        Self {
            m_overlap: M_OVERLAP as u32,
            max_fetch: DEFAULT_MAX_FETCH,
        }
    }
}

impl SyncConfig {
    /// Checks `1 ≤ m_overlap ≤ M_OVERLAP` (a pruned view holds at most
    /// `2·M_OVERLAP − 1` nodes).
    ///
    /// # Errors
    /// [`InvalidSyncConfig`] otherwise.
    pub fn validate(&self) -> Result<(), InvalidSyncConfig> {
        if self.m_overlap == 0 || self.m_overlap as usize > M_OVERLAP {
            return Err(InvalidSyncConfig);
        }
        Ok(())
    }

    /// With `M_overlap`.
    ///
    /// # Errors
    /// [`InvalidSyncConfig`] unless `1 ≤ m_overlap ≤ M_OVERLAP`.
    pub fn with_m_overlap(self, m_overlap: u32) -> Result<Self, InvalidSyncConfig> {
        let s = Self { m_overlap, ..self };
        s.validate().map(|()| s)
    }
}

/// What synchronized processing did (summed over tiles with `+`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct SyncCounters {
    /// Depth ranges processed.
    pub ranges: u64,
    /// Pruned views built (one per range that did not overflow).
    pub views: u64,
    /// Views whose root was missing (no surface in the range: skipped).
    pub empty_views: u64,
    /// Ranges traced with the full tree because more than `M_overlap`
    /// entries overlapped the range start.
    pub overflow_ranges: u64,
    /// Ranges traced with the full tree because the view refused the
    /// active set (evaluation stack or node capacity).
    pub view_failures: u64,
    /// View nodes whose parameters did not fit in `D_cache`.
    pub uncached_nodes: u64,
    /// Nodes over all built views.
    pub view_nodes: u64,
    /// The largest active set.
    pub max_active: u64,
    /// Ray subintervals traced (one ray on one range).
    pub ray_ranges: u64,
    /// Node evaluations: `(field evals + bound evals) × nodes` of the field
    /// each subinterval was traced with (the cost measure that follows the
    /// local overlap, paper Fig. 1).
    pub node_evals: u64,
}

impl core::ops::Add for SyncCounters {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            ranges: self.ranges + o.ranges,
            views: self.views + o.views,
            empty_views: self.empty_views + o.empty_views,
            overflow_ranges: self.overflow_ranges + o.overflow_ranges,
            view_failures: self.view_failures + o.view_failures,
            uncached_nodes: self.uncached_nodes + o.uncached_nodes,
            view_nodes: self.view_nodes + o.view_nodes,
            max_active: self.max_active.max(o.max_active),
            ray_ranges: self.ray_ranges + o.ray_ranges,
            node_evals: self.node_evals.saturating_add(o.node_evals),
        }
    }
}

/// One depth range of a tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthRange<T> {
    /// `[z_b, z_e]` in camera depth.
    pub z: [T; 2],
    /// Traced with the full tree (`M_overlap` overflow); the active
    /// buffer is then not meaningful.
    pub full_tree: bool,
    /// The number of active entries (the first `active` slots of the
    /// active buffer, sorted by post-order index).
    pub active: usize,
}

/// The fetch heuristic of Alg. 3 over one tile's entries (see the
/// [module docs](self)); the active set lives in a caller-provided buffer
/// of entry indices whose length is `M_overlap`.
#[derive(Clone, Debug)]
pub struct RangeCursor<'e, T> {
    entries: &'e [TileEntry<T>],
    next: usize,
    z0: T,
    len: usize,
}

impl<'e, T: Real> RangeCursor<'e, T> {
    /// A cursor at the front of `entries` (sorted by `z_entry`, depths not
    /// NaN, as [`ABuffer`](crate::tiles::ABuffer) stores them).
    pub fn new(entries: &'e [TileEntry<T>]) -> Self {
        Self {
            entries,
            next: 0,
            z0: T::NEG_INFINITY,
            len: 0,
        }
    }

    /// The next range, `None` after the last. `active` holds the active
    /// set between calls (entry indices sorted by post-order index; do not
    /// modify it); its length is `M_overlap` (at least 1).
    pub fn next_range(&mut self, active: &mut [u32], max_fetch: u32) -> Option<DepthRange<T>> {
        let e = self.entries;
        let n = e.len();
        if active.is_empty() {
            return None;
        }
        // 1. drop the entries that end before the range.
        let mut w = 0;
        for r in 0..self.len {
            let i = active[r];
            if e[i as usize].z_exit > self.z0 {
                active[w] = i;
                w += 1;
            }
        }
        self.len = w;
        if self.len == 0 {
            if self.next >= n {
                return None;
            }
            if e[self.next].z_entry > self.z0 {
                self.z0 = e[self.next].z_entry;
            }
        }
        // 2. mandatory fetches.
        while self.next < n && e[self.next].z_entry <= self.z0 {
            if self.len == active.len() {
                return Some(self.overflow());
            }
            self.insert(active, self.next);
            self.next += 1;
        }
        let mut max_exit = T::NEG_INFINITY;
        for &i in &active[..self.len] {
            max_exit = max_exit.max(e[i as usize].z_exit);
        }
        // 3. optional fetches.
        let mut fetched = 0;
        while fetched < max_fetch
            && self.len < active.len()
            && self.next < n
            && e[self.next].z_entry < max_exit
        {
            max_exit = max_exit.max(e[self.next].z_exit);
            self.insert(active, self.next);
            self.next += 1;
            fetched += 1;
        }
        // 4. the range end (eq. 22).
        let z1 = match e.get(self.next) {
            Some(x) => x.z_entry.min(max_exit),
            None => max_exit,
        };
        let r = DepthRange {
            z: [self.z0, z1],
            full_tree: false,
            active: self.len,
        };
        self.z0 = z1;
        Some(r)
    }

    /// Inserts entry `i`, keeping the active set sorted by node index.
    fn insert(&mut self, active: &mut [u32], i: usize) {
        let node = self.entries[i].node;
        let mut j = self.len;
        while j > 0 && self.entries[active[j - 1] as usize].node > node {
            active[j] = active[j - 1];
            j -= 1;
        }
        active[j] = i as u32;
        self.len += 1;
    }

    /// A full-tree range after an `M_overlap` overflow: up to the end of
    /// every entry fetched so far, extended while unfetched entries start
    /// inside it; the active set is then empty.
    fn overflow(&mut self) -> DepthRange<T> {
        let e = self.entries;
        let mut z1 = self.z0;
        for x in &e[..self.next] {
            z1 = z1.max(x.z_exit);
        }
        while self.next < e.len() && e[self.next].z_entry < z1 {
            z1 = z1.max(e[self.next].z_exit);
            self.next += 1;
        }
        self.len = 0;
        let r = DepthRange {
            z: [self.z0, z1],
            full_tree: true,
            active: 0,
        };
        self.z0 = z1;
        r
    }
}

/// One pixel ray of a tile and its progress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileRay<T> {
    /// The ray.
    pub ray: Ray<T>,
    /// Its span in the scene box; `None`: misses it (not traced).
    pub span: Option<[T; 2]>,
    /// `c = d·forward` ([`depth_factor`]): `t = z / c`.
    pub c: T,
    /// The trace record so far (roots in the caller's buffer).
    pub trace: Trace<T>,
    /// Finished (opaque hit, span exhausted, or a stopping status).
    pub done: bool,
}

impl<T: Real> TileRay<T> {
    /// The ray through pixel `pixel = [x, y]` of an image of
    /// `size = [width, height]` ([`Camera::ray`]), with its span in
    /// `bounds` ([`ray_box_span`]).
    pub fn new(camera: &Camera<T>, pixel: [u32; 2], size: [u32; 2], bounds: &[[T; 3]; 2]) -> Self {
        let ray = camera.ray(pixel[0], pixel[1], size[0], size[1]);
        let span = ray_box_span(&ray, bounds);
        Self {
            ray,
            span,
            c: depth_factor(camera, &ray),
            trace: Trace {
                roots: 0,
                status: Status::Finished,
                t_reached: span.map_or(T::ZERO, |s| s[0]),
                stats: RayStats::default(),
            },
            done: span.is_none(),
        }
    }
}

/// What to trace for one tile.
#[derive(Clone, Copy, Debug)]
pub struct TileJob<'a, T> {
    /// The full blobtree.
    pub tree: BlobtreeRef<'a>,
    /// The tile's A-buffer entries, sorted by entry depth.
    pub entries: &'a [TileEntry<T>],
    /// The ray-processing method.
    pub method: Method,
    /// Opaque or transparent.
    pub mode: Mode,
    /// Tracing parameters (`max_steps` is shared by a ray's ranges).
    pub params: Params<T>,
    /// Synchronization settings.
    pub config: SyncConfig,
}

/// The caller's buffers for one tile (on the GPU: registers and shared
/// memory).
#[derive(Debug)]
pub struct TileBuffers<'b, T> {
    /// The tile's rays.
    pub rays: &'b mut [TileRay<T>],
    /// Roots, `roots_per_ray` slots per ray (ray `k` at
    /// `k·roots_per_ray`).
    pub roots: &'b mut [Root<T>],
    /// The normal at each root (same layout as `roots`).
    pub normals: &'b mut [[T; 3]],
    /// Root slots per ray (1 for opaque mode).
    pub roots_per_ray: usize,
    /// The active set (entry indices); its length bounds `M_overlap`.
    pub active: &'b mut [u32],
    /// Scratch for the active post-order indices (same length as
    /// `active`).
    pub nodes: &'b mut [u32],
}

/// Traces every ray of one tile by synchronized ranges (Alg. 3; see the
/// [module docs](self)). Rays are updated in place: roots and normals in
/// the buffers, the trace record in [`TileRay::trace`]. Allocation- and
/// recursion-free.
///
/// A Taylor method on a tree without Taylor bounds marks every ray
/// [`Status::Unsupported`] (as [`trace`] does). Buffers too short for `rays.len() · roots_per_ray` roots, or a
/// `roots_per_ray` of 0, leave the affected rays with
/// [`Status::Unsupported`]; an invalid [`SyncConfig`] or tracing parameters
/// mark every ray unsupported. Never panics on such input.
pub fn trace_tile<T: Real>(job: &TileJob<'_, T>, buf: &mut TileBuffers<'_, T>) -> SyncCounters {
    let mut counters = SyncCounters::default();
    let need = buf.rays.len().saturating_mul(buf.roots_per_ray);
    let bad = job.config.validate().is_err()
        || job.params.validate().is_err()
        || buf.roots_per_ray == 0
        || buf.roots.len() < need
        || buf.normals.len() < need
        || buf.active.is_empty()
        || buf.nodes.len() < buf.active.len();
    if bad {
        for r in buf.rays.iter_mut().filter(|r| !r.done) {
            r.trace.status = Status::Unsupported;
            r.done = true;
        }
        return counters;
    }
    // The Taylor methods need Taylor bounds, which a blobtree (full or
    // pruned) may lack: then nothing is traced, as `trace` would say.
    if let Some(r) = buf.rays.iter().find(|r| !r.done) {
        let t = r.trace.t_reached;
        let taylor = match job.method {
            Method::LinearTaylor => Some(job.tree.taylor_linear(&r.ray, t, t).is_some()),
            Method::QuadraticTaylor => Some(job.tree.taylor_quadratic(&r.ray, t, t).is_some()),
            _ => None,
        };
        if taylor == Some(false) {
            for r in buf.rays.iter_mut().filter(|r| !r.done) {
                r.trace.status = Status::Unsupported;
                r.done = true;
            }
            return counters;
        }
    }
    let cap = (job.config.m_overlap as usize)
        .min(buf.active.len())
        .min(M_OVERLAP);
    let mut cursor = RangeCursor::new(job.entries);
    loop {
        if buf.rays.iter().all(|r| r.done) {
            break;
        }
        let Some(range) = cursor.next_range(&mut buf.active[..cap], job.config.max_fetch) else {
            break;
        };
        counters.ranges += 1;
        counters.max_active = counters.max_active.max(range.active as u64);
        if range.full_tree {
            counters.overflow_ranges += 1;
            trace_range(
                &job.tree,
                job.tree.len() as u64,
                range.z,
                job,
                buf,
                &mut counters,
            );
            continue;
        }
        for j in 0..range.active {
            buf.nodes[j] = job.entries[buf.active[j] as usize].node;
        }
        match DefaultPrunedView::build(job.tree, &buf.nodes[..range.active]) {
            Ok(view) => {
                counters.views += 1;
                counters.view_nodes += view.len() as u64;
                counters.uncached_nodes += view.uncached_nodes() as u64;
                if view.is_empty() {
                    counters.empty_views += 1;
                    continue;
                }
                trace_range(&view, view.len() as u64, range.z, job, buf, &mut counters);
            }
            Err(_) => {
                counters.view_failures += 1;
                trace_range(
                    &job.tree,
                    job.tree.len() as u64,
                    range.z,
                    job,
                    buf,
                    &mut counters,
                );
            }
        }
    }
    for r in buf.rays.iter_mut() {
        if !r.done {
            if let Some(s) = r.span {
                r.trace.t_reached = s[1];
            }
            r.done = true;
        }
    }
    counters
}

/// Traces the unfinished rays of the tile on the depth range `z` with
/// `field` (a view or the full tree, `nodes` nodes).
fn trace_range<T: Real, F: Field<T>>(
    field: &F,
    nodes: u64,
    z: [T; 2],
    job: &TileJob<'_, T>,
    buf: &mut TileBuffers<'_, T>,
    counters: &mut SyncCounters,
) {
    let rpr = buf.roots_per_ray;
    for (k, r) in buf.rays.iter_mut().enumerate() {
        if r.done {
            continue;
        }
        let Some(span) = r.span else {
            continue;
        };
        let ta = (z[0] / r.c).max(span[0]);
        let tb = (z[1] / r.c).min(span[1]);
        if !(ta <= tb) {
            continue;
        }
        let remaining = job.params.max_steps.saturating_sub(r.trace.stats.steps);
        if remaining == 0 {
            r.trace.status = Status::MaxSteps;
            r.trace.t_reached = ta;
            r.done = true;
            continue;
        }
        let have = r.trace.roots as usize;
        let base = k * rpr;
        if have >= rpr {
            r.trace.status = Status::BufferFull;
            r.trace.t_reached = ta;
            r.done = true;
            continue;
        }
        let prev = if have > 0 {
            Some(buf.roots[base + have - 1].t)
        } else {
            None
        };
        let params = Params {
            max_steps: remaining,
            ..job.params
        };
        let slot = &mut buf.roots[base + have..base + rpr];
        let tr = trace(field, &r.ray, [ta, tb], job.method, job.mode, &params, slot);
        counters.ray_ranges += 1;
        let evals = u64::from(tr.stats.field_evals) + u64::from(tr.stats.bound_evals);
        counters.node_evals = counters.node_evals.saturating_add(evals * nodes);
        r.trace.stats = r.trace.stats + tr.stats;
        let mut got = (tr.roots as usize).min(slot.len());
        // A root on the shared boundary of two ranges is registered once.
        if got > 0 && prev.is_some_and(|p| !((slot[0].t - p).abs() > job.params.eps)) {
            slot.copy_within(1..got, 0);
            got -= 1;
        }
        let normals = &mut buf.normals[base + have..base + have + got];
        for (n, root) in normals.iter_mut().zip(&slot[..got]) {
            let p = [0, 1, 2].map(|i| r.ray.origin[i] + root.t * r.ray.dir[i]);
            *n = normal(field, p);
        }
        r.trace.roots += got as u32;
        r.trace.t_reached = tr.t_reached;
        match tr.status {
            Status::Finished => {
                if job.mode == Mode::Opaque && got > 0 {
                    r.done = true;
                }
            }
            status => {
                r.trace.status = status;
                r.done = true;
            }
        }
    }
}

/// A placeholder root for buffers.
pub const fn empty_root<T: Real>() -> Root<T> {
    Root {
        t: T::ZERO,
        side: Side::Touch,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec;
    use std::vec::Vec;

    fn entry(node: u32, z: [f64; 2]) -> TileEntry<f64> {
        TileEntry {
            node,
            z_entry: z[0],
            z_exit: z[1],
        }
    }

    /// Every range's active set holds every entry overlapping it, ranges
    /// are contiguous where entries exist, and overflows are flagged.
    fn check_cursor(entries: &[TileEntry<f64>], m: usize, max_fetch: u32) -> (usize, usize) {
        let mut active = vec![0u32; m];
        let mut cursor = RangeCursor::new(entries);
        let mut ranges = 0;
        let mut overflows = 0;
        let mut last_end = f64::NEG_INFINITY;
        while let Some(r) = cursor.next_range(&mut active, max_fetch) {
            ranges += 1;
            assert!(r.z[0] < r.z[1], "empty range {r:?}");
            assert!(r.z[0] >= last_end);
            last_end = r.z[1];
            if r.full_tree {
                overflows += 1;
                continue;
            }
            let set: Vec<u32> = active[..r.active]
                .iter()
                .map(|&i| entries[i as usize].node)
                .collect();
            assert!(set.windows(2).all(|w| w[0] < w[1]), "not sorted: {set:?}");
            for e in entries {
                let overlaps = e.z_entry < r.z[1] && e.z_exit > r.z[0];
                if overlaps {
                    assert!(set.contains(&e.node), "{e:?} missing in {r:?}");
                }
            }
            assert!(r.active <= m);
        }
        // Every entry's depth interval is covered by the ranges.
        (ranges, overflows)
    }

    #[test]
    fn cursor_keeps_every_overlapping_entry() {
        let mut s = 99u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for m in [1usize, 3, 8, 128] {
            let mut entries: Vec<_> = (0..200u32)
                .map(|i| {
                    let a = 10.0 * rnd();
                    entry(i * 3 + (i % 3), [a, a + 0.02 + 0.5 * rnd()])
                })
                .collect();
            entries.sort_by(|a, b| a.z_entry.partial_cmp(&b.z_entry).unwrap());
            let (ranges, overflows) = check_cursor(&entries, m, 8);
            assert!(ranges > 0);
            if m >= 128 {
                assert_eq!(overflows, 0);
            }
            if m == 1 {
                assert!(overflows > 0);
            }
        }
    }

    #[test]
    fn cursor_skips_empty_space() {
        let e = [
            entry(4, [1.0, 2.0]),
            entry(1, [1.5, 2.5]),
            entry(0, [5.0, 6.0]),
        ];
        let mut active = [0u32; 4];
        let mut c = RangeCursor::new(&e);
        let r = c.next_range(&mut active, 0).unwrap();
        assert_eq!((r.z, r.active), ([1.0, 1.5], 1));
        // eq. 22: up to the largest exit (the next entry starts later).
        let r = c.next_range(&mut active, 0).unwrap();
        assert_eq!((r.z, r.active), ([1.5, 2.5], 2));
        // sorted by node: 1 then 4
        assert_eq!([active[0], active[1]].map(|i| e[i as usize].node), [1, 4]);
        let r = c.next_range(&mut active, 0).unwrap();
        assert_eq!((r.z, r.active), ([5.0, 6.0], 1));
        assert!(c.next_range(&mut active, 0).is_none());
        // With optional fetches the first two entries share one range.
        let mut c = RangeCursor::new(&e);
        let r = c.next_range(&mut active, 8).unwrap();
        assert_eq!((r.z, r.active), ([1.0, 2.5], 2));
    }

    #[test]
    fn overflow_falls_back_to_the_full_tree() {
        let e = [
            entry(0, [0.0, 3.0]),
            entry(2, [0.0, 1.0]),
            entry(4, [2.0, 4.0]),
            entry(6, [5.0, 6.0]),
        ];
        let mut active = [0u32; 1];
        let mut c = RangeCursor::new(&e);
        let r = c.next_range(&mut active, 8).unwrap();
        // Two entries start at 0 > M = 1: full tree up to 4 (entry 4
        // starts inside [0, 3]).
        assert!(r.full_tree);
        assert_eq!(r.z, [0.0, 4.0]);
        let r = c.next_range(&mut active, 8).unwrap();
        assert!(!r.full_tree);
        assert_eq!((r.z, r.active), ([5.0, 6.0], 1));
        assert!(c.next_range(&mut active, 8).is_none());
    }

    #[test]
    fn config_validation() {
        assert!(SyncConfig::default().validate().is_ok());
        assert!(SyncConfig::default().with_m_overlap(0).is_err());
        assert!(
            SyncConfig::default()
                .with_m_overlap(M_OVERLAP as u32 + 1)
                .is_err()
        );
        assert_eq!(
            SyncConfig::default().with_m_overlap(4).unwrap().m_overlap,
            4
        );
    }
}
