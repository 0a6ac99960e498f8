#!/usr/bin/env bash
# Instruction counts per query of semgraph_covariance_bench's kernels with callgrind, at d = 8
# and 64: compiled pose with covariance, the hand-written Eigen chain with covariance, and the
# compiled pose without covariance; prints Ir per query and the two ratios.
#   bench/covariance_icount.sh [BUILD_DIR]   (ITERS, default 1000)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build}"
bin="$build/bench/semgraph_covariance_bench"
iters="${ITERS:-1000}"
work="$(mktemp -d -t semgraph-covicount.XXXXXX)"
command -v valgrind >/dev/null || { echo "covariance_icount.sh: valgrind is not installed" >&2; exit 1; }
ir() {  # kernel d -> Ir per query
  local out="$work/$1-$2.out"
  LD_BIND_NOW=1 valgrind --tool=callgrind --callgrind-out-file="$out" \
    --toggle-collect="icount_$1" "$bin" icount "$1" "$2" "$iters" >/dev/null 2>&1 || true
  local total
  total="$(grep -E '^(summary|totals):' "$out" | head -1 | awk '{print $2}')"
  echo $(( total / iters ))
}
echo "| d | compiled with covariance | hand-written Eigen chain | compiled without | cov / hand | cov / without |"
echo "|---|---|---|---|---|---|"
for d in 8 64; do
  c="$(ir compiled_cov "$d")"; r="$(ir raw_eigen_cov "$d")"; p="$(ir compiled_plain "$d")"
  printf '| %s | %s | %s | %s | %.2f | %.2f |\n' "$d" "$c" "$r" "$p" \
    "$(echo "$c / $r" | bc -l)" "$(echo "$c / $p" | bc -l)"
done
