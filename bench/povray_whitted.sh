#!/usr/bin/env bash
# glint against POV-Ray 3.7 on a classic Whitted scene (bench/povray/whitted.glint and
# whitted.pov: seven analytic objects, two point lights, mirror and glass, 800x600),
# on the same cores, in two tables:
#
# 1. Trace rate without anti-aliasing, best and median of ROUNDS runs: rays counted as
#    POV-Ray counts them — camera, reflected and refracted rays, and shadow rays apart,
#    a shadow ray that goes on past a transparent surface counting once more for each
#    leg, as POV-Ray's "Shadow Ray Tests" do — over each renderer's own trace time
#    (POV-Ray's "Trace Time"; glint's "traced in", which leaves out parsing, the BVH
#    build and writing the image, as POV-Ray's does).
#    glint counts all its rays together; a second run with shadows off counts the
#    others (shadow rays spawn no rays, so the ray tree is the same).
# 2. The whole process at equal anti-aliasing error: each renderer's error is the RMS
#    difference (8-bit steps, sRGB) from its own converged image; POV-Ray runs with its
#    usual anti-aliasing (+A0.3 +R3), glint with a ladder of settings, and the table
#    gives wall-clock times from start to exit, best of ROUNDS runs each (read from
#    bash's clock, not a `date` process whose start-up would count against the faster
#    renderer). A second ladder renders the same scene
#    with glint's checker filtered over each pixel's footprint (`filtered true`, which
#    POV-Ray's procedural checker has no counterpart of), its error measured against
#    its own converged image and, for comparison, the point-sampled one.
#
#   bench/povray_whitted.sh          # results in target/povray-whitted/
#   THREADS=1 ROUNDS=5 bench/povray_whitted.sh
#
# Needs POV-Ray 3.7 (`apt-get install -y povray`) and python3.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
out="${OUT:-$root/target/povray-whitted}"
glint="${GLINT:-$root/target/release/glint}"
threads="${THREADS:-2}"
rounds="${ROUNDS:-3}"
scene="$root/bench/povray/whitted"
aa_error="$root/bench/povray/aa_error.py"

# shellcheck source=povray/prelude.sh
source "$root/bench/povray/prelude.sh"
sed 's/^  max_depth 5$/  max_depth 5\n  shadows false/' "$scene.glint" >"$out/whitted-no-shadows.glint"
grep -q 'shadows false' "$out/whitted-no-shadows.glint"
sed 's/cells \[2 2\] }/cells [2 2] filtered true }/' "$scene.glint" >"$out/whitted-filtered.glint"
grep -q 'filtered true' "$out/whitted-filtered.glint"

# glint NAME ARGS…: renders to NAME.ppm; prints "wall traced rays".
glint_run() {
    local name="$1" start end
    shift
    start=$EPOCHREALTIME
    "$glint" render "$@" -o "$out/$name.ppm" -j "$threads" 2>"$out/$name.log"
    end=$EPOCHREALTIME
    sed -n 's/.*traced in \([0-9.]*\) s.*: \([0-9]*\) rays,.*/\1 \2/p' "$out/$name.log" | tail -1 |
        { read -r traced rays; echo "$(echo "$end - $start" | bc) $traced $rays"; }
}

# pov NAME OPTIONS…: renders to NAME.ppm; prints "wall traced rays shadow_rays".
pov_run() {
    local name="$1" start end
    shift
    start=$EPOCHREALTIME
    (cd "$out" && povray "+I$scene.pov" "+L$root/bench/povray" "+O$name.ppm" +FP +W800 +H600 -D -V \
        "+WT$threads" "$@" >"$name.log" 2>&1) || { echo "POV-Ray failed; see $out/$name.log" >&2; exit 1; }
    end=$EPOCHREALTIME
    local traced rays shadow
    traced=$(sed -n 's/.*Trace Time:.*(\([0-9.]*\) seconds).*/\1/p' "$out/$name.log")
    rays=$(sed -n 's/^Rays: *\([0-9]*\).*/\1/p' "$out/$name.log")
    shadow=$(sed -n 's/^Shadow Ray Tests: *\([0-9]*\).*/\1/p' "$out/$name.log")
    echo "$(echo "$end - $start" | bc) $traced $rays $shadow"
}

echo "== trace rate, no anti-aliasing, 800x600, $threads threads, best and median of $rounds"
g_times=""; p_times=""
for _ in $(seq "$rounds"); do
    read -r _ g_traced g_all < <(glint_run glint-1 "$scene.glint")
    read -r _ p_traced p_rays p_shadow < <(pov_run pov-1 -A)
    g_times="$g_times $g_traced"; p_times="$p_times $p_traced"
