/work/main/crates/gpu-shader/target/debug/build/boundtrace-gpu-shader/68d9ac18e12d73b2/out/boundtrace_gpu_shader-68d9ac18e12d73b2.d: src/lib.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-gpu-shader/68d9ac18e12d73b2/out/libboundtrace_gpu_shader-68d9ac18e12d73b2.rmeta: src/lib.rs

src/lib.rs:
