#!/usr/bin/env bash
# Configures and builds semgraph.
#
#   scripts/build.sh [BUILD_DIR] [extra cmake args...]
#
# BUILD_DIR defaults to build/ at the repository root; a relative BUILD_DIR is taken from the
# current directory. The build type is Release unless an extra argument sets
# -DCMAKE_BUILD_TYPE (later -D arguments win). Builds with 2 jobs (SEMGRAPH_JOBS overrides).
# Builds every target, or only the targets listed in SEMGRAPH_TARGETS (space-separated).
# Examples:
#   scripts/build.sh
#   scripts/build.sh build-debug -DCMAKE_BUILD_TYPE=Debug -DSEMGRAPH_BUILD_BENCH=OFF
#   SEMGRAPH_TARGETS="semgraph_demo semgraph_cli" scripts/build.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${1:-$root/build}"
if [ $# -gt 0 ]; then shift; fi
jobs="${SEMGRAPH_JOBS:-2}"

echo "build: + cmake -S $root -B $build_dir -DCMAKE_BUILD_TYPE=Release $*"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
target_args=()
for target in ${SEMGRAPH_TARGETS:-}; do target_args+=(--target "$target"); done
echo "build: + cmake --build $build_dir -j$jobs ${target_args[*]}"
cmake --build "$build_dir" -j"$jobs" "${target_args[@]}"
