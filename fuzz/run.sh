#!/usr/bin/env bash
# Usage: fuzz/run.sh SECONDS [TARGET...]
# Builds every fuzz target (nightly, cargo-fuzz), seeds the corpora (seed.sh), then runs
# each target for SECONDS, one after another, and prints the executions of each.
# Crashes, timeouts and out-of-memory inputs are kept under fuzz/artifacts/<target>/;
# fork mode lets a target go on after a crash so it uses all its time.
# Environment: FUZZ_TARGET_DIR (default: fuzz/target), FUZZ_NICE (default 10).
set -euo pipefail
seconds="${1:?usage: fuzz/run.sh SECONDS [TARGET...]}"
shift
fuzz_dir="$(cd "$(dirname "$0")" && pwd)"
cd "$fuzz_dir"
all=(native course_xml course_json challenge_yaml mitsuba_xml pbrt obj ply gltf image render_scene)
[ $# -gt 0 ] && targets=("$@") || targets=("${all[@]}")
target_dir="${FUZZ_TARGET_DIR:-$fuzz_dir/target}"
nice_level="${FUZZ_NICE:-10}"

nice -n "$nice_level" cargo +nightly fuzz build --sanitizer none --target-dir "$target_dir"
"$fuzz_dir/seed.sh"
bin_dir="$target_dir/x86_64-unknown-linux-gnu/release"
mkdir -p logs
summary=()
for target in "${targets[@]}"; do
    mkdir -p "artifacts/$target"
    log="logs/$target.log"
    echo "== $target for ${seconds}s (log: fuzz/$log)"
    # One worker; the renderer's thread pool kept to one thread as well.
    RAYON_NUM_THREADS=1 nice -n "$nice_level" "$bin_dir/$target" "corpus/$target" \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
        -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
        -artifact_prefix="artifacts/$target/" >"$log" 2>&1 || true
    # Fork mode: the parent's last status line ("#N: cov: …") counts every child's
    # executions; without fork, libFuzzer's final stats do.
    execs=$(grep -oE '^#[0-9]+: cov' "$log" | tail -1 | grep -oE '[0-9]+' || true)
    [ -n "$execs" ] || execs=$(grep -oE 'stat::number_of_executed_units: [0-9]+' "$log" | awk '{s += $2} END {print s + 0}')
    found=$(find "artifacts/$target" -type f | wc -l)
    summary+=("$(printf '%-15s %12s executions  %3s artifacts' "$target" "$execs" "$found")")
    echo "${summary[-1]}"
done
echo "== summary"
printf '%s\n' "${summary[@]}"
