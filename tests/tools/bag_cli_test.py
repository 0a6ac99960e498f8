#!/usr/bin/env python3
"""`semgraph bag info`, `semgraph bag check` and the `bag` op of scene scripts, end to end.

A ROS 1 bag with every finding of the ROS spec's section 5 is written here by Debian's
python3-rosbag (an independent writer); the clean bags are the fixtures of tests/ros (Foxglove's
MCAP writer, python3-rosbag, Python's sqlite3). Expected findings and values are worked out by
hand below, not by semgraph.

usage: bag_cli_test.py SEMGRAPH FOXGLOVE_FIXTURES ROSBAG_FIXTURES SCRATCH
"""
import json
import math
import os
import subprocess
import sys

import genpy
import rosbag
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

TOOL, FOXGLOVE, ROSBAG, SCRATCH = sys.argv[1:5]
T0 = 1_700_000_000
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what)


def run(*args, stdin=None):
    p = subprocess.run([TOOL, *args], capture_output=True, text=True, input=stdin)
    return p.returncode, p.stdout, p.stderr


def tf(stamp, parent, child, xyz=(0, 0, 0), q=(0, 0, 0, 1)):
    t = TransformStamped()
    t.header.stamp = genpy.Time(T0 + int(stamp), int(round((stamp % 1) * 1e9)))
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
    (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
     t.transform.rotation.w) = q
    return t


def write_dirty_bag(path):
    """Static tree base_link -> camera; odom -> base_link moves; then one of each refusal."""
    with rosbag.Bag(path, "w") as bag:
        def put(topic, log, *transforms):
            bag.write(topic, TFMessage(transforms=list(transforms)), genpy.Time(T0 + log))
        put("/tf_static", 0, tf(0, "base_link", "camera", (0.1, 0, 0.5)))
        put("/tf", 1, tf(1, "odom", "base_link", (1, 0, 0)), tf(1, "map", "odom"))
        put("/tf", 2, tf(2, "odom", "base_link", (2, 0, 0)), tf(2, "map", "odom"))
        put("/tf", 3, tf(3, "world", "base_link"))                   # multiple_pose_parents
        put("/tf", 4, tf(4, "world", "base_link"))                   # same group, count 2
        put("/tf", 5, tf(5, "base_link", "map"))                     # pose_cycle
        put("/tf_static", 6, tf(0, "base_link", "camera", (0.2, 0, 0.5)))  # constant_pose_change
        put("/tf", 7, tf(7, "odom", "odom"))                         # self_edge
        put("/tf", 8, tf(8, "odom", "base_link", (float("nan"), 0, 0)))  # invalid_number
        put("/tf", 9, tf(9, "odom", "base_link", q=(0, 0, 0, 1.2)))  # invalid_rotation
        put("/tf", 10, tf(10, "odom", "base_link", q=(0, 0, 0, 1.004)))  # normalized, applied


def dirty_checks(path):
    code, out, err = run("bag", "check", path)
    check(code == 1, f"bag check of the dirty bag exits 1 (got {code}, {err})")
    lines = [json.loads(line) for line in out.splitlines()]
    groups = {(g["error"], g["parent"], g["child"]): g for g in lines if "summary" not in g}
    expected = {
        ("multiple_pose_parents", "world", "base_link"): 2,
        ("pose_cycle", "base_link", "map"): 1,
        ("constant_pose_change", "base_link", "camera"): 1,
        ("self_edge", "odom", "odom"): 1,
        ("invalid_number", "odom", "base_link"): 1,
        ("invalid_rotation", "odom", "base_link"): 1,
    }
    check(set(groups) == set(expected), f"finding groups {sorted(groups)}")
    for key, count in expected.items():
        g = groups.get(key)
        if g:
            check(g["count"] == count, f"{key} count {g['count']}")
            check(g["topic"] in ("/tf", "/tf_static"), f"{key} topic")
            check(g["message"] != "", f"{key} message")
    g = groups.get(("multiple_pose_parents", "world", "base_link"))
    if g:
        check(g["first_log_time"] == T0 + 3 and g["last_log_time"] == T0 + 4, f"log times {g}")
        check(g["first_stamp"] == T0 + 3 and g["last_stamp"] == T0 + 4, f"stamps {g}")
    summary = lines[-1]
    check(summary.get("summary") is True and summary["transforms"] == 13 and
          summary["findings"] == 7 and summary["groups"] == 6, f"summary {summary}")
    # The same bag through a script: the op fails with the first finding, the counts, and the
    # graph holds what was applied: base_link at x = 1.5 at t = 1.5 s (linear interpolation).
    script = os.path.join(SCRATCH, "dirty.yaml")
    with open(script, "w") as f:
        f.write(f"""time: {{interpolation: linear, window: 1000}}
ops:
  - {{op: bag, file: {os.path.basename(path)}}}
  - {{op: query, kind: position, of: base_link, wrt: odom, at: {T0 + 1.5}}}
  - {{op: query, kind: position, of: camera, wrt: map, at: {T0 + 1.5}}}
""")
    code, out, err = run("run", script)
    ops = [json.loads(line) for line in out.splitlines()]
    check(code == 1 and len(ops) == 3, f"run of the dirty script: {code} {err} {out}")
    if len(ops) == 3:
        op = ops[0]
        check(op["ok"] is False and op["error"] == "multiple_pose_parents", f"bag op {op}")
        check((op["transforms"], op["applied"], op["refused"], op["covered"], op["normalized"]) ==
              (13, 6, 7, 0, 1), f"bag op counts {op}")
        check(op["messages"] == 11 and op["skipped"] == 0, f"bag op messages {op}")
        check(abs(op["start"] - T0) < 1e-6 and abs(op["end"] - (T0 + 10)) < 1e-6, f"range {op}")
        check(ops[1]["ok"] and max(abs(a - b) for a, b in zip(ops[1]["position"], [1.5, 0, 0]))
              < 1e-9, f"interpolated position {ops[1]}")
        check(ops[2]["ok"] and max(abs(a - b) for a, b in zip(ops[2]["position"], [1.6, 0, 0.5]))
              < 1e-9, f"chain through the static camera {ops[2]}")


def clean_checks():
    foxglove = json.load(open(os.path.join(FOXGLOVE, "expected.json")))
    n_tf = sum(len(m["value"]["transforms"]) for m in foxglove["bag_messages"]
               if m["topic"] in ("/tf", "/tf_static"))
    for b in foxglove["bags"]:
        path = os.path.join(FOXGLOVE, b["file"])
        code, out, err = run("bag", "check", path)
        check(code == 0, f"bag check {b['file']}: {code} {err}")
        summary = json.loads(out.splitlines()[-1])
        check(summary == {"summary": True, "messages": summary["messages"], "transforms": n_tf,
                          "findings": 0, "groups": 0}, f"summary of {b['file']}: {summary}")
        code, out, err = run("bag", "info", path)
        check(code == 0 and "format:    mcap" in out and "= camera  [body base_link]" in out,
              f"bag info {b['file']}: {out}")
    rosbags = json.load(open(os.path.join(ROSBAG, "expected.json")))
    for name, bag in rosbags["bags"].items():
        code, out, err = run("bag", "check", os.path.join(ROSBAG, name))
        check(code == 0, f"bag check {name}: {code} {err}")
        counts = {}
        for m in bag["messages"]:
            counts[m["topic"]] = counts.get(m["topic"], 0) + 1
        code, out, err = run("bag", "info", os.path.join(ROSBAG, name))
        for topic, n in counts.items():
            check(any(line.split()[:1] == [topic] and line.split()[2] == str(n)
                      for line in out.splitlines()), f"bag info {name}: {topic} x {n}\n{out}")


