#!/usr/bin/env bash
# glint's mesh BVH against native Embree 3 (C++, Debian's libembree-dev), side by side
# on the same mesh and the same rays: build time, and closest/any-hit rays per second
# for camera (coherent) and random (incoherent) rays, single and in packets, on 1 and 2
# threads. glint and Embree run in interleaved rounds; each run times every query
# ROUNDS times and reports the median with the slowest and fastest; the table shows the
# median over rounds of those medians, the spread (min–max) of the medians, and
# glint/Embree ratios. glint's packets (8 rays) are compared with Embree's best packet
# width (4, 8 or 16) for the same query. Embree also runs in its robust mode
# (RTC_SCENE_FLAG_ROBUST: robust traversal and a Pluecker triangle test meant to be
# watertight, guarantees glint always gives; Embree's default Moeller-Trumbore test can
# miss along shared edges), as a like-for-like column beside the default.
#
# Usage: bench/embree_native.sh [GLBENCH1 file]    (default: glint bench's 1M-triangle scene)
# Environment: NO_BUILD=1 skips `cargo build`; QUICK=1 uses the 40,000-triangle scene;
# REPEATS (3) interleaved rounds; ROUNDS (5) timed runs per query; THREADS ("1 2");
# GLINT, the glint binary (default: target/release/glint); EMBREE_ISA (e.g. avx2), the
# kernels Embree may use (default: the best the CPU has; glint uses AVX2).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
repeats="${REPEATS:-3}"
rounds="${ROUNDS:-5}"
threads="${THREADS:-1 2}"

if [[ ! -f /usr/include/embree3/rtcore.h ]]; then
    echo "installing Debian's libembree-dev" >&2
    apt-get install -y -qq libembree-dev >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq libembree-dev >/dev/null; }
fi
[[ -z "${NO_BUILD:-}" ]] && cargo build --release -q -p glint-cli
glint="${GLINT:-$root/target/release/glint}"
g++ -O2 -std=c++17 bench/embree_native.cpp -lembree3 -lpthread -o "$work/embree_native"

input="${1:-$work/scene.bin}"
if [[ -z "${1:-}" ]]; then
    "$glint" bench ${QUICK:+--quick} --write-input "$input"
fi

for t in $threads; do
    for r in $(seq "$repeats"); do
        echo "threads $t, round $r: Embree…" >&2
        "$work/embree_native" "$input" "$t" "$rounds" >> "$work/embree_$t.jsonl"
        echo "threads $t, round $r: Embree, robust mode…" >&2
        EMBREE_ROBUST=1 "$work/embree_native" "$input" "$t" "$rounds" >> "$work/embree_robust_$t.jsonl"
        echo "threads $t, round $r: glint…" >&2
        "$glint" bench --input "$input" --threads "$t" --rounds "$rounds" --json >> "$work/glint_$t.jsonl"
    done
done

python3 - "$work" $threads <<'PY'
import json, statistics, sys
work, threads = sys.argv[1], sys.argv[2:]
def load(name):
    return [json.loads(line) for line in open(f"{work}/{name}") if line.strip()]
def spread(runs, key):
    values = [r[key] for r in runs if r.get(key) is not None]
    return statistics.median(values), min(values), max(values)
for t in threads:
    e, g, er = load(f"embree_{t}.jsonl"), load(f"glint_{t}.jsonl"), load(f"embree_robust_{t}.jsonl")
    clock = "Mrays per CPU second of the tracing thread" if t == "1" else "Mrays per wall-clock second"
    print(f"\n{int(g[0]['triangles'])} triangles, {t} tracing thread(s), {clock}; median (min–max) of {len(g)} rounds")
    gb, eb = spread(g, "build_s"), spread(e, "build_s")
    print(f"{'BVH build, CPU s (lower is better)':44} glint {gb[0]:7.3f}   Embree {eb[0]:7.3f}   glint/Embree {gb[0]/eb[0]:5.2f}")
    gw, ew = spread(g, "build_wall_s"), spread(e, "build_wall_s")
    print(f"{'BVH build, wall s':44} glint {gw[0]:7.3f}   Embree {ew[0]:7.3f}   glint/Embree {gw[0]/ew[0]:5.2f}")
    for kind in ["coherent", "incoherent"]:
        for query in ["closest", "any"]:
            gm = spread(g, f"{kind}_{query}_rays_per_s")
            em = spread(e, f"{kind}_{query}_rays_per_s")
            rm = spread(er, f"{kind}_{query}_rays_per_s")
            print(f"{kind+' '+query+', single':44} glint {gm[0]/1e6:7.3f} ({gm[1]/1e6:.2f}–{gm[2]/1e6:.2f})"
                  f"   Embree {em[0]/1e6:7.3f} ({em[1]/1e6:.2f}–{em[2]/1e6:.2f})   glint/Embree {gm[0]/em[0]:5.2f}"
                  f"   robust Embree {rm[0]/1e6:7.3f}   glint/robust {gm[0]/rm[0]:5.2f}")
            gp = spread(g, f"{kind}_{query}_packet_rays_per_s")
            def best_packets(runs):
                return max((spread(runs, f"{kind}_{query}_packet{w}_rays_per_s") + (w,) for w in (4, 8, 16)), key=lambda x: x[0])
            best, robust = best_packets(e), best_packets(er)
            print(f"{kind+' '+query+', packets':44} glint {gp[0]/1e6:7.3f} ({gp[1]/1e6:.2f}–{gp[2]/1e6:.2f})"
                  f"   Embree {best[0]/1e6:7.3f} ({best[1]/1e6:.2f}–{best[2]/1e6:.2f}) x{best[3]:<2}  glint/Embree {gp[0]/best[0]:5.2f}"
                  f"   robust Embree {robust[0]/1e6:7.3f} x{robust[3]:<2}  glint/robust {gp[0]/robust[0]:5.2f}")
    def disagree(runs):
        return int(sum(r.get(k, 0) for r in runs for k in r if "disagree" in k))
    print(f"rays whose hits disagree with glint's reference or packets with single rays: glint {disagree(g)}, "
          f"Embree {disagree(e)}, robust Embree {disagree(er)}")
PY
