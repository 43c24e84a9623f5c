#!/usr/bin/env bash
# Fills fuzz/corpus/<target>/ with the repository's scenes, meshes and small images
# (and ../shared/course-scenes when it is there), plus the tiny seeds in fuzz/seeds/.
# The corpus is built at run time and not committed.
set -euo pipefail
fuzz_dir="$(cd "$(dirname "$0")" && pwd)"
repo="$(dirname "$fuzz_dir")"
corpus="$fuzz_dir/corpus"
sources=("$repo/scenes" "$repo/bench" "$repo/crates" "$repo/docs" "$fuzz_dir/seeds" "$fuzz_dir/../../shared/course-scenes")

# seed TARGET MAX_BYTES EXT...: copies files with those extensions, up to MAX_BYTES each
# (big seeds make every execution slow).
seed() {
    local target="$1" max="$2"
    shift 2
    local names=()
    for ext in "$@"; do names+=(-o -iname "*.$ext"); done
    mkdir -p "$corpus/$target"
    for dir in "${sources[@]}"; do
        [ -d "$dir" ] || continue
        find "$dir" -path '*/target' -prune -o -type f -size -"$max"c \( -false "${names[@]}" \) -print0 |
            while IFS= read -r -d '' file; do
                cp "$file" "$corpus/$target/$(echo "$file" | md5sum | cut -c1-16).${file##*.}"
            done
    done
    echo "$target: $(find "$corpus/$target" -type f | wc -l) seeds"
}

seed native 262144 glint
seed course_xml 262144 xml
seed course_json 262144 json
seed challenge_yaml 262144 yml yaml
seed mitsuba_xml 262144 xml
seed pbrt 262144 pbrt
seed obj 32768 obj
seed ply 262144 ply
seed gltf 262144 gltf glb
seed image 65536 png jpg jpeg hdr exr
mkdir -p "$corpus/render_scene"
