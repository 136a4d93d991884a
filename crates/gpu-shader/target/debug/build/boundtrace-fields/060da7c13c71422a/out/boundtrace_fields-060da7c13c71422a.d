/work/main/crates/gpu-shader/target/debug/build/boundtrace-fields/060da7c13c71422a/out/boundtrace_fields-060da7c13c71422a.d: /work/main/crates/fields/src/lib.rs /work/main/crates/fields/src/blob.rs /work/main/crates/fields/src/blobtree/mod.rs /work/main/crates/fields/src/blobtree/encoding.rs /work/main/crates/fields/src/blobtree/eval.rs /work/main/crates/fields/src/blobtree/traversal.rs /work/main/crates/fields/src/blobtree/view.rs /work/main/crates/fields/src/bounding.rs /work/main/crates/fields/src/density.rs /work/main/crates/fields/src/error.rs /work/main/crates/fields/src/homothetic.rs /work/main/crates/fields/src/homothetic_skeleton.rs /work/main/crates/fields/src/hrbf.rs /work/main/crates/fields/src/kernel.rs /work/main/crates/fields/src/operator.rs /work/main/crates/fields/src/scalis.rs /work/main/crates/fields/src/sdf.rs /work/main/crates/fields/src/transform.rs

/work/main/crates/gpu-shader/target/debug/build/boundtrace-fields/060da7c13c71422a/out/libboundtrace_fields-060da7c13c71422a.rmeta: /work/main/crates/fields/src/lib.rs /work/main/crates/fields/src/blob.rs /work/main/crates/fields/src/blobtree/mod.rs /work/main/crates/fields/src/blobtree/encoding.rs /work/main/crates/fields/src/blobtree/eval.rs /work/main/crates/fields/src/blobtree/traversal.rs /work/main/crates/fields/src/blobtree/view.rs /work/main/crates/fields/src/bounding.rs /work/main/crates/fields/src/density.rs /work/main/crates/fields/src/error.rs /work/main/crates/fields/src/homothetic.rs /work/main/crates/fields/src/homothetic_skeleton.rs /work/main/crates/fields/src/hrbf.rs /work/main/crates/fields/src/kernel.rs /work/main/crates/fields/src/operator.rs /work/main/crates/fields/src/scalis.rs /work/main/crates/fields/src/sdf.rs /work/main/crates/fields/src/transform.rs

/work/main/crates/fields/src/lib.rs:
/work/main/crates/fields/src/blob.rs:
/work/main/crates/fields/src/blobtree/mod.rs:
/work/main/crates/fields/src/blobtree/encoding.rs:
/work/main/crates/fields/src/blobtree/eval.rs:
/work/main/crates/fields/src/blobtree/traversal.rs:
/work/main/crates/fields/src/blobtree/view.rs:
/work/main/crates/fields/src/bounding.rs:
/work/main/crates/fields/src/density.rs:
/work/main/crates/fields/src/error.rs:
/work/main/crates/fields/src/homothetic.rs:
/work/main/crates/fields/src/homothetic_skeleton.rs:
/work/main/crates/fields/src/hrbf.rs:
/work/main/crates/fields/src/kernel.rs:
/work/main/crates/fields/src/operator.rs:
/work/main/crates/fields/src/scalis.rs:
/work/main/crates/fields/src/sdf.rs:
/work/main/crates/fields/src/transform.rs:
