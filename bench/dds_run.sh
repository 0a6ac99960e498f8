#!/usr/bin/env bash
# Distributed-scene benchmark on loopback: Cyclone's ddsperf round trip (the floor: one-way =
# round trip / 2) beside dds_bench's end-to-end latency (SetPose in the publisher -> a mirror's
# compiled query sees the value) and sustained updates/s into a mirror with a reader running.
#   bench/dds_run.sh [BUILD_DIR]      (default build/; needs ddsperf from cyclonedds-tools)
# Two dds_bench runs: the reader spinning with one write per update, and the reader blocked
# until the mirror's on_change with Publisher::BeginBatch/Flush batches of 100 updates.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
export CYCLONEDDS_URI="file://$root/tests/dds/cyclonedds-loopback.xml"
cmake --build "$build" -j2 --target dds_bench
echo "== ddsperf ping/pong, 12-byte samples, 5 s (round trip)"
timeout 9 ddsperf -D7 -i 42 pong > /dev/null 2>&1 &
sleep 0.5
timeout 8 ddsperf -D5 -i 42 ping 2>&1 | grep 'size 12' | tail -1
wait
echo "== dds_bench, reader spinning, one DDS write per update (end-to-end one-way latency, throughput)"
"$build/bench/dds_bench" 20000 300000 spin 1
echo "== dds_bench, reader waiting for the mirror's on_change, batches of 100 updates per write"
"$build/bench/dds_bench" 20000 300000 wait 100
