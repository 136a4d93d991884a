//! Builds `crates/gpu-shader` to SPIR-V with rust-gpu and copies the module
//! to the path given as the first argument; the optional second argument
//! is the (absolute) target directory of the shader build;
//! `BOUNDTRACE_SHADER_FEATURES` (comma-separated) gives the shader crate's
//! features instead of its default ones.
//!
//! Run through `scripts/build-spirv.sh`, which installs the pinned nightly
//! and picks the output path the host crate (`boundtrace-gpu`) loads.

use std::path::PathBuf;
use std::process::ExitCode;

use spirv_builder::{Capability, ModuleResult, SpirvBuilder};

fn main() -> ExitCode {
    let mut args = std::env::args_os().skip(1);
    let (Some(out), target_dir, None) = (args.next(), args.next(), args.next()) else {
        eprintln!("usage: boundtrace-gpu-builder OUTPUT.spv [SHADER_TARGET_DIR]");
        return ExitCode::FAILURE;
    };
    let out = PathBuf::from(out);
    let shader = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../gpu-shader");
    // The tracer's shared code (the `trace_sphere` and `trace_pixels` entry
    // points) uses `u8`/`i8` (enum discriminants such as
    // `core::cmp::Ordering`'s), `i64`/`u64` and `f64` (exact integer → float
    // conversions) on the per-ray path; the host requests SHADER_INT64 and
    // SHADER_F64 where the adapter has them.
    let mut builder = SpirvBuilder::new(&shader, "spirv-unknown-vulkan1.1")
        .release(true)
        .capability(Capability::Int8)
        .capability(Capability::Int64)
        .capability(Capability::Float64);
    // The shader crate's features, comma-separated, instead of its default
    // ones (e.g. `segment`, or `sphere,trace`).
    if let Ok(features) = std::env::var("BOUNDTRACE_SHADER_FEATURES") {
        let list: Vec<String> = features
            .split(',')
            .filter(|f| !f.is_empty())
            .map(str::to_owned)
            .collect();
        if list.iter().any(|f| f == "trace") {
            // spirv-opt fails on the whole tracer ("ID overflow": too many
            // ids after rust-gpu's inlining); the driver optimises anyway.
            builder = builder.extra_arg("--no-spirv-opt");
        }
        builder = builder
            .shader_crate_default_features(false)
            .shader_crate_features(list);
    }
    // `BOUNDTRACE_NO_SPIRV_OPT=1`: rust-gpu's module as it links, without
    // spirv-opt (to measure a module that spirv-opt cannot handle; a driver
    // must then inline every call itself).
    if std::env::var_os("BOUNDTRACE_NO_SPIRV_OPT").is_some_and(|v| v == "1") {
        builder = builder.extra_arg("--no-spirv-opt");
    }
    if let Some(dir) = target_dir {
        builder = builder.target_dir_path(PathBuf::from(dir));
    }
    let result = match builder.build() {
        Ok(result) => result,
        Err(err) => {
            eprintln!("SPIR-V build of {} failed: {err}", shader.display());
            return ExitCode::FAILURE;
        }
    };
    let ModuleResult::SingleModule(spv) = &result.module else {
        eprintln!("SPIR-V build produced several modules; expected one");
        return ExitCode::FAILURE;
    };
    if let Some(dir) = out.parent() {
        if let Err(err) = std::fs::create_dir_all(dir) {
            eprintln!("cannot create {}: {err}", dir.display());
            return ExitCode::FAILURE;
        }
    }
    // Copied beside the target, then renamed over it: an interrupted copy
    // never leaves half a module where the host loads it.
    let mut partial = out.clone().into_os_string();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    if let Err(err) = std::fs::copy(spv, &partial).and_then(|_| std::fs::rename(&partial, &out)) {
        eprintln!("cannot copy {} to {}: {err}", spv.display(), out.display());
        return ExitCode::FAILURE;
    }
    println!("SPIR-V module: {}", out.display());
    ExitCode::SUCCESS
}
