"""Every error class of the module: RejectedError (refused adds, removals, handle lookups and
updates, with the spec's codes), QueryError (failed queries), ScriptError, and TypeError /
ValueError for wrong Python arguments, each naming what is wrong; a refused operation changes
nothing (the graph's canonical dump is compared before and after)."""

import math
import pickle

import numpy as np
import pytest

import semgraph
from conftest import build_spray_painting

NAN = math.nan

# (expected code, words the message must contain, the operation)
REJECTIONS = [
    ("invalid_name", ["empty"], lambda g: g.add_body("")),
    ("invalid_name", ["point: name is empty"], lambda g: g.add_pose(of="", body="N", wrt="b")),
    ("duplicate_body", ["body B already exists"], lambda g: g.add_body("B")),
    ("frame_without_body", ["must name the body"], lambda g: g.add_frame("x", "")),
    ("duplicate_frame", ["{b}|B already exists"], lambda g: g.add_frame("b", "B")),
    ("unknown_body", ["body NOPE does not exist"], lambda g: g.add_frame("y", "NOPE")),
    ("invalid_number", ["position component 0 is nan"],
     lambda g: g.add_pose(of="n", body="N", wrt="b", position=[NAN, 0, 0])),
    ("invalid_number", ["inf"],
     lambda g: g.add_pose(of="n", body="N", wrt="b", quaternion=[math.inf, 0, 0, 0])),
    ("invalid_number", ["linear"],
     lambda g: g.add_twist(point="e", ref_body="B", expressed_in="e", linear=[0, NAN, 0])),
    ("invalid_rotation", ["quaternion norm"],
     lambda g: g.add_pose(of="n", body="N", wrt="b", quaternion=[1, 1, 0, 0])),
    ("invalid_rotation", ["reflection"],
     lambda g: g.add_pose(of="n", body="N", wrt="b", rotation_matrix=np.diag([1.0, 1.0, -1.0]))),
    ("frame_body_mismatch", ["{f1} is attached to body O1, not C"],
     lambda g: g.add_pose(of="f1", body="C", wrt="c", ref_body="C")),
    ("self_edge", ["itself"], lambda g: g.add_pose(of="c", wrt="c")),
    ("constant_pose_change", ["constant"], lambda g: g.add_pose(of="f1", wrt="o1", rpy=[0, 0, 0.5])),
    ("multiple_pose_parents", ["{o1}|O1 already has a pose parent {c}|C"],
     lambda g: g.add_pose(of="o1", wrt="e")),
    ("pose_cycle", ["cycle"], lambda g: g.add_pose(of="b", wrt="o2")),
    ("pose_not_convertible", ["[q] must be a frame in the pose tree of {b}"],
     lambda g: g.add_pose(of="n", body="N", wrt="b", ref_body="B", expressed_in="q")),
    ("twist_same_body", ["relative to itself"],
     lambda g: g.add_twist(point="f1", ref_body="O1", expressed_in="f1")),
    ("multiple_twist_parents", ["already has a twist parent: body C"],
     lambda g: g.add_twist(point="o1", ref_body="B", expressed_in="o1")),
    ("duplicate_twist_path", ["already follows from the twist edges"],
     lambda g: g.add_twist(point="f1", body="O1", ref_body="B", expressed_in="f1")),
    ("twist_not_convertible", ["[q] must be a frame in the pose tree of {b}"],
     lambda g: g.add_twist(point="b", ref_body="Z", expressed_in="q")),
    ("no_such_edge", ["there is no pose edge {e}|E -> {c}|C"], lambda g: g.remove_pose(of="c", wrt="e")),
    ("no_such_edge", ["there is no twist edge E -> {c}|C"],
     lambda g: g.remove_twist(point="c", ref_body="E")),
    ("unknown_frame", ["frame {zz} does not exist"], lambda g: g.remove_pose(of="zz", wrt="b")),
    ("unknown_frame", ["zz"], lambda g: g.pose_handle(of="zz", wrt="b")),
    ("no_such_edge", [], lambda g: g.pose_handle(of="c", wrt="e")),
    ("constant_pose_change", [], lambda g: g.pose_handle(of="f1", wrt="o1")),
    ("no_such_edge", [], lambda g: g.twist_handle(point="c", ref_body="E")),
]


def scene_with_extra_trees():
    """The spray scene plus a second pose tree {w} -> {q}."""
    g = build_spray_painting()
    g.add_pose(of="q", body="Q", wrt="w", ref_body="W", position=[1, 0, 0])
    return g


@pytest.mark.parametrize("code,words,op", REJECTIONS, ids=[f"{c}-{i}" for i, (c, _, _) in enumerate(REJECTIONS)])
def test_refused_operation_raises_rejected_error_and_changes_nothing(code, words, op):
    g = scene_with_extra_trees()
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        op(g)
    e = info.value
    assert e.code == code
    assert isinstance(e.message, str) and e.message
    for w in words:
        assert w in e.message, e.message
    assert str(e) == e.message and code in e.message or str(e).endswith(f"({code})")
    assert isinstance(e, semgraph.Error)
    assert g.dump() == before
    assert g.check_invariants() == ""


def test_duplicate_pose_path_when_linking_trees():
    g = build_spray_painting()
    g.add_pose(of="x", body="X", wrt="c2", ref_body="C")
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        g.add_pose(of="c2", body="C", wrt="b", ref_body="B")
    assert info.value.code == "duplicate_pose_path"
    assert g.dump() == before


def test_representation_constraint_on_add():
    g = semgraph.SceneGraph(representation="homogeneous")
    with pytest.raises(semgraph.RejectedError) as info:
        g.add_pose(of="a", body="A", wrt="b", ref_body="B", expressed_in="a")
    assert info.value.code == "representation_constraint"
    assert "homogeneous" in info.value.message
    assert g.num_frames == 0 and g.num_bodies == 0  # the frames it would have created are gone


def test_refused_add_leaves_values_and_queries_unchanged(spray):
    before = spray.pose(of="f1", wrt="o2")
    with pytest.raises(semgraph.RejectedError):
        spray.add_pose(of="f1", wrt="o1", position=[5, 5, 5])  # constant_pose_change
    after = spray.pose(of="f1", wrt="o2")
    np.testing.assert_array_equal(before.position, after.position)
    np.testing.assert_array_equal(before.quaternion, after.quaternion)


def test_rejected_error_pickles():
    e = semgraph.RejectedError("self_edge", "pose of {c} wrt {c} rejected (self_edge): ...")
    e2 = pickle.loads(pickle.dumps(e))
    assert (e2.code, e2.message) == (e.code, e.message)
    q = semgraph.QueryError("unknown_frame", "m", "point", "of")
    q2 = pickle.loads(pickle.dumps(q))
    assert (q2.code, q2.message, q2.field, q2.argument) == ("unknown_frame", "m", "point", "of")


# ------------------------------------------------------------------ queries

QUERY_FAILURES = [
    # (code, field, argument, query)
    ("invalid_name", "point", "of", lambda g: g.pose(wrt="b")),
    ("invalid_name", "coordinate_frame", "expressed_in", lambda g: g.angular_velocity(body="O1", ref_body="B")),
    ("unknown_frame", "point", "of", lambda g: g.pose(of="zz", wrt="b")),
    ("unknown_frame", "point", "point", lambda g: g.pose(of="f1", point="zz", wrt="b")),
    ("unknown_frame", "ref_point", "wrt", lambda g: g.position(of="f1", wrt="zz")),
    ("unknown_frame", "coordinate_frame", "expressed_in", lambda g: g.pose(of="f1", wrt="b", expressed_in="zz")),
    ("unknown_frame", "point", "point", lambda g: g.twist(point="zz", ref_body="B", expressed_in="b")),
    ("unknown_frame", "coordinate_frame", "expressed_in",
     lambda g: g.twist(point="f1", ref_body="B", expressed_in="zz")),
    ("unknown_body", "body", "body", lambda g: g.pose(of="f1", body="ZZ", wrt="b")),
    ("unknown_body", "ref_body", "ref_body", lambda g: g.twist(point="f1", ref_body="ZZ", expressed_in="b")),
    ("frame_body_mismatch", "point", "of", lambda g: g.pose(of="f1", body="C", wrt="b")),
    ("frame_body_mismatch", "ref_orientation", "wrt", lambda g: g.orientation(of="f1", wrt="b", ref_body="E")),
    ("no_pose_path", None, None, lambda g: g.pose(of="f1", wrt="q")),
    ("no_pose_path", None, None, lambda g: g.twist(point="f1", ref_body="B", expressed_in="q")),
    ("no_twist_path", None, None, lambda g: g.twist(point="n", ref_body="B", expressed_in="b")),
    ("no_twist_path", None, None, lambda g: g.angular_velocity(body="N", ref_body="B", expressed_in="b")),
]


