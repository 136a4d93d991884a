# Sourced by the device run scripts (compile-check.sh, variant-check.sh) in
# the repository root on the lent machine: $D (the carried target/device),
# $OUT, a log folder $C, `el` (seconds since start), the modules unpacked,
# and Vulkan set up from the carried Debian packages in .gl/.
D=$PWD/target/device
OUT=${OUT:-/tmp/out}
C=/tmp/clog
mkdir -p "$OUT" "$C"
t0=$(date +%s)
el() { echo $(($(date +%s) - t0)); }
find "$D" -name '*.spv.xz' -exec xz -d -T0 {} +
chmod +x "$D"/bin/*
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
if ! ls /usr/share/vulkan/icd.d/*nvidia* /etc/vulkan/icd.d/*nvidia* >/dev/null 2>&1; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    echo "VK_DRIVER_FILES=$VK_DRIVER_FILES"
fi
export XDG_RUNTIME_DIR=/tmp/xdg-$(id -u)
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
FT=$D/bin/gpu_frame_times
