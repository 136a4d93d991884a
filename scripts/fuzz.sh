#!/usr/bin/env bash
# Runs the cargo-fuzz targets of fuzz/ for a bounded time each.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      (default: 30 s, every target)
#
# Installs what it needs: the pinned nightly (the same one the SPIR-V build
# uses) with rustup, and cargo-fuzz with cargo install. New inputs go to
# fuzz/corpus/<target>/ (not committed; the committed seeds are read from
# fuzz/seeds/<target>/), crashes to fuzz/artifacts/<target>/. Exits non-zero
# on the first violation, printing the target's report. FUZZ_JOBS=N runs N
# jobs per target in parallel (libFuzzer -fork).
set -euo pipefail
cd "$(dirname "$0")/.."

NIGHTLY=$(scripts/nightly.sh)
secs=${1:-30}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(interval_ops affine_ops forward_bounds field_bounds sparse_equivalence tracer_first_hit scene_parse)
fi

if ! command -v cargo-fuzz >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}/fuzz"
for t in "${targets[@]}"; do
    mkdir -p "fuzz/corpus/$t"
    printf '\n==> fuzz %s for %ss\n' "$t" "$secs"
    fork=()
    if [ -n "${FUZZ_JOBS:-}" ]; then fork=(-fork="$FUZZ_JOBS"); fi
    cargo "+$NIGHTLY" fuzz run --sanitizer none --debug-assertions --features libfuzzer \
        "$t" "fuzz/corpus/$t" "fuzz/seeds/$t" -- \
        -max_total_time="$secs" -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 "${fork[@]}"
done
