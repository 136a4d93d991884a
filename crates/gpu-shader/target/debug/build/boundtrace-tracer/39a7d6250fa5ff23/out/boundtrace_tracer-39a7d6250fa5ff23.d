/work/main/crates/gpu-shader/target/debug/build/boundtrace-tracer/39a7d6250fa5ff23/out/boundtrace_tracer-39a7d6250fa5ff23.d: /work/main/crates/tracer/src/lib.rs /work/main/crates/tracer/src/bisect.rs /work/main/crates/tracer/src/camera.rs /work/main/crates/tracer/src/march.rs /work/main/crates/tracer/src/method.rs /work/main/crates/tracer/src/pixel.rs /work/main/crates/tracer/src/scalis/mod.rs /work/main/crates/tracer/src/scalis/bounds.rs /work/main/crates/tracer/src/scalis/list.rs /work/main/crates/tracer/src/sync.rs /work/main/crates/tracer/src/tiles.rs /work/main/crates/tracer/src/trace.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-tracer/39a7d6250fa5ff23/out/libboundtrace_tracer-39a7d6250fa5ff23.rmeta: /work/main/crates/tracer/src/lib.rs /work/main/crates/tracer/src/bisect.rs /work/main/crates/tracer/src/camera.rs /work/main/crates/tracer/src/march.rs /work/main/crates/tracer/src/method.rs /work/main/crates/tracer/src/pixel.rs /work/main/crates/tracer/src/scalis/mod.rs /work/main/crates/tracer/src/scalis/bounds.rs /work/main/crates/tracer/src/scalis/list.rs /work/main/crates/tracer/src/sync.rs /work/main/crates/tracer/src/tiles.rs /work/main/crates/tracer/src/trace.rs

/work/main/crates/tracer/src/lib.rs:
/work/main/crates/tracer/src/bisect.rs:
/work/main/crates/tracer/src/camera.rs:
/work/main/crates/tracer/src/march.rs:
/work/main/crates/tracer/src/method.rs:
/work/main/crates/tracer/src/pixel.rs:
/work/main/crates/tracer/src/scalis/mod.rs:
/work/main/crates/tracer/src/scalis/bounds.rs:
/work/main/crates/tracer/src/scalis/list.rs:
/work/main/crates/tracer/src/sync.rs:
/work/main/crates/tracer/src/tiles.rs:
/work/main/crates/tracer/src/trace.rs:
