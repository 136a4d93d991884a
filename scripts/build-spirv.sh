#!/usr/bin/env bash
# Builds boundtrace's SPIR-V compute shader (crates/gpu-shader) with rust-gpu.
#
# Installs the pinned nightly (rust-gpu 0.11 needs nightly-2026-08-15 with
# rust-src, rustc-dev, llvm-tools) with rustup when missing, builds the
# builder (crates/gpu-builder; its target dir is cached under
# $CARGO_TARGET_DIR/spirv-builder, the first build takes ~8 min on 2 cores)
# and writes the modules to the paths the host crate loads:
#
#     ${CARGO_TARGET_DIR:-target}/spirv/boundtrace-gpu-shader.spv                 (sphere tracing, probes)
#     ${CARGO_TARGET_DIR:-target}/spirv/boundtrace-gpu-shader-segment-blobs.spv   (segment tracing, `Blobs` scenes)
#     ${CARGO_TARGET_DIR:-target}/spirv/boundtrace-gpu-shader-segment-groups.spv  (segment tracing, `BlobGroups` scenes)
#     …-linear-taylor-blobs.spv, …-linear-taylor-groups.spv,
#     …-quadratic-taylor-blobs.spv, …-quadratic-taylor-groups.spv (forward Taylor methods)
#     …-sphere-blobtree.spv                                                      (sphere tracing, `Blobtree` scenes)
#     …-linear-bottom-up-blobs.spv, …-linear-bottom-up-groups.spv,
#     …-quadratic-bottom-up-blobs.spv, …-quadratic-bottom-up-groups.spv (forward bottom-up bounds)
#     …-linear-mixed-blobs.spv, …-linear-mixed-groups.spv,
#     …-quadratic-mixed-blobs.spv, …-quadratic-mixed-groups.spv (forward mixed bounds:
#                                         `trace_*` and `taylor_*`)
#     …-scalis.spv                        (`scalis-quadratic` and `interval` on SCALIS skeletons:
#                                         `trace_scalis` and `trace_scalis_tight`)
#     …-segment-hrbf.spv, …-linear-bottom-up-hrbf.spv,
#     …-quadratic-bottom-up-hrbf.spv, …-linear-mixed-hrbf.spv,
#     …-quadratic-mixed-hrbf.spv          (`Hrbf` scenes: segment tracing with bottom-up
#                                         lines, the forward bottom-up and mixed methods)
#     …-sphere-homothetic.spv, …-segment-homothetic.spv,
#     …-linear-taylor-homothetic.spv, …-linear-bottom-up-homothetic.spv,
#     …-quadratic-bottom-up-homothetic.spv, …-linear-mixed-homothetic.spv,
#     …-quadratic-mixed-homothetic.spv    (`Homothetic` skeletons of scene files)
#
# The bottom-up, mixed, SCALIS, HRBF and homothetic modules are written as rust-gpu links them,
# without spirv-opt (seconds instead of minutes, and a few GB instead of
# ~19 GB or more than this machine's 24 GB): the driver inlines and
# optimises them (lavapipe does, in about the time it takes with an
# optimised module: BENCHMARKS.md "GPU", session 28).
#
# (boundtrace-gpu also honours BOUNDTRACE_GPU_SPV=/path/to/module.spv, and
# looks for the other modules beside it). With BOUNDTRACE_SHADER_FEATURES
# set (e.g. `sphere,trace`), only the first module is built, with those
# features.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

toolchain=$(scripts/nightly.sh)

