#!/usr/bin/env bash
# The whole test suite, exactly as CI runs it (.ci/run calls this script).
#
# Works on a fresh machine with rustup: installs the components and targets
# it needs. Set CARGO_TARGET_DIR to reuse a build cache outside the clone.
# PROPTEST_CASES raises the property-test case count (default 10000 per op).
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "toolchain: rustfmt, clippy, thumbv7em-none-eabihf (no_std check)"
rustup component add rustfmt clippy >/dev/null
rustup target add thumbv7em-none-eabihf >/dev/null

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy (deny warnings)"
cargo clippy --workspace --all-targets -- -D warnings

step "GPU: Vulkan driver (lavapipe when none) and the SPIR-V module (rust-gpu nightly)"
scripts/gpu-test.sh
# lavapipe wants a runtime dir; the GPU difftests run in the workspace tests.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    export XDG_RUNTIME_DIR="${TMPDIR:-/tmp}/boundtrace-xdg-$(id -u)"
    mkdir -p "$XDG_RUNTIME_DIR" && chmod 0700 "$XDG_RUNTIME_DIR"
fi

step "cargo test --workspace (GPU difftests included: they fail, never skip, with CI=true)"
cargo test --workspace

step "boundtrace render --backend gpu (sphere tracing on the GPU; fails, never skips, with CI=true)"
cargo test -p boundtrace-cli --features gpu --test cli gpu_backend

step "cargo test boundtrace-ia-core, -inclusion, -fields and -tracer with the libm back end"
cargo test -p boundtrace-ia-core -p boundtrace-inclusion --no-default-features --features libm
cargo test -p boundtrace-fields --no-default-features --features libm,alloc
cargo test -p boundtrace-tracer --no-default-features --features libm,alloc --lib

step "cargo test boundtrace-tracer with the parallel feature (rayon; output equals serial)"
cargo test -p boundtrace-tracer --features parallel --lib

step "cargo doc (deny warnings)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps

step "no_std build of boundtrace-ia-core, -inclusion, -fields, -tracer and -gpu-kernel for thumbv7em-none-eabihf"
cargo build -p boundtrace-ia-core -p boundtrace-inclusion -p boundtrace-fields \
    -p boundtrace-tracer -p boundtrace-gpu-kernel --target thumbv7em-none-eabihf \
    --no-default-features --features libm
step "no_std + alloc build of boundtrace-fields and -tracer (builders, HRBF storage, images)"
cargo build -p boundtrace-fields -p boundtrace-tracer --target thumbv7em-none-eabihf \
    --no-default-features --features libm,alloc

step "fuzz targets: fmt, clippy, and replay of the committed seeds and regressions (stable)"
cargo fmt --manifest-path fuzz/Cargo.toml -- --check
cargo clippy --manifest-path fuzz/Cargo.toml --all-targets -- -D warnings
cargo test --manifest-path fuzz/Cargo.toml --release

step "fuzz targets: ${FUZZ_SECONDS:-20} s each under libFuzzer (installs the pinned nightly and cargo-fuzz)"
./scripts/fuzz.sh "${FUZZ_SECONDS:-20}"

step "ITF1788 conformance report"
report=$(find "${CARGO_TARGET_DIR:-target}" -name itf1788-report.txt -path '*tmp*' 2>/dev/null | head -n 1)
if [ -n "$report" ]; then cat "$report"; fi

step "forward-bound property test report"
find "${CARGO_TARGET_DIR:-target}" -name 'forward-bounds-report-*.txt' -path '*tmp*' \
    -exec cat {} \; 2>/dev/null || true

printf '\nAll checks passed.\n'
