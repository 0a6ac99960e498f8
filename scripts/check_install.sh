#!/usr/bin/env bash
# Checks that an installed semgraph can be used: installs BUILD_DIR into a temporary prefix,
# then configures, builds and runs the consumer project tests/consumer against it
# (find_package(semgraph) + semgraph::semgraph), with the compiler and flags of BUILD_DIR.
#
#   scripts/check_install.sh BUILD_DIR
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: scripts/check_install.sh BUILD_DIR" >&2
  exit 2
fi
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="$1"
cache="$build_dir/CMakeCache.txt"
if [ ! -f "$cache" ]; then
  echo "check_install: $build_dir is not a configured build directory" >&2
  exit 2
fi

tmp="$(mktemp -d "${TMPDIR:-/tmp}/semgraph-install.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"

echo "check_install: + cmake --install $build_dir --prefix $prefix"
cmake --install "$build_dir" --prefix "$prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; exit 1; }

# Same compiler, flags and build type as the installed build (a sanitizer build needs them).
cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$cache"; }
consumer_args=(-DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
               -DCMAKE_CXX_COMPILER="$(cache_value CMAKE_CXX_COMPILER)"
               -DCMAKE_CXX_FLAGS="$(cache_value CMAKE_CXX_FLAGS)"
               -DCMAKE_BUILD_TYPE="$(cache_value CMAKE_BUILD_TYPE)")
echo "check_install: + cmake -S tests/consumer -B $tmp/build -DCMAKE_PREFIX_PATH=$prefix"
cmake -S "$root/tests/consumer" -B "$tmp/build" "${consumer_args[@]}"
cmake --build "$tmp/build" -j"${SEMGRAPH_JOBS:-2}"

found="$(sed -n 's/^semgraph_DIR:PATH=//p' "$tmp/build/CMakeCache.txt")"
case "$found" in
  "$prefix"/*) ;;
  *) echo "check_install: semgraph was found in '$found', not in the install prefix" >&2; exit 1 ;;
esac

echo "check_install: + semgraph_consumer"
"$tmp/build/semgraph_consumer"
echo "check_install: ok"
