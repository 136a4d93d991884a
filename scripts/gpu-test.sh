#!/usr/bin/env bash
# Prepares the GPU difftests (crates/gpu-spirv): a Vulkan driver (lavapipe,
# installed with apt-get only when no Vulkan ICD is present) and the SPIR-V
# modules (scripts/build-spirv.sh). The tests themselves run in
# `cargo test -p boundtrace-gpu` (scripts/test.sh runs it once this script
# is done); with CI=true a missing adapter or module makes them FAIL, never
# skip.
set -euo pipefail
cd "$(dirname "$0")/.."

# Whether any Vulkan ICD manifest is installed (either directory may be
# absent).
have_icd() {
    local f
    for f in /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json; do
        [ -e "$f" ] && return 0
    done
    return 1
}
if ! have_icd; then
    echo "==> no Vulkan driver: installing lavapipe (mesa-vulkan-drivers, libvulkan1)"
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
    else
        echo "cannot install lavapipe (needs root and apt-get); the GPU tests will fail in CI" >&2
    fi
fi

scripts/build-spirv.sh
