# shellcheck shell=bash
# Shared by bench/mitsuba_compare.sh and bench/mitsuba_speed.sh (sourced, not run).
# Expects $root (the repository root) to be set.

mitsuba_dir="${root:?set root before sourcing common.sh}/bench/mitsuba"
python="${PYTHON:-python3}"
# Rendered Mitsuba images are cached here, named by everything that determines them.
refs="${MITSUBA_REFS:-/work/mitsuba-refs}"

die() {
    echo "error: $*" >&2
    exit 1
}

# Finds libLLVM for Dr.Jit's LLVM backend unless DRJIT_LIBLLVM_PATH is already set.
find_libllvm() {
    if [[ -n "${DRJIT_LIBLLVM_PATH:-}" ]]; then
        [[ -e "$DRJIT_LIBLLVM_PATH" ]] || die "DRJIT_LIBLLVM_PATH=$DRJIT_LIBLLVM_PATH does not exist"
        return
    fi
    local cand
    for cand in /usr/lib/x86_64-linux-gnu/libLLVM-19.so /usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
        /usr/lib/aarch64-linux-gnu/libLLVM-19.so; do
        if [[ -e "$cand" ]]; then
            export DRJIT_LIBLLVM_PATH="$cand"
            return
        fi
    done
}

# Fails with the install commands unless Mitsuba 3, numpy and (for llvm variants) libLLVM are usable.
check_mitsuba() {
    local variants="$*"
    "$python" -c 'import mitsuba, numpy' 2>/dev/null ||
        die "Mitsuba 3 is not installed for $python; see bench/mitsuba/README.md:
    python3 -m pip install mitsuba==3.9.1 numpy
    apt-get install -y libllvm19"
    if [[ "$variants" == *llvm* ]]; then
        find_libllvm
        DRJIT_LIBLLVM_PATH="${DRJIT_LIBLLVM_PATH:-}" "$python" -c '
import sys, mitsuba as mi
try:
    mi.set_variant("llvm_ad_rgb")
except Exception as e:
    sys.exit(str(e))
' >/dev/null 2>&1 || die "Mitsuba's llvm_ad_rgb variant does not load (needs libLLVM: apt-get install -y libllvm19 and
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so); set MITSUBA_VARIANT=scalar_rgb to avoid it"
    fi
    [[ -f "$mitsuba_dir/assets/envmap.exr" && -f "$mitsuba_dir/assets/ring.obj" && -f "$mitsuba_dir/assets/panel.ply" ]] ||
        "$python" "$mitsuba_dir/make_assets.py" >/dev/null
    mkdir -p "$refs" || die "cannot create the reference cache $refs (set MITSUBA_REFS)"
}

# Short hash of a scene file and every asset, so that cached renders go stale when either changes.
scene_hash() {
    cat "$mitsuba_dir/$1.xml" "$mitsuba_dir"/assets/* | sha256sum | cut -c1-10
}

# mitsuba_render SCENE WIDTH HEIGHT SPP MAX_DEPTH SEED VARIANT THREADS
# Renders (or finds in the cache) a Mitsuba image and prints its path. The JSON summary of a
# fresh render (timings) is kept next to it as .json.
mitsuba_render() {
    local scene="$1" w="$2" h="$3" spp="$4" depth="$5" seed="$6" variant="$7" threads="$8"
    local name
    name="$scene-$(scene_hash "$scene")-${w}x${h}-d$depth-${spp}spp-seed$seed-$variant"
    local exr="$refs/$name.exr"
    if [[ ! -s "$exr" || ! -s "$refs/$name.json" ]]; then
        echo "  Mitsuba $variant: $scene ${w}x${h}, $spp spp, seed $seed ..." >&2
        "$python" "$mitsuba_dir/render.py" "$mitsuba_dir/$scene.xml" -o "$exr.tmp.exr" \
            --variant "$variant" --threads "$threads" --spp "$spp" --seed "$seed" \
            -D width="$w" -D height="$h" -D max_depth="$depth" --strict -q \
            >"$refs/$name.json.tmp" 2>"$refs/$name.log" || {
            cat "$refs/$name.log" >&2
            die "Mitsuba failed on $scene (log: $refs/$name.log)"
        }
        tail -n 1 "$refs/$name.json.tmp" | sed "s|$exr.tmp.exr|$exr|" >"$refs/$name.json"
        rm -f "$refs/$name.json.tmp"
        mv "$exr.tmp.exr" "$exr"
    else
        echo "  Mitsuba $variant: $scene ${w}x${h}, $spp spp, seed $seed (cached)" >&2
    fi
    echo "$exr"
}

# scene_default SCENE NAME: the value of <default name="NAME" value="..."/> in SCENE.xml.
scene_default() {
    sed -n "s/.*<default name=\"$2\" value=\"\([^\"]*\)\".*/\1/p" "$mitsuba_dir/$1.xml" | head -n 1
}
