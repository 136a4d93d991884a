#!/usr/bin/env bash
# Installs the pinned nightly that rust-gpu 0.11 (scripts/build-spirv.sh)
# and cargo-fuzz (scripts/fuzz.sh) use, with the components rust-gpu
# needs (rust-src, rustc-dev, llvm-tools), when it or one of them is
# missing; prints the toolchain's name.
set -euo pipefail

toolchain=nightly-2026-08-15
if ! rustup run "$toolchain" rustc --version >/dev/null 2>&1 ||
    ! rustup component list --toolchain "$toolchain" --installed 2>/dev/null | grep -q '^rustc-dev'; then
    echo "==> installing $toolchain (rust-src, rustc-dev, llvm-tools) for rust-gpu and cargo-fuzz" >&2
    rustup toolchain install "$toolchain" --profile minimal -c rust-src,rustc-dev,llvm-tools >&2
fi
echo "$toolchain"
