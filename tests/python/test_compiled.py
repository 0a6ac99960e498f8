"""Compiled queries, handles and batch updates: the same numbers as the one-shot queries (and as
the oracle) after every kind of update, invalidation after removals, and lifetime (a compiled
query, handle or batch keeps its graph alive; nothing dangles)."""

import gc
import threading

import numpy as np
import pytest

import semgraph
from conftest import POSES, World, assert_rotation, build_spray_painting, rpy_rotation, wxyz


def moved_world(e_angles, e_position):
    """The oracle with the robot joint pose {b} -> {e} replaced."""
    poses = [(of, body, wrt, rb, e_angles, e_position) if of == "e" else (of, body, wrt, rb, a, p)
             for of, body, wrt, rb, a, p in POSES]
    return World(poses)


def every_compiled(g):
    return {
        "pose": (g.compile_pose(of="f1", wrt="o2", expressed_in="c"),
                 lambda: g.pose(of="f1", wrt="o2", expressed_in="c")),
        "position": (g.compile_position(of="f1", wrt="b", expressed_in="o2"),
                     lambda: g.position(of="f1", wrt="b", expressed_in="o2")),
        "orientation": (g.compile_orientation(of="o2", wrt="o1"), lambda: g.orientation(of="o2", wrt="o1")),
        "twist": (g.compile_twist(point="f1", ref_body="O2", expressed_in="o2"),
                  lambda: g.twist(point="f1", ref_body="O2", expressed_in="o2")),
        "linear": (g.compile_linear_velocity(point="o2", body="O1", ref_body="O2", expressed_in="b"),
                   lambda: g.linear_velocity(point="o2", body="O1", ref_body="O2", expressed_in="b")),
        "angular": (g.compile_angular_velocity(body="O1", ref_body="E", expressed_in="c"),
                    lambda: g.angular_velocity(body="O1", ref_body="E", expressed_in="c")),
    }


FIELDS = ["position", "quaternion", "linear", "angular"]


def assert_same_result(a, b):
    assert type(a) is type(b)
    assert a.semantics == b.semantics
    for f in FIELDS:
        if hasattr(a, f):
            np.testing.assert_allclose(getattr(a, f), getattr(b, f), atol=1e-12, rtol=0)


def test_compiled_equals_one_shot_for_every_kind(spray):
    for name, (compiled, one_shot) in every_compiled(spray).items():
        r = compiled.evaluate()
        assert_same_result(r, one_shot())
        assert compiled.is_valid
        assert repr(compiled).startswith("Compiled")
    kinds = {k: type(c.evaluate()).__name__ for k, (c, _) in every_compiled(spray).items()}
    assert kinds == {"pose": "Pose", "position": "Position", "orientation": "Orientation",
                     "twist": "Twist", "linear": "LinearVelocity", "angular": "AngularVelocity"}


def test_compiled_pose_path_length(spray):
    q = spray.compile_pose(of="f1", wrt="o2")
    assert q.num_pose_edges == 5  # f1 -> o1 -> c -> b <- e <- o2
    t = spray.compile_twist(point="f1", ref_body="O2", expressed_in="o2")
    assert t.num_twist_edges == 4


def test_compiled_queries_follow_set_pose_add_pose_and_set_twist(spray):
    compiled = every_compiled(spray)
    h = spray.pose_handle(of="e", wrt="b")
    assert repr(h) == "PoseHandle(of='e', wrt='b')" and h.is_valid
    angles, position = (0.3, -0.2, 0.9), (0.4, 0.1, 0.8)
    spray.set_pose(h, position=position, rpy=angles)
    world = moved_world(angles, position)
    X = compiled["pose"][0].evaluate()
    p, R = world.pose("f1", "f1", "o2", "o2", "c")
    np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
    assert_rotation(X.quaternion, R)
    for _, (c, one_shot) in compiled.items():
        assert_same_result(c.evaluate(), one_shot())
    # An update through add_pose of the existing edge is seen too (same edge, same epoch).
    angles2, position2 = (0.0, 0.1, -0.4), (0.6, 0.0, 0.5)
    spray.add_pose(of="e", wrt="b", position=position2, rotation_matrix=rpy_rotation(*angles2).as_matrix())
    X = compiled["pose"][0].evaluate()
    p, R = moved_world(angles2, position2).pose("f1", "f1", "o2", "o2", "c")
    np.testing.assert_allclose(X.position, p, atol=1e-12, rtol=0)
    assert h.is_valid
    # Twist updates: the joint velocities B -> e.
    t = spray.twist_handle(point="e", ref_body="B")
    assert repr(t) == "TwistHandle(point='e', ref_body='B')"
    spray.set_twist(t, linear=[0.1, 0.2, 0.3], angular=[0.0, 0.0, 0.5])
    for _, (c, one_shot) in compiled.items():
        assert_same_result(c.evaluate(), one_shot())
    w = compiled["angular"][0].evaluate().angular
    spray.set_twist(t, linear=[0.1, 0.2, 0.3], angular=[0.0, 0.0, 0.0])
    assert not np.allclose(w, compiled["angular"][0].evaluate().angular)


