#!/usr/bin/env bash
# Error against time for every pixel-sampling strategy, on one machine in one run.
# Writes docs/images/sampling/*.png and prints the Markdown table for docs/sampling.md.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release -q -p glint-cli --example sampling_bench -- docs/images/sampling
