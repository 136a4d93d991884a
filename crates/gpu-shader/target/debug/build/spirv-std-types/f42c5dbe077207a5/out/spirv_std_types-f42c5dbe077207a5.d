/work/main/crates/gpu-shader/target/debug/build/spirv-std-types/f42c5dbe077207a5/out/spirv_std_types-f42c5dbe077207a5.d: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md

/work/main/crates/gpu-shader/target/debug/build/spirv-std-types/f42c5dbe077207a5/out/libspirv_std_types-f42c5dbe077207a5.rmeta: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md

/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/lib.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/image_params.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/spirv-std-types-0.11.0/src/../README.md:
