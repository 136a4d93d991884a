//! Helpers shared by the benches.

/// Operands per benchmark iteration.
pub const LEN: usize = 1024;

/// Deterministic pseudo-random values in `[lo, hi)` (xorshift).
pub fn values(seed: u64, lo: f64, hi: f64) -> Vec<f64> {
    let mut s = seed | 1;
    (0..LEN)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect()
}
