#!/usr/bin/env bash
# Sets up the machine (Debian 12), builds the demo in build/ and runs it. Only the demo and the
# three library layers it links are built (not the tests, benchmarks, fuzzers or the tool), so
# the first result comes quickly; scripts/test.sh later builds the rest in the same build/.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

scripts/setup.sh
SEMGRAPH_TARGETS=semgraph_demo scripts/build.sh build
echo "demo: + build/examples/semgraph_demo"
echo
build/examples/semgraph_demo
