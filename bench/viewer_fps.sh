#!/usr/bin/env bash
# The viewer's speed on the built-in default scene at 640×360, one sample per pixel,
# on every core (RAYON_NUM_THREADS=N to choose): passes per second (rendering alone),
# frames per second (rendering and drawing the window's picture), and the median time
# from an orbit input — arriving while a pass is in flight — to its first picture (a
# subsampled preview) and to its first full one-sample frame. Headless: the numbers
# leave out only the copy to the screen. Best of 3 runs by frames per second.
# Further arguments go to the viewer: `bench/viewer_fps.sh --device gpu` measures the
# GPU's sample passes (rays per second then reads 0: the GPU does not count rays).
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-target}"
cargo build --release -q -p glint-view --bin glint-view
for _ in 1 2 3; do
  "$target/release/glint-view" --no-window --bench --width 640 --height 360 "$@"
done | sort -t: -k3 -n | tail -1
