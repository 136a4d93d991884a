//! [`FlatBlobGroups`]: the sharp union of blob groups over flat data (the
//! `blobs` scene on the GPU).

use boundtrace_fields::{Blobs, PointBlob};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, FieldNum, ForwardLinear, ForwardQuadratic, Ray};

/// `f = minₙ fₙ` over blob groups `fₙ = iso − Σ blobs of group n`, stored
/// flat: group `n` is `blobs[ends[n−1]..ends[n]]` (`ends[−1] = 0`).
///
/// The same field as
/// [`UnionAll`](boundtrace_fields::density::UnionAll) of
/// [`Blobs`] (its `eval`, Lipschitz and Taylor bounds are the same
/// `min`/`max` folds over each group's [`Blobs`] methods), but without an
/// array of group values, so a shader can build it over storage buffers.
///
/// The ends are the first `groups` words of `ends` and a group is a
/// [`Blobs::window_unchecked`] of the whole blob buffer: a shader cannot
/// sub-slice a storage buffer.
///
/// Invariant (checked by [`new`](Self::new)): at least one group, `ends`
/// non-decreasing and within `blobs`, every group non-empty, `iso` finite.
#[derive(Clone, Copy, Debug)]
pub struct FlatBlobGroups<'a, T> {
    iso: T,
    ends: &'a [u32],
    groups: usize,
    blobs: &'a [PointBlob<T>],
}

impl<'a, T: Real> FlatBlobGroups<'a, T> {
    /// The union of the groups ending at `ends` in `blobs`; `None` when
    /// the invariant does not hold.
    pub fn new(iso: T, ends: &'a [u32], blobs: &'a [PointBlob<T>]) -> Option<Self> {
        let f = Self::from_parts(iso, ends, ends.len(), blobs);
        f.is_valid().then_some(f)
    }

    /// The union of the groups ending at `ends[..groups]`, without the
    /// check (for the shader, which must not build an `Option` of slices
    /// nor sub-slice `ends`): check [`is_valid`](Self::is_valid) before
    /// use; an invalid value never reads out of bounds.
    pub fn from_parts(iso: T, ends: &'a [u32], groups: usize, blobs: &'a [PointBlob<T>]) -> Self {
        Self {
            iso,
            ends,
            groups,
            blobs,
        }
    }

    /// Whether the invariant holds.
    pub fn is_valid(&self) -> bool {
        if self.groups == 0 || self.groups > self.ends.len() || !self.iso.is_finite() {
            return false;
        }
        let mut start = 0u32;
        let mut n = 0;
        while n < self.groups {
            if self.ends[n] <= start || self.ends[n] as usize > self.blobs.len() {
                return false;
            }
            start = self.ends[n];
            n += 1;
        }
        true
    }

    /// Group `n` (`< groups`) as a blob set: a window of the blob buffer
    /// (no `Option`, no sub-slice: both are beyond rust-gpu 0.11). The
    /// invariant, checked before use, keeps the window non-empty and in
    /// range; an index past `ends` gives an empty window.
    #[inline]
    fn group(&self, n: usize) -> Blobs<T, &'a [PointBlob<T>]> {
        let end_of = |i: usize| {
            if i < self.ends.len() {
                self.ends[i] as usize
            } else {
                0
            }
        };
        let start = if n == 0 { 0 } else { end_of(n - 1) };
        Blobs::window_unchecked(self.iso, self.blobs, start, end_of(n))
    }

    /// The number of groups.
    pub fn len(&self) -> usize {
        self.groups
    }

    /// Whether there is no group (never, by the invariant).
    pub fn is_empty(&self) -> bool {
        self.groups == 0
    }
}

impl<T: Real> Field<T> for FlatBlobGroups<'_, T> {
    fn eval<N: FieldNum<T>>(&self, p: [N; 3]) -> N {
        let mut acc: Option<N> = None;
        let mut n = 0;
        while n < self.groups {
            let g = self.group(n).eval(p);
            acc = Some(match acc {
                Some(a) => a.min(g),
                None => g,
            });
            n += 1;
        }
        match acc {
            Some(a) => a,
            None => N::constant(T::nan()),
        }
    }
    fn lipschitz(&self) -> Option<T> {
        let mut l = T::ZERO;
        let mut n = 0;
        while n < self.groups {
            l = l.max(self.group(n).lipschitz()?);
            n += 1;
        }
        Some(l)
    }
    // One call site per group bound (a GPU driver inlines every call).
    fn taylor_linear(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardLinear<T>> {
        let mut acc: Option<ForwardLinear<T>> = None;
        let mut n = 0;
        while n < self.groups {
            let g = self.group(n).taylor_linear(ray, t0, t1)?;
            acc = Some(match acc {
                Some(a) => a.min(g),
                None => g,
            });
            n += 1;
        }
        acc
    }
    fn taylor_quadratic(&self, ray: &Ray<T>, t0: T, t1: T) -> Option<ForwardQuadratic<T>> {
        let mut acc: Option<ForwardQuadratic<T>> = None;
        let mut n = 0;
        while n < self.groups {
            let g = self.group(n).taylor_quadratic(ray, t0, t1)?;
            acc = Some(match acc {
                Some(a) => a.min(g),
                None => g,
            });
            n += 1;
        }
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::Kernel;
    use boundtrace_fields::density::UnionAll;

    #[test]
    fn equals_the_union_of_blob_sets() {
        let k = Kernel::compact(6, 0.6f64).unwrap();
        let b = |x: f64, y: f64| PointBlob::new([x, y, 0.0], 1.0, k).unwrap();
        let blobs = [
            b(-0.5, 0.0),
            b(-0.3, 0.1),
            b(0.4, 0.0),
            b(0.6, -0.1),
            b(0.5, 0.2),
        ];
        let flat = FlatBlobGroups::new(0.5, &[2, 5], &blobs).unwrap();
        let union = UnionAll::new([
            Blobs::new(0.5, &blobs[..2]).unwrap(),
            Blobs::new(0.5, &blobs[2..]).unwrap(),
        ])
        .unwrap();
        for i in 0..40 {
            let p = [-1.0 + 0.05 * i as f64, 0.03 * i as f64 - 0.5, 0.1];
            let (a, b): (f64, f64) = (flat.eval(p), union.eval(p));
            assert_eq!(a, b);
        }
        assert_eq!(flat.lipschitz(), union.lipschitz());
        let ray = Ray::new([-2.0, 0.05, 0.0], [1.0, 0.0, 0.0]);
        for (t0, t1) in [(0.0, 0.5), (1.0, 1.4), (1.5, 2.5)] {
            assert_eq!(
                flat.taylor_linear(&ray, t0, t1),
                union.taylor_linear(&ray, t0, t1)
            );
            assert_eq!(
                flat.taylor_quadratic(&ray, t0, t1),
                union.taylor_quadratic(&ray, t0, t1)
            );
        }
        assert_eq!(flat.len(), 2);
    }

    #[test]
    fn rejects_bad_ends() {
        let k = Kernel::compact(6, 0.6f64).unwrap();
        let blobs = [PointBlob::new([0.0; 3], 1.0, k).unwrap(); 3];
        assert!(FlatBlobGroups::new(0.5, &[], &blobs).is_none());
        assert!(FlatBlobGroups::new(0.5, &[2, 2], &blobs).is_none()); // empty group
        assert!(FlatBlobGroups::new(0.5, &[4], &blobs).is_none()); // past the end
        assert!(FlatBlobGroups::new(f64::NAN, &[3], &blobs).is_none());
        assert!(FlatBlobGroups::new(0.5, &[1, 3], &blobs).is_some());
        // `from_parts` reads the first `groups` words only (the shader's
        // whole word buffer), and checks the count against them.
        let words = [1, 3, 77, 0];
        let two = FlatBlobGroups::from_parts(0.5, &words, 2, &blobs);
        assert!(two.is_valid() && two.len() == 2);
        assert!(!FlatBlobGroups::from_parts(0.5, &words, 3, &blobs).is_valid());
        assert!(!FlatBlobGroups::from_parts(0.5, &words, 5, &blobs).is_valid());
        assert!(!FlatBlobGroups::from_parts(0.5, &words, 0, &blobs).is_valid());
        let p = [0.2, 0.1, 0.0];
        let (a, b): (f64, f64) = (
            two.eval(p),
            FlatBlobGroups::new(0.5, &words[..2], &blobs)
                .unwrap()
                .eval(p),
        );
        assert_eq!(a, b);
    }
}
