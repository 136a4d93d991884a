//! The toolchain probe on the GPU: `boundtrace-ia-core` interval code
//! compiled to SPIR-V by rust-gpu (`interval_square`) must give exactly the
//! CPU's floats. Needs the module (`scripts/build-spirv.sh`) and a Vulkan
//! adapter; with `CI` set (`true`/`1`) their absence FAILS the test, else it
//! is skipped loudly.

use boundtrace_gpu::{GpuError, interval_probe};
use boundtrace_ia_core::Interval;

#[test]
fn interval_square_matches_the_cpu_bit_for_bit() {
    let xs: Vec<f32> = (0..300)
        .map(|i| (i as f32 - 150.0) * 0.037 + 1e-3 * (i % 7) as f32)
        .chain([0.0, -0.5, -1.0, 1e-30, -3.0e5, 7.25])
        .collect();
    let (gpu, info) = match interval_probe(&xs) {
        Ok(r) => r,
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. }))
            if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") =>
        {
            panic!("CI must run the GPU probe, but: {e}")
        }
        Err(e @ (GpuError::NoAdapter(_) | GpuError::ShaderMissing { .. })) => {
            eprintln!("\n!!!!!!!! SKIPPING the GPU probe: {e} !!!!!!!!\n");
            return;
        }
        Err(e) => panic!("GPU error: {e}"),
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
