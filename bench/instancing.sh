#!/usr/bin/env bash
# Two-level instancing at scale: a field of flowering plants (one ~10,600-triangle plant
# placed as two instanced meshes) on a 293,000-triangle terrain, rendered at 1920×1080
# with one sample per pixel on all cores. Prints time and peak memory for 3,000, 30,000
# and 100,000 plants (up to about a billion instanced triangles); memory should follow the
# instance count, not the instanced triangle count.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p glint-cli --example plants
out=$(mktemp -d)
for plants in 3000 30000 100000; do
  ./target/release/examples/plants "$out/plants-$plants.png" "$plants" 1920 1080 | if [ "$plants" = 3000 ]; then cat; else tail -1; fi
done
echo "images in $out"
