#!/usr/bin/env bash
# Instructions per query on a loaded bag (bench/ros_icount.cc) with callgrind:
#   bench/ros_icount.sh [BUILD_DIR]      (ITERS, default 1000; DEPTHS, default "2 3 4 5 6 7 8";
#                                         QUERIES=0 skips the queries, INGEST=0 the ingest)
# For each AGE (recent, middle), kernel and depth d: Ir collected inside icount_<kernel> / ITERS
# (valgrind --tool=callgrind --toggle-collect=icount_<kernel>, LD_BIND_NOW=1), then the ratio
# tf2 / semgraph for the one-shot and the compiled query. Prints markdown tables.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build-bench}"
bin="$build/bench/semgraph_ros_icount"
iters="${ITERS:-1000}"
depths="${DEPTHS:-2 3 4 5 6 7 8}"
work="$(mktemp -d -t semgraph-ros-icount.XXXXXX)"
export SEMGRAPH_BENCH_TMP="${SEMGRAPH_BENCH_TMP:-$work}"
command -v valgrind >/dev/null || { echo "ros_icount.sh: valgrind is not installed" >&2; exit 1; }
[ -x "$bin" ] || { echo "ros_icount.sh: $bin not found (build semgraph_ros_icount)" >&2; exit 1; }
count() {  # kernel d age -> Ir per query
  local out="$work/$1.$2.$3.out"
  LD_BIND_NOW=1 valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect="icount_$1" \
    "$bin" "$1" "$2" "$iters" "$3" >"$work/$1.$2.$3.log" 2>&1 || { echo "n/a"; return; }
  awk -v n="$iters" '/^totals:/ {t=$2} /^summary:/ {s=$2} END {v = (t != "" ? t : s); printf "%d", v / n}' "$out"
}
ages="recent middle"
[ "${QUERIES:-1}" = 0 ] && ages=""
for age in $ages; do
  echo "### AGE = $age"
  echo
  printf "| kernel \\\\ d |"; for d in $depths; do printf " %s |" "$d"; done; echo
  printf "|---|"; for d in $depths; do printf -- "---:|"; done; echo
  declare -A ir=()
  for k in oneshot_at compiled_at tf2_at; do
    printf "| %s |" "$k"
    for d in $depths; do ir[$k.$d]="$(count "$k" "$d" "$age")"; printf " %s |" "${ir[$k.$d]}"; done
    echo
  done
  for k in oneshot_at compiled_at; do
    printf "| tf2_at / %s |" "$k"
    for d in $depths; do
      awk -v a="${ir[tf2_at.$d]}" -v b="${ir[$k.$d]}" 'BEGIN {if (a == "n/a" || b == 0) printf " - |"; else printf " %.2f |", a / b}'
    done
    echo
  done
  unset ir
  echo
done
# Ingest: Ir per transform (16,002 transforms per iteration, ITERS_INGEST iterations, default 3).
ingest_iters="${ITERS_INGEST:-3}"
[ "${INGEST:-1}" = 0 ] && { echo "(callgrind files: $work)"; exit 0; }
echo "### Ingest, Ir per transform"
echo
echo "| kernel | Ir per transform |"
echo "|---|---:|"
for k in ingest_tflift ingest_tf2; do
  total="$(iters="$ingest_iters"; out="$work/$k.out"
    LD_BIND_NOW=1 valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect="icount_$k" \
      "$bin" "$k" 8 "$ingest_iters" >"$work/$k.log" 2>&1 || { echo "n/a"; exit 0; }
    awk '/^totals:/ {t=$2} /^summary:/ {s=$2} END {print (t != "" ? t : s)}' "$out")"
  if [ "$total" = "n/a" ]; then echo "| $k | n/a |"; else
    awk -v t="$total" -v n="$ingest_iters" -v k="$k" 'BEGIN {printf "| %s | %.0f |\n", k, t / (n * 16002)}'; fi
done
echo
echo "(callgrind files: $work)"