done
read -r _ _ g_rays < <(glint_run glint-no-shadows "$out/whitted-no-shadows.glint")
g_shadow=$((g_all - g_rays))
python3 - "$g_rays" "$g_shadow" "$p_rays" "$p_shadow" "$g_times" "$p_times" <<'PY'
import statistics, sys
g_r, g_s, p_r, p_s = map(float, sys.argv[1:5])
g_times, p_times = ([float(t) for t in a.split()] for a in sys.argv[5:7])
print("| renderer | camera + secondary rays | shadow rays | trace time, best / median (s) | M rays/s (all), best |")
print("|---|---:|---:|---:|---:|")
for name, times, r, s in (("glint", g_times, g_r, g_s), ("POV-Ray 3.7", p_times, p_r, p_s)):
    t, m = min(times), statistics.median(times)
    print(f"| {name} | {r:,.0f} | {s:,.0f} | {t:.3f} / {m:.3f} | {(r + s) / t / 1e6:.2f} |")
rate = lambda t_g, t_p: ((g_r + g_s) / t_g) / ((p_r + p_s) / t_p)
print(f"glint/POV-Ray ray rate: {rate(min(g_times), min(p_times)):.2f}x "
      f"(by the medians: {rate(statistics.median(g_times), statistics.median(p_times)):.2f}x)")
PY

# best_wall RUN NAME ARGS…: RUN (glint_run or pov_run) ROUNDS times; prints the
# fastest wall time (the image is the same each time).
best_wall() {
    local fastest="" wall
    for _ in $(seq "$rounds"); do
        read -r wall _ < <("$@")
        if [[ -z "$fastest" ]] || (($(echo "$wall < $fastest" | bc))); then fastest=$wall; fi
    done
    echo "$fastest"
}

# report_best LABEL: the fastest glint wall time in `best` against POV-Ray's; clears `best`.
report_best() {
    if [[ -n "$best" ]]; then
        printf "%s: fastest glint setting at POV-Ray's error or less: %.3f s, %.2fx faster than POV-Ray\n" \
            "$1" "$best" "$(echo "$p_wall / $best" | bc -l)"
    else
        echo "$1: no glint setting reached POV-Ray's error"
    fi
    best=""
}

echo
echo "== whole process at equal anti-aliasing error (each against its own converged image)"
glint_run glint-reference "$scene.glint" --samples 16 --pattern jittered >/dev/null
pov_run pov-reference +A0.0 +AM1 +R8 +J >/dev/null
echo "| renderer, settings | wall (s) | AA error (8-bit RMS) |"
echo "|---|---:|---:|"
p_wall=$(best_wall pov_run pov-aa +A0.3 +AM1 +R3)
p_error=$(python3 "$aa_error" "$out/pov-aa.ppm" "$out/pov-reference.ppm")
printf '| POV-Ray +A0.3 +R3 | %.3f | %s |\n' "$p_wall" "$p_error"
p_none=$(python3 "$aa_error" "$out/pov-1.ppm" "$out/pov-reference.ppm")
echo "| POV-Ray, no anti-aliasing | – | $p_none |"
best=""
for settings in "--samples 2" "--samples 2 --pattern sobol" "--samples 3 --pattern sobol" \
    "--samples 4 --pattern sobol" "--adaptive 1,16,0.05" "--adaptive 2,8,0.04" "--adaptive 2,16,0.03" \
    "--adaptive 4,16,0.02"; do
    # shellcheck disable=SC2086 # the settings are words
    wall=$(best_wall glint_run glint-aa "$scene.glint" $settings)
    error=$(python3 "$aa_error" "$out/glint-aa.ppm" "$out/glint-reference.ppm")
    printf '| glint %s | %.3f | %s |\n' "$settings" "$wall" "$error"
    if (($(echo "$error <= $p_error" | bc))) && { [[ -z "$best" ]] || (($(echo "$wall < $best" | bc))); }; then
        best=$wall
    fi
done
g_none=$(python3 "$aa_error" "$out/glint-1.ppm" "$out/glint-reference.ppm")
echo "| glint, no anti-aliasing | – | $g_none |"
report_best "point-sampled checker"

echo
echo "== glint with the checker filtered over each pixel's footprint"
glint_run glint-filtered-reference "$out/whitted-filtered.glint" --samples 16 --pattern jittered >/dev/null
echo "| glint settings, checker filtered | wall (s) | AA error (own converged image) | AA error (point-sampled converged image) |"
echo "|---|---:|---:|---:|"
for settings in "--samples 1" "--adaptive 1,4,0.3" "--adaptive 1,4,0.1" "--adaptive 1,8,0.05" "--adaptive 1,16,0.03" "--adaptive 2,8,0.04"; do
    # shellcheck disable=SC2086 # the settings are words
    wall=$(best_wall glint_run glint-filtered "$out/whitted-filtered.glint" $settings)
    error=$(python3 "$aa_error" "$out/glint-filtered.ppm" "$out/glint-filtered-reference.ppm")
    error_point=$(python3 "$aa_error" "$out/glint-filtered.ppm" "$out/glint-reference.ppm")
    printf '| glint %s | %.3f | %s | %s |\n' "$settings" "$wall" "$error" "$error_point"
    if (($(echo "$error <= $p_error" | bc))) && { [[ -z "$best" ]] || (($(echo "$wall < $best" | bc))); }; then
        best=$wall
    fi
done
report_best "filtered checker"