target=${CARGO_TARGET_DIR:-$root/target}
case "$target" in /*) ;; *) target="$root/$target" ;; esac
out="$target/spirv/boundtrace-gpu-shader.spv"

# Builds one module: `module FEATURES PATH [no-opt]` (FEATURES empty: the shader
# crate's default features). `cargo run` puts the codegen backend
# (librustc_codegen_spirv.so) and the nightly's rustc libraries on the
# library path; the nested shader build gets its own target dir.
module() {
    local features=$1 path=$2 opt=${3:-opt}
    (cd crates/gpu-builder &&
        if [ -n "$features" ]; then export BOUNDTRACE_SHADER_FEATURES=$features; fi &&
        shader_target="$target/spirv-shader" &&
        # Their own shader target dir: the flag changes rust-gpu's codegen
        # arguments, which would rebuild the shared one's dependencies.
        if [ "$opt" = no-opt ]; then
            export BOUNDTRACE_NO_SPIRV_OPT=1
            shader_target="$target/spirv-shader-no-opt"
        fi &&
        CARGO_TARGET_DIR="$target/spirv-builder" cargo +"$toolchain" run --release --locked -q -- \
            "$path" "$shader_target")
}

echo "==> building the SPIR-V builder (cached in $target/spirv-builder) and compiling crates/gpu-shader"
module "${BOUNDTRACE_SHADER_FEATURES:-}" "$out"

# The leg modules of segment tracing and the forward Taylor methods, one
# per method and blob scene kind: spirv-opt runs out of memory on segment
# tracing of both kinds in one module. They share the main module's shader
# target dir: only the shader crate (its features) differs between them, so
# its dependencies are compiled to SPIR-V once. Skipped when
# BOUNDTRACE_SHADER_FEATURES picks the main module's features.
# The blobtree module comes right after segment tracing's: scripts/test.sh
# runs the GPU tests that need little memory (sphere, segment, blobtrees)
# while the forward-Taylor modules build, and those modules' tests (several
# GB per pipeline on lavapipe) once every module is built.
if [ -z "${BOUNDTRACE_SHADER_FEATURES:-}" ]; then
    for method in segment linear-taylor quadratic-taylor; do
        for kind in blobs groups; do
            echo "==> compiling the $method module for $kind"
            module "$method-$kind" "${out%.spv}-$method-$kind.spv"
        done
        if [ "$method" = segment ]; then
            echo "==> compiling the sphere module for blobtrees"
            module sphere-blobtree "${out%.spv}-sphere-blobtree.spv"
        fi
    done
    # The bottom-up and mixed modules, without spirv-opt (see above). A
    # mixed module has two entry points, the bottom-up side (`trace_*`)
    # and the Taylor side (`taylor_*`), two pipelines that lavapipe
    # compiles in a few GB each, where one with both took ≈ 20 GB
    # (BENCHMARKS.md "GPU", sessions 28 and 32).
    methods="linear-bottom-up quadratic-bottom-up linear-mixed quadratic-mixed"
    for method in $methods; do
        for kind in blobs groups; do
            echo "==> compiling the $method module for $kind (no spirv-opt)"
            module "$method-$kind" "${out%.spv}-$method-$kind.spv" no-opt
        done
    done
    # `scalis-quadratic` and `interval` on SCALIS skeletons (two entry
    # points, `trace_scalis` and its intervals' tight stages,
    # `trace_scalis_tight`: two pipelines that lavapipe compiles in a few
    # GB each, where the two in one needed more than 19 GB, BENCHMARKS.md
    # "GPU", sessions 29-30), without spirv-opt likewise.
    echo "==> compiling the scalis module (no spirv-opt)"
    module scalis "${out%.spv}-scalis.spv" no-opt
    # The HRBF scenes (no global Lipschitz or Taylor bound): segment
    # tracing with the CPU's bound (bottom-up lines) and the bottom-up
    # methods, without spirv-opt likewise.
    for method in segment linear-bottom-up quadratic-bottom-up linear-mixed quadratic-mixed; do
        echo "==> compiling the $method module for hrbf (no spirv-opt)"
        module "$method-hrbf" "${out%.spv}-$method-hrbf.spv" no-opt
    done
    # The homothetic-distance skeletons of scene files (global and
    # directional Lipschitz bounds, no quadratic Taylor bound), likewise.
    for method in sphere segment linear-taylor linear-bottom-up quadratic-bottom-up linear-mixed quadratic-mixed; do
        echo "==> compiling the $method module for homothetic skeletons (no spirv-opt)"
        module "$method-homothetic" "${out%.spv}-$method-homothetic.spv" no-opt
    done
fi
