#!/usr/bin/env bash
# Regenerates the generated sections of BENCHMARKS.md (issue 12).
#
#   scripts/benchmarks.sh [--only NAME[,NAME…]] [--quick] [--list] [--dry-run]
#
# A generated section of BENCHMARKS.md is delimited by
#   <!-- BEGIN generated: NAME (scripts/benchmarks.sh; do not edit by hand) -->
#   …
#   <!-- END generated: NAME -->
# and its body is replaced by: the exact command, the machine (CPU model,
# cores, date, commit), then the command's stdout. Text outside the markers
# is never touched. A section whose command fails leaves BENCHMARKS.md
# unchanged for that section and makes the script exit non-zero.
#
#   --only NAMES  regenerate only these sections (comma-separated)
#   --quick       fewer repetitions / smaller inputs (to try the script;
#                 do not commit numbers produced with it)
#   --list        print the section names and their commands, then exit
#   --dry-run     print the new section bodies instead of editing the file
#
# Sections:
#   stats             per-scene tables (scripts/stats-tables.sh; long run)
#   slicing           thesis Table 2.1: slicing vs per-voxel sampling,
#                     scalis-foam 512x512, 512/1024 slices, 3 repetitions
#   fidget-heightmap  fidget's heightmap vs our first-hit depth image
#                     (crates/bench-fidget, outside the workspace)
#   fidget-intervals  interval containment: ours vs fidget
#   criterion         criterion suite → ratio tables (scripts/criterion_table.py)
#
# Environment: CARGO_TARGET_DIR is honoured (criterion's output is read from
# $CARGO_TARGET_DIR/criterion, default target/criterion).
set -euo pipefail

cd "$(dirname "$0")/.."
DOC=BENCHMARKS.md
ALL=(stats slicing fidget-heightmap fidget-intervals criterion)
QUICK=0
DRY=0
ONLY=""

usage() { sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//'; }

while [ $# -gt 0 ]; do
    case "$1" in
        --only) [ $# -ge 2 ] || { echo "error: --only needs a value" >&2; exit 2; }; ONLY="$2"; shift 2 ;;
        --quick) QUICK=1; shift ;;
        --dry-run) DRY=1; shift ;;
        --list) LIST=1; shift ;;
        -h|--help) usage; exit 0 ;;
        *) echo "error: unknown option $1" >&2; usage >&2; exit 2 ;;
    esac
done

FIDGET="cargo run --release --quiet --manifest-path crates/bench-fidget/Cargo.toml --"

# The command of a section (one string, run with bash -c; printed verbatim).
command_of() {
    case "$1" in
        stats)
            if [ "$QUICK" = 1 ]; then echo "scripts/stats-tables.sh --quick"; else echo "scripts/stats-tables.sh"; fi ;;
        slicing)
            if [ "$QUICK" = 1 ]; then
                echo "cargo run --release --quiet --example slice -- --scene scalis-foam --size 128 --slices 128 --sample-2n --reps 2"
            else
                echo "cargo run --release --quiet --example slice -- --scene scalis-foam --size 512 --slices 512 --sample-2n --reps 3"
            fi ;;
        fidget-heightmap)
            if [ "$QUICK" = 1 ]; then
                echo "$FIDGET heightmap --scenes aggregate-1,aggregate-2,examples/scenes/primitives.json --size 64 --threads 1 --reps 2"
            else
                echo "$FIDGET heightmap --scenes aggregate-1,aggregate-2,aggregate-3,examples/scenes/primitives.json,examples/scenes/operators.json --size 128 --threads 1,2 --reps 3 --renderers fidget-jit,fidget-vm,full:sphere,sync:sphere && $FIDGET heightmap --scenes aggregate-4 --size 128 --threads 2 --reps 1 --renderers fidget-jit,sync:sphere && $FIDGET heightmap --scenes aggregate-1,aggregate-2,aggregate-3 --size 128 --threads 2 --reps 3 --eps voxel --renderers fidget-jit,full:sphere,sync:sphere"
            fi ;;
        fidget-intervals)
            if [ "$QUICK" = 1 ]; then echo "$FIDGET intervals --samples 20000"; else echo "$FIDGET intervals --samples 1000000"; fi ;;
        criterion)
            if [ "$QUICK" = 1 ]; then
                echo "BOUNDTRACE_BENCH_QUICK=1 cargo bench --quiet --features parallel --bench per_ray --bench frame >&2 && python3 scripts/criterion_table.py"
            else
                echo "cargo bench --quiet --features parallel --bench per_ray --bench frame >&2 && python3 scripts/criterion_table.py"
            fi ;;
        *) return 1 ;;
    esac
}

# What must exist for a section's command to run.
check_tools() {
    case "$1" in
        stats)
            [ -x scripts/stats-tables.sh ] || {
                echo "error: section 'stats' needs scripts/stats-tables.sh (executable), which is missing" >&2
                return 1
            } ;;
        fidget-heightmap|fidget-intervals)
            [ -f crates/bench-fidget/Cargo.toml ] || {
                echo "error: section '$1' needs crates/bench-fidget" >&2
                return 1
            } ;;
        criterion)
            command -v python3 >/dev/null || {
                echo "error: section 'criterion' needs python3 (scripts/criterion_table.py)" >&2
                return 1
            }
            [ -f scripts/criterion_table.py ] || {
                echo "error: section 'criterion' needs scripts/criterion_table.py" >&2
                return 1
            } ;;
    esac
}

if [ "${LIST:-0}" = 1 ]; then
    for s in "${ALL[@]}"; do printf '%s\n    %s\n' "$s" "$(command_of "$s")"; done
    exit 0
fi

if [ -n "$ONLY" ]; then
    IFS=',' read -r -a SECTIONS <<< "$ONLY"
else
    SECTIONS=("${ALL[@]}")
fi
for s in "${SECTIONS[@]}"; do
    command_of "$s" >/dev/null || { echo "error: unknown section '$s' (known: ${ALL[*]})" >&2; exit 2; }
done

machine() {
    local model cores
    model=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -n1)
    cores=$(nproc 2>/dev/null || echo "?")
    echo "Machine: ${model:-unknown CPU}, $cores logical cores ($(uname -sm)); $(date -u '+%Y-%m-%d %H:%M UTC'); commit \`$(git rev-parse --short HEAD 2>/dev/null || echo unknown)\`$(git diff --quiet 2>/dev/null || echo ' (with local changes)')$([ "$QUICK" = 1 ] && echo '; **--quick run**')."
}

# Replaces the body of section $1 in $DOC with the file $2.
replace_section() {
    local name="$1" body="$2" tmp
    if ! grep -q "^<!-- BEGIN generated: $name[ (]" "$DOC" || ! grep -q "^<!-- END generated: $name -->" "$DOC"; then
        echo "error: $DOC has no markers for section '$name'" >&2
        return 1
    fi
    tmp=$(mktemp)
    awk -v name="$name" -v body="$body" '
        BEGIN { skip = 0 }
        index($0, "<!-- BEGIN generated: " name " ") == 1 || $0 == "<!-- BEGIN generated: " name " -->" {
            print; while ((getline line < body) > 0) print line; skip = 1; next
        }
        $0 == "<!-- END generated: " name " -->" { skip = 0 }
        !skip { print }
    ' "$DOC" > "$tmp"
    mv "$tmp" "$DOC"
}

status=0
for s in "${SECTIONS[@]}"; do
    cmd=$(command_of "$s")
    if ! check_tools "$s"; then status=1; continue; fi
    echo ">> $s: $cmd" >&2
    out=$(mktemp)
    {
        echo
        echo "Command: \`$cmd\`"
        echo
        machine
        echo
    } > "$out"
    if bash -c "$cmd" >> "$out"; then
        echo >> "$out"
        if [ "$DRY" = 1 ]; then
            cat "$out"
        else
            replace_section "$s" "$out" || status=1
        fi
    else
        echo "error: section '$s': the command failed; $DOC left unchanged for it" >&2
        status=1
    fi
    rm -f "$out"
done
exit $status
