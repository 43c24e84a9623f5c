#!/usr/bin/env bash
# What --checkpoint costs: wall time of the same render without checkpoints, with the
# default interval (5 s) and with one save a second, each run RUNS times (median
# reported), plus the checkpoint's size on disk, read off a render killed near its end
# (bytes a tile and a pixel, extrapolated to the whole image), and the time a --resume
# of that checkpoint takes.
#
# Environment: NO_BUILD=1 skips `cargo build`; SCENE (the default scene), ARGS
# ("--integrator path --spp 16"), RUNS (3).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
runs="${RUNS:-3}"
read -r -a args <<< "${ARGS:---integrator path --spp 16}"
scene=()
[[ -n "${SCENE:-}" ]] && scene=("$SCENE")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
[[ -z "${NO_BUILD:-}" ]] && cargo build --release -q -p glint-cli
glint="$root/target/release/glint"

# Median wall seconds of `glint render` with the extra arguments given.
median_seconds() {
    local times=()
    for _ in $(seq "$runs"); do
        local start end
        start=$(date +%s.%N)
        "$glint" render "${scene[@]}" "${args[@]}" -q -o "$work/out.exr" "$@"
        end=$(date +%s.%N)
        times+=("$(echo "$end - $start" | bc)")
    done
    printf '%s\n' "${times[@]}" | sort -n | sed -n "$(( (runs + 1) / 2 ))p"
}

plain=$(median_seconds)
every5=$(median_seconds --checkpoint "$work/c.ckpt")
every1=$(median_seconds --checkpoint "$work/c.ckpt" --checkpoint-every 1)
printf 'render without checkpoints     %6.2f s\n' "$plain"
printf 'with --checkpoint (every 5 s)  %6.2f s  (%+.1f%%)\n' "$every5" "$(echo "($every5 / $plain - 1) * 100" | bc -l)"
printf 'with --checkpoint-every 1      %6.2f s  (%+.1f%%)\n' "$every1" "$(echo "($every1 / $plain - 1) * 100" | bc -l)"

# Size: a render killed at 90% of its time leaves most tiles in the file.
"$glint" render "${scene[@]}" "${args[@]}" -q -o "$work/k.exr" --checkpoint "$work/k.ckpt" --checkpoint-every 0.5 &
pid=$!
sleep "$(echo "$plain * 0.9" | bc -l)"
kill -9 "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
bytes=$(stat -c %s "$work/k.ckpt")
start=$(date +%s.%N)
resumed=$("$glint" render "${scene[@]}" "${args[@]}" -o "$work/r.exr" --resume "$work/k.ckpt" 2>&1 | grep resuming || true)
end=$(date +%s.%N)
done_tiles=$(echo "$resumed" | awk '{print $3}')
total_tiles=$(echo "$resumed" | awk '{print $5}')
echo "killed at 90%: checkpoint of $bytes bytes holding ${done_tiles:-?} of ${total_tiles:-?} tiles"
if [[ -n "$done_tiles" && "$done_tiles" -gt 0 ]]; then
    per_tile=$(( bytes / done_tiles ))
    echo "  $per_tile bytes a tile (16x16 pixels): $(( per_tile / 256 )) bytes a pixel;" \
         "the whole image: $(( per_tile * total_tiles / 1024 )) KiB"
fi
printf 'resume of the rest: %.2f s\n' "$(echo "$end - $start" | bc)"
cmp -s "$work/out.exr" "$work/r.exr" && echo "resumed image identical to the uninterrupted one" ||
    { echo "resumed image DIFFERS from the uninterrupted one"; exit 1; }
