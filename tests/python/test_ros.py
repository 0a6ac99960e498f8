"""semgraph.ros against bags written by independent writers (docs/ros.md, "Testing against
independent writers"): Foxglove's npm packages (MCAP, ctest ros.fixtures), Debian's
python3-rosbag and Python's sqlite3 (ROS 1 and rosbag2 sqlite3, ctest ros_bag_fixtures). The
expected values are the writers' inputs (their expected.json), never semgraph's output. Bags
with faults are written here by python3-rosbag (genpy messages). The live test runs
`semgraph serve --ros` in its own process and listens from Python.

Run by ctest `python_ros` (FIXTURES_REQUIRED: the two fixture steps); without the fixtures the
bag tests skip."""

import json
import math
import os
import random
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph

from conftest import source_dir

if not semgraph._semgraph._has_ros:
    pytest.skip("built without the ROS layer", allow_module_level=True)

import semgraph.ros as ros  # noqa: E402


def build_dir():
    return os.environ.get("SEMGRAPH_BUILD_DIR", os.path.join(source_dir(), "build"))


def foxglove_dir():
    return os.environ.get("SEMGRAPH_ROS_FIXTURES", os.path.join(build_dir(), "tests", "ros", "fixtures"))


def bag_fixtures_dir():
    return os.environ.get("SEMGRAPH_ROS_BAG_FIXTURES",
                          os.path.join(build_dir(), "tests", "ros", "bag_fixtures"))


def load_json(path):
    if not os.path.exists(path):
        pytest.skip(f"no fixtures at {path} (ctest -R 'ros.fixtures|ros_bag_fixtures')")
    with open(path) as f:
        return json.load(f)


# --- The writers' inputs as (topic, log_time_ns, kind, value) in log-time order ------------------

def flat_transform(topic, log_time, parent, child, stamp_ns, xyz, xyzw):
    return ("tf", topic, log_time, parent, child, stamp_ns, tuple(xyz), tuple(xyzw))


def foxglove_bags():
    d = load_json(os.path.join(foxglove_dir(), "expected.json"))
    expected = []
    msgs = sorted(d["bag_messages"], key=lambda m: int(m["log_time"]))  # stable: ties keep order
    for m in msgs:
        t, v = int(m["log_time"]), m["value"]
        if m["type"].endswith("TFMessage"):
            for x in v["transforms"]:
                h, tr = x["header"], x["transform"]
                expected.append(flat_transform(
                    m["topic"], t, h["frame_id"], x["child_frame_id"],
                    h["stamp"]["sec"] * 10**9 + h["stamp"]["nanosec"],
                    [tr["translation"][k] for k in "xyz"], [tr["rotation"][k] for k in "xyzw"]))
        elif m["type"].endswith("JointState"):
            s = v["header"]["stamp"]
            expected.append(("js", m["topic"], t, s["sec"] * 10**9 + s["nanosec"], v["name"],
                             v["position"], v["velocity"], v["effort"]))
    files = [os.path.join(foxglove_dir(), b["file"]) for b in d["bags"]]
    return files, expected


def python_bags():
    d = load_json(os.path.join(bag_fixtures_dir(), "expected.json"))
    out = []
    for name, bag in d["bags"].items():
        expected = []
        for m in bag["messages"]:
            t, v = int(m["log_time"]), m["value"]
            if m["kind"] == "tf":
                for x in v["transforms"]:
                    expected.append(flat_transform(m["topic"], t, x["frame_id"], x["child_frame_id"],
                                                   x["stamp"][0] * 10**9 + x["stamp"][1],
                                                   x["translation"], x["rotation"]))
            elif m["kind"] == "joint_state":
                expected.append(("js", m["topic"], t, v["stamp"][0] * 10**9 + v["stamp"][1],
                                 v["name"], v["position"], v["velocity"], v["effort"]))
        out.append((os.path.join(bag_fixtures_dir(), name), bag["format"], expected))
    return out


def all_bags():
    files, expected = foxglove_bags()
    return [(f, "mcap", expected) for f in files] + python_bags()