def test_refused_set_pose_keeps_the_value(spray):
    h = spray.pose_handle(of="e", wrt="b")
    before = spray.dump()
    for kwargs, code in [(dict(quaternion=[2, 0, 0, 0]), "invalid_rotation"),
                         (dict(position=[0, np.inf, 0]), "invalid_number"),
                         (dict(rotation_matrix=np.ones((3, 3))), "invalid_rotation")]:
        with pytest.raises(semgraph.RejectedError) as info:
            spray.set_pose(h, **kwargs)
        assert info.value.code == code
        assert "set_pose of the pose edge {b} -> {e} rejected" in info.value.message
    t = spray.twist_handle(point="e", ref_body="B")
    with pytest.raises(semgraph.RejectedError) as info:
        spray.set_twist(t, angular=[np.nan, 0, 0])
    assert info.value.code == "invalid_number"
    assert spray.dump() == before


def test_removal_invalidates_compiled_queries_and_handles(spray):
    compiled = every_compiled(spray)
    unaffected = spray.compile_pose(of="o2", wrt="b")
    h = spray.pose_handle(of="o1", wrt="c")
    spray.remove_pose(of="o1", wrt="c")
    for name in ["pose", "position", "orientation"]:
        c = compiled[name][0]
        assert not c.is_valid
        with pytest.raises(semgraph.QueryError) as info:
            c.evaluate()
        assert info.value.code == "query_invalidated"
        assert "compile it again" in info.value.message
    assert unaffected.is_valid and unaffected.evaluate() is not None
    assert not h.is_valid
    with pytest.raises(semgraph.RejectedError) as info:
        spray.set_pose(h, position=[0, 0, 0])
    assert info.value.code == "no_such_edge"
    # Re-adding the edge does not revive the old handle or query: recompile.
    spray.add_pose(of="o1", wrt="c", position=[0.5, 0.2, 1.1])
    assert not h.is_valid and not compiled["pose"][0].is_valid
    again = spray.compile_pose(of="f1", wrt="o2", expressed_in="c")
    assert_same_result(again.evaluate(), spray.pose(of="f1", wrt="o2", expressed_in="c"))
    # Twist removal invalidates the twist queries that read the edge.
    spray.remove_twist(point="e", ref_body="B")
    with pytest.raises(semgraph.QueryError) as info:
        compiled["twist"][0].evaluate()
    assert info.value.code == "query_invalidated"


def chain(n):
    g = semgraph.SceneGraph()
    for i in range(n):
        g.add_pose(of=f"j{i + 1}", body=f"L{i + 1}", wrt=f"j{i}", ref_body=f"L{i}", position=[1, 0, 0])
    for i in range(n):
        g.add_twist(point=f"j{i + 1}", ref_body=f"L{i}", expressed_in=f"j{i + 1}")
    return g


def test_pose_batch_sets_every_edge_from_one_array():
    n = 50
    g = chain(n)
    batch = g.pose_batch([g.pose_handle(of=f"j{i + 1}", wrt=f"j{i}") for i in range(n)])
    assert len(batch) == n and repr(batch) == f"PoseBatch({n} edges)"
    rng = np.random.default_rng(7)
    positions = rng.uniform(-1, 1, (n, 3))
    rotations = [rpy_rotation(*a) for a in rng.uniform(-3, 3, (n, 3))]
    values = np.hstack([positions, np.array([wxyz(r) for r in rotations])])
    batch.set(values)
    # The oracle: chain the edges by hand.
    R, p = np.eye(3), np.zeros(3)
    for i in range(n):
        p = p + R @ positions[i]
        R = R @ rotations[i].as_matrix()
    X = g.pose(of=f"j{n}", wrt="j0")
    np.testing.assert_allclose(X.position, p, atol=1e-11, rtol=0)
    assert_rotation(X.quaternion, R, tol=1e-11)
    # (N, 4, 4) homogeneous matrices give the same state.
    T = np.tile(np.eye(4), (n, 1, 1))
    for i in range(n):
        T[i, :3, :3] = rotations[i].as_matrix()
        T[i, :3, 3] = positions[i]
    g2 = chain(n)
    g2.pose_batch([g2.pose_handle(of=f"j{i + 1}", wrt=f"j{i}") for i in range(n)]).set(T)
    X2 = g2.pose(of=f"j{n}", wrt="j0")
    np.testing.assert_allclose(X2.position, p, atol=1e-11, rtol=0)
    assert_rotation(X2.quaternion, R, tol=1e-11)


