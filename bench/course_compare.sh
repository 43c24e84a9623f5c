#!/usr/bin/env bash
# Renders every course scene listed in the course-scenes collection's SOURCES.md with the
# settings of its reference image, compares the two, prints a table and rewrites
# docs/compatibility.md. Images and difference images go to target/course_compare/.
#
#   bench/course_compare.sh [COURSE_SCENES_DIR] [--only TEXT]
#
# COURSE_SCENES_DIR defaults to ../shared/course-scenes beside the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-../shared/course-scenes}"
[ $# -gt 0 ] && shift
if [ ! -f "$dir/SOURCES.md" ]; then
  echo "no course scenes at $dir (expected $dir/SOURCES.md)" >&2
  exit 2
fi
cargo run --release --quiet -p glint-scene --example course_compare -- \
  "$dir" --out target/course_compare --doc docs/compatibility.md "$@"
