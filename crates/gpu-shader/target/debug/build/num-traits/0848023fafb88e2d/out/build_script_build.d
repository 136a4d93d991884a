/work/main/crates/gpu-shader/target/debug/build/num-traits/0848023fafb88e2d/out/build_script_build.d: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/num-traits-0.2.19/build.rs

/work/main/crates/gpu-shader/target/debug/build/num-traits/0848023fafb88e2d/out/build_script_build: /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/num-traits-0.2.19/build.rs

/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/num-traits-0.2.19/build.rs:
