#!/usr/bin/env bash
# Sets up the machine (Debian 12), builds semgraph in build/, runs every test with ctest, then
# checks that an installed semgraph works for a consumer project (scripts/check_install.sh):
# the static build of build/, and a shared-library build of the libraries and the tool only in
# build/shared (BUILD_SHARED_LIBS=ON, unoptimized: it checks linking and exports, not speed).
#
#   scripts/test.sh [extra ctest args...]      e.g. scripts/test.sh -R NameTable
#
# Exits non-zero if any step fails.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

scripts/setup.sh --dds --ros --bench  # every layer and every peer the tests compare with
scripts/build.sh build

status=0
echo "test: + ctest --test-dir build --output-on-failure -j2 $*"
ctest --test-dir build --output-on-failure -j2 "$@" || status=1
scripts/check_install.sh build || status=1
scripts/check_install.sh --shared --unoptimized build/shared build || status=1

if [ "$status" -ne 0 ]; then
  echo "test: FAILED" >&2
else
  echo "test: all passed"
fi
exit "$status"