def corrupt_checks(path):
    data = open(path, "rb").read()
    cut = os.path.join(SCRATCH, "cut.bag")
    open(cut, "wb").write(data[: len(data) * 2 // 3])
    code, out, err = run("bag", "check", cut)
    check(code == 2 and cut in err and "byte" in err, f"corrupt bag check: {code} {err}")
    script = os.path.join(SCRATCH, "cut.yaml")
    with open(script, "w") as f:
        f.write("ops:\n  - {op: bag, file: cut.bag}\n"
                "  - {op: query, kind: pose, of: base_link, wrt: odom}\n")
    code, out, err = run("run", script)
    ops = [json.loads(line) for line in out.splitlines()]
    check(ops[0]["error"] == "invalid_bag" and "cut.bag" in ops[0]["message"], f"op {ops[0]}")
    check(ops[1]["error"] == "unknown_frame", f"nothing applied: {ops[1]}")
    code, out, err = run("bag", "check", os.path.join(SCRATCH, "missing.bag"))
    check(code == 2, "a missing file exits 2")
    code, out, err = run("bag", "check", path, "--static", "nope")
    check(code == 2 and "--static" in err, "bad usage exits 2")


def covariance_checks():
    """covariance.mcap (Foxglove's writer): /amcl_pose through the op's pose_topics, /odom
    through its topics; the queries at a message's stamp return its numbers (docs/ros.md)."""
    foxglove = json.load(open(os.path.join(FOXGLOVE, "expected.json")))
    bag = foxglove["covariance_bag"]
    amcl = next(m["value"] for m in bag["messages"] if m["topic"] == "/amcl_pose")
    odom = next(m["value"] for m in bag["messages"] if m["topic"] == "/odom")
    stamp = lambda v: v["header"]["stamp"]["sec"] + v["header"]["stamp"]["nanosec"] * 1e-9
    script = os.path.join(SCRATCH, "covariance.yaml")
    with open(script, "w") as f:
        f.write(f"""time: {{interpolation: linear, window: 1000}}
ops:
  - {{op: bag, file: {os.path.join(FOXGLOVE, bag["file"])}, topics: [/odom],
     pose_topics: {{/amcl_pose: base_footprint}}}}
  - {{op: query, kind: pose, of: base_footprint, wrt: map, at: {stamp(amcl)!r}, covariance: true}}
  - {{op: query, kind: twist, point: base_link, ref_body: odom, coord: base_link,
     at: {stamp(odom)!r}, covariance: true}}
""")
    code, out, err = run("run", script)
    ops = [json.loads(line) for line in out.splitlines()]
    check(len(ops) == 3, f"run of the covariance script: {code} {err} {out}")
    if len(ops) != 3:
        return
    op = ops[0]
    check(op["ok"] is False and op["error"] in ("invalid_covariance", "invalid_number"),
          f"the bad messages are findings: {op}")
    check((op["poses_with_covariance"], op["odometry"], op["covariance_refused"]) == (2, 2, 2),
          f"covariance counts {op}")
    check(ops[1]["ok"] and max(abs(a - b) for a, b in
                               zip(ops[1]["covariance"], amcl["pose"]["covariance"])) < 1e-15,
          f"pose covariance {ops[1]}")
    check(ops[2]["ok"] and max(abs(a - b) for a, b in
                               zip(ops[2]["covariance"], odom["twist"]["covariance"])) < 1e-15,
          f"twist covariance {ops[2]}")
    # The same messages in a ROS 1 bag (python3-rosbag) and a rosbag2 sqlite3 bag (Foxglove's
    # CDR bytes): the same two finding groups from every format.
    rosbag = json.load(open(os.path.join(ROSBAG, "expected.json")))
    paths = [os.path.join(FOXGLOVE, bag["file"])] + [
        os.path.join(ROSBAG, rosbag[k]["file"]) for k in ("covariance_bag", "sqlite3_covariance_bag")
        if k in rosbag]
    check(len(paths) == 3, f"three covariance bags: {paths}")
    for path in paths:
        code, out, err = run("bag", "check", path, "--topics", "/odom",
                             "--pose-topic", "/amcl_pose=base_footprint")
        lines = [json.loads(line) for line in out.splitlines()]
        groups = [g for g in lines if "summary" not in g]
        check(code == 1 and sorted((g["topic"], g["error"]) for g in groups) ==
              [("/amcl_pose", "invalid_covariance"), ("/odom", "invalid_number")],
              f"bag check of {path}: {code} {err} {out}")
        check(lines[-1].get("messages") == 6, f"bag check of {path}: summary {lines[-1]}")
    code, out, err = run("bag", "check", os.path.join(FOXGLOVE, bag["file"]), "--pose-topic", "x")
    check(code == 2 and "--pose-topic" in err, f"bad --pose-topic exits 2: {code} {err}")


os.makedirs(SCRATCH, exist_ok=True)
dirty = os.path.join(SCRATCH, "dirty.bag")
write_dirty_bag(dirty)
dirty_checks(dirty)
clean_checks()
covariance_checks()
corrupt_checks(dirty)
print("bag_cli_test:", "FAILED" if failures else "ok", f"({len(failures)} failures)")
sys.exit(1 if failures else 0)
