#!/usr/bin/env bash
# Side-by-side validation of glint's path tracer against Mitsuba 3 on the scenes of
# bench/mitsuba/ (Mitsuba 3 XML that both renderers read). For each scene: Mitsuba renders it
# twice with two seeds (A and B), glint once, all at the same resolution and spp; the table
# gives rMSE(glint, A), the noise floor rMSE(B, A) and their ratio (~1 when glint agrees with
# Mitsuba and is as noisy per sample; see bench/mitsuba/compare.py for the metric).
#
#   bench/mitsuba_compare.sh                       # all scenes, scene resolutions, 512 spp
#   SPP=128 SCENES="cornell envmap" bench/mitsuba_compare.sh
#   MITSUBA_ONLY=1 bench/mitsuba_compare.sh        # no glint: check the Mitsuba half only
#
# Environment (defaults in brackets):
#   SCENES [cornell glass-metal envmap emissive-mesh]   WIDTH, HEIGHT [each scene's own]
#   SPP [512]   MAX_DEPTH [each scene's own, 8]   THREADS [2]   SEED_A [3]  SEED_B [4]
#   MITSUBA_VARIANT [llvm_ad_rgb; scalar_rgb also works, ~3x slower]
#   MITSUBA_REFS [/work/mitsuba-refs]: cache of Mitsuba renders (reruns only render glint);
#       the highest-spp render there of the same scene, resolution and depth, if it has more
#       spp than SPP and a seed other than SEED_A and SEED_B, is the converged reference of
#       two more columns (glint and Mitsuba A against it).
#   GLINT [target/release/glint, built here with cargo build --release -p glint-cli unless
#       NO_BUILD=1]   GLINT_ARGS [extra arguments for glint render]   OUT [target/mitsuba-compare]
#
# Needs Mitsuba 3 for python3 (see bench/mitsuba/README.md for the install commands); CI does
# not run this. With the defaults it takes about 9 minutes on 2 cores: Mitsuba ~4.5 (cached
# afterwards) and glint ~4.5 at 0.8 Msamples/s (as on 2026-12-01); SPP=1024 doubles both.
# 512 spp keeps the converged references of /work/mitsuba-refs (1024-4096 spp) usable.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
# shellcheck source=mitsuba/common.sh
source "$root/bench/mitsuba/common.sh"

scenes="${SCENES:-cornell glass-metal envmap emissive-mesh}"
spp="${SPP:-512}"
threads="${THREADS:-2}"
seed_a="${SEED_A:-3}"
seed_b="${SEED_B:-4}"
variant="${MITSUBA_VARIANT:-llvm_ad_rgb}"
out="${OUT:-$root/target/mitsuba-compare}"
glint="${GLINT:-$root/target/release/glint}"
mitsuba_only="${MITSUBA_ONLY:-0}"

[[ "$seed_a" != "$seed_b" ]] || die "SEED_A and SEED_B must differ"
for scene in $scenes; do
    [[ -f "$mitsuba_dir/$scene.xml" ]] || die "no scene $mitsuba_dir/$scene.xml (SCENES=$scenes)"
done
check_mitsuba "$variant"
mkdir -p "$out"

if [[ "$mitsuba_only" != 1 ]]; then
    if [[ -z "${GLINT:-}" && "${NO_BUILD:-0}" != 1 ]]; then
        echo "building glint (cargo build --release -p glint-cli) ..." >&2
        (cd "$root" && cargo build --release -p glint-cli) || die "cargo build --release -p glint-cli failed"
    fi
    [[ -x "$glint" ]] || die "no glint binary at $glint (build it with cargo build --release -p glint-cli, or set GLINT)"
fi

manifest="$out/manifest.tsv"
: >"$manifest"
failed=()
for scene in $scenes; do
    w="${WIDTH:-$(scene_default "$scene" width)}"
    h="${HEIGHT:-$(scene_default "$scene" height)}"
    depth="${MAX_DEPTH:-$(scene_default "$scene" max_depth)}"
    [[ -n "$w" && -n "$h" && -n "$depth" ]] || die "$scene.xml lacks a width, height or max_depth <default>"
    echo "== $scene: ${w}x${h}, $spp spp, max_depth $depth" >&2

    a=$(mitsuba_render "$scene" "$w" "$h" "$spp" "$depth" "$seed_a" "$variant" "$threads")
    b=$(mitsuba_render "$scene" "$w" "$h" "$spp" "$depth" "$seed_b" "$variant" "$threads")

    # A converged reference: the highest-spp cached render of this scene at this size and
    # depth, independent of A and B (another seed: a render with seed A and more spp would
    # share A's first passes).
    ref=-
    best=0
    shopt -s nullglob
    for f in "$refs/$scene-$(scene_hash "$scene")-${w}x${h}-d$depth-"*spp-seed*.exr; do
        n=$(basename "$f" | sed -n 's/.*-\([0-9]*\)spp-seed.*/\1/p')
        s=$(basename "$f" | sed -n 's/.*-seed\([0-9]*\)-.*/\1/p')
        [[ "$s" != "$seed_a" && "$s" != "$seed_b" ]] || continue
        if [[ -n "$n" && "$n" -gt "$spp" && "$n" -gt "$best" ]]; then
            best=$n
            ref=$f
        fi
    done
    shopt -u nullglob
    [[ "$ref" == - ]] || echo "  converged reference: $(basename "$ref")" >&2

    g=-
    g_secs=-
    if [[ "$mitsuba_only" != 1 ]]; then
        g="$out/$scene-glint.exr"
        glint_cmd=("$glint" render "$mitsuba_dir/$scene.xml" -o "$g" --spp "$spp" --width "$w" --height "$h" -j "$threads" -q)
        if [[ -n "${MAX_DEPTH:-}" ]]; then
            glint_cmd+=(--max-depth "$depth")
        fi
        # shellcheck disable=SC2206 # GLINT_ARGS is split on purpose
        glint_cmd+=(${GLINT_ARGS:-})
        echo "  glint: ${glint_cmd[*]}" >&2
        start=$EPOCHREALTIME
        if "${glint_cmd[@]}" >"$out/$scene-glint.log" 2>&1; then
            g_secs=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.3f", b - a }')
        else
            echo "  glint FAILED on $scene; its output ($out/$scene-glint.log):" >&2
            sed 's/^/    /' "$out/$scene-glint.log" >&2
            failed+=("$scene")
            g=-
        fi
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$g" "$a" "$b" "$ref" "$g_secs" "${a%.exr}.json" >>"$manifest"
done

echo >&2
echo "glint vs Mitsuba 3 ($variant), $spp spp, seeds $seed_a/$seed_b, $threads threads; rMSE = mean((x-ref)^2/(ref^2+1e-2)), both clamped to [0,50]"
echo
"$python" "$mitsuba_dir/compare.py" table --out "$out" "$manifest"
if ((${#failed[@]})); then
    echo >&2
    die "glint failed on: ${failed[*]} (logs in $out)"
fi
