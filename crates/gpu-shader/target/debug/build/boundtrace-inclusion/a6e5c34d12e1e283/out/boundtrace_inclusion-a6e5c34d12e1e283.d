/work/main/crates/gpu-shader/target/debug/build/boundtrace-inclusion/a6e5c34d12e1e283/out/boundtrace_inclusion-a6e5c34d12e1e283.d: /work/main/crates/inclusion/src/lib.rs /work/main/crates/inclusion/src/compose.rs /work/main/crates/inclusion/src/field.rs /work/main/crates/inclusion/src/jet.rs /work/main/crates/inclusion/src/linear.rs /work/main/crates/inclusion/src/num.rs /work/main/crates/inclusion/src/poly.rs /work/main/crates/inclusion/src/quadratic.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-inclusion/a6e5c34d12e1e283/out/libboundtrace_inclusion-a6e5c34d12e1e283.rmeta: /work/main/crates/inclusion/src/lib.rs /work/main/crates/inclusion/src/compose.rs /work/main/crates/inclusion/src/field.rs /work/main/crates/inclusion/src/jet.rs /work/main/crates/inclusion/src/linear.rs /work/main/crates/inclusion/src/num.rs /work/main/crates/inclusion/src/poly.rs /work/main/crates/inclusion/src/quadratic.rs

/work/main/crates/inclusion/src/lib.rs:
/work/main/crates/inclusion/src/compose.rs:
/work/main/crates/inclusion/src/field.rs:
/work/main/crates/inclusion/src/jet.rs:
/work/main/crates/inclusion/src/linear.rs:
/work/main/crates/inclusion/src/num.rs:
/work/main/crates/inclusion/src/poly.rs:
/work/main/crates/inclusion/src/quadratic.rs:
