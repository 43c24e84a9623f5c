#!/usr/bin/env bash
# glint's mesh BVH against Embree (through the embreex Python bindings) on the same
# ~1M-triangle mesh and the same rays: build time and rays per CPU-second for coherent
# (camera) and incoherent (random) rays, closest hit and any hit, as glint/Embree ratios;
# and memory per triangle (glint's exact array bytes, and both processes' resident-set
# growth around one build).
# glint's numbers come from `glint bench --input`; the obvhs column is the obvhs crate's
# CWBVH over the same triangles, with glint's triangle test (examples/obvhs_bench.rs).
#
# Usage: bench/embree_compare.sh [work dir, default /tmp/glint-embree-bench]
# Needs python3 with venv and network access the first time (pip install embreex numpy).
set -euo pipefail
cd "$(dirname "$0")/.."
work="${1:-/tmp/glint-embree-bench}"
venv=/tmp/glint-embree-venv
mkdir -p "$work"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q "embreex==4.4.0.post1" numpy
fi
cargo build -q --release -p glint-cli --bin glint --example obvhs_bench
# Three rounds, Embree and glint interleaved, each library's best kept: other load on a
# shared machine then skews one side's numbers less.
embree="" glint=""
for round in 1 2 3; do
    echo "round $round: generating the mesh and rays, timing Embree…" >&2
    embree="$embree$("$venv/bin/python" bench/embree_compare.py "$work")"$'\n'
    echo "round $round: timing glint (glint bench)…" >&2
    glint="$glint$(target/release/glint bench --input "$work/scene.bin" --json)"$'\n'
done
echo "timing obvhs…" >&2
obvhs=$(target/release/examples/obvhs_bench "$work/scene.bin")
"$venv/bin/python" - "$embree" "$glint" "$obvhs" <<'PY'
import json, sys
def best(lines):
    """Per key, the best round: the highest rate, the shortest time, the first otherwise."""
    rounds = [json.loads(l) for l in lines.splitlines() if l.strip()]
    out = dict(rounds[0])
    for r in rounds[1:]:
        for k, v in r.items():
            if k.endswith("_per_s"):
                out[k] = max(out[k], v)
            elif k.endswith("_s"):
                out[k] = min(out[k], v)
    return out
e, g = best(sys.argv[1]), best(sys.argv[2])
g.update(json.loads(sys.argv[3]))
print(f"{int(g['triangles'])} triangles; rays on one thread, builds on all {int(g['threads'])} cores; CPU seconds, best of 3 runs x 3 interleaved rounds")
print(f"{'measure':30} {'glint':>8} {'obvhs':>8} {'Embree':>8} {'glint/Embree':>13} {'obvhs/Embree':>13}")
def row(name, key, scale, unit):
    a, o, b = g[key] / scale, g["obvhs_" + key] / scale, e[key] / scale
    print(f"{name:30} {a:>8.3f} {o:>8.3f} {b:>8.3f} {a / b:>13.2f} {o / b:>13.2f}   {unit}")
row("BVH build", "build_s", 1, "s (lower is better)")
for kind in ["coherent", "incoherent"]:
    for query, label in [("closest", "closest hit"), ("any", "any hit")]:
        row(f"{kind} rays, {label}", f"{kind}_{query}_rays_per_s", 1e6, "Mrays/s (higher is better)")
for query, label in [("closest", "closest hit"), ("any", "any hit")]:
    a, b = g[f"coherent_{query}_packet_rays_per_s"] / 1e6, e[f"coherent_{query}_rays_per_s"] / 1e6
    print(f"{'coherent, ' + label + ', packets':30} {a:>8.3f} {'':>8} {b:>8.3f} {a / b:>13.2f}   glint's 8-ray packets vs Embree's single rays (embreex has no packet API)")
print(f"{'  glint build, wall clock':30} {g['build_wall_s']:>8.3f}   s on {int(g['threads'])} threads")
t = g["triangles"]
print("memory, bytes per triangle (same mesh):")
print(f"  glint Mesh::memory_bytes (exact array bytes)       {g['memory_bytes'] / t:8.1f}")
for key, label in [("rss_growth_trimmed_bytes", "resident growth, free heap returned"),
                   ("rss_growth_bytes", "resident growth, as it stands")]:
    print(f"  {label:48} glint {g[key] / t:6.1f}  Embree {e[key] / t:6.1f}  glint/Embree {g[key] / e[key]:.2f}")
print(f"  glint exact / Embree resident (free heap returned) {g['memory_bytes'] / e['rss_growth_trimmed_bytes']:.2f}")
for kind in ["coherent", "incoherent"]:
    print(f"{kind}: hit fraction glint {g[kind + '_hit_fraction']:.4f} / obvhs {g['obvhs_' + kind + '_hit_fraction']:.4f}"
          f" / Embree {e[kind + '_hit_fraction']:.4f}; rays whose closest hit differs from Embree's: "
          f"{int(g[kind + '_disagree_with_reference'])}")
PY
