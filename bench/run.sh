#!/usr/bin/env bash
# The one command that runs every semgraph benchmark:
#
#   bench/run.sh                 # build build-bench (Release), run everything, summarize
#
# Steps:
#  1. cmake -S . -B build-bench (Release, no tests/fuzz/tools/examples) && cmake --build -j$JOBS
#  2. semgraph_bench with 5 repetitions, random interleaving, aggregates only, 0.1 s warm-up,
#     pinned to CPU $PIN (taskset, when available; PIN= turns pinning off), JSON to
#     bench/results/<date>.json (console output to bench/results/<date>.log)
#  3. the 1e5 and 1e6 random-tree builds once more, each in a fresh process (memory check:
#     rss_B_per_frame without earlier allocations in the process), bench/results/<date>-memcheck.json
#  4. bench/icount.sh (callgrind instruction counts), bench/results/icount-<date>.json
#  5. bench/summarize.py: markdown tables of medians and ratios, bench/results/<date>.md
#
# Environment: JOBS (default 2), PIN (default 1), BUILD (default build-bench), FILTER (a
# --benchmark_filter regex, default all), SKIP_ICOUNT=1, SKIP_MEMCHECK=1, REPS (default 5).
# About 12-15 minutes on the 2-vCPU development VM; run nothing else heavy meanwhile.
# The results carry no absolute paths: the benchmark binary is run from the repository root by a
# relative path (Google Benchmark records argv[0] as "executable"), and icount.sh records paths
# relative to the root, so checked-in results are the same on every machine.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="$(realpath -m "${BUILD:-$root/build-bench}")"
jobs="${JOBS:-2}"
pin="${PIN-1}"
reps="${REPS:-5}"
stamp="$(date -u +%Y-%m-%dT%H%M%SZ)"
results="$here/results"
mkdir -p "$results"

echo "run.sh: building $build (Release)"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DSEMGRAPH_BUILD_TESTS=OFF \
      -DSEMGRAPH_BUILD_FUZZ=OFF -DSEMGRAPH_BUILD_TOOLS=OFF -DSEMGRAPH_BUILD_EXAMPLES=OFF >/dev/null
cmake --build "$build" -j"$jobs" --target semgraph_bench semgraph_icount

taskset_cmd=()
if [ -n "$pin" ] && command -v taskset >/dev/null && taskset -c "$pin" true 2>/dev/null; then
  taskset_cmd=(taskset -c "$pin")
  echo "run.sh: pinned to CPU $pin"
else
  echo "run.sh: not pinned"
fi

cd "$root"
bench="$(realpath -m --relative-to="$root" "$build")/bench/semgraph_bench"
json="$results/$stamp.json"
# Which library version is measured (read-only git queries; no index writes).
commit="$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if ! GIT_OPTIONAL_LOCKS=0 git -C "$root" diff --quiet HEAD -- core coord semantics 2>/dev/null; then
  commit="$commit+local-changes"
fi
loadavg="$(cut -d' ' -f1-3 /proc/loadavg | tr ' ' '/')"
filter_args=()
if [ -n "${FILTER:-}" ]; then filter_args=(--benchmark_filter="$FILTER"); fi
echo "run.sh: $bench -> $json"
"${taskset_cmd[@]}" "$bench" \
  --benchmark_enable_random_interleaving=true \
  --benchmark_repetitions="$reps" \
  --benchmark_report_aggregates_only=true \
  --benchmark_min_warmup_time=0.1 \
  --benchmark_out="$json" --benchmark_out_format=json \
  --benchmark_context=semgraph_commit="$commit",load_before="$loadavg" \
  "${filter_args[@]}" 2>&1 | tee "$results/$stamp.log"

memcheck=()
if [ "${SKIP_MEMCHECK:-0}" != "1" ]; then
  mem_json="$results/$stamp-memcheck.json"
  parts=()
  for b in 'build_random_tree/100000/' 'build_random_tree/1000000/' \
           'tf2_build_tree_static/100000/' 'tf2_build_tree_static/1000000/'; do
    part="$results/.memcheck-$stamp-${#parts[@]}.json"
    if "${taskset_cmd[@]}" "$bench" --benchmark_filter="^$b" --benchmark_repetitions=1 \
         --benchmark_out="$part" --benchmark_out_format=json >/dev/null 2>&1; then
      parts+=("$part")
    fi
  done
  python3 - "$mem_json" "${parts[@]}" <<'EOF'
import json, sys
out, parts = sys.argv[1], sys.argv[2:]
merged = None
for p in parts:
    d = json.load(open(p))
    if merged is None:
        merged = d
    else:
        merged["benchmarks"] += d["benchmarks"]
if merged:
    json.dump(merged, open(out, "w"), indent=1)
EOF
  rm -f "${parts[@]}"
  [ -f "$mem_json" ] && memcheck=(--memcheck "$mem_json")
fi

icount=()
if [ "${SKIP_ICOUNT:-0}" != "1" ]; then
  icount_json="$results/icount-$stamp.json"
  ICOUNT_DIR="$results/callgrind-$stamp" "$here/icount.sh" "$build" "$icount_json" | tee "$results/icount-$stamp.md"
  icount=(--icount "$icount_json")
fi

python3 "$here/summarize.py" "$json" "${memcheck[@]}" "${icount[@]}" | tee "$results/$stamp.md"
echo "run.sh: results in $results/$stamp.{json,log,md}"
