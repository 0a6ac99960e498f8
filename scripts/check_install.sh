#!/usr/bin/env bash
# Checks that an installed semgraph can be used: installs BUILD_DIR into a temporary prefix,
# then, against that prefix only:
#   - the files: libraries (shared: SONAME libsemgraph_<layer>.so.MAJOR.MINOR, only semgraph's
#     API exported), headers with the generated export headers, pkg-config files, docs;
#   - CMake: configures, builds and runs the consumer project tests/consumer
#     (find_package(semgraph): semgraph::semgraph, and semgraph::script when the tools are
#     built, whose LoadSceneFile of examples/spray_painting.yaml must print the very lines the
#     installed `semgraph run` prints);
#   - pkg-config: builds the same consumer sources with `pkg-config --cflags --libs` of
#     semgraph.pc / semgraph-script.pc and runs them.
# The compiler, flags and build type are those of BUILD_DIR.
#
#   scripts/check_install.sh BUILD_DIR
#   scripts/check_install.sh --shared [--unoptimized] SHARED_DIR [FROM_DIR]
#
# --shared: first configures SHARED_DIR (unless it is configured already) as a shared-library
# build (BUILD_SHARED_LIBS=ON) of the libraries and the tool only - no tests, examples,
# benchmarks, fuzzers or Python module - with the compiler and flags of FROM_DIR when given,
# builds it, then checks it as above. --unoptimized builds it at -O0 (Debug without -g): what
# is checked is installing, linking and the exported symbols, and -O0 compiles several times
# faster (scripts/test.sh uses it).
set -euo pipefail

usage() { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; }
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="${SEMGRAPH_JOBS:-2}"

cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$2"; }