@pytest.mark.parametrize("code,field,argument,query", QUERY_FAILURES,
                         ids=[f"{c}-{i}" for i, (c, _, _, _) in enumerate(QUERY_FAILURES)])
def test_failed_query_raises_query_error(code, field, argument, query):
    g = build_spray_painting()
    g.add_pose(of="q", body="Q", wrt="w", ref_body="W")
    g.add_pose(of="n", body="N", wrt="b", ref_body="B")  # in the tree, no twist
    with pytest.raises(semgraph.QueryError) as info:
        query(g)
    e = info.value
    assert (e.code, e.field, e.argument) == (code, field, argument), e.message
    assert e.message and str(e).endswith(f"({code})")
    assert isinstance(e, semgraph.Error)
    # The compiled form refuses the same query with the same error.


def test_compile_refuses_like_the_one_shot_query(spray):
    for one_shot, compile_ in [
        (lambda: spray.pose(of="zz", wrt="b"), lambda: spray.compile_pose(of="zz", wrt="b")),
        (lambda: spray.position(of="f1", body="C", wrt="b"), lambda: spray.compile_position(of="f1", body="C", wrt="b")),
        (lambda: spray.orientation(of="f1", wrt="b", ref_body="Z"), lambda: spray.compile_orientation(of="f1", wrt="b", ref_body="Z")),
        (lambda: spray.twist(point="f1", ref_body="ZZ", expressed_in="b"), lambda: spray.compile_twist(point="f1", ref_body="ZZ", expressed_in="b")),
        (lambda: spray.linear_velocity(point="zz", ref_body="B", expressed_in="b"), lambda: spray.compile_linear_velocity(point="zz", ref_body="B", expressed_in="b")),
        (lambda: spray.angular_velocity(body="O1", ref_body="B", expressed_in="zz"), lambda: spray.compile_angular_velocity(body="O1", ref_body="B", expressed_in="zz")),
    ]:
        with pytest.raises(semgraph.QueryError) as a:
            one_shot()
        with pytest.raises(semgraph.QueryError) as b:
            compile_()
        assert (a.value.code, a.value.message, a.value.field, a.value.argument) == \
               (b.value.code, b.value.message, b.value.field, b.value.argument)


# ------------------------------------------------------------------ Python argument errors

TYPE_ERRORS = [
    ("pose(): of must be a str or None, not int", lambda g: g.pose(of=3, wrt="b")),
    ("pose(): expressed_in must be a str or None, not bytes", lambda g: g.pose(of="c", wrt="b", expressed_in=b"c")),
    ("add_body(): name must be a str or None, not list", lambda g: g.add_body(["B"])),
    ("add_pose(): position must be 3 numbers", lambda g: g.add_pose(of="n", wrt="b", position="abc")),
    ("add_pose(): position must be 3 numbers", lambda g: g.add_pose(of="n", wrt="b", position=[1, "2", 3])),
    ("add_pose(): position must be 3 numbers", lambda g: g.add_pose(of="n", wrt="b", position=np.array(["1", "2", "3"]))),
    ("add_pose(): quaternion must be 4 numbers", lambda g: g.add_pose(of="n", wrt="b", quaternion=object())),
    ("add_pose(): rotation must be a quaternion (w, x, y, z) or a 3x3 rotation matrix", lambda g: g.add_pose(of="n", wrt="b", rotation=5)),
    ("add_pose(): give at most one of rotation=, quaternion=, rotation_matrix=, rpy=; got quaternion=, rpy=",
     lambda g: g.add_pose(of="n", wrt="b", quaternion=[1, 0, 0, 0], rpy=[0, 0, 0])),
    ("add_twist(): angular must be 3 numbers", lambda g: g.add_twist(point="e", ref_body="B", expressed_in="e", angular={"x": 1})),
    ("set_pose(): position must be 3 numbers", lambda g: g.set_pose(g.pose_handle(of="e", wrt="b"), position="x")),
    ("SceneGraph(): representation must be a str or None, not int", lambda g: semgraph.SceneGraph(representation=1)),
    ("pose_batch(): handles must be a sequence of PoseHandle, not int", lambda g: g.pose_batch(3)),
    ("pose_batch(): handles[1] must be a PoseHandle, not str", lambda g: g.pose_batch([g.pose_handle(of="e", wrt="b"), "x"])),
    ("PoseBatch.set(): values must be numeric", lambda g: g.pose_batch([g.pose_handle(of="e", wrt="b")]).set("abc")),
]


