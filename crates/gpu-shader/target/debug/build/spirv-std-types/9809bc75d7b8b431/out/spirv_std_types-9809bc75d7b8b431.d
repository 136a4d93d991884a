/work/main/crates/gpu-shader/target/debug/build/spirv-std-types/9809bc75d7b8b431/out/spirv_std_types-9809bc75d7b8b431.d: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/spirv_attr_version.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md

/work/main/crates/gpu-shader/target/debug/build/spirv-std-types/9809bc75d7b8b431/out/libspirv_std_types-9809bc75d7b8b431.rlib: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/spirv_attr_version.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md

/work/main/crates/gpu-shader/target/debug/build/spirv-std-types/9809bc75d7b8b431/out/libspirv_std_types-9809bc75d7b8b431.rmeta: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/spirv_attr_version.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md

/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/spirv_attr_version.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md:

# env-dep:CARGO_PKG_VERSION_MAJOR=0
# env-dep:CARGO_PKG_VERSION_MINOR=11
