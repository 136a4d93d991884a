//! Per-ray primitive lists: the A-buffer of thesis Part III §1.5 on the CPU.
//!
//! For one ray, [`RayPrimitives`] holds the sphere-cone supports
//! ([`ScalisSegment::support`]) that the ray crosses on its span, as
//! [`PrimitiveHit`]s sorted by entry: the entry and exit parameters (of the
//! capsule around the sphere-cone, a superset of the support, so the
//! primitive's density is exactly `0` outside `[entry, exit]`), the argmin
//! of the homothetic distance along the ray (§1.3.2, eq. 1.6, clamped to
//! `[entry, exit]`) and the primitive's index. The storage is the caller's
//! fixed-capacity slice: no allocation, no recursion. When more supports are
//! crossed than fit, the list is marked [`overflowed`](RayPrimitives::overflowed)
//! and the tracers fall back to evaluating the whole skeleton (never a wrong
//! answer, only a slower one).
//!
//! With `alloc`, [`PrimitiveLists`] builds the lists of a whole ray set (an
//! image) into two flat arrays (offsets and hits), in parallel with the
//! `parallel` feature.

use boundtrace_fields::scalis::ScalisSegment;
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Ray;
use core::fmt;

/// One support crossed by a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct PrimitiveHit<T> {
    /// Where the ray enters the support (clipped to the span).
    pub entry: T,
    /// Where it leaves it (clipped to the span); `entry ≤ exit`.
    pub exit: T,
    /// The argmin of the primitive's homothetic distance along the ray
    /// (§1.3.2), clamped to `[entry, exit]`.
    pub argmin: T,
    /// The primitive's index in the skeleton.
    pub index: u32,
}

impl<T: Real> PrimitiveHit<T> {
    /// A placeholder value for storage arrays.
    pub const fn empty() -> Self {
        Self {
            entry: T::ZERO,
            exit: T::ZERO,
            argmin: T::ZERO,
            index: 0,
        }
    }
}

/// Why primitive lists cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListError {
    /// A segment has an infinite support (Cauchy kernel): its clipped
    /// support is only approximate, so the lists would not be sound.
    InfiniteSupport {
        /// The segment's index.
        index: usize,
    },
    /// The skeleton has more than `u32::MAX` segments.
    TooManySegments,
}

impl fmt::Display for ListError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ListError::InfiniteSupport { index } => write!(
                f,
                "SCALIS segment {index} has an infinite (Cauchy) support; per-ray primitive lists need compact kernels"
            ),
            ListError::TooManySegments => f.write_str("more than u32::MAX SCALIS segments"),
        }
    }
}

impl core::error::Error for ListError {}

/// Checks that every segment has a compact support.
///
/// # Errors
/// [`ListError`] for a Cauchy segment or too many segments.
pub fn check_segments<T: Real>(segments: &[ScalisSegment<T>]) -> Result<(), ListError> {
    if u32::try_from(segments.len()).is_err() {
        return Err(ListError::TooManySegments);
    }
    match segments.iter().position(|s| s.support_box().is_none()) {
        Some(index) => Err(ListError::InfiniteSupport { index }),
        None => Ok(()),
    }
}

/// The support crossing of one segment on `span`, if any.
#[inline]
pub fn hit_of<T: Real>(
    segment: &ScalisSegment<T>,
    index: u32,
    ray: &Ray<T>,
    span: [T; 2],
) -> Option<PrimitiveHit<T>> {
    // Cheap rejection by the support box (slab test, conservative).
    let [lo, hi] = segment.support_box()?;
    let (mut t0, mut t1) = (span[0], span[1]);
    let mut k = 0;
    while k < 3 {
        let (o, d) = (ray.origin[k], ray.dir[k]);
        if d == T::ZERO {
            if o < lo[k] || o > hi[k] {
                return None;
            }
        } else {
            let (a, b) = ((lo[k] - o) / d, (hi[k] - o) / d);
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            // widened by a few ulps: rounding must not cut the box
            let slack = (a.abs().max(b.abs()) + T::ONE) * T::EPSILON * T::from_f64(8.0);
            t0 = t0.max(a - slack);
            t1 = t1.min(b + slack);
        }
        k += 1;
    }
    if !(t0 <= t1) {
        return None;
    }
    let (e, x) = segment
        .support(T::ZERO)
        .ray_entry_exit(ray.origin, ray.dir)?;
    let (entry, exit) = (e.max(span[0]), x.min(span[1]));
    if !(entry <= exit) {
        return None;
    }
    let argmin = match segment.segment().argmin_along_ray(ray) {
        Some((t, _, _)) if t.is_finite() => t.max(entry).min(exit),
        _ => entry + (exit - entry) * T::HALF,
    };
    Some(PrimitiveHit {
        entry,
        exit,
        argmin,
        index,
    })
}

/// The sorted support crossings of one ray, in caller-provided storage.
#[derive(Debug)]
pub struct RayPrimitives<'a, T> {
    hits: &'a mut [PrimitiveHit<T>],
    len: usize,
    overflow: bool,
}

impl<'a, T: Real> RayPrimitives<'a, T> {
    /// The crossings of `ray` on `span` with the supports of `segments`,
    /// sorted by entry (insertion sort; allocation-free), in `storage`.
    /// Segments with an infinite support (Cauchy) are not listed: check the
    /// skeleton with [`check_segments`] first.
    pub fn build(
        segments: &[ScalisSegment<T>],
        ray: &Ray<T>,
        span: [T; 2],
        storage: &'a mut [PrimitiveHit<T>],
    ) -> Self {
        let mut out = Self::empty(storage);
        for (i, s) in segments.iter().enumerate() {
            if !out.insert(hit_of(s, i as u32, ray, span)) {
                break;
            }
        }
        out
    }

    /// [`build`](Self::build) over the segments `candidates` of
    /// `segments` only (indices into `segments`, in increasing order; an
    /// index out of range is skipped): the same list as `build` whenever
    /// the candidates hold every segment whose support the ray crosses,
    /// e.g. those whose [`ScalisSegment::support_box`] meets a tile of
    /// rays. Hits carry the index into `segments`.
    pub fn build_among(
        segments: &[ScalisSegment<T>],
        candidates: &[u32],
        ray: &Ray<T>,
        span: [T; 2],
        storage: &'a mut [PrimitiveHit<T>],
    ) -> Self {
        let mut out = Self::empty(storage);
        for &i in candidates {
            let Some(s) = segments.get(i as usize) else {
                continue;
            };
            if !out.insert(hit_of(s, i, ray, span)) {
                break;
            }
        }
        out
    }

    /// An empty list over `storage`.
    fn empty(storage: &'a mut [PrimitiveHit<T>]) -> Self {
        Self {
            hits: storage,
            len: 0,
            overflow: false,
        }
    }

    /// Inserts `h` in entry order (after the equal entries: a stable
    /// insertion sort); `false` when the storage is full (overflow).
    #[inline]
    fn insert(&mut self, h: Option<PrimitiveHit<T>>) -> bool {
        let Some(h) = h else {
            return true;
        };
        if self.len >= self.hits.len() {
            self.overflow = true;
            return false;
        }
        let mut j = self.len;
        while j > 0 && self.hits[j - 1].entry > h.entry {
            self.hits[j] = self.hits[j - 1];
            j -= 1;
        }
        self.hits[j] = h;
        self.len += 1;
        true
    }

    /// The crossings, sorted by entry (incomplete when
    /// [`overflowed`](Self::overflowed)).
    #[inline]
    pub fn hits(&self) -> &[PrimitiveHit<T>] {
        &self.hits[..self.len]
    }

    /// Whether the storage was too small: the list is incomplete and must
    /// not be used for tracing.
    #[inline]
    pub fn overflowed(&self) -> bool {
        self.overflow
    }
}

/// The merged covered regions of a sorted hit list: calls `f(start, end,
/// first, last)` for every maximal union of overlapping `[entry, exit]`
/// intervals, with the range `first..last` of the hits it contains. Empty
/// space between regions is skipped without evaluation. Returns early when
/// `f` returns `false`.
pub fn for_each_region<T: Real, F: FnMut(T, T, usize, usize) -> bool>(
    hits: &[PrimitiveHit<T>],
    mut f: F,
) {
    let mut i = 0;
    while i < hits.len() {
        let (start, mut end) = (hits[i].entry, hits[i].exit);
        let mut j = i + 1;
        while j < hits.len() && hits[j].entry <= end {
            end = end.max(hits[j].exit);
            j += 1;
        }
        if !f(start, end, i, j) {
            return;
        }
        i = j;
    }
}

#[cfg(feature = "alloc")]
pub use flat::PrimitiveLists;

#[cfg(feature = "alloc")]
mod flat {
    use super::{PrimitiveHit, hit_of};
    use alloc::vec::Vec;
    use boundtrace_fields::scalis::ScalisSegment;
    use boundtrace_ia_core::Real;
    use boundtrace_inclusion::Ray;

