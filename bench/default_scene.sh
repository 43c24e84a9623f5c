#!/usr/bin/env bash
# Time, ray throughput and peak memory of the built-in default scene at 800×600, on 1 and
# 2 threads (best of 5 runs each): as `glint render` ships it (one sample per pixel, up to
# 8 at edges, the floor's checker filtered over each pixel), and at one sample per pixel.
# Prints glint's own summary lines; nothing is compared against a peer here (see bench/
# for side-by-side runs).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p glint-cli
out=$(mktemp -d)
best_of_5() {
  for _ in 1 2 3 4 5; do
    ./target/release/glint render -o "$out/default.png" "$@" 2>&1 | tail -1
  done | sort -t' ' -k7 -n | head -1
}
for threads in 1 2; do
  echo "== $threads thread(s), as shipped"
  best_of_5 -j "$threads"
  echo "== $threads thread(s), one sample per pixel"
  best_of_5 -j "$threads" --samples 1
done
rm -rf "$out"
