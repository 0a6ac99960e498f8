#!/usr/bin/env bash
# semgraph serve --ros + echo --ros + check --ros on loopback (DDS domains 149, 150):
#  - the pose echo --ros prints for what serve --ros broadcasts (its first /tf samples wait for
#    echo: --subscribers 1) equals the answer `semgraph run`
#    prints for the same query on the same script, within 1e-12;
#  - check --ros on that clean stream (static own_body: arrival-order free): no finding, exit 0;
#  - check --ros on a stream with a second parent for a frame (ros_dds_test_node, an
#    independent raw writer): its finding as a JSON line, the summary, exit 1;
#  - check --ros --pose-topic --odom-topic: a good pose, a bad odometry message's finding.
#   cli_test.sh SEMGRAPH_BINARY TEST_NODE SCRIPT
set -euo pipefail
# This run's own discovery tag (as tests/dds/dds_isolation.h): Cyclone DDS ignores participants
# with another tag, e.g. the same test run at the same time from another checkout.
tag="semgraph-test-$$-$RANDOM$RANDOM"
export CYCLONEDDS_URI="${CYCLONEDDS_URI:+$CYCLONEDDS_URI,}<Discovery><Tag>$tag</Tag></Discovery>"
tool="$1"
node="$2"
script="$3"
out="$(mktemp -d)"
# Says which step failed and prints that step's output (set -e alone would fail silently).
fail() {
  echo "cli_test: $1; $2:" >&2
  cat "$2" >&2
  exit 1
}
"$tool" serve --ros "$script" --domain 149 --subscribers 1 --seconds 15 > "$out/serve" &
serve_pid=$!
trap 'kill -9 $serve_pid 2>/dev/null || true; rm -rf "$out"' EXIT
"$tool" echo --ros pose camera arm --domain 149 --rate 10 --seconds 8 > "$out/echo" || true
# own_body: a late joiner may take a /tf sample of {base} before the transient-local
# /tf_static that joins it to {world}; in same_body mode that order is frame_body_mismatch
# (docs/ros.md, live lift), which is not what this check is about.
"$tool" check --ros --static own_body --domain 149 --seconds 2 > "$out/clean" || {
  echo "check --ros on the clean stream failed; its output:" >&2
  cat "$out/clean" >&2
  exit 1
}
"$tool" run "$script" > "$out/run" || true
python3 - "$out/echo" "$out/run" "$out/clean" <<'PY'
import json, sys
answers = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
ok = [a for a in answers if a["ok"]]
assert ok, answers
run = [json.loads(l) for l in open(sys.argv[2])]
want = next(r for r in run if r.get("kind") == "query pose")
got = ok[-1]
for key in ("position", "quaternion"):
    for a, b in zip(got[key], want[key]):
        assert abs(a - b) <= 1e-12, (key, got[key], want[key])
assert abs(got["stamp"] - 100.5) < 1e-6, got
clean = [json.loads(l) for l in open(sys.argv[3])]
assert clean[-1]["summary"] and clean[-1]["findings"] == 0 and clean[-1]["transforms"] >= 4, clean
print("echo --ros matches run:", got["position"], "; clean check:", clean[-1])
PY
# A second parent for frame b.
"$tool" check --ros --domain 150 --seconds 6 > "$out/check" &
check_pid=$!
# a -> b, then c -> b, once each: the node waits until the listener is matched and in sync
# with its rt/tf writer (wait_subscribers), so both reach it; then until they are acknowledged.
printf 'wait_subscribers 1\ntf a b 10 0 0 0 0 0 0 0 1\ntf c b 10 0 0 0 0 0 0 0 1\nwait_acks\n' |
  "$node" 150 > "$out/node"
set +e
wait $check_pid
code=$?
set -e
grep -q '^ok 4$' "$out/node" || fail "the node did not finish the two-parent stream" "$out/node"
test "$code" = 1 || fail "check --ros on the two-parent stream exited $code, not 1" "$out/check"
python3 - "$out/check" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
finding = lines[0]
assert finding["error"] == "multiple_pose_parents", lines
assert (finding["topic"], finding["parent"], finding["child"]) == ("/tf", "c", "b"), finding
assert finding["count"] == 1 and abs(finding["first_stamp"] - 10.0) < 1e-9, finding
summary = lines[-1]
assert summary["summary"] and summary["findings"] == 1 and summary["groups"] == 1, lines
assert 2 <= summary["transforms"] == summary["messages"] <= 4, lines
print("check --ros:", finding["message"])
PY
# Pose and odometry topics: a good pose, then an odometry message with a NaN in its twist
# covariance, three times (stamps 20/21, 22/23, 24/25, half a second apart). Their readers are
# best effort: the node waits until its writers matched the listener's readers, then 2 s for the
# listener's side of the match (a best-effort reader drops samples of a writer it has not
# discovered yet; 300 ms was not enough once, in CI under load, and the CLI has no way to say it
# matched); a loaded sanitizer run still lost the one odometry message once, hence the repeats.
"$tool" check --ros --domain 150 --seconds 8 --pose-topic /amcl_pose=base_footprint \
  --odom-topic /odom > "$out/cov" &
check_pid=$!
# identity quaternion, then a 6x6 identity covariance (row-major); the twist's has a NaN
cov="0 0 0 1 $(python3 -c 'print(" ".join(str(float(i == j)) for i in range(6) for j in range(6)))')"
twist="0.4 0 0 0 0 0.1 $(python3 -c 'print(" ".join("nan" if i == j == 2 else str(float(i == j)) for i in range(6) for j in range(6)))')"
printf '%s\n' 'wait_match pose /amcl_pose 1' 'wait_match odom /odom 1' 'sleep 2000' \
  "pose /amcl_pose map 20 0 1 2 0 $cov" "odom /odom odom base_link 21 0 0.5 0 0 $cov $twist" \
  'sleep 500' \
  "pose /amcl_pose map 22 0 1 2 0 $cov" "odom /odom odom base_link 23 0 0.5 0 0 $cov $twist" \
  'sleep 500' \
  "pose /amcl_pose map 24 0 1 2 0 $cov" "odom /odom odom base_link 25 0 0.5 0 0 $cov $twist" |
  "$node" 150 > "$out/node_cov"
set +e
wait $check_pid
code=$?
set -e
grep -q '^ok 11$' "$out/node_cov" || fail "the node did not finish the pose and odometry" "$out/node_cov"
test "$code" = 1 || fail "check --ros on pose and odometry exited $code, not 1" "$out/cov"
python3 - "$out/cov" <<'PY'
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
finding = lines[0]
assert finding["error"] == "invalid_number", lines
assert (finding["topic"], finding["parent"], finding["child"]) == ("/odom", "odom", "base_link"), finding
assert min(abs(finding["first_stamp"] - t) for t in (21.0, 23.0, 25.0)) < 1e-9, finding
summary = lines[-1]
assert summary["summary"] and summary["groups"] == 1, lines
assert 1 <= summary["findings"] <= 3 and 2 <= summary["messages"] <= 6, lines
print("check --ros with pose and odometry topics:", finding["message"])
PY
