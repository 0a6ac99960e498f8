#!/usr/bin/env bash
# Instruction counts of the time benchmarks (bench/time_icount.cc) with callgrind:
#   bench/time_icount.sh [BUILD_DIR]     (ITERS, default 1000; DEPTHS, default "1 8 64")
# Prints Ir per operation for each kernel and depth (total Ir inside icount_<fn> / ITERS).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build-bench}"
bin="$build/bench/semgraph_time_icount"
iters="${ITERS:-1000}"
work="$(mktemp -d -t semgraph-time-icount.XXXXXX)"
count() {  # kernel function d
  LD_BIND_NOW=1 valgrind --tool=callgrind --callgrind-out-file="$work/$1.$3.out" --toggle-collect="icount_$2" \
    "$bin" "$1" "$3" "$iters" >/dev/null 2>&1 || { echo "n/a"; return; }
  local ir
  ir=$(callgrind_annotate "$work/$1.$3.out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1; exit}')
  if [ -z "$ir" ]; then echo "n/a"; else echo $(( ir / iters )); fi
}
printf "| kernel | %s |\n|---|%s\n" "$(echo ${DEPTHS:-1 8 64} | sed 's/ / | /g')" "$(for d in ${DEPTHS:-1 8 64}; do printf -- '---|'; done)"
for k in "compiled_at_linear compiled_at" "compiled_at_screw compiled_at" "oneshot_at_linear oneshot_at" \
         "raw_interp_chain raw_interp_chain" "raw_chain raw_chain" "tf2_at tf2_at" \
         "stamped_insert stamped_insert" "tf2_insert tf2_insert"; do
  set -- $k
  row="| $1 |"
  for d in ${DEPTHS:-1 8 64}; do row="$row $(count "$1" "$2" "$d") |"; done
  echo "$row"
done
