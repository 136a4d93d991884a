#!/usr/bin/env bash
# Prepares target/device for a run on a lent NVIDIA machine (the `device`
# tool; BENCHMARKS.md "GPU", session 22): the host binaries
# (gpu_frame_times, the probe test), Debian's Vulkan loader and the glvnd
# libraries (.gl/, unpacked there by the run scripts), the modules of
# scripts/build-spirv.sh (xz-compressed: they travel in a 64 MiB tree), and
# compile-test variants of the modules made with spirv-tools (apt-get
# install spirv-tools) and the Python tools beside this script:
#
#   target/device/spirv/            the modules as built
#   target/device/spirv-phifree/    no OpPhi of a struct holding pointers,
#                                   then spirv-opt's insert/extract folding
#   target/device/spirv-phisplit/   the same without the folding
#   target/device/var/<v>/          linear-taylor (Blobs) only: noi8,
#                                   nocopy, noi8_nocopy, O, Os, all, orig
#
# The modules are read from $SPIRV_DIR (default: $CARGO_TARGET_DIR/spirv).
# Then: device run `bash scripts/device/compile-check.sh` (or
# variant-check.sh) with carry ["target/device", ".gl"].
set -euo pipefail
cd "$(dirname "$0")/../.."
here=scripts/device
target=${CARGO_TARGET_DIR:-target}
spv=${SPIRV_DIR:-$target/spirv}
dst=target/device
mkdir -p "$dst"/bin .gl
cargo build --release -p boundtrace-gpu --example gpu_frame_times
cp "$target"/release/examples/gpu_frame_times "$dst"/bin/
probe=$(cargo test --release -p boundtrace-gpu --test probe --no-run --message-format=json 2>/dev/null |
    sed -n 's/.*"executable":"\([^"]*probe[^"]*\)".*/\1/p' | tail -n 1)
cp "$probe" "$dst"/bin/probe
strip "$dst"/bin/*
if [ -z "$(ls .gl/*.deb 2>/dev/null)" ]; then
    grep -qx '/.gl/' .git/info/exclude 2>/dev/null || { mkdir -p .git/info && echo /.gl/ >>.git/info/exclude; }
    o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    mkdir -p /tmp/amd64/partial
    apt-get $o update >/dev/null
    (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
variant() { # in.spv out.spv steps…  (phisplit, opt, noi8, nocopy)
    local t
    t=$(mktemp -d)
    spirv-dis --raw-id "$1" -o "$t/x.spvasm"
    local out=$2
    shift 2
    for step in "$@"; do
        case $step in
        phisplit)
            python3 $here/phi_split.py "$t/x.spvasm" "$t/y.spvasm"
            python3 $here/pointer_phi.py "$t/y.spvasm" "$t/x.spvasm"
            ;;
        opt)
            spirv-as --preserve-numeric-ids --target-env vulkan1.1 "$t/x.spvasm" -o "$t/x.spv"
            spirv-opt --target-env=vulkan1.1 --eliminate-insert-extract --eliminate-dead-code-aggressive \
                --eliminate-insert-extract --eliminate-dead-code-aggressive "$t/x.spv" -o "$t/y.spv"
            spirv-dis --raw-id "$t/y.spv" -o "$t/x.spvasm"
            ;;
        *) python3 $here/knock_out.py "$t/x.spvasm" "$t/y.spvasm" "$step" && mv "$t/y.spvasm" "$t/x.spvasm" ;;
        esac
    done
    spirv-as --preserve-numeric-ids --target-env vulkan1.1 "$t/x.spvasm" -o "$out"
    spirv-val --target-env vulkan1.1 "$out"
    rm -rf "$t"
}
pack() { xz -T2 -6 -c "$1" >"$2.xz"; }
mkdir -p "$dst"/spirv "$dst"/spirv-phifree "$dst"/spirv-phisplit
tmp=$(mktemp -d)
for f in "$spv"/*.spv; do
    b=$(basename "$f")
    pack "$f" "$dst/spirv/$b"
    variant "$f" "$tmp/$b" phisplit opt && pack "$tmp/$b" "$dst/spirv-phifree/$b"
    variant "$f" "$tmp/$b" phisplit && pack "$tmp/$b" "$dst/spirv-phisplit/$b"
done
lt=boundtrace-gpu-shader-linear-taylor-blobs.spv
for v in orig noi8 nocopy noi8,nocopy O Os all; do
    d=$dst/var/${v//,/_}
    mkdir -p "$d"
    cp "$dst/spirv/boundtrace-gpu-shader.spv.xz" "$d/"
    case $v in
    orig) cp "$spv/$lt" "$tmp/$lt" ;;
    O | Os) spirv-opt --target-env=vulkan1.1 -$v "$spv/$lt" -o "$tmp/$lt" ;;
    all) variant "$spv/$lt" "$tmp/$lt" phisplit opt noi8,nocopy ;;
    *) variant "$spv/$lt" "$tmp/$lt" "$v" ;;
    esac
    pack "$tmp/$lt" "$d/$lt"
done
rm -rf "$tmp"
du -sh "$dst" .gl
