#!/usr/bin/env bash
# scripts/fuzz.sh TARGET SECONDS: build the libFuzzer binary of fuzz/TARGET.cc with clang (own
# build dir build-libfuzzer: ASan + UBSan, coverage of the whole library) and fuzz it for
# SECONDS, starting from fuzz/corpus/TARGET/. Prints exec/s and the total number of executions.
# SECONDS = 0 only builds.
#
#   TARGET   scene_ops_fuzzer | scene_script_fuzzer | yaml_tree_fuzzer | ros_messages_fuzzer |
#            mcap_reader_fuzzer | ros1_bag_reader_fuzzer
#   env      JOBS (build parallelism, default 1), FUZZ_FLAGS (extra libFuzzer flags, e.g.
#            "-jobs=2 -workers=2"), BUILD_DIR (default <repo>/build-libfuzzer)
#
# A BUILD_DIR configured already with -DSEMGRAPH_LIBFUZZER=ON (e.g. CI's clang ASan + UBSan
# build, whose flags include fuzzer-no-link) is used as it is: only the target is built.
#
# New interesting inputs go to BUILD_DIR/corpus/TARGET (the checked-in seeds are only read;
# copy inputs worth keeping into fuzz/corpus/TARGET/ by hand, e.g. after `-merge=1`). Crashes,
# leaks and timeouts land in fuzz/crashes/TARGET-*; replay one with
#   BUILD_DIR/fuzz/TARGET fuzz/crashes/TARGET-crash-...
# Exit status: 0 when the run found nothing, 1 when it left an artifact, 2 on usage errors.
set -euo pipefail

if [[ $# -ne 2 || ! "$2" =~ ^[0-9]+$ ]]; then
  echo "usage: $0 TARGET SECONDS   (TARGET: one of fuzz/*_fuzzer.cc, e.g. scene_ops_fuzzer)" >&2
  exit 2
fi
target=$1
seconds=$2
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BUILD_DIR:-$repo/build-libfuzzer}
seeds=$repo/fuzz/corpus/$target
crashes=$repo/fuzz/crashes
work=$build/corpus/$target
if [[ ! -f $repo/fuzz/$target.cc ]]; then
  echo "$0: unknown target $target (no fuzz/$target.cc)" >&2
  exit 2
fi

# The whole library gets coverage instrumentation (fuzzer-no-link); the oracle, Eigen and the
# standard library do not (fuzz/coverage_ignorelist.txt: they would only slow the search down).
flags="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all -fno-omit-frame-pointer"
flags+=" -fsanitize-coverage-ignorelist=$repo/fuzz/coverage_ignorelist.txt"
if grep -qx 'SEMGRAPH_LIBFUZZER:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: reusing the libFuzzer build $build as configured"
else
  CXX=${CXX:-clang++} cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSEMGRAPH_LIBFUZZER=ON -DSEMGRAPH_BUILD_TESTS=OFF -DSEMGRAPH_BUILD_BENCH=OFF \
    -DSEMGRAPH_BUILD_EXAMPLES=OFF -DSEMGRAPH_BUILD_TOOLS=ON -DCMAKE_CXX_FLAGS="$flags" >/dev/null
fi
cmake --build "$build" --target "$target" -j "${JOBS:-1}"
if [[ $seconds -eq 0 ]]; then  # build only (e.g. before `ctest --test-dir $build -R '^fuzz\.'`)
  echo "built $build/fuzz/$target"
  exit 0
fi

mkdir -p "$work" "$crashes"
log=$build/$target.log
echo "fuzzing $target for ${seconds}s (log: $log)"
status=0
# shellcheck disable=SC2086  # FUZZ_FLAGS is a list of flags
"$build/fuzz/$target" -max_len=4096 -max_total_time="$seconds" -timeout=25 -rss_limit_mb=4096 \
  -print_final_stats=1 -artifact_prefix="$crashes/$target-" ${FUZZ_FLAGS:-} "$work" "$seeds" \
  >"$log" 2>&1 || status=$?

execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
cov=$(grep -aE '^#[0-9]+' "$log" | tail -1 | sed -n 's/.*cov: \([0-9]*\).*ft: \([0-9]*\).*corp: \([0-9/a-zA-Z]*\).*/cov \1, features \2, corpus \3/p')
echo "$target: ${execs:-?} executions, ${rate:-?} exec/s over ${seconds}s${cov:+; $cov}"
if [[ $status -ne 0 ]]; then
  echo "$target: the fuzzer stopped with status $status; artifacts:" >&2
  ls -1 "$crashes/$target-"* 2>/dev/null >&2 || true
  echo "---- the end of $log:" >&2
  tail -n 80 "$log" >&2
  exit 1
fi