@pytest.mark.parametrize("text,op", TYPE_ERRORS, ids=[t[:40] for t, _ in TYPE_ERRORS])
def test_wrong_python_type_raises_type_error_naming_the_argument(text, op):
    g = build_spray_painting()
    before = g.dump()
    with pytest.raises(TypeError) as info:
        op(g)
    assert str(info.value).startswith(text), str(info.value)
    assert g.dump() == before


VALUE_ERRORS = [
    ("add_pose(): position must have 3 elements, got 2", lambda g: g.add_pose(of="n", wrt="b", position=[1, 2])),
    ("add_pose(): position must be 3 numbers, got shape (2, 3)",
     lambda g: g.add_pose(of="n", wrt="b", position=np.zeros((2, 3)))),
    ("add_pose(): rotation_matrix must be a 3x3 matrix, got shape (2, 2)",
     lambda g: g.add_pose(of="n", wrt="b", rotation_matrix=[[1, 0], [0, 1]])),
    ("add_pose(): rotation must have 4 elements, got 5", lambda g: g.add_pose(of="n", wrt="b", rotation=[1, 0, 0, 0, 0])),
    ("add_pose(): rotation_matrix is not a regular array of numbers",
     lambda g: g.add_pose(of="n", wrt="b", rotation_matrix=[[1, 0, 0], [0, 1], [0, 0, 1]])),
    ("SceneGraph(): representation must be 'quaternion' or 'homogeneous', not 'euler'",
     lambda g: semgraph.SceneGraph(representation="euler")),
    ("PoseBatch.set(): values must have shape (N, 7)", lambda g: g.pose_batch([g.pose_handle(of="e", wrt="b")]).set(np.zeros((1, 6)))),
    ("PoseBatch.set(): values has 2 rows, the batch has 1 edges",
     lambda g: g.pose_batch([g.pose_handle(of="e", wrt="b")]).set(np.zeros((2, 7)))),
    ("TwistBatch.set(): values must have shape (N, 6)",
     lambda g: g.twist_batch([g.twist_handle(point="e", ref_body="B")]).set(np.zeros(6))),
    ("set_pose(): the handle belongs to another SceneGraph",
     lambda g: build_spray_painting().set_pose(g.pose_handle(of="e", wrt="b"))),
    ("pose_batch(): a handle belongs to another SceneGraph",
     lambda g: build_spray_painting().pose_batch([g.pose_handle(of="e", wrt="b")])),
]


@pytest.mark.parametrize("text,op", VALUE_ERRORS, ids=[t[:40] for t, _ in VALUE_ERRORS])
def test_wrong_python_value_raises_value_error_naming_the_argument(text, op):
    g = build_spray_painting()
    before = g.dump()
    with pytest.raises(ValueError) as info:
        op(g)
    assert str(info.value).startswith(text), str(info.value)
    assert not isinstance(info.value, semgraph.Error)
    assert g.dump() == before


def test_unknown_keyword_is_a_type_error(spray):
    with pytest.raises(TypeError):
        spray.pose(of="f1", relative_to="o2")
    with pytest.raises(TypeError):
        spray.pose("f1", "o2")  # roles are keyword-only


@pytest.mark.skipif(not semgraph._semgraph._has_tools, reason="built without the tool library")
def test_script_error_is_a_value_error_with_the_location():
    with pytest.raises(semgraph.ScriptError) as info:
        semgraph.run_script_text("ops:\n  - {op: bogus}\n", "scene.yaml")
    e = info.value
    assert isinstance(e, ValueError) and isinstance(e, semgraph.Error)
    assert (e.line, e.column) == (2, 10)  # the op's value
    assert str(e).startswith("scene.yaml:2:10: unknown op \"bogus\"")
    assert "bogus" in e.message
    with pytest.raises(FileNotFoundError):
        semgraph.run_script("/nonexistent/scene.yaml")
    with pytest.raises(TypeError):
        semgraph.run_script(3)
