#!/usr/bin/env bash
# The whole test suite, exactly as CI runs it (.ci/run calls this script).
#
# Works on a fresh machine with rustup: installs the components and targets
# it needs. Set CARGO_TARGET_DIR to reuse a build cache outside the clone.
# PROPTEST_CASES raises the property-test case count (default 10000 per op).
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step with the wall-clock time and the seconds since the start.
step() { printf '\n==> %s [%s, %d s]\n' "$*" "$(date -u +%H:%M:%S)" "$SECONDS"; }

step "toolchain: rustfmt, clippy, thumbv7em-none-eabihf (no_std check)"
rustup component add rustfmt clippy >/dev/null
rustup target add thumbv7em-none-eabihf >/dev/null

step "pinned nightly for rust-gpu and cargo-fuzz (installed when missing)"
scripts/nightly.sh >/dev/null

# The GPU preparation (lavapipe when no Vulkan driver, and the SPIR-V
# modules: nine with spirv-opt, ~40 min cold on 2 cores, one core at a time, with peaks
# of 14-18 GB, and twenty-one in seconds without it: bottom-up, mixed, SCALIS,
# HRBF, homothetic) runs in the background from here, while the CPU-only steps
# below run beside it on one cargo job (so that the two fit in memory).
# The GPU tests wait until the last module is built: beside a module build
# even the sphere difftest left too little of this machine's 24 GB (a
# module build was killed by the kernel's OOM killer, session 26; the
# forward-Taylor tests alone take 13-16 GB).
gpu_log=$(mktemp "${TMPDIR:-/tmp}/boundtrace-gpu-build.XXXXXX")
step "GPU: Vulkan driver (lavapipe when none) and the SPIR-V modules (rust-gpu), in the background (log: $gpu_log)"
scripts/gpu-test.sh >"$gpu_log" 2>&1 &
gpu_pid=$!
gpu_status=
kill_tree() {
    local child
    for child in $(pgrep -P "$1" 2>/dev/null); do kill_tree "$child"; done
    kill "$1" 2>/dev/null || true
}
trap 'kill_tree "$gpu_pid"' EXIT
# Fails the run with the build log when the GPU preparation failed; sets
# gpu_status once it has ended.
gpu_reap() {
    if [ -z "$gpu_status" ] && ! kill -0 "$gpu_pid" 2>/dev/null; then
        gpu_status=0
        wait "$gpu_pid" || gpu_status=$?
    fi
    if [ -n "$gpu_status" ] && [ "$gpu_status" != 0 ]; then
        cat "$gpu_log"
        echo "GPU preparation (scripts/gpu-test.sh) failed (status $gpu_status)" >&2
        exit 1
    fi
}
cpu_jobs=${CARGO_BUILD_JOBS:-}
export CARGO_BUILD_JOBS=1

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy (deny warnings)"
cargo clippy --workspace --all-targets -- -D warnings

step "cargo test --workspace, except the GPU host crate (its tests run after the SPIR-V build)"
cargo test --workspace --exclude boundtrace-gpu

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

if [ -n "$cpu_jobs" ]; then export CARGO_BUILD_JOBS=$cpu_jobs; else unset CARGO_BUILD_JOBS; fi

# lavapipe wants a runtime dir.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    export XDG_RUNTIME_DIR="${TMPDIR:-/tmp}/boundtrace-xdg-$(id -u)"
    mkdir -p "$XDG_RUNTIME_DIR" && chmod 0700 "$XDG_RUNTIME_DIR"
fi

# The GPU tests (they fail, never skip, with CI=true), once the modules
# are built: the difftests and the CLI's GPU test, one process each (a
# tracer's pipelines take several GB on lavapipe), two at a time, then
# every test of the crate not run before (so a new test cannot be left
# out).
step "GPU tests: building them while the SPIR-V modules build"
cargo test -p boundtrace-gpu --no-run
cargo test -p boundtrace-cli --features gpu --test cli --no-run

step "waiting for the GPU preparation (the SPIR-V modules)"
until [ -n "$gpu_status" ]; do
    gpu_reap
    sleep 5
done
trap - EXIT
cat "$gpu_log"
rm -f "$gpu_log"

done_tests=()
# `gpu_queue ITEM…`: runs the items two at a time, in the order given (the
# longest first), each the moment a core is free; an item is a difftest's
# exact name, or `cli` for the CLI's GPU test. lavapipe compiles a
# pipeline on one core, for minutes and several GB (BENCHMARKS.md "GPU",
# sessions 13, 28 and 36), so two processes use both cores; any two of
# these peaked below 18 GB together (session 36). Each item must report
# its tests passed (a name that matches no test would pass silently).
gpu_queue() {
    local outs=() item out failed=0
    for item in "$@"; do
        while [ "$(jobs -rp | wc -l)" -ge 2 ]; do
            wait -n || true
        done
        out=$(mktemp "${TMPDIR:-/tmp}/boundtrace-gpu-tests.XXXXXX")
        outs+=("$item=$out")
        step "GPU test $item (two at a time)"
        if [ "$item" = cli ]; then
            cargo test -p boundtrace-cli --features gpu --test cli gpu_backend >"$out" 2>&1 &
        else
            cargo test -p boundtrace-gpu --test difftest -- --exact "$item" >"$out" 2>&1 &
        fi
    done
    wait
    for entry in "${outs[@]}"; do
        item=${entry%%=*}
        out=${entry#*=}
        printf '\n--- %s\n' "$item"
        cat "$out"
        if ! grep -q "test result: ok. [1-9][0-9]* passed; 0 failed" "$out"; then
            echo "GPU test $item did not pass" >&2
            failed=1
        fi
        rm -f "$out"
        if [ "$item" != cli ]; then done_tests+=("$item"); fi
    done
    if [ "$failed" != 0 ]; then exit 1; fi
}
step "GPU difftests and the CLI's GPU test, two at a time"
gpu_queue \
    quadratic_mixed_matches_the_cpu_in_both_modes \
    linear_mixed_matches_the_cpu_in_both_modes \
    homothetic_methods_match_the_cpu_in_both_modes \
    homothetic_bottom_up_and_mixed_match_the_cpu_in_both_modes \
    quadratic_bottom_up_matches_the_cpu_in_both_modes \
    scalis_methods_match_the_cpu_in_both_modes \
    linear_bottom_up_matches_the_cpu_in_both_modes \
    sphere_matches_the_cpu_on_blobtrees_whole_and_tiled \
    sphere_matches_the_cpu_in_both_modes \
    homothetic_quadratic_mixed_matches_the_cpu_in_both_modes \
    segment_matches_the_cpu_in_both_modes \
    quadratic_taylor_matches_the_cpu_in_both_modes \
    cli \
    hrbf_methods_match_the_cpu_in_both_modes \
    linear_taylor_matches_the_cpu_in_both_modes

step "cargo test -p boundtrace-gpu: every other test (unit tests, probes, the rest of the difftests)"
skips=()
for t in "${done_tests[@]}"; do skips+=(--skip "$t"); done
cargo test -p boundtrace-gpu -- --exact "${skips[@]}"

step "ITF1788 conformance report"
report=$(find "${CARGO_TARGET_DIR:-target}" -name itf1788-report.txt -path '*tmp*' 2>/dev/null | head -n 1)
if [ -n "$report" ]; then cat "$report"; fi

step "forward-bound property test report"
find "${CARGO_TARGET_DIR:-target}" -name 'forward-bounds-report-*.txt' -path '*tmp*' \
    -exec cat {} \; 2>/dev/null || true

printf '\nAll checks passed.\n'