shared=0
unoptimized=0
if [ "${1:-}" = "--shared" ]; then shared=1; shift; fi
if [ "$shared" -eq 1 ] && [ "${1:-}" = "--unoptimized" ]; then unoptimized=1; shift; fi
if [ $# -lt 1 ] || [ $# -gt $((1 + shared)) ]; then usage >&2; exit 2; fi
build_dir="$1"

if [ "$shared" -eq 1 ]; then
  from_args=()
  if [ $# -eq 2 ]; then
    from_cache="$2/CMakeCache.txt"
    [ -f "$from_cache" ] || { echo "check_install: $2 is not a configured build directory" >&2; exit 2; }
    from_args=(-DCMAKE_CXX_COMPILER="$(cache_value CMAKE_CXX_COMPILER "$from_cache")"
               -DCMAKE_CXX_FLAGS="$(cache_value CMAKE_CXX_FLAGS "$from_cache")"
               -DCMAKE_BUILD_TYPE="$(cache_value CMAKE_BUILD_TYPE "$from_cache")")
  fi
  if [ "$unoptimized" -eq 1 ]; then  # later -D arguments win
    from_args+=(-DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0)
  fi
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    echo "check_install: + cmake -S $root -B $build_dir -DBUILD_SHARED_LIBS=ON (libraries and tool only)"
    cmake -S "$root" -B "$build_dir" -DBUILD_SHARED_LIBS=ON -DSEMGRAPH_BUILD_TESTS=OFF \
      -DSEMGRAPH_BUILD_BENCH=OFF -DSEMGRAPH_BUILD_FUZZ=OFF -DSEMGRAPH_BUILD_EXAMPLES=OFF \
      -DSEMGRAPH_BUILD_PYTHON=OFF -DSEMGRAPH_BUILD_TOOLS=ON "${from_args[@]}" >/dev/null
  fi
  echo "check_install: + cmake --build $build_dir -j$jobs"
  cmake --build "$build_dir" -j"$jobs"
fi

cache="$build_dir/CMakeCache.txt"
if [ ! -f "$cache" ]; then
  echo "check_install: $build_dir is not a configured build directory" >&2
  exit 2
fi
is_shared=0
case "$(cache_value BUILD_SHARED_LIBS "$cache")" in ON | on | TRUE | true | 1 | YES | yes) is_shared=1 ;; esac
kind=static; [ "$is_shared" -eq 1 ] && kind=shared

tmp="$(mktemp -d "${TMPDIR:-/tmp}/semgraph-install.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
fail() { echo "check_install ($kind): $*" >&2; exit 1; }

echo "check_install ($kind): + cmake --install $build_dir --prefix $prefix"
cmake --install "$build_dir" --prefix "$prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; exit 1; }

# ---------------------------------------------------------------- the installed files
libdir="$(dirname "$(find "$prefix" -name semgraphConfig.cmake -print -quit)")"
libdir="${libdir%/cmake/semgraph}"
[ -d "$libdir" ] || fail "no semgraphConfig.cmake installed"
has_script=0
[ -f "$prefix/include/semgraph/script/scene_script.h" ] && has_script=1
layers=(base semantics coord topology core)
[ "$has_script" -eq 1 ] && layers+=(script)
version="$(sed -n 's/^Version: //p' "$libdir/pkgconfig/semgraph.pc")"
[ -n "$version" ] || fail "no pkg-config file $libdir/pkgconfig/semgraph.pc"
major_minor="${version%.*}"
for layer in "${layers[@]}"; do
  [ -f "$prefix/include/semgraph/$layer/export.h" ] || fail "missing include/semgraph/$layer/export.h"
  if [ "$is_shared" -eq 1 ]; then
    lib="$libdir/libsemgraph_$layer.so"
    [ -L "$lib" ] || fail "missing $lib"
    soname="$(readelf -d "$lib" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')"
    [ "$soname" = "libsemgraph_$layer.so.$major_minor" ] || fail "$lib: SONAME '$soname', expected libsemgraph_$layer.so.$major_minor"
    [ -f "$libdir/libsemgraph_$layer.so.$version" ] || fail "missing libsemgraph_$layer.so.$version"
    # Only the API is exported: no symbol of an anonymous namespace or of core's message text
    # (core/src/text.h), and the API itself is there.
    nm -D -C --defined-only "$lib" >"$tmp/symbols.txt"
    if grep -E '\(anonymous namespace\)|semgraph::core::text::' "$tmp/symbols.txt" >"$tmp/leaks.txt"; then
      head -5 "$tmp/leaks.txt" >&2
      fail "$lib exports internal symbols"
    fi
  else
    [ -f "$libdir/libsemgraph_$layer.a" ] || fail "missing $libdir/libsemgraph_$layer.a"
  fi
done
if [ "$is_shared" -eq 1 ]; then
  nm -D -C --defined-only "$libdir/libsemgraph_core.so" "$libdir/libsemgraph_topology.so" >"$tmp/symbols.txt"
  for api in 'semgraph::core::SceneGraph<semgraph::coord::QuaternionBackend>::AddBody' \
             'semgraph::topology::PoseForest::CommonAncestor' \
             'semgraph::core::CheckInvariants<semgraph::coord::QuaternionBackend>' \
             'semgraph::core::Dump<semgraph::coord::HomogeneousBackend>'; do
    grep -qF "$api" "$tmp/symbols.txt" || fail "the shared libraries do not export $api"
  done
fi
for doc in README.md LICENSE rules.md scene-script.md coming-from-tf2.md realtime.md architecture.md; do
  [ -f "$prefix/share/doc/semgraph/$doc" ] || fail "missing share/doc/semgraph/$doc"
done
echo "check_install ($kind): installed files ok (${layers[*]})"

# ---------------------------------------------------------------- CMake consumer
# Same compiler, flags and build type as the installed build (a sanitizer build needs them).
consumer_args=(-DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
               -DCMAKE_CXX_COMPILER="$(cache_value CMAKE_CXX_COMPILER "$cache")"
               -DCMAKE_CXX_FLAGS="$(cache_value CMAKE_CXX_FLAGS "$cache")"
               -DCMAKE_BUILD_TYPE="$(cache_value CMAKE_BUILD_TYPE "$cache")")
echo "check_install ($kind): + cmake -S tests/consumer -B $tmp/build -DCMAKE_PREFIX_PATH=$prefix"
cmake -S "$root/tests/consumer" -B "$tmp/build" "${consumer_args[@]}" >"$tmp/consumer.log" ||
  { cat "$tmp/consumer.log"; exit 1; }
cmake --build "$tmp/build" -j"$jobs"

found="$(sed -n 's/^semgraph_DIR:PATH=//p' "$tmp/build/CMakeCache.txt")"
case "$found" in
  "$prefix"/*) ;;
  *) fail "semgraph was found in '$found', not in the install prefix" ;;
esac

example="$root/examples/spray_painting.yaml"
check_script_consumer() {  # $1: the consumer binary
  "$prefix/bin/semgraph" run "$example" >"$tmp/cli.jsonl" || fail "semgraph run $example failed"
  "$1" "$example" >"$tmp/load.jsonl" || fail "$1 $example failed"
  [ -s "$tmp/cli.jsonl" ] || fail "semgraph run printed nothing"
  diff -u "$tmp/cli.jsonl" "$tmp/load.jsonl" || fail "LoadSceneFile and semgraph run differ"
}

echo "check_install ($kind): + semgraph_consumer (CMake)"
"$tmp/build/semgraph_consumer"
if [ "$has_script" -eq 1 ]; then
  [ -x "$tmp/build/semgraph_script_consumer" ] || fail "semgraph::script was not found by the consumer"
  echo "check_install ($kind): + semgraph_script_consumer (CMake) vs semgraph run, $(basename "$example")"
  check_script_consumer "$tmp/build/semgraph_script_consumer"
fi

# ---------------------------------------------------------------- pkg-config consumer
cxx="$(cache_value CMAKE_CXX_COMPILER "$cache")"
read -r -a cxx_flags <<<"$(cache_value CMAKE_CXX_FLAGS "$cache") -std=c++20 -O0"  # nothing inlined
pc() { PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config "$@"; }
[ "$(pc --modversion semgraph)" = "$version" ] || fail "pkg-config does not find semgraph $version"
run_env=()
[ "$is_shared" -eq 1 ] && run_env=(env LD_LIBRARY_PATH="$libdir")
echo "check_install ($kind): + $cxx tests/consumer/main.cc \$(pkg-config --cflags --libs semgraph)"
read -r -a pc_flags <<<"$(pc --cflags --libs semgraph)"
"$cxx" "${cxx_flags[@]}" "$root/tests/consumer/main.cc" -o "$tmp/pc_consumer" "${pc_flags[@]}"
"${run_env[@]}" "$tmp/pc_consumer"
if [ "$has_script" -eq 1 ]; then
  echo "check_install ($kind): + $cxx tests/consumer/script_main.cc \$(pkg-config --cflags --libs semgraph-script)"
  read -r -a pc_flags <<<"$(pc --cflags --libs semgraph-script)"
  "$cxx" "${cxx_flags[@]}" "$root/tests/consumer/script_main.cc" -o "$tmp/pc_script_consumer" "${pc_flags[@]}"
  cat >"$tmp/pc_script_consumer.sh" <<EOF
#!/bin/sh
exec ${run_env[*]} "$tmp/pc_script_consumer" "\$@"
EOF
  chmod +x "$tmp/pc_script_consumer.sh"
  check_script_consumer "$tmp/pc_script_consumer.sh"
fi
echo "check_install ($kind): ok"
