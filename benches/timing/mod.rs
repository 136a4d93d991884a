//! Criterion warm-up and measurement times shared by the `frame` and
//! `per_ray` benches.

use std::time::Duration;

/// Warm-up and measurement times: `(warm_ms, measure_ms)`, or 100 / 300 ms
/// when `BOUNDTRACE_BENCH_QUICK` is set (`scripts/benchmarks.sh --quick`).
pub fn times(warm_ms: u64, measure_ms: u64) -> (Duration, Duration) {
    let quick = std::env::var_os("BOUNDTRACE_BENCH_QUICK").is_some();
    let (w, m) = if quick {
        (100, 300)
    } else {
        (warm_ms, measure_ms)
    };
    (Duration::from_millis(w), Duration::from_millis(m))
}
