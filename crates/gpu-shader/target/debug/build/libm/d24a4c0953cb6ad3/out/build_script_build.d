/work/main/crates/gpu-shader/target/debug/build/libm/d24a4c0953cb6ad3/out/build_script_build.d: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/build.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/configure.rs

/work/main/crates/gpu-shader/target/debug/build/libm/d24a4c0953cb6ad3/out/build_script_build: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/build.rs /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/configure.rs

/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/build.rs:
/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/libm-0.2.16/configure.rs:
