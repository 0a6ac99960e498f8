#!/usr/bin/env bash
# Instruction counts per query of semgraph_accelerations_bench's kernels with callgrind, at d = 8
# and 64: the compiled acceleration query, the hand-written Eigen chains (one pass: the limit;
# per edge: the evaluator's structure) and the compiled twist query on the same path; prints Ir
# per query and the ratios.
#   bench/accelerations_icount.sh [BUILD_DIR]   (ITERS, default 200)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build}"
bin="$build/bench/semgraph_accelerations_bench"
iters="${ITERS:-200}"
work="$(mktemp -d -t semgraph-accicount.XXXXXX)"
trap 'rm -rf "$work"' EXIT
command -v valgrind >/dev/null || { echo "accelerations_icount.sh: valgrind is not installed" >&2; exit 1; }
ir() {  # kernel d -> Ir per query
  local out="$work/$1-$2.out"
  LD_BIND_NOW=1 valgrind --tool=callgrind --callgrind-out-file="$out" \
    --toggle-collect="icount_$1" "$bin" icount "$1" "$2" "$iters" >/dev/null 2>&1 || true
  local total
  total="$(grep -E '^(summary|totals):' "$out" | head -1 | awk '{print $2}')"
  echo $(( total / iters ))
}
echo "| d | compiled acceleration | raw chain (one pass) | raw per edge | compiled twist | acc / raw chain | acc / per edge | acc / twist |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for d in 8 64; do
  c="$(ir compiled_acceleration "$d")"; r="$(ir raw_acceleration_chain "$d")"
  e="$(ir raw_acceleration_per_edge "$d")"; t="$(ir compiled_twist "$d")"
  printf '| %s | %s | %s | %s | %s | %.2f | %.2f | %.2f |\n' "$d" "$c" "$r" "$e" "$t" \
    "$(echo "$c / $r" | bc -l)" "$(echo "$c / $e" | bc -l)" "$(echo "$c / $t" | bc -l)"
done
