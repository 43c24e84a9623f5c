#!/usr/bin/env bash
# Renders the solids of the gallery scenes (CSG, blobs, implicit surfaces) in glint and
# in POV-Ray with the same camera and resolution, as flat white on black coverage masks,
# and reports the share of pixels on which the two renderers agree.
#
#   bench/povray_compare.sh            # 400x300, results in target/povray-compare/
#   WIDTH=800 HEIGHT=600 bench/povray_compare.sh
#
# Needs POV-Ray 3.7 (`apt-get install -y povray`) and python3. The scene pairs live in
# bench/povray/: NAME.glint and NAME.pov describe the same objects; camera.inc explains
# how POV-Ray's left-handed camera with a horizontal angle is made to match glint's.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
width="${WIDTH:-400}"
height="${HEIGHT:-300}"
out="${OUT:-$root/target/povray-compare}"
glint="${GLINT:-$root/target/release/glint}"
threads="${THREADS:-2}"

# shellcheck source=povray/prelude.sh
source "$root/bench/povray/prelude.sh"

for scene in csg blobs implicit; do
    start=$(date +%s.%N)
    "$glint" render "$root/bench/povray/$scene.glint" -o "$out/$scene-glint.ppm" \
        --width "$width" --height "$height" -j "$threads" -q
    mid=$(date +%s.%N)
    # POV-Ray may only write below its working directory: run it from the output folder.
    (cd "$out" && povray "+I$root/bench/povray/$scene.pov" "+L$root/bench/povray" "+O$scene-povray.ppm" \
        "+W$width" "+H$height" -A +FP -D "+WT$threads" >"$scene-povray.log" 2>&1) || {
        echo "POV-Ray failed on $scene; see $out/$scene-povray.log" >&2
        exit 1
    }
    end=$(date +%s.%N)
    python3 "$root/bench/povray/compare_masks.py" "$out/$scene-glint.ppm" "$out/$scene-povray.ppm" \
        --name "$scene" --diff "$out/$scene-diff.ppm"
    printf '  time: glint %.2f s, POV-Ray %.2f s\n' "$(echo "$mid - $start" | bc)" "$(echo "$end - $mid" | bc)"
done
echo "masks and difference images (red: glint only, green: POV-Ray only) in $out"
