#!/usr/bin/env bash
# The GPU backend's speed, in one call of a few minutes, side by side with its peers:
#   1. Cornell box (bench/mitsuba/cornell.xml, max_depth 8): path samples per second of
#      glint --device gpu, glint --device cpu, and Mitsuba 3's cuda_ad_rgb (OptiX) when its
#      CUDA variant loads (else llvm_ad_rgb on the CPU), each run twice, the second (warm:
#      kernels compiled and cached) reported;
#   2. primary rays per second on a 1M-triangle mesh: glint's path integrator with
#      max_depth 1 (camera rays and the emission lookup only) on the GPU and the CPU.
# glint's rates exclude setup (scene loading, BVH build, upload and kernel compilation),
# which it prints apart; its CPU rate counts every ray (camera, shadow and bounce rays),
# its GPU rate path samples. Mitsuba's is samples over its render time for all passes.
#
# Environment: NO_BUILD=1 skips `cargo build`; SIZE (512), SPP (256), MESH_SPP (16),
# MESH_SIZE (1024) scale the work (use SIZE=128 SPP=16 MESH_SIZE=256 MESH_SPP=4 on lavapipe).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
size="${SIZE:-512}"
spp="${SPP:-256}"
mesh_size="${MESH_SIZE:-1024}"
mesh_spp="${MESH_SPP:-16}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

if [[ -z "${NO_BUILD:-}" ]]; then
    cargo build --release -q -p glint-cli
fi
glint="$root/target/release/glint"

# The rate glint prints: "... : X M samples/s".
glint_rate() {
    "$glint" render "$@" 2>&1 | grep -v XDG_RUNTIME_DIR | tee /dev/stderr | sed -n 's/.*: \([0-9.]*\) M samples\/s.*/\1/p; s/.*rays, \([0-9.]*\) Mrays\/s.*/\1 Mrays/p' | tail -1
}

echo "== Cornell box ${size}x${size}, ${spp} spp, max_depth 8"
cornell=(bench/mitsuba/cornell.xml --width "$size" --height "$size" --spp "$spp" -o "$work/c.exr")
glint_rate "${cornell[@]}" --device gpu >/dev/null
gpu_rate=$(glint_rate "${cornell[@]}" --device gpu)
echo "glint gpu: ${gpu_rate} M samples/s; glint cpu: $(glint_rate "${cornell[@]}" --device cpu)/s (every ray)"

variant=""
for v in cuda_ad_rgb llvm_ad_rgb; do
    if python3 -c "import mitsuba as mi; mi.set_variant('$v')" 2>/dev/null; then
        variant="$v"
        break
    fi
done
if [[ -n "$variant" ]]; then
    mitsuba=(python3 bench/mitsuba/render.py bench/mitsuba/cornell.xml -o "$work/m.exr" --variant "$variant"
        --threads "$(nproc)" --spp "$spp" --pass-spp "$spp" -D "width=$size" -D "height=$size" -q)
    "${mitsuba[@]}" >/dev/null
    summary=$("${mitsuba[@]}" | tail -1)
    m_rate=$(python3 -c "import json,sys; print(round(json.loads(sys.argv[1])['samples_per_s'] / 1e6, 3))" "$summary")
    echo "mitsuba $variant: ${m_rate} M samples/s"
    echo "glint gpu / mitsuba $variant: $(echo "scale=2; $gpu_rate / $m_rate" | bc)x"
else
    echo "mitsuba: not installed (pip install mitsuba); skipped"
fi

echo "== primary rays, 1M-triangle mesh, ${mesh_size}x${mesh_size}, ${mesh_spp} spp"
python3 - "$work/bumpy.ply" <<'EOF'
# A bumpy sphere of 2·707·707 ≈ 1M triangles, binary PLY.
import math, struct, sys
n = 707
verts = []
for i in range(n + 1):
    theta = math.pi * i / n
    for j in range(n + 1):
        phi = 2 * math.pi * j / n
        r = 1 + 0.03 * math.sin(9 * theta) * math.sin(11 * phi)
        verts.append((r * math.sin(theta) * math.cos(phi), r * math.cos(theta), r * math.sin(theta) * math.sin(phi)))
faces = []
for i in range(n):
    for j in range(n):
        a = i * (n + 1) + j
        b, c, d = a + 1, a + n + 1, a + n + 2
        faces.append((a, c, b))
        faces.append((b, c, d))
with open(sys.argv[1], "wb") as f:
    f.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n".encode())
    f.write(b"".join(struct.pack("<3f", *v) for v in verts))
    f.write(b"".join(struct.pack("<B3i", 3, *t) for t in faces))
EOF
cat >"$work/mesh.glint" <<EOF
settings { width $mesh_size height $mesh_size integrator path { max_depth 1 } background 0.5 }
camera { eye [0 0 3.2] look_at [0 0 0] fov 40 }
material "m" { bsdf diffuse { reflectance 0.5 } emission 1 }
mesh "bumpy" { file "$work/bumpy.ply" }
mesh_instance "bumpy" { material "m" }
EOF
primary=("$work/mesh.glint" --spp "$mesh_spp" -o "$work/p.png")
glint_rate "${primary[@]}" --device gpu >/dev/null
echo "glint gpu primary rays: $(glint_rate "${primary[@]}" --device gpu) M rays/s"
echo "glint cpu primary rays: $(glint_rate "${primary[@]}" --device cpu)/s"
