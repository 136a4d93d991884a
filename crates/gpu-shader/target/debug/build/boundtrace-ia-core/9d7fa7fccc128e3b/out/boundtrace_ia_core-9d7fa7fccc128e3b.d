/work/main/crates/gpu-shader/target/debug/build/boundtrace-ia-core/9d7fa7fccc128e3b/out/boundtrace_ia_core-9d7fa7fccc128e3b.d: /work/main/crates/ia-core/src/lib.rs /work/main/crates/ia-core/src/affine.rs /work/main/crates/ia-core/src/interval.rs /work/main/crates/ia-core/src/math.rs /work/main/crates/ia-core/src/real.rs /work/main/crates/ia-core/src/round.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-ia-core/9d7fa7fccc128e3b/out/libboundtrace_ia_core-9d7fa7fccc128e3b.rmeta: /work/main/crates/ia-core/src/lib.rs /work/main/crates/ia-core/src/affine.rs /work/main/crates/ia-core/src/interval.rs /work/main/crates/ia-core/src/math.rs /work/main/crates/ia-core/src/real.rs /work/main/crates/ia-core/src/round.rs

/work/main/crates/ia-core/src/lib.rs:
/work/main/crates/ia-core/src/affine.rs:
/work/main/crates/ia-core/src/interval.rs:
/work/main/crates/ia-core/src/math.rs:
/work/main/crates/ia-core/src/real.rs:
/work/main/crates/ia-core/src/round.rs:
