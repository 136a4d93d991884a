#!/usr/bin/env bash
# Second device run: compile-test variants of the linear-taylor (Blobs) leg
# module (scripts/device/prepare.sh): without Int8, without OpCopyMemory,
# both, spirv-opt -O / -Os, and all of that on the phi-free module.
set -u
. scripts/device/setup.sh
for v in orig noi8 nocopy noi8_nocopy O Os all; do
    f="$C/v-$v.txt"
    (
        start=$(date +%s%N)
        BOUNDTRACE_GPU_SPV=$D/var/$v/boundtrace-gpu-shader.spv __GL_SHADER_DISK_CACHE=0 \
            timeout 160 "$FT" 64 1 compile-only methods=linear-taylor scenes=blobs-sum >"$f" 2>&1
        echo "rc=$? after $(( ($(date +%s%N) - start) / 1000000 )) ms" >>"$f"
    ) &
done
wait
echo "== compile stage done at $(el) s"
head -1 "$C/v-orig.txt"
for f in "$C"/v-*.txt; do echo "$(basename "$f" .txt): $(grep -v '^adapter\|^|' "$f" | tr '\n' ' ' | tail -c 200)"; done
tar czf "$OUT/variant-logs.tgz" -C "$C" .
for v in noi8 nocopy noi8_nocopy O Os all; do
    if grep -q '^rc=0' "$C/v-$v.txt"; then
            echo "== frame times with variant $v at $(el) s"
        BOUNDTRACE_GPU_SPV=$D/var/$v/boundtrace-gpu-shader.spv timeout $((330 - $(el))) \
            "$FT" 1024 5 cpu methods=linear-taylor scenes=blobs-sum 2>"$OUT/ft.err" | tee "$OUT/ft.txt"
        tail -3 "$OUT/ft.err"
        break
    fi
done
echo "== done at $(el) s"
