#!/usr/bin/env bash
# Time, ray throughput and peak memory of the built-in default scene at 800×600 with one
# sample per pixel, on 1 and 2 threads (best of 5 runs each). Prints glint's own summary
# lines; nothing is compared against a peer here (see bench/ for side-by-side runs).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p glint-cli
out=$(mktemp -d)
for threads in 1 2; do
  echo "== $threads thread(s)"
  for _ in 1 2 3 4 5; do
    ./target/release/glint render -o "$out/default.png" --width 800 --height 600 --samples 1 -j "$threads" 2>&1 | tail -1
  done | sort -t' ' -k7 -n | head -1
done
rm -rf "$out"
