"""Time from Python (docs/time.md): graph options, stamped adds and sets (int = nanoseconds,
float = seconds), the query policies (at, latest, latest_common, time travel, not_before,
max_extrapolation), twists from poses, the TimeReport, explain_pose / explain_twist and
compiled queries under a policy.

The reference motion is analytic: body B moves on a helix about the world's z axis (a constant
screw twist), so its pose at any time has a closed form, built here with numpy; body A screws
along x. Every expected value below comes from those formulas, never from semgraph."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph
from conftest import assert_rotation

OMEGA, RADIUS, VZ, THETA0 = 0.8, 0.5, 0.3, 0.2
CENTER = np.array([1.0, 2.0, 0.0])
B_STAMPS = [0.25 * k for k in range(9)]  # 0 .. 2 s
A_STAMPS = [0.5 * k for k in range(4)]  # 0 .. 1.5 s


def rz(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rx(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def X_WB(t):
    """The helix: R = Rz(w t + th0), p = center + r (cos, sin, 0) + (0, 0, vz t)."""
    th = OMEGA * t + THETA0
    return rz(th), CENTER + RADIUS * np.array([math.cos(th), math.sin(th), 0.0]) + np.array([0.0, 0.0, VZ * t])


# B's twist relative to W at b's origin, in [b]: constant (w x (p - c) + vz z, rotated into [b]).
V_WB_b = np.array([0.0, RADIUS * OMEGA, VZ])
W_WB_b = np.array([0.0, 0.0, OMEGA])


def X_WA(t):
    """A screws along x: R = Rx(0.5 t), p = (t, 0, 0)."""
    return rx(0.5 * t), np.array([t, 0.0, 0.0])


def relative(X_ref, X):
    """X_ref^-1 X: (R, p) of X in the frame of X_ref."""
    return X_ref[0].T @ X[0], X_ref[0].T @ (X[1] - X_ref[1])


def quat(R):
    x, y, z, w = Rotation.from_matrix(R).as_quat()
    return [w, x, y, z]


def stamp_arg(t, k):
    """Alternate the two spellings of a time: int nanoseconds and float seconds."""
    return round(t * 1e9) if k % 2 == 0 else float(t)


def add_samples(g, of, body, stamps, motion):
    for k, t in enumerate(stamps):
        R, p = motion(t)
        g.add_pose(of=of, body=body, wrt="w", ref_body="W", position=p, quaternion=quat(R), stamp=stamp_arg(t, k))


def helix_graph(**options):
    g = semgraph.SceneGraph(**options)
    add_samples(g, "b", "B", B_STAMPS, X_WB)
    return g


def assert_pose(result, R, p, tol=1e-12):
    np.testing.assert_allclose(result.position, p, atol=tol, rtol=0)
    assert_rotation(result.quaternion, R, tol)


def test_screw_interpolation_reproduces_the_constant_screw_motion():
    g = helix_graph()
    for t in [0.6, 0.125, 1.9, 1.0]:
        X = g.pose(of="b", wrt="w", at=t)
        assert_pose(X, *X_WB(t))
        assert X.time.time == pytest.approx(t, abs=1e-15)
        assert X.time.time_ns == round(t * 1e9)
        assert not X.time.extrapolated
    X = g.pose(of="b", wrt="w", at=0.6)
    assert (X.time.oldest, X.time.newest) == (0.5, 0.75)  # the bracket read
    assert "TimeReport(time=0.600000000 s" in repr(X.time)
    assert repr(X).endswith(", time=TimeReport(time=0.600000000 s, oldest=0.500000000 s, newest=0.750000000 s, "
                            "extrapolated=False))")
    assert "time=" not in repr(g.pose(of="b", wrt="w"))


def test_linear_interpolation_is_lerp_of_positions_and_slerp_of_rotations():
    g = helix_graph(interpolation="linear")
    assert g.time_options["interpolation"] == "linear"
    lam = (0.6 - 0.5) / 0.25
    p = (1 - lam) * X_WB(0.5)[1] + lam * X_WB(0.75)[1]  # the chord, not the helix
    X = g.pose(of="b", wrt="w", at=0.6)
    assert_pose(X, X_WB(0.6)[0], p)  # the slerp of two rotations about z is the rotation about z
    assert np.linalg.norm(p - X_WB(0.6)[1]) > 1e-4  # so the two modes really differ here


def test_int_is_nanoseconds_and_float_is_seconds():
    g = helix_graph()
    a = g.pose(of="b", wrt="w", at=1.5)
    b = g.pose(of="b", wrt="w", at=1_500_000_000)
    c = g.pose(of="b", wrt="w", at=np.int64(1_500_000_000))
    d = g.pose(of="b", wrt="w", at=np.float32(1.5))
    for r in (b, c, d):
        np.testing.assert_array_equal(r.position, a.position)
        assert r.time.time_ns == 1_500_000_000
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=-1)  # one nanosecond before the first sample
    assert e.value.code == "extrapolation"
    # The smallest step: 1 ns after a sample is inside the bracket.
    assert g.pose(of="b", wrt="w", at=500_000_001).time.time_ns == 500_000_001


def test_extrapolation_is_refused_unless_allowed_and_then_integrates_the_twist():
    g = helix_graph()
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=2.1)
    assert e.value.code == "extrapolation"
    assert "{b}" in e.value.message and "2.000" in e.value.message
    # No twist edge: a horizon alone does not help.
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=2.1, max_extrapolation=0.2)
    assert e.value.code == "extrapolation"
    g.add_twist(point="b", ref_body="W", expressed_in="b", linear=V_WB_b, angular=W_WB_b)
    X = g.pose(of="b", wrt="w", at=2.1, max_extrapolation=0.2)
    assert_pose(X, *X_WB(2.1), tol=1e-11)
    assert X.time.extrapolated
    X = g.pose(of="b", wrt="w", at=2.1, max_extrapolation=200_000_000)  # the horizon in ns
    assert X.time.extrapolated
    with pytest.raises(semgraph.QueryError) as e:  # beyond the horizon
        g.pose(of="b", wrt="w", at=2.5, max_extrapolation=0.2)
    assert e.value.code == "extrapolation"
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=2.1, max_extrapolation=-0.1)
    assert (e.value.code, e.value.argument) == ("invalid_number", "max_extrapolation")


def test_latest_common_with_a_horizon_integrates_back_before_the_first_sample():
    # z (static at (0, 0, 1) in w) has samples at -1 and -0.5 s; b's start at 0: latest common
    # of b wrt z is t* = -0.5 s, half a second before b's first sample.
    g = helix_graph()
    add_samples(g, "z", "Z", [-1.0, -0.5], lambda t: (np.eye(3), np.array([0.0, 0.0, 1.0])))
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="z", at="latest_common")
    assert e.value.code == "extrapolation"
    g.add_twist(point="b", ref_body="W", expressed_in="b", linear=V_WB_b, angular=W_WB_b)
    # The helix is a constant screw motion: integrated back from 0 s it is X_WB(-0.5) exactly.
    X = g.pose(of="b", wrt="z", at="latest_common", max_extrapolation=0.6)
    assert_pose(X, *relative((np.eye(3), np.array([0.0, 0.0, 1.0])), X_WB(-0.5)), tol=1e-11)
    assert X.time.time == -0.5
    assert X.time.extrapolated
    with pytest.raises(semgraph.QueryError) as e:  # the gap (0.5 s) beyond the horizon
        g.pose(of="b", wrt="z", at="latest_common", max_extrapolation=0.4)
    assert e.value.code == "extrapolation"


def test_latest_latest_common_and_time_travel():
    g = helix_graph()
    add_samples(g, "a", "A", A_STAMPS, X_WA)
    # latest: each edge's newest sample (b at 2.0, a at 1.5)
    X = g.pose(of="b", wrt="a", at="latest")
    assert_pose(X, *relative(X_WA(1.5), X_WB(2.0)))
    assert (X.time.oldest, X.time.newest, X.time.time) == (1.5, 2.0, None)
    # untimed: the same values, no report
    U = g.pose(of="b", wrt="a")
    np.testing.assert_allclose(U.position, X.position, atol=1e-15)
    assert U.time is None
    # latest common: both at 1.5 (tf2's Time(0))
    X = g.pose(of="b", wrt="a", at="latest_common")
    assert_pose(X, *relative(X_WA(1.5), X_WB(1.5)))
    assert X.time.time == 1.5
    # at t: both interpolated at t
    X = g.pose(of="b", wrt="a", at=0.6)
    assert_pose(X, *relative(X_WA(0.6), X_WB(0.6)))
    # time travel: b at 0.5, a at 1.25, through the world frame
    X = g.pose(of="b", wrt="a", at=0.5, ref_at=1.25, fixed="w")
    assert_pose(X, *relative(X_WA(1.25), X_WB(0.5)))
    assert (X.time.time, X.time.ref_time) == (0.5, 1.25)
    P = g.position(of="b", wrt="a", at=0.5, ref_at=1.25, fixed="w")
    np.testing.assert_allclose(P.position, relative(X_WA(1.25), X_WB(0.5))[1], atol=1e-12)
    O = g.orientation(of="b", wrt="a", at=0.6)
    assert_rotation(O.quaternion, relative(X_WA(0.6), X_WB(0.6))[0])
    assert O.time.time == pytest.approx(0.6)
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="a", at=0.5, ref_at=1.25, fixed="nowhere")
    assert (e.value.code, e.value.argument) == ("unknown_frame", "fixed")


def test_not_before_reports_a_stale_edge():
    g = helix_graph()
    assert g.pose(of="b", wrt="w", not_before=1.0).time.newest == 2.0
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", not_before=2.5)
    assert e.value.code == "stale"
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=1.0, not_before=2_500_000_000)
    assert e.value.code == "stale"


def test_twists_from_the_pose_history_equal_the_analytic_twist():
    g = helix_graph()
    for t in [0.6, 1.0, 2.0]:
        T = g.twist(point="b", ref_body="W", expressed_in="b", at=t, source="poses")
        np.testing.assert_allclose(T.linear, V_WB_b, atol=1e-10, rtol=0)
        np.testing.assert_allclose(T.angular, W_WB_b, atol=1e-10, rtol=0)
        assert T.time.time == pytest.approx(t)
    # In the world frame at the world origin: v = w x (0 - c) + vz z, with w = omega z.
    T = g.twist(point="w", body="B", ref_body="W", expressed_in="w", at=0.6, source="poses")
    w = np.array([0.0, 0.0, OMEGA])
    np.testing.assert_allclose(T.angular, w, atol=1e-10)
    np.testing.assert_allclose(T.linear, np.cross(w, -CENTER) + [0, 0, VZ], atol=1e-10)
    L = g.linear_velocity(point="b", ref_body="W", expressed_in="b", at=0.6, source="poses")
    np.testing.assert_allclose(L.linear, V_WB_b, atol=1e-10)
    A = g.angular_velocity(body="B", ref_body="W", expressed_in="w", at=0.6, source="poses")
    np.testing.assert_allclose(A.angular, w, atol=1e-10)
    # No twist edge: the default source has no twist path.
    with pytest.raises(semgraph.QueryError) as e:
        g.twist(point="b", ref_body="W", expressed_in="b", at=0.6)
    assert e.value.code == "no_twist_path"
    with pytest.raises(ValueError, match="source"):
        g.twist(point="b", ref_body="W", expressed_in="b", at=0.6, source="guess")


def test_stamped_twist_edges_are_interpolated_linearly():
    g = semgraph.SceneGraph()
    g.add_pose(of="b", body="B", wrt="w", ref_body="W")
    g.add_twist(point="b", ref_body="W", expressed_in="b", linear=[1, 0, 0], angular=[0, 0, 0.2], stamp=1.0)
    g.add_twist(point="b", ref_body="W", expressed_in="b", linear=[3, 0, 0], angular=[0, 0, 0.6], stamp=2_000_000_000)
    T = g.twist(point="b", ref_body="W", expressed_in="b", at=1.25)
    np.testing.assert_allclose(T.linear, [1.5, 0, 0], atol=1e-15)
    np.testing.assert_allclose(T.angular, [0, 0, 0.3], atol=1e-15)
    uses = g.explain_twist(point="b", ref_body="W", expressed_in="b", at=1.25)
    assert [(u.kind, u.of, u.relative_to, u.read_from, u.read_to) for u in uses] == [("twist", "b", "W", 1.0, 2.0)]


def test_explain_lists_the_edges_read_also_when_the_query_fails():
    g = helix_graph()
    add_samples(g, "a", "A", A_STAMPS, X_WA)
    g.add_pose(of="m", body="B", wrt="b", ref_body="B", position=[0, 0, 1])  # constant, timeless
    uses = {u.of: u for u in g.explain_pose(of="m", wrt="a", at=0.6)}
    assert set(uses) == {"m", "b", "a"}
    assert not uses["m"].stamped and uses["m"].first is None
    b = uses["b"]
    assert (b.kind, b.relative_to, b.stamped, b.first, b.last, b.read_from, b.read_to) == (
        "pose", "w", True, 0.0, 2.0, 0.5, 0.75)
    assert (uses["a"].read_from_ns, uses["a"].read_to_ns) == (500_000_000, 1_000_000_000)
    with pytest.raises(semgraph.QueryError):
        g.pose(of="m", wrt="a", at=1.8)  # a has no sample after 1.5
    uses = {u.of: u for u in g.explain_pose(of="m", wrt="a", at=1.8)}
    assert uses["a"].last == 1.5 and uses["b"].read_from == 1.75
    assert "EdgeUse(pose w -> {b}" in repr(uses["b"])


def test_compiled_queries_evaluate_at_a_time():
    g = helix_graph()
    add_samples(g, "a", "A", A_STAMPS, X_WA)
    c = g.compile_pose(of="b", wrt="a")
    X = c.evaluate(at=0.6)
    assert_pose(X, *relative(X_WA(0.6), X_WB(0.6)))
    assert X.time.time == pytest.approx(0.6)
    Y = g.pose(of="b", wrt="a", at=0.6)
    np.testing.assert_array_equal(X.position, Y.position)
    L = c.evaluate(at="latest_common")
    assert L.time.time == 1.5
    assert c.evaluate().time is None
    with pytest.raises(semgraph.QueryError) as e:
        c.evaluate(at=3.0)
    assert e.value.code == "extrapolation"
    with pytest.raises(semgraph.QueryError) as e:
        c.evaluate(not_before=5.0)
    assert e.value.code == "stale"
    p = g.compile_position(of="b", wrt="w").evaluate(at=1.1)
    np.testing.assert_allclose(p.position, X_WB(1.1)[1], atol=1e-12)
    o = g.compile_orientation(of="b", wrt="w").evaluate(at=1.1)
    assert_rotation(o.quaternion, X_WB(1.1)[0])
    t = g.compile_twist(point="b", ref_body="W", expressed_in="b", source="poses").evaluate(at=0.6)
    np.testing.assert_allclose(t.linear, V_WB_b, atol=1e-10)
    assert t.time.time == pytest.approx(0.6)
    lv = g.compile_linear_velocity(point="b", ref_body="W", expressed_in="b", source="poses").evaluate(at=0.6)
    np.testing.assert_allclose(lv.linear, V_WB_b, atol=1e-10)
    assert lv.semantics == g.linear_velocity(point="b", ref_body="W", expressed_in="b", at=0.6,
                                             source="poses").semantics
    av = g.compile_angular_velocity(body="B", ref_body="W", expressed_in="w", source="poses").evaluate(at=0.6)
    np.testing.assert_allclose(av.angular, [0, 0, OMEGA], atol=1e-10)
    assert av.semantics == "AngularVelocityCoord(B, W, [w])"
    with pytest.raises(semgraph.QueryError) as e:  # no twist edges: the default source has no path
        g.compile_linear_velocity(point="b", ref_body="W", expressed_in="b")
    assert e.value.code == "no_twist_path"


def test_an_untimed_compiled_twist_from_poses_reads_the_latest_samples():
    # Untimed, a compiled twist from poses reads under Latest: the helix's constant twist from
    # the newest two samples, and with a single sample no derivative: "extrapolation", as the
    # one-shot query says (not a zero twist, not "query_invalidated").
    g = helix_graph()
    t = g.compile_twist(point="b", ref_body="W", expressed_in="b", source="poses").evaluate()
    np.testing.assert_allclose(t.linear, V_WB_b, atol=1e-10)
    np.testing.assert_allclose(t.angular, W_WB_b, atol=1e-10)
    one = semgraph.SceneGraph()
    add_samples(one, "b", "B", [0.5], X_WB)
    for compile_kind in (one.compile_twist, one.compile_linear_velocity):
        c = compile_kind(point="b", ref_body="W", expressed_in="b", source="poses")
        with pytest.raises(semgraph.QueryError) as e:
            c.evaluate()
        assert e.value.code == "extrapolation"
    with pytest.raises(semgraph.QueryError) as e:
        one.twist(point="b", ref_body="W", expressed_in="b", source="poses")
    assert e.value.code == "extrapolation"


def test_stamped_set_pose_by_handle_in_and_out_of_order():
    g = helix_graph()
    h = g.pose_handle(of="b", wrt="w")
    for t in [2.5, 2.25]:  # the second one out of order
        R, p = X_WB(t)
        g.set_pose(h, position=p, quaternion=quat(R), stamp=t)
    assert_pose(g.pose(of="b", wrt="w", at=2.4), *X_WB(2.4))
    assert g.explain_pose(of="b", wrt="w", at=2.4)[0].read_from == 2.25
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(h, position=[0, 0, 0])  # a stamped edge needs a stamp
    assert e.value.code == "stamp_mismatch"
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(h, position=[0, 0, 0], stamp=math.nan)
    assert e.value.code == "invalid_number" and "stamp" in e.value.message
    with pytest.raises(TypeError, match="stamp"):
        g.set_pose(h, position=[0, 0, 0], stamp="now")
    with pytest.raises(TypeError, match="stamp"):
        g.set_pose(h, position=[0, 0, 0], stamp=True)
    assert g.dump() == before


def test_stamped_set_twist_by_handle():
    g = semgraph.SceneGraph()
    g.add_pose(of="b", body="B", wrt="w", ref_body="W")
    g.add_twist(point="b", ref_body="W", expressed_in="b", linear=[1, 0, 0], stamp=0)
    h = g.twist_handle(point="b", ref_body="W")
    g.set_twist(h, linear=[2, 0, 0], stamp=1.0)
    np.testing.assert_allclose(g.twist(point="b", ref_body="W", expressed_in="b", at=0.5).linear, [1.5, 0, 0], atol=1e-15)


def test_stamp_rules_refuse_and_change_nothing():
    g = semgraph.SceneGraph(window=1.0, duplicate_stamp="reject", sample_capacity=2)
    assert g.time_options == {"window": 1.0, "window_ns": 1_000_000_000, "interpolation": "screw",
                              "duplicate_stamp": "reject", "sample_capacity": 2}
    g.add_pose(of="b", body="B", wrt="w", ref_body="W", position=[0, 0, 0], stamp=5.0)
    g.add_pose(of="t", body="T", wrt="w", ref_body="W", position=[0, 0, 0])  # timeless
    cases = [
        ("stamp_too_old", lambda: g.add_pose(of="b", wrt="w", position=[1, 0, 0], stamp=3.9)),
        ("duplicate_stamp", lambda: g.add_pose(of="b", wrt="w", position=[1, 0, 0], stamp=5.0)),
        ("stamp_mismatch", lambda: g.add_pose(of="t", wrt="w", position=[1, 0, 0], stamp=5.0)),
        ("stamp_mismatch", lambda: g.add_pose(of="b", wrt="w", position=[1, 0, 0])),
        ("invalid_number", lambda: g.add_pose(of="b", wrt="w", position=[1, 0, 0], stamp=math.inf)),
        ("invalid_number", lambda: g.add_pose(of="b", wrt="w", stamp=2 ** 70)),
    ]
    for code, op in cases:
        before = g.dump()
        with pytest.raises(semgraph.RejectedError) as e:
            op()
        assert e.value.code == code, (code, e.value.message)
        assert g.dump() == before
    g.add_pose(of="b", wrt="w", position=[0, 0, 0], stamp=5.0)  # the same value again: a no-op
    g.add_pose(of="b", wrt="w", position=[1, 0, 0], stamp=5.5)
    g.add_pose(of="b", wrt="w", position=[2, 0, 0], stamp=6.0)  # capacity 2: drops 5.0
    assert g.explain_pose(of="b", wrt="w")[0].first == 5.5


def test_time_options_and_time_keywords_are_checked():
    for kwargs, code in [({"window": 0.0}, "invalid_number"), ({"window": -5}, "invalid_number"),
                         ({"sample_capacity": 1}, "invalid_number")]:
        with pytest.raises(semgraph.RejectedError) as e:
            semgraph.SceneGraph(**kwargs)
        assert e.value.code == code
    with pytest.raises(ValueError, match="interpolation"):
        semgraph.SceneGraph(interpolation="cubic")
    with pytest.raises(ValueError, match="duplicate_stamp"):
        semgraph.SceneGraph(duplicate_stamp="keep")
    with pytest.raises(TypeError, match="window"):
        semgraph.SceneGraph(window="10s")
    with pytest.raises(TypeError, match="sample_capacity"):
        semgraph.SceneGraph(sample_capacity=2.5)
    assert semgraph.SceneGraph(window=2_000_000_000).time_options["window"] == 2.0
    g = helix_graph()
    with pytest.raises(ValueError, match="at must be"):
        g.pose(of="b", wrt="w", at="soon")
    with pytest.raises(TypeError, match="at must be a time"):
        g.pose(of="b", wrt="w", at=[1.0])
    with pytest.raises(ValueError, match="max_extrapolation"):
        g.pose(of="b", wrt="w", max_extrapolation=0.1)
    with pytest.raises(ValueError, match="ref_at"):
        g.pose(of="b", wrt="w", at=1.0, ref_at=0.5)
    with pytest.raises(ValueError, match="time travel needs at="):
        g.pose(of="b", wrt="w", ref_at=0.5, fixed="w")
    with pytest.raises(TypeError):  # twists have no time travel
        g.twist(point="b", ref_body="W", expressed_in="b", at=1.0, ref_at=0.5, fixed="w")
    with pytest.raises(semgraph.QueryError) as e:
        g.pose(of="b", wrt="w", at=math.nan)
    assert e.value.code == "invalid_number"
    with pytest.raises(ValueError, match="stamp= and repair="):
        g.add_pose(of="b", wrt="w", stamp=1.0, repair=True)


def test_explain_twist_from_poses_lists_the_differentiated_edges():
    g = helix_graph()
    uses = g.explain_twist(point="b", ref_body="W", expressed_in="b", at=0.6, source="poses")
    assert [(u.kind, u.of, u.relative_to, u.read_from, u.read_to) for u in uses] == [
        ("pose_derivative", "b", "w", 0.5, 0.75)]
