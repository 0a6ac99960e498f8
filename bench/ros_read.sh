#!/usr/bin/env bash
# The bag reading benchmark: a 1 GiB MCAP bag streamed from a warm page cache.
#   bench/ros_read.sh [BUILD_DIR]   (MIB, default 1024; RUNS, default 3; COMPRESSION none|zstd;
#                                    SEMGRAPH_BENCH_TMP: where the bag is written, default /tmp)
# Writes the bag once with the bench's own MCAP writer (semgraph_ros_bag_read write: the robot
# of bench/ros_bench_data.h, /tf messages of 8 transforms, 1 MiB chunks with CRC32s, a summary),
# and a 1 MiB bag of the same content for the baseline memory; reads the file once with cat to
# warm the page cache; then RUNS times each of
#   read   OpenBag + Next over every record            scan   ScanBag (decodes every message)
#   load   LoadBag into a graph (10 s window, 1,024 samples per edge)
# under /usr/bin/time -v, and prints the median MB/s (10^6 bytes/s) by wall time and by CPU time
# (user + system: on a shared machine the wall time also counts other processes' turns), and the
# peak RSS of the process (time -v's "Maximum resident set size"), for the 1 GiB bag and the
# 1 MiB one.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build-bench}"
bin="$build/bench/semgraph_ros_bag_read"
mib="${MIB:-1024}"
runs="${RUNS:-3}"
compression="${COMPRESSION:-none}"
dir="${SEMGRAPH_BENCH_TMP:-/tmp}"
[ -x "$bin" ] || { echo "ros_read.sh: $bin not found (build semgraph_ros_bag_read)" >&2; exit 1; }
big="$dir/semgraph_ros_read_${mib}MiB_$compression.mcap"
small="$dir/semgraph_ros_read_1MiB_$compression.mcap"
[ -f "$big" ] || "$bin" write "$big" "$mib" "$compression" >&2
[ -f "$small" ] || "$bin" write "$small" 1 "$compression" >&2
cat "$big" > /dev/null
printf "| op | bag | MB/s wall (median of %s) | MB/s CPU (median) | peak RSS (MiB) | RSS growth while reading (MiB) |\n|---|---|---:|---:|---:|---:|\n" "$runs"
for op in read scan load; do
  for f in "$big" "$small"; do
    rates=() cpu_rates=() rss=0 growth=0
    for i in $(seq "$runs"); do
      line="$(/usr/bin/time -v "$bin" "$op" "$f" 2>"$dir/ros_read.time")"
      rates+=("$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["MB_per_s"])' "$line")")
      g="$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["rss_growth_kib"])' "$line")"
      r="$(awk -F': ' '/Maximum resident set size/ {print $2}' "$dir/ros_read.time")"
      cpu="$(awk -F': ' '/User time|System time/ {s += $2} END {print s}' "$dir/ros_read.time")"
      cpu_rates+=("$(awk -v b="$(stat -c %s "$f")" -v c="$cpu" 'BEGIN {print (c > 0 ? b / c / 1e6 : 0)}')")
      [ "$r" -gt "$rss" ] && rss="$r"
      [ "$g" -gt "$growth" ] && growth="$g"
    done
    median="$(printf '%s\n' "${rates[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
    cpu_median="$(printf '%s\n' "${cpu_rates[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')"
    printf "| %s | %s (%s bytes) | %s | %.1f | %.1f | %.1f |\n" "$op" "$(basename "$f")" \
      "$(stat -c %s "$f")" "$median" "$cpu_median" "$(echo "$rss / 1024" | bc -l)" \
      "$(echo "$growth / 1024" | bc -l)"
  done
done
