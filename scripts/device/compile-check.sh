#!/usr/bin/env bash
# A device run (the `device` tool; files from scripts/device/prepare.sh,
# carry ["target/device", ".gl"]): does the NVIDIA driver compile the
# tracing pipelines
# (modules as built, with the default stack and a 4 GiB stack; "phifree":
# no OpPhi of structs holding pointers, spirv-opt folded; "phisplit": the
# same without the folding)? Then frame times.
set -u
. scripts/device/setup.sh
ls -la "$D"/spirv*
export __GL_SHADER_DISK_CACHE_PATH=/tmp/nvcache __GL_SHADER_DISK_CACHE_SIZE=4000000000 __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1
mkdir -p /tmp/nvcache
{
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
    ls /usr/share/vulkan/icd.d /etc/vulkan/icd.d /usr/local/nvidia/share/vulkan/icd.d 2>&1
    which gdb cuda-gdb 2>&1
    ulimit -s
    nproc
} 2>&1 | tee "$OUT/env.txt"

# Is there an adapter at all? (the probes of the main module: fast)
if ! CI=true BOUNDTRACE_GPU_SPV=$D/spirv/boundtrace-gpu-shader.spv timeout 60 "$D/bin/probe" --test-threads 1 interval >"$OUT/probe0.txt" 2>&1; then
    cat "$OUT/probe0.txt" | tail -20
    VK_LOADER_DEBUG=error,warn,driver BOUNDTRACE_GPU_SPV=$D/spirv/boundtrace-gpu-shader.spv timeout 60 "$FT" 8 1 compile-only methods=sphere scenes=blobs-sum 2>&1 | tail -40
    ldconfig -p | grep -i "vulkan\|GLX\|EGL\|nvidia" | head -20
    exit 1
fi
tail -5 "$OUT/probe0.txt"
entries="sphere:blobs-sum segment:blobs-sum segment:blobs linear-taylor:blobs-sum linear-taylor:blobs quadratic-taylor:blobs-sum quadratic-taylor:blobs"
# Stage 1: every entry compiled in its own process (the driver's disk
# cache off for the default stack, on for the big one, which stage 3 uses), for each module variant, with the
# default stack and a 4 GiB one (RLIMIT_STACK also sets glibc's default
# thread stack size), all in parallel.
for vs in spirv:default spirv:big spirv-phifree:big spirv-phisplit:big; do
    v=${vs%%:*}
    st=${vs##*:}
        for e in $entries; do
            m=${e%%:*}
            s=${e##*:}
            f="$C/c-$v-$st-$m-$s.txt"
            (
                cache=0
                if [ $st = big ]; then ulimit -s 4194304; cache=1; fi
                start=$(date +%s%N)
                BOUNDTRACE_GPU_SPV=$D/$v/boundtrace-gpu-shader.spv __GL_SHADER_DISK_CACHE=$cache \
                    timeout 170 "$FT" 64 1 compile-only methods=$m scenes=$s >"$f" 2>&1
                echo "rc=$? after $(( ($(date +%s%N) - start) / 1000000 )) ms" >>"$f"
            ) &
        done
done
wait
echo "== compile stage done at $(el) s"
tar czf "$OUT/compile-logs.tgz" -C "$C" .
for f in "$C"/c-*.txt; do echo "$(basename "$f" .txt): $(grep -v '^adapter\|^|' "$f" | tr '\n' ' ' | tail -c 160)"; done
head -1 "$C"/c-spirv-default-sphere-blobs-sum.txt

pick=""
for v in spirv spirv-phifree spirv-phisplit; do
    ok=""
    for e in $entries; do
        m=${e%%:*}
        s=${e##*:}
        grep -q '^rc=0' "$C/c-$v-big-$m-$s.txt" && ok="$ok $m"
    done
    echo "$v compiled with the big stack:$ok"
    if [ -z "$pick" ] && [ -n "$ok" ]; then pick=$v; methods=$(echo $ok | tr ' ' '\n' | sort -u | paste -sd, -); fi
done

# Stage 2: if nothing compiled, where does the crash happen (stack depth)?
GDB=$(command -v gdb || command -v cuda-gdb || true)
if [ -z "$pick" ] && [ -n "$GDB" ]; then
    BOUNDTRACE_GPU_SPV=$D/spirv/boundtrace-gpu-shader.spv __GL_SHADER_DISK_CACHE=0 \
        timeout 120 "$GDB" -batch -ex run -ex 'bt 15' -ex 'bt -6' -ex 'info registers rsp' \
        --args "$FT" 64 1 compile-only methods=quadratic-taylor scenes=blobs-sum \
        >"$OUT/gdb.txt" 2>&1
    grep -v '^\[' "$OUT/gdb.txt" | tail -n 45
fi

# Stage 3: frame times at 1024² with the CPU (every core) beside them and
# a pixel-by-pixel comparison.
if [ -n "$pick" ]; then
    ulimit -s 4194304
    export BOUNDTRACE_GPU_SPV=$D/$pick/boundtrace-gpu-shader.spv
    echo "== frame times ($pick): $methods at $(el) s"
    timeout $((400 - $(el))) "$FT" 1024 5 cpu methods=$methods scenes=blobs,blobs-sum \
        2>"$OUT/ft-1024.err" | tee "$OUT/ft-1024.txt"
    echo "rc=$? at $(el) s"
    tail -4 "$OUT/ft-1024.err"
    if [ "$(el)" -lt 380 ]; then
        timeout $((430 - $(el))) "$D/bin/probe" --test-threads 1 --nocapture >"$OUT/probe.txt" 2>&1
        echo "probe rc=$?"
        tail -25 "$OUT/probe.txt"
    fi
fi
echo "== done at $(el) s"