def record_tuple(r):
    if isinstance(r, ros.TransformRecord):
        return ("tf", r.topic, r.log_time_ns, r.frame_id, r.child_frame_id, r.stamp_ns,
                tuple(r.translation.tolist()), tuple(r.xyzw.tolist()))
    return ("js", r.topic, r.log_time_ns, r.stamp_ns, r.names, r.position.tolist(),
            r.velocity.tolist(), r.effort.tolist())


# --- read_bag ------------------------------------------------------------------------------------

def test_read_bag_yields_every_transform_and_joint_state_as_written():
    bags = all_bags()
    assert len(bags) >= 10
    for path, fmt, expected in bags:
        it = ros.read_bag(path)
        assert it.format == fmt, path
        got = [record_tuple(r) for r in it]
        assert len(got) == len(expected), path
        assert got == expected, path  # exact: the same doubles, names, stamps, log times
        with pytest.raises(StopIteration):
            next(it)


def test_read_bag_records_carry_lifted_names_rotations_and_the_static_flag():
    path, _, expected = python_bags()[0]
    records = list(ros.read_bag(path, topics=["/tf", "/tf_static"]))
    assert len(records) == sum(1 for e in expected if e[0] == "tf")
    odom = next(r for r in records if r.frame_id == "/map")
    assert (odom.parent, odom.child, odom.static) == ("map", "odom", False)
    camera = next(r for r in records if r.child == "camera")
    assert camera.static and camera.topic == "/tf_static"
    x, y, z, w = camera.xyzw
    np.testing.assert_array_equal(camera.quaternion, [w, x, y, z])
    R = Rotation.from_quat(camera.xyzw).as_matrix()
    np.testing.assert_allclose(camera.rotation_matrix, R, atol=1e-15)
    assert camera.log_time == pytest.approx(camera.log_time_ns * 1e-9)
    assert camera.stamp == pytest.approx(camera.stamp_ns * 1e-9)


def test_read_bag_streams():
    path = foxglove_bags()[0][0]
    it = ros.read_bag(path)
    first = next(it)
    assert first.topic == "/tf_static"  # the URDF on /robot_description (a String) is passed over
    assert sum(1 for _ in it) == len(foxglove_bags()[1]) - 1


# --- load_bag / check_bag ------------------------------------------------------------------------

def pose_of(graph, child, parent, at=None):
    X = graph.pose(of=child, wrt=parent, at=at) if at is not None else graph.pose(of=child, wrt=parent)
    return X.position, X.rotation_matrix


def test_load_bag_answers_every_recorded_transform_at_its_stamp():
    for path, fmt, expected in all_bags():
        report = ros.load_bag(path, sample_capacity=4096)
        assert report.ok and report.exit_status == 0 and report.findings == [], path
        tfs = [e for e in expected if e[0] == "tf"]
        assert report.transforms == report.applied == len(tfs), path
        g = report.graph
        for _, topic, _, parent, child, stamp, xyz, xyzw in tfs:
            at = None if topic == "/tf_static" else stamp
            p, R = pose_of(g, child.lstrip("/"), parent.lstrip("/"), at)
            np.testing.assert_allclose(p, xyz, atol=1e-12, rtol=0)
            np.testing.assert_allclose(R, Rotation.from_quat(xyzw).as_matrix(), atol=1e-12)


def test_load_bag_interpolates_linearly_between_samples_like_tf2():
    files, expected = foxglove_bags()
    report = ros.load_bag(files[0], sample_capacity=4096)
    samples = sorted((e for e in expected if e[0] == "tf" and e[1] == "/tf"), key=lambda e: e[5])
    a, b = samples[100], samples[101]
    assert a[5] < b[5]
    t = (a[5] + b[5]) // 2
    s = (t - a[5]) / (b[5] - a[5])
    X = report.graph.pose(of="base_link", wrt="odom", at=t)
    np.testing.assert_allclose(X.position, (1 - s) * np.array(a[6]) + s * np.array(b[6]), atol=1e-12)
    assert X.time.time_ns == t and (X.time.oldest_ns, X.time.newest_ns) == (a[5], b[5])


def test_load_bag_into_a_graph_and_the_bags_robot_description():
    files, expected = foxglove_bags()
    g = semgraph.SceneGraph(window=3600.0, interpolation="linear", sample_capacity=4096)
    report = ros.load_bag(files[1], g, topics=["/tf", "/tf_static", "/joint_states", "/robot_description"])
    assert report.graph is g and report.loaded_robot_description and report.ok
    joints = [e for e in expected if e[0] == "js"]
    assert report.joint_states == len(joints)
    # the URDF's revolute z joint "shoulder" base_link -> arm: Rz(position) at each stamp
    _, _, _, stamp, names, position, _, _ = joints[-1]
    X = g.pose(of="arm", wrt="base_link", at=stamp)
    np.testing.assert_allclose(X.rotation_matrix, Rotation.from_euler("z", position[0]).as_matrix(),
                               atol=1e-12)


def test_check_bag_options_window_and_log_time_range():
    files, expected = foxglove_bags()
    tfs = [e for e in expected if e[0] == "tf" and e[1] == "/tf"]
    start, end = tfs[10][2], tfs[19][2]
    report = ros.check_bag(files[0], start=start, end=end)
    assert report.transforms == 10 + 2  # the window's /tf plus the statics, whatever their time
    assert report.end_ns == end and report.start_ns <= start
    # own_body: each static child on a body of its own (a timeless inter-body pose)
    own = ros.check_bag(files[0], static="own_body")
    assert own.ok and own.graph.pose(of="laser", body="laser", wrt="base_link") is not None
    same = ros.check_bag(files[0])
    with pytest.raises(semgraph.QueryError) as e:
        same.graph.pose(of="laser", body="laser", wrt="base_link")
    assert e.value.argument == "body"
    with pytest.raises(ValueError, match="own_body"):
        ros.check_bag(files[0], static="rigid")
    with pytest.raises(ValueError, match="two|both|listed"):
        ros.check_bag(files[0], bodies={"A": ["laser"], "B": ["laser"]})
    with pytest.raises(TypeError):
        ros.check_bag(files[0], topics="/tf")


def covariance_bags():
    """(path, messages) of the three bags of PoseWithCovarianceStamped (/amcl_pose) and Odometry
    (/odom): Foxglove's covariance.mcap, python3-rosbag's ros1_covariance.bag and the sqlite3
    bag of Foxglove's CDR bytes (ros2_covariance.db3), with their writers' values."""
    fox = load_json(os.path.join(foxglove_dir(), "expected.json"))["covariance_bag"]
    bags = load_json(os.path.join(bag_fixtures_dir(), "expected.json"))
    return [(os.path.join(foxglove_dir(), fox["file"]), fox["messages"])] + [
        (os.path.join(bag_fixtures_dir(), bags[k]["file"]), bags[k]["messages"])
        for k in ("covariance_bag", "sqlite3_covariance_bag")]


def stamp_ns(header):
    return header["stamp"]["sec"] * 10**9 + header["stamp"]["nanosec"]


def test_load_bag_pose_topics_give_stamped_poses_and_twists_with_covariance():
    for path, messages in covariance_bags():
        report = ros.load_bag(path, topics=["/odom"], pose_topics={"/amcl_pose": "base_footprint"})
        assert report.messages == 6, path
        assert (report.poses_with_covariance, report.odometry, report.covariance_refused) == \
            (2, 2, 2), path
        g = report.graph
        bad = [m for m in messages if m["bad"]]
        assert [(f.code, f.topic, f.first_stamp_ns) for f in report.findings] == [
            ("invalid_covariance" if m["topic"] == "/amcl_pose" else "invalid_number",
             m["topic"], stamp_ns(m["value"]["header"])) for m in bad], path
        for m in messages:
            if m["bad"]:
                continue
            v, t = m["value"], stamp_ns(m["value"]["header"])
            parent = v["header"]["frame_id"]
            child = v.get("child_frame_id", "base_footprint")
            X, S = g.pose_with_covariance(of=child, wrt=parent, expressed_in=parent, at=t)
            p, q = v["pose"]["pose"]["position"], v["pose"]["pose"]["orientation"]
            np.testing.assert_allclose(X.position, [p["x"], p["y"], p["z"]], atol=1e-12, rtol=0)
            np.testing.assert_allclose(
                X.rotation_matrix,
                Rotation.from_quat([q["x"], q["y"], q["z"], q["w"]]).as_matrix(), atol=1e-12)
            # ROS's row-major 6x6 over (x, y, z, rotX, rotY, rotZ): semgraph's default order
            np.testing.assert_allclose(S, np.reshape(v["pose"]["covariance"], (6, 6)),
                                       atol=1e-15, rtol=0)
            if m["topic"] != "/odom":
                continue
            V, St = g.twist_with_covariance(point=child, body=g.body_of(child),
                                            ref_body=g.body_of(parent), expressed_in=child, at=t)
            lin, ang = v["twist"]["twist"]["linear"], v["twist"]["twist"]["angular"]
            np.testing.assert_allclose(V.linear, [lin[k] for k in "xyz"], atol=1e-15, rtol=0)
            np.testing.assert_allclose(V.angular, [ang[k] for k in "xyz"], atol=1e-15, rtol=0)
            np.testing.assert_allclose(St, np.reshape(v["twist"]["covariance"], (6, 6)),
                                       atol=1e-15, rtol=0)


def test_pose_topics_argument_errors():
    path = covariance_bags()[0][0]
    with pytest.raises(TypeError, match="pose_topics must be a dict"):
        ros.load_bag(path, pose_topics=[("/amcl_pose", "base_footprint")])
    with pytest.raises(TypeError):
        ros.check_bag(path, pose_topics={"/amcl_pose": 3})
    with pytest.raises(ValueError, match="an empty frame for '/amcl_pose'"):
        ros.check_bag(path, pose_topics={"/amcl_pose": ""})
    # check_bag takes it too; without a frame the pose topic is not read
    report = ros.check_bag(path, topics=["/odom"], pose_topics={"/amcl_pose": "base_footprint"})
    assert report.poses_with_covariance == 2 and report.exit_status == 1
    assert ros.check_bag(path, topics=["/odom"]).poses_with_covariance == 0


def test_bag_info_lists_the_tree_topics_and_ranges():
    files, expected = foxglove_bags()
    info = ros.bag_info(files[2])
    assert info.format == "mcap" and info.messages == 1217
    counts = {t.name: t.messages for t in info.topics}
    assert counts == {"/robot_description": 1, "/tf_static": 1, "/tf": 1200, "/chatter": 3,
                      "/joint_states": 12}
    assert next(t for t in info.topics if t.name == "/tf").type == "tf2_msgs/msg/TFMessage"
    frames = [(f.name, f.parent, f.static, f.body, f.depth) for f in info.frames]
    assert frames == [("odom", None, False, "odom", 0), ("base_link", "odom", False, "base_link", 1),
                      ("laser", "base_link", True, "base_link", 2),
                      ("camera", "base_link", True, "base_link", 2)]
    stamps = [e[5] for e in expected if e[0] == "tf" and e[1] == "/tf"] + \
             [e[3] for e in expected if e[0] == "js"]
    assert (info.first_stamp_ns, info.last_stamp_ns) == (min(stamps), max(stamps))


# --- findings on bags with faults, written by python3-rosbag -------------------------------------

def write_faulty_bag(path):
    rosbag = pytest.importorskip("rosbag")
    import genpy
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage

    def ts(sec, parent, child, xyz=(0, 0, 0), q=(0, 0, 0, 1)):
        t = TransformStamped()
        t.header.stamp = genpy.Time(sec, 0)
        t.header.frame_id, t.child_frame_id = parent, child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
        r = t.transform.rotation
        r.x, r.y, r.z, r.w = q
        return t

    with rosbag.Bag(path, "w") as bag:
        bag.write("/tf_static", TFMessage([ts(100, "base_link", "laser", (0.25, 0, 0.1))]), genpy.Time(100))
        bag.write("/tf", TFMessage([ts(101, "odom", "base_link", (1, 0, 0))]), genpy.Time(101))
        bag.write("/tf", TFMessage([ts(102, "map", "base_link", (2, 0, 0)),     # second parent
                                    ts(102, "odom", "base_link", (1.5, 0, 0))]), genpy.Time(102))
        bag.write("/tf", TFMessage([ts(103, "map", "base_link", (2, 0, 0)),
                                    ts(103, "arm", "arm"),                         # self edge
                                    ts(103, "odom", "wheel", q=(0, 0, 0, 2)),      # not unit
                                    ts(103, "odom", "caster", (float("nan"), 0, 0))]), genpy.Time(103))
        bag.write("/tf_static", TFMessage([ts(104, "base_link", "laser", (0.3, 0, 0.1))]),
                  genpy.Time(104))                                                 # static changed
        late = ts(101, "odom", "base_link", (1.125, 0, 0))
        late.header.stamp = genpy.Time(101, 250_000_000)                           # out of order
        bag.write("/tf", TFMessage([late]), genpy.Time(105))


def test_check_bag_finds_each_fault_with_its_code_frames_and_times(tmp_path):
    path = str(tmp_path / "faulty.bag")
    write_faulty_bag(path)
    report = ros.check_bag(path)
    assert not report.ok and report.exit_status == 1
    found = {(f.code, f.topic, f.parent, f.child): f for f in report.findings}
    assert set(found) == {
        ("multiple_pose_parents", "/tf", "map", "base_link"),
        ("self_edge", "/tf", "arm", "arm"),
        ("invalid_rotation", "/tf", "odom", "wheel"),
        ("invalid_number", "/tf", "odom", "caster"),
        ("constant_pose_change", "/tf_static", "base_link", "laser"),
    }
    two = found[("multiple_pose_parents", "/tf", "map", "base_link")]
    assert two.count == 2
    assert (two.first_stamp_ns, two.last_stamp_ns) == (102 * 10**9, 103 * 10**9)
    assert (two.first_log_time, two.last_log_time) == (102.0, 103.0)
    assert "odom" in two.message
    line = json.loads(two.to_json())
    assert (line["error"], line["parent"], line["child"], line["count"]) == \
        ("multiple_pose_parents", "map", "base_link", 2)
    assert report.summary == {"summary": True, "messages": 6, "transforms": 10,
                              "findings": report.findings_total, "groups": 5}
    assert report.findings_total == 6 and report.refused == 6
    # the graph kept the first parent's samples, refused the second's
    X = report.graph.pose(of="base_link", wrt="odom", at=102 * 10**9)
    np.testing.assert_allclose(X.position, [1.5, 0, 0], atol=1e-12)
    # the same bag against the semgraph tool's exit status and lines
    cli = os.environ.get("SEMGRAPH_CLI")
    if cli:
        out = subprocess.run([cli, "bag", "check", path], capture_output=True, text=True)
        assert out.returncode == report.exit_status
        assert [json.loads(l) for l in out.stdout.splitlines()[:-1]] == \
            [json.loads(f.to_json()) for f in report.findings]


def test_a_window_finds_stale_samples(tmp_path):
    path = str(tmp_path / "faulty.bag")
    write_faulty_bag(path)
    report = ros.check_bag(path, window=0.5, topics=["/tf"])
    old = [f for f in report.findings if f.code == "stamp_too_old"]
    assert [(f.parent, f.child, f.first_stamp_ns, f.first_log_time_ns) for f in old] == \
        [("odom", "base_link", 101_250_000_000, 105 * 10**9)]
    assert ros.check_bag(path, window=2.0, topics=["/tf"]).findings_total == 5  # in the window


# --- hostile files -------------------------------------------------------------------------------

def hostile_files(tmp_path):
    mcap = foxglove_bags()[0][0]
    rosbag1 = python_bags()[0][0]
    data = open(mcap, "rb").read()
    (tmp_path / "cut.mcap").write_bytes(data[: len(data) // 2])
    (tmp_path / "magic.mcap").write_bytes(b"\x89NOTMCAP" + data[8:])
    b1 = open(rosbag1, "rb").read()
    (tmp_path / "cut.bag").write_bytes(b1[: len(b1) - 100])
    (tmp_path / "empty.db3").write_bytes(b"")
    return {"cut.mcap": ("truncated", "crc_mismatch", "malformed"), "magic.mcap": ("unknown_format",),
            "cut.bag": ("truncated", "malformed"), "empty.db3": ("unknown_format", "truncated", "io")}


def test_a_corrupt_bag_raises_bag_error_with_file_and_offset_and_changes_nothing(tmp_path):
    for name, codes in hostile_files(tmp_path).items():
        path = str(tmp_path / name)
        g = semgraph.SceneGraph()
        g.add_pose(of="x", body="X", wrt="odom", ref_body="odom", position=[1, 2, 3])
        before = g.dump()
        with pytest.raises(ros.BagError) as e:
            ros.load_bag(path, g)
        assert e.value.code in codes, (name, str(e.value))
        assert e.value.file == path and str(e.value).startswith(f"{path}: byte {e.value.offset}: ")
        assert isinstance(e.value, semgraph.Error)
        assert g.dump() == before, name
        with pytest.raises(ros.BagError):
            ros.bag_info(path)
        with pytest.raises(ros.BagError):
            list(ros.read_bag(path))
    with pytest.raises(ros.BagError) as e:
        ros.check_bag(str(tmp_path / "missing.bag"))
    assert e.value.code == "io"


# --- live ----------------------------------------------------------------------------------------

LIVE_SCENE = """ops:
  - {op: pose, of: base, body: base, wrt: world, ref_body: world, position: [1.0, 2.0, 0.0], rotation: {rpy: [0.0, 0.0, 0.5]}}
  - {op: pose, of: camera, body: base, wrt: base, ref_body: base, position: [0.1, 0.0, 0.4], rotation: {rpy: [0.1, 0.2, 0.3]}}
  - {op: pose, of: arm, body: arm, wrt: base, ref_body: base, position: [0.0, 0.0, 0.5], rotation: {rpy: [0.0, 0.0, 0.0]}, stamp: 100.0}
  - {op: pose, of: arm, body: arm, wrt: base, ref_body: base, position: [0.0, 0.1, 0.6], rotation: {rpy: [0.0, 0.3, 0.0]}, stamp: 100.5}
"""

needs_dds = pytest.mark.skipif(not semgraph._semgraph._has_ros_dds, reason="built without Cyclone DDS")


def rpy(r, p, y):
    return Rotation.from_euler("ZYX", [y, p, r]).as_matrix()


@pytest.fixture
def loopback(monkeypatch):
    uri = os.path.join(source_dir(), "tests", "dds", "cyclonedds-loopback.xml")
    monkeypatch.setenv("CYCLONEDDS_URI", "file://" + os.path.abspath(uri))
    return random.Random().randrange(160, 230)


@needs_dds
def test_listener_reads_what_semgraph_serve_broadcasts(tmp_path, loopback):
    cli = os.environ.get("SEMGRAPH_CLI")
    if not cli:
        pytest.skip("no semgraph tool (SEMGRAPH_CLI)")
    scene = tmp_path / "scene.yaml"
    scene.write_text(LIVE_SCENE)
    with ros.Listener(domain=loopback) as listener:
        assert listener.domain == loopback
        server = subprocess.Popen([cli, "serve", "--ros", str(scene), "--domain", str(loopback),
                                   "--seconds", "20"], stdout=subprocess.DEVNULL, env=os.environ.copy())
        try:
            # the /tf_static message (2 transforms) and the /tf message with both samples
            # (serve re-sends it 300 ms after a new subscriber matched)
            assert listener.wait(10.0, frames=["world", "base", "camera", "arm"], transforms=4)
            assert listener.stats["tf_static"] >= 1 and listener.stats["tf"] >= 1
            X_WC = listener.with_graph(lambda g: g.pose(of="camera", wrt="world"))
            R_WB = rpy(0, 0, 0.5)
            np.testing.assert_allclose(X_WC.position, np.array([1, 2, 0]) + R_WB @ [0.1, 0, 0.4],
                                       atol=1e-12)
            np.testing.assert_allclose(X_WC.rotation_matrix, R_WB @ rpy(0.1, 0.2, 0.3), atol=1e-12)
            X_BA = listener.with_graph(lambda g: g.pose(of="arm", wrt="base", at=100.25))
            np.testing.assert_allclose(X_BA.position, [0, 0.05, 0.55], atol=1e-12)
            assert listener.findings() == [] and listener.poll_findings() == []
            with pytest.raises(semgraph.QueryError) as e:  # fn's exception, raised by with_graph
                listener.with_graph(lambda g: g.pose(of="nowhere", wrt="world"))
            assert e.value.code == "unknown_frame"
            # compiled: evaluated outside with_graph, while the listener runs
            q = listener.with_graph(lambda g: g.compile_pose(of="camera", wrt="world"))
            np.testing.assert_allclose(q.evaluate().position, X_WC.position, atol=1e-15)
            with pytest.raises(semgraph.RejectedError) as e:
                listener.graph.add_body("X")
            assert e.value.code == "read_only"
        finally:
            server.terminate()
            server.wait(10)
    assert listener.closed
    listener.graph.add_pose(of="y", body="Y", wrt="world", ref_body="world")  # writable again


def spd6(scale, seed):
    """A symmetric positive definite 6x6 with distinct entries: A A^T + diag."""
    A = np.sin(seed + 7 * np.arange(6)[:, None] + 3 * np.arange(6)[None, :])
    return scale * (A @ A.T + (1 + 0.25 * seed) * np.eye(6))


def numbers(xs):
    return " ".join(repr(float(x)) for x in np.ravel(xs))  # repr: exact, read back by strtod


@needs_dds
def test_listener_pose_and_odometry_topics_from_another_process(loopback):
    # ros_dds_test_node (tests/ros_dds) writes raw PoseWithCovarianceStamped and Odometry
    # samples built from the IDL structs, not through semgraph.
    node_path = os.path.join(build_dir(), "tests", "ros_dds", "ros_dds_test_node")
    if not os.path.exists(node_path):
        pytest.skip(f"no {node_path}")
    sec = 1733300030
    p, yaw, S = [1.5, -0.25, 0.125], 0.4, spd6(0.01, 1)
    q = [0, 0, math.sin(yaw / 2), math.cos(yaw / 2)]
    po, qo, So = [0.2, 0.1, 0], [0, 0, 0, 1], spd6(0.001, 2)
    v, w, St = [0.4, -0.05, 0], [0, 0.01, 0.2], spd6(1e-4, 3)
    bad = S.copy()
    bad[0, 1] += 0.5  # not symmetric
    with ros.Listener(domain=loopback, pose_topics={"/amcl_pose": "base_footprint"},
                      odometry_topics=["/odom"]) as listener:
        node = subprocess.Popen([node_path, str(loopback)], stdin=subprocess.PIPE,
                                stdout=subprocess.PIPE, text=True, env=os.environ.copy())

        def command(line):
            node.stdin.write(line + "\n")
            node.stdin.flush()
            reply = node.stdout.readline()
            assert reply.startswith("ok"), (line, reply)

        def until(pred, timeout=20.0):
            deadline = time.time() + timeout
            while not pred() and time.time() < deadline:
                time.sleep(0.005)
            return pred()

        try:
            command("wait_match pose /amcl_pose 1")
            command("wait_match odom /odom 1")
            assert until(lambda: listener.publishers("/amcl_pose") == 1 and
                         listener.publishers("/odom") == 1)
            assert listener.publishers("/tf_nope") == 0
            command(f"pose /amcl_pose map {sec} 0 {numbers(p + q)} {numbers(S)}")
            command(f"odom /odom odom base_link {sec} 0 {numbers(po + qo)} {numbers(So)} "
                    f"{numbers(v + w)} {numbers(St)}")
            command(f"pose /amcl_pose map {sec + 1} 0 {numbers(p + q)} {numbers(bad)}")
            assert until(lambda: listener.stats["poses_with_covariance"] == 2 and
                         listener.stats["odometry"] == 1), listener.stats
            stats = listener.stats
            assert (stats["poses_with_covariance_applied"], stats["odometry_applied"],
                    stats["covariance_refused"]) == (1, 1, 1)
            (f,) = listener.findings()
            assert (f.code, f.topic, f.parent, f.child, f.first_stamp_ns) == \
                ("invalid_covariance", "/amcl_pose", "map", "base_footprint", (sec + 1) * 10**9)

            def read_back(g):
                t = sec * 10**9
                X, SX = g.pose_with_covariance(of="base_footprint", wrt="map", expressed_in="map",
                                               at=t)
                Xo, SXo = g.pose_with_covariance(of="base_link", wrt="odom", expressed_in="odom",
                                                 at=t)
                V, SV = g.twist_with_covariance(point="base_link", body=g.body_of("base_link"),
                                                ref_body=g.body_of("odom"),
                                                expressed_in="base_link", at=t)
                return X, SX, Xo, SXo, V, SV

            X, SX, Xo, SXo, V, SV = listener.with_graph(read_back)
            np.testing.assert_allclose(X.position, p, atol=1e-15, rtol=0)
            np.testing.assert_allclose(X.rotation_matrix, Rotation.from_quat(q).as_matrix(),
                                       atol=1e-15)
            np.testing.assert_allclose(SX, S, atol=1e-15, rtol=0)  # ROS's 6x6, unchanged
            np.testing.assert_allclose(Xo.position, po, atol=1e-15, rtol=0)
            np.testing.assert_allclose(SXo, So, atol=1e-15, rtol=0)
            np.testing.assert_allclose(V.linear, v, atol=1e-15, rtol=0)
            np.testing.assert_allclose(V.angular, w, atol=1e-15, rtol=0)
            np.testing.assert_allclose(SV, St, atol=1e-15, rtol=0)
        finally:
            node.stdin.close()
            node.wait(10)
    with pytest.raises(ValueError, match="not a ROS 2 topic name"):
        ros.Listener(domain=loopback, odometry_topics=["odom"])
    with pytest.raises(TypeError, match="odometry_topics must be a sequence of str"):
        ros.Listener(domain=loopback, odometry_topics="/odom")


@needs_dds
def test_listener_reports_findings_as_they_happen_from_two_broadcasters(loopback):
    a = semgraph.SceneGraph()
    a.add_pose(of="b", body="B", wrt="a", ref_body="A", position=[1, 0, 0], stamp=10.0)
    c = semgraph.SceneGraph()
    c.add_pose(of="b", body="B", wrt="c", ref_body="C", position=[2, 0, 0], stamp=10.0)
    with ros.Listener(domain=loopback) as listener:
        first, second = ros.Broadcaster(a, domain=loopback), ros.Broadcaster(c, domain=loopback)
        deadline = time.time() + 10
        while time.time() < deadline and (first.subscribers < 1 or second.subscribers < 1):
            time.sleep(0.02)
        time.sleep(0.3)
        assert first.broadcast() == (1, 0)
        assert listener.wait(5.0, frames=["a", "b"])
        time.sleep(0.1)
        assert second.broadcast() == (1, 0)
        deadline = time.time() + 5
        events = []
        while time.time() < deadline and not events:
            events = listener.poll_findings()
            time.sleep(0.02)
        (finding, new), = events
        assert new and (finding.code, finding.topic, finding.parent, finding.child) == \
            ("multiple_pose_parents", "/tf", "c", "b")
        assert finding.first_stamp_ns == 10 * 10**9 and finding.count == 1
        assert [f.code for f in listener.findings()] == ["multiple_pose_parents"]
        X = listener.with_graph(lambda g: g.pose(of="b", wrt="a", at=10.0))
        np.testing.assert_allclose(X.position, [1, 0, 0], atol=1e-15)


# --- the docs' example ---------------------------------------------------------------------------

def test_docs_ros_example_runs_on_a_fixture_bag(tmp_path):
    with open(os.path.join(source_dir(), "docs", "python.md")) as f:
        text = f.read()
    import re
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "semgraph.ros" in b)
    path = foxglove_bags()[0][0]
    env = {"__name__": "docs_example"}
    exec(compile(block.replace('"run.mcap"', repr(path)), "docs/python.md", "exec"), env)
    assert env["report"].ok and env["X"].time.time_ns == 1733300000_500_000_000
