/work/main/crates/gpu-shader/target/debug/build/boundtrace-gpu-kernel/6c34112943648eb0/out/boundtrace_gpu_kernel-6c34112943648eb0.d: /work/main/crates/gpu-kernel/src/lib.rs /work/main/crates/gpu-kernel/src/groups.rs /work/main/crates/gpu-kernel/src/scalis.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-gpu-kernel/6c34112943648eb0/out/libboundtrace_gpu_kernel-6c34112943648eb0.rmeta: /work/main/crates/gpu-kernel/src/lib.rs /work/main/crates/gpu-kernel/src/groups.rs /work/main/crates/gpu-kernel/src/scalis.rs

/work/main/crates/gpu-kernel/src/lib.rs:
/work/main/crates/gpu-kernel/src/groups.rs:
/work/main/crates/gpu-kernel/src/scalis.rs:
