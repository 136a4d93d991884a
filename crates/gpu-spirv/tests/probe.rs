//! The toolchain probe on the GPU: `boundtrace-ia-core` interval code
//! compiled to SPIR-V by rust-gpu (`interval_square`) must give exactly the
//! CPU's floats. Needs the module (`scripts/build-spirv.sh`) and a Vulkan
//! adapter; with `CI` set (`true`/`1`) their absence FAILS the test, else it
//! is skipped loudly.

use boundtrace_gpu::{GpuError, arith_probe, interval_probe};
use boundtrace_ia_core::Interval;

/// A probe's result; `None` (the test is skipped, loudly) without an
/// adapter or module, which FAILS instead when `CI` is set.
fn ran<T>(r: Result<T, GpuError>) -> Option<T> {
    match r {
        Ok(r) => Some(r),
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. }))
            if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") =>
        {
            panic!("CI must run the GPU probe, but: {e}")
        }
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. })) => {
            eprintln!("\n!!!!!!!! SKIPPING the GPU probe: {e} !!!!!!!!\n");
            None
        }
        Err(e) => panic!("GPU error: {e}"),
    }
}

#[test]
fn interval_square_matches_the_cpu_bit_for_bit() {
    let xs: Vec<f32> = (0..300)
        .map(|i| (i as f32 - 150.0) * 0.037 + 1e-3 * (i % 7) as f32)
        .chain([0.0, -0.5, -1.0, 1e-30, -3.0e5, 7.25])
        .collect();
    let Some((gpu, info)) = ran(interval_probe(&xs)) else {
        return;
    };
    eprintln!("GPU probe on {} ({:?})", info.name, info.device_type);
    let mut bad = Vec::new();
    for (x, g) in xs.iter().zip(&gpu) {
        let cpu = Interval::new(*x, *x + 1.0).sqr().hi();
        if cpu.to_bits() != g.to_bits() {
            bad.push(format!("x = {x:e}: cpu {cpu:e}, gpu {g:e}"));
        }
    }
    assert!(
        bad.is_empty(),
        "{} of {} differ:\n{}",
        bad.len(),
        xs.len(),
        bad.join("\n")
    );
}

/// The driver's `÷ × + −` against the CPU's correctly rounded ones on
/// 20,000 pairs over many magnitudes. `×`, `+` and `−` must match (Vulkan
/// requires them correctly rounded); `÷` may be off by Vulkan's allowed
/// 2.5 ulp, which `ia-core` widens quotients for on SPIR-V (3 steps): the
/// test checks that bound and prints how often the driver differs.
#[test]
fn arithmetic_is_within_vulkan_precision() {
    // A small deterministic generator: mantissas and exponents spread
    // over 2^-60 … 2^60, both signs.
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut float = || {
        let r = next();
        let m = 1.0 + (r >> 40) as f32 / (1u64 << 24) as f32;
        let e = ((r >> 8) % 121) as i32 - 60;
        let s = if r & 1 == 0 { 1.0 } else { -1.0 };
        s * m * 2f32.powi(e)
    };
    let pairs: Vec<[f32; 2]> = (0..20_000).map(|_| [float(), float()]).collect();
    let Some((gpu, info)) = ran(arith_probe(&pairs)) else {
        return;
    };
    // Float steps between two finite floats of the same sign.
    let steps = |x: f32, y: f32| (x.to_bits() as i64 - y.to_bits() as i64).unsigned_abs();
    let mut differ = [0usize; 4];
    let mut worst = [0u64; 4];
    for (&[a, b], g) in pairs.iter().zip(&gpu) {
        let cpu = [a / b, a * b, a + b, a - b];
        for k in 0..4 {
            if cpu[k].to_bits() != g[k].to_bits() {
                differ[k] += 1;
                let d =
                    if cpu[k].is_finite() && g[k].is_finite() && cpu[k].signum() == g[k].signum() {
                        steps(cpu[k], g[k])
                    } else {
                        u64::MAX
                    };
                worst[k] = worst[k].max(d);
            }
        }
    }
    eprintln!(
        "{} ({:?}): of {} pairs, differ from the CPU: ÷ {} (worst {} steps), × {}, + {}, − {}",
        info.name,
        info.device_type,
        pairs.len(),
        differ[0],
        worst[0],
        differ[1],
        differ[2],
        differ[3]
    );
    assert_eq!(
        (differ[1], differ[2], differ[3]),
        (0, 0, 0),
        "×, + and − must be correctly rounded"
    );
    assert!(worst[0] <= 3, "÷ beyond ia-core's SPIR-V margin of 3 steps");
}
