#!/usr/bin/env bash
# semgraph serve + echo + dot --live on loopback (DDS domain 31): the mirrored answer equals
# the one `semgraph run` prints for the same query on the same script, within 1e-12.
#   cli_test.sh SEMGRAPH_BINARY SCRIPT
set -euo pipefail
# This run's own discovery tag (as tests/dds/dds_isolation.h): Cyclone DDS ignores participants
# with another tag, e.g. the same test run at the same time from another checkout.
tag="semgraph-test-$$-$RANDOM$RANDOM"
export CYCLONEDDS_URI="${CYCLONEDDS_URI:+$CYCLONEDDS_URI,}<Discovery><Tag>$tag</Tag></Discovery>"
tool="$1"
script="$2"
out="$(mktemp -d)"
"$tool" serve "$script" --domain 31 --seconds 8 > "$out/serve" &
serve_pid=$!
trap 'kill -9 $serve_pid 2>/dev/null || true; rm -rf "$out"' EXIT
"$tool" echo pose f1 o2 --domain 31 --count 1 --seconds 5 > "$out/echo"
"$tool" dot --live --domain 31 --seconds 5 > "$out/dot"
"$tool" run "$script" > "$out/run" || true
grep -q 'digraph semgraph' "$out/dot"
grep -c ' -> ' "$out/dot" | grep -qx 9  # 5 pose + 4 twist edges
python3 - "$out/echo" "$out/run" <<'PY'
import json, sys
echo = json.loads(open(sys.argv[1]).readline())
run = [json.loads(l) for l in open(sys.argv[2])]
want = next(r for r in run if r.get("kind") == "query pose" and r.get("line") == 47)
for key in ("position", "quaternion"):
    for a, b in zip(echo[key], want[key]):
        assert abs(a - b) <= 1e-12, (key, echo[key], want[key])
print("echo matches run:", echo["position"])
PY