    /// The primitive lists of a whole ray set in two flat arrays: the hits
    /// of ray `i` are `hits[offsets[i]..offsets[i + 1]]`, sorted by entry
    /// (complete: no capacity limit).
    #[derive(Clone, Debug, Default, PartialEq)]
    pub struct PrimitiveLists<T> {
        offsets: Vec<usize>,
        hits: Vec<PrimitiveHit<T>>,
    }

    fn one<T: Real>(
        segments: &[ScalisSegment<T>],
        ray: &Ray<T>,
        span: [T; 2],
        out: &mut Vec<PrimitiveHit<T>>,
    ) {
        let start = out.len();
        for (i, s) in segments.iter().enumerate() {
            if let Some(h) = hit_of(s, i as u32, ray, span) {
                out.push(h);
            }
        }
        out[start..].sort_by(|a, b| {
            a.entry
                .partial_cmp(&b.entry)
                .unwrap_or(core::cmp::Ordering::Equal)
        });
    }

    impl<T: Real + Send + Sync> PrimitiveLists<T> {
        /// The lists of `rays` (each with its span), built in parallel
        /// (rayon, by chunks of rays; the same result as serial) with the
        /// `parallel` feature. Segments with an infinite support are not
        /// listed (see [`check_segments`](super::check_segments)).
        pub fn build(segments: &[ScalisSegment<T>], rays: &[(Ray<T>, [T; 2])]) -> Self {
            const CHUNK: usize = 256;
            #[cfg(feature = "parallel")]
            let parts: Vec<(Vec<usize>, Vec<PrimitiveHit<T>>)> = {
                use rayon::prelude::*;
                rays.par_chunks(CHUNK)
                    .map(|c| Self::chunk(segments, c))
                    .collect()
            };
            #[cfg(not(feature = "parallel"))]
            let parts: Vec<(Vec<usize>, Vec<PrimitiveHit<T>>)> = rays
                .chunks(CHUNK)
                .map(|c| Self::chunk(segments, c))
                .collect();
            let mut offsets = Vec::with_capacity(rays.len() + 1);
            offsets.push(0);
            let mut hits = Vec::new();
            for (lens, h) in parts {
                for l in lens {
                    offsets.push(hits.len() + l);
                }
                hits.extend(h);
            }
            Self { offsets, hits }
        }

        /// One chunk: the end offsets (relative to the chunk) and the hits.
        fn chunk(
            segments: &[ScalisSegment<T>],
            rays: &[(Ray<T>, [T; 2])],
        ) -> (Vec<usize>, Vec<PrimitiveHit<T>>) {
            let mut ends = Vec::with_capacity(rays.len());
            let mut hits = Vec::new();
            for (ray, span) in rays {
                one(segments, ray, *span, &mut hits);
                ends.push(hits.len());
            }
            (ends, hits)
        }
    }

