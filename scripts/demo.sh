#!/usr/bin/env bash
# Sets up the machine (Debian 12), builds semgraph in build/ and runs the demo.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

scripts/setup.sh
scripts/build.sh build
echo "demo: + build/examples/semgraph_demo"
echo
build/examples/semgraph_demo
