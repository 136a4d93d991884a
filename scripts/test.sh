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
# of 14-18 GB, and fourteen in seconds without it: bottom-up, mixed, SCALIS,
# HRBF) runs in the background from here, while the CPU-only steps
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
# are built: the difftests in groups, one process each (a tracer's
# pipelines take several GB on lavapipe), then every test of the crate not
# run before (so a new test cannot be left out).
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
# `gpu_tests TESTS…`: runs the difftests named (exactly).
gpu_tests() {
    step "GPU difftests $*"
    local out
    out=$(mktemp "${TMPDIR:-/tmp}/boundtrace-gpu-tests.XXXXXX")
    cargo test -p boundtrace-gpu --test difftest -- --exact "$@" 2>&1 | tee "$out"
    # A name that matches no test would pass silently.
    if ! grep -q "test result: ok. $# passed" "$out"; then
        echo "expected $# difftests to pass: $*" >&2
        exit 1
    fi
    rm -f "$out"
    done_tests+=("$@")
}
gpu_tests sphere_matches_the_cpu_in_both_modes
gpu_tests segment_matches_the_cpu_in_both_modes
gpu_tests sphere_matches_the_cpu_on_blobtrees_whole_and_tiled
gpu_tests linear_taylor_matches_the_cpu_in_both_modes
gpu_tests quadratic_taylor_matches_the_cpu_in_both_modes
# `gpu_tests_beside A B`: difftests A and B in two processes at once. The
# bottom-up modules come without spirv-opt, so lavapipe spends
# minutes inlining and compiling each pipeline, on one core (its memory:
# BENCHMARKS.md "GPU", session 28); two processes use both cores.
gpu_tests_beside() {
    step "GPU difftests $1 and $2, side by side"
    local out1 out2 pid1 pid2
    out1=$(mktemp "${TMPDIR:-/tmp}/boundtrace-gpu-tests.XXXXXX")
    out2=$(mktemp "${TMPDIR:-/tmp}/boundtrace-gpu-tests.XXXXXX")
    cargo test -p boundtrace-gpu --test difftest -- --exact "$1" >"$out1" 2>&1 &
    pid1=$!
    cargo test -p boundtrace-gpu --test difftest -- --exact "$2" >"$out2" 2>&1 &
    pid2=$!
    wait "$pid1" || true
    wait "$pid2" || true
    cat "$out1" "$out2"
    # Each must report its one test passed (a name that matches no test
    # would pass silently).
    if ! grep -q "test result: ok. 1 passed" "$out1" || ! grep -q "test result: ok. 1 passed" "$out2"; then
        echo "expected difftests $1 and $2 to pass" >&2
        exit 1
    fi
    rm -f "$out1" "$out2"
    done_tests+=("$1" "$2")
}
gpu_tests_beside linear_bottom_up_matches_the_cpu_in_both_modes quadratic_bottom_up_matches_the_cpu_in_both_modes
# The mixed methods likewise: two pipelines per module (the bottom-up and
# the Taylor side), 7.5 and 9.6 GB peak, about 8 min each (BENCHMARKS.md
# "GPU", session 32).
gpu_tests_beside linear_mixed_matches_the_cpu_in_both_modes quadratic_mixed_matches_the_cpu_in_both_modes
# `scalis-quadratic` and the per-primitive `interval` on the SCALIS
# skeletons (the `scalis` module's two pipelines, shared by both methods:
# about 4.5 min and 8.6 GB on lavapipe).
gpu_tests scalis_methods_match_the_cpu_in_both_modes
# Segment tracing, the bottom-up and the mixed methods on the HRBF scenes
# (the five `*-hrbf` modules: 35-70 s per pipeline on lavapipe), beside
# the three methods of a homothetic-distance skeleton (the `*-homothetic`
# modules: 35-145 s per pipeline).
gpu_tests_beside hrbf_methods_match_the_cpu_in_both_modes homothetic_methods_match_the_cpu_in_both_modes

step "cargo test -p boundtrace-gpu: every other test (unit tests, probes, the rest of the difftests)"
skips=()
for t in "${done_tests[@]}"; do skips+=(--skip "$t"); done
cargo test -p boundtrace-gpu -- --exact "${skips[@]}"

step "boundtrace render --backend gpu (sphere tracing on the GPU; fails, never skips, with CI=true)"
cargo test -p boundtrace-cli --features gpu --test cli gpu_backend

step "ITF1788 conformance report"
report=$(find "${CARGO_TARGET_DIR:-target}" -name itf1788-report.txt -path '*tmp*' 2>/dev/null | head -n 1)
if [ -n "$report" ]; then cat "$report"; fi

step "forward-bound property test report"
find "${CARGO_TARGET_DIR:-target}" -name 'forward-bounds-report-*.txt' -path '*tmp*' \
    -exec cat {} \; 2>/dev/null || true

printf '\nAll checks passed.\n'