def test_refused_batch_changes_nothing():
    n = 10
    g = chain(n)
    handles = [g.pose_handle(of=f"j{i + 1}", wrt=f"j{i}") for i in range(n)]
    batch = g.pose_batch(handles)
    values = np.tile([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], (n, 1))
    values[7, 3] = 2.0  # row 7: not a unit quaternion
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        batch.set(values)
    assert info.value.code == "invalid_rotation"
    assert "row 7 of the pose edge {j7} -> {j8}" in info.value.message
    assert g.dump() == before
    T = np.tile(np.eye(4), (n, 1, 1))
    T[3, 3, 0] = 1.0  # row 3: bottom row not [0 0 0 1]
    with pytest.raises(semgraph.RejectedError) as info:
        batch.set(T)
    assert info.value.code == "invalid_rotation" and "row 3" in info.value.message
    values[7, 3] = 1.0
    values[2, 1] = np.nan
    with pytest.raises(semgraph.RejectedError) as info:
        batch.set(values)
    assert info.value.code == "invalid_number" and "row 2" in info.value.message
    assert g.dump() == before
    # A removed edge: the whole batch is refused, the other edges keep their values.
    g.remove_pose(of="j5", wrt="j4")
    values[2, 1] = 0.5
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        batch.set(values)
    assert info.value.code == "no_such_edge" and "row 4" in info.value.message
    assert g.dump() == before


def test_twist_batch():
    n = 5
    g = chain(n)
    batch = g.twist_batch([g.twist_handle(point=f"j{i + 1}", ref_body=f"L{i}") for i in range(n)])
    values = np.zeros((n, 6))
    values[:, 5] = np.arange(1, n + 1)  # angular z
    values[:, 0] = 0.1
    batch.set(values)
    w = g.angular_velocity(body=f"L{n}", ref_body="L0", expressed_in="j0").angular
    # All edges are pure translations along x, so the frames stay parallel: w adds up.
    np.testing.assert_allclose(w, [0, 0, n * (n + 1) / 2], atol=1e-12, rtol=0)
    values[1, 0] = np.inf
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        batch.set(values)
    assert info.value.code == "invalid_number" and "row 1" in info.value.message
    assert g.dump() == before


def test_batch_update_runs_concurrently_with_compiled_readers():
    """PoseBatch.set releases the GIL; readers in this thread must see each edge untorn: every
    evaluation equals one of the two values the writer alternates between."""
    g = chain(1)
    batch = g.pose_batch([g.pose_handle(of="j1", wrt="j0")])
    q = g.compile_pose(of="j1", wrt="j0")
    a = np.array([[1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0]])
    b = np.array([[-4.0, 5.0, -6.0, 0.0, 0.0, 0.0, 1.0]])
    batch.set(a)
    stop = threading.Event()

    def writer():
        while not stop.is_set():
            batch.set(b)
            batch.set(a)

    t = threading.Thread(target=writer)
    t.start()
    try:
        for _ in range(20000):
            X = q.evaluate()
            pos = tuple(X.position)
            assert pos in [(1.0, 2.0, 3.0), (-4.0, 5.0, -6.0)]
            if pos[0] == 1.0:
                np.testing.assert_array_equal(X.quaternion, [1, 0, 0, 0])
            else:
                np.testing.assert_array_equal(X.quaternion, [0, 0, 0, 1])
    finally:
        stop.set()
        t.join()


# ------------------------------------------------------------------ lifetime

def test_compiled_query_keeps_its_graph_alive():
    def make():
        g = build_spray_painting()
        return g.compile_pose(of="f1", wrt="o2"), g.pose(of="f1", wrt="o2")

    q, expected = make()
    gc.collect()  # the SceneGraph object is gone; its C++ graph is not
    r = q.evaluate()
    np.testing.assert_array_equal(r.position, expected.position)
    assert r.semantics == "PoseCoord({f1}|O1, {o2}|O2, [o2])"


def test_handles_and_batches_keep_their_graph_alive():
    g = build_spray_painting()
    q = g.compile_pose(of="o2", wrt="b")
    batch = g.pose_batch([g.pose_handle(of="e", wrt="b")])
    del g
    gc.collect()
    batch.set(np.array([[1.0, 2.0, 3.0, 1.0, 0.0, 0.0, 0.0]]))
    X = q.evaluate()  # o2 = e + R_be p_eo2 with R_be = I
    np.testing.assert_allclose(X.position, [1.0, 2.05, 3.12], atol=1e-12, rtol=0)


def test_results_outlive_the_graph():
    r = build_spray_painting().twist(point="f1", ref_body="O2", expressed_in="o2")
    gc.collect()
    assert r.semantics == "TwistCoord(f1|O1, O2, [o2])" and r.linear.shape == (3,)


def test_result_arrays_are_copies(spray):
    X = spray.pose(of="c", wrt="b")
    p = X.position
    p[0] = 100.0
    assert X.position[0] != 100.0
    assert X.position.dtype == np.float64