    impl<T> PrimitiveLists<T> {
        /// The number of rays.
        pub fn len(&self) -> usize {
            self.offsets.len().saturating_sub(1)
        }
        /// Whether there is no ray.
        pub fn is_empty(&self) -> bool {
            self.len() == 0
        }
        /// The hits of ray `i`, sorted by entry (empty for `i ≥ len`).
        pub fn hits(&self, i: usize) -> &[PrimitiveHit<T>] {
            match (self.offsets.get(i), self.offsets.get(i + 1)) {
                (Some(&a), Some(&b)) => &self.hits[a..b],
                _ => &[],
            }
        }
        /// The total number of hits (the A-buffer's size).
        pub fn total_hits(&self) -> usize {
            self.hits.len()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::homothetic::{Segment, SegmentKernel};
    use boundtrace_inclusion::FieldNum;

    fn seg(a: [f64; 3], b: [f64; 3], r: f64) -> ScalisSegment<f64> {
        let k = SegmentKernel::compact_polynomial(6, 2.0).unwrap();
        ScalisSegment::new(Segment::new(a, r, b, r).unwrap(), k, 1.0).unwrap()
    }

    fn three() -> [ScalisSegment<f64>; 3] {
        [
            seg([3.0, -1.0, 0.0], [3.0, 1.0, 0.0], 0.2),
            seg([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], 0.2),
            seg([0.0, 5.0, 0.0], [1.0, 5.0, 0.0], 0.2),
        ]
    }

    #[test]
    fn hits_are_sorted_and_contain_the_support() {
        let segs = three();
        let ray = Ray::new([-2.0, 0.1, 0.05], [1.0, 0.0, 0.0]);
        let mut store = [PrimitiveHit::empty(); 4];
        let l = RayPrimitives::build(&segs, &ray, [0.0, 10.0], &mut store);
        assert!(!l.overflowed());
        let h = l.hits();
        assert_eq!(h.len(), 2, "{h:?}");
        assert_eq!((h[0].index, h[1].index), (1, 0));
        assert!(h[0].entry <= h[1].entry);
        // the argmin is where the ray crosses the segment's line
        assert!((h[0].argmin - 2.0).abs() < 1e-9 && (h[1].argmin - 5.0).abs() < 1e-9);
        // the density is zero outside [entry, exit], nonzero at the argmin
        for (hit, s) in h.iter().map(|x| (x, &segs[x.index as usize])) {
            for i in 0..=200 {
                let t = 10.0 * f64::from(i) / 200.0;
                let d: f64 = s.density(ray.at::<f64>(t, t));
                if t < hit.entry || t > hit.exit {
                    assert_eq!(d, 0.0, "t = {t}");
                }
            }
            let d: f64 = s.density(ray.at::<f64>(hit.argmin, hit.argmin));
            assert!(d > 0.0);
        }
    }

    #[test]
    fn lists_among_candidates_match_the_full_lists() {
        let segs = three();
        let ray = Ray::new([-2.0, 0.1, 0.05], [1.0, 0.0, 0.0]);
        let (mut a, mut b) = ([PrimitiveHit::empty(); 4], [PrimitiveHit::empty(); 4]);
        let full = RayPrimitives::build(&segs, &ray, [0.0, 10.0], &mut a);
        // every crossed segment among the candidates (an unknown index is
        // skipped): the same list, with the skeleton's indices
        let among = RayPrimitives::build_among(&segs, &[0, 1, 7], &ray, [0.0, 10.0], &mut b);
        assert_eq!(full.hits(), among.hits());
        assert_eq!(among.hits().len(), 2);
        // a crossed segment left out is not listed
        let mut c = [PrimitiveHit::empty(); 4];
        let part = RayPrimitives::build_among(&segs, &[0, 2], &ray, [0.0, 10.0], &mut c);
        assert_eq!(part.hits().len(), 1);
        assert_eq!(part.hits()[0].index, 0);
        // overflow as in `build`
        let mut d = [PrimitiveHit::empty(); 1];
        let small = RayPrimitives::build_among(&segs, &[0, 1], &ray, [0.0, 10.0], &mut d);
        assert!(small.overflowed());
    }

    #[test]
    fn overflow_is_reported_and_regions_merge() {
        let segs = three();
        let ray = Ray::new([-2.0, 0.1, 0.05], [1.0, 0.0, 0.0]);
        let mut store = [PrimitiveHit::empty(); 1];
        let l = RayPrimitives::build(&segs, &ray, [0.0, 10.0], &mut store);
        assert!(l.overflowed());
        let mut store = [PrimitiveHit::empty(); 4];
        let l = RayPrimitives::build(&segs, &ray, [0.0, 10.0], &mut store);
        let mut regions = [(0.0, 0.0, 0, 0); 4];
        let mut n = 0;
        for_each_region(l.hits(), |a, b, i, j| {
            regions[n] = (a, b, i, j);
            n += 1;
            true
        });
        // supports of radius 0.4 around x = 0 and x = 3: two regions
        assert_eq!(n, 2);
        assert!(regions[0].1 < regions[1].0);
        assert_eq!(
            (regions[0].2, regions[0].3, regions[1].2, regions[1].3),
            (0, 1, 1, 2)
        );
        assert_eq!(check_segments(&segs), Ok(()));
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn flat_lists_match_the_per_ray_lists() {
        let segs = three();
        let rays: alloc::vec::Vec<(Ray<f64>, [f64; 2])> = (0..50)
            .map(|i| {
                let y = -1.5 + 7.0 * f64::from(i) / 49.0;
                (Ray::new([-2.0, y, 0.05], [1.0, 0.01, 0.0]), [0.0, 10.0])
            })
            .collect();
        let flat = PrimitiveLists::build(&segs, &rays);
        assert_eq!(flat.len(), 50);
        let mut total = 0;
        for (i, (ray, span)) in rays.iter().enumerate() {
            let mut store = [PrimitiveHit::empty(); 4];
            let l = RayPrimitives::build(&segs, ray, *span, &mut store);
            assert_eq!(flat.hits(i), l.hits());
            total += l.hits().len();
        }
        assert_eq!(flat.total_hits(), total);
        assert!(total > 0);
        let _ = <f64 as FieldNum<f64>>::constant(0.0);
    }
}
