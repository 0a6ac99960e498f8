"""Compiled queries with covariance (SceneGraph.compile_*_with_covariance, python/src/
compiled_covariance.cc): on random scenes with stamped and timeless covariances, every kind's
evaluate() equals the one-shot *_with_covariance query (value, covariance, semantics, TimeReport)
now, at the newest samples, between samples, extrapolated after the last sample and at the
latest common time; cases by hand (the edge covariances and Jacobians in numpy, never read back
from the module); bad input and evaluation after a removal raise as the plain compiled queries
do."""

import gc
import os
import re

import numpy as np
import pytest

import semgraph
from conftest import rpy_rotation, source_dir

RZ90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
RX90 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])
I3, Z3 = np.eye(3), np.zeros((3, 3))
S1 = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def spd(rng, scale):
    """A dense symmetric positive definite 6x6 matrix."""
    A = rng.normal(size=(6, 6))
    return scale * (A @ A.T + 6 * np.eye(6))


def report(r):
    t = r.time
    return (t.time_ns, t.ref_time_ns, t.oldest_ns, t.newest_ns, t.extrapolated)


def query_error(call):
    with pytest.raises(semgraph.QueryError) as info:
        call()
    return info.value.code, info.value.argument, info.value.message


def assert_same(got, want):
    """(result, covariance) pairs: the same kind, semantics, numbers (rtol 1e-12; entries near
    zero against the matrix's scale) and TimeReport."""
    (r, S), (r0, S0) = got, want
    assert type(r) is type(r0)
    assert r.semantics == r0.semantics
    for f in ["position", "quaternion", "linear", "angular"]:
        if hasattr(r0, f):
            a, b = getattr(r, f), getattr(r0, f)
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(b).max()))
    assert S.shape == S0.shape and S.dtype == np.float64
    np.testing.assert_allclose(S, S0, rtol=1e-12, atol=1e-12 * np.abs(S0).max())
    if r0.time is None:
        assert r.time is None
    else:
        assert report(r) == report(r0)


# ------------------------------------------------------------------------- random scenes

STAMPS = [0.0, 0.5, 1.0]  # seconds; every stamped edge has a sample at each


def random_scene(seed, representation="quaternion", n=6):
    """Bodies B0 (root, frame f0) .. Bn, frame fi of Bi under a random earlier frame: a pose edge
    (stamped with a random value and covariance at each of STAMPS, or timeless with a
    covariance) and the twist edge of the same bodies (timeless or stamped, with a covariance);
    a frame gi fixed in each body (exact). Returns (graph, rng, parent index of each fi)."""
    rng = np.random.default_rng(seed)
    g = semgraph.SceneGraph(representation=representation)
    parent = {}
    for i in range(1, n + 1):
        j = int(rng.integers(0, i))
        parent[i] = j
        kw = dict(of=f"f{i}", body=f"B{i}", wrt=f"f{j}", ref_body=f"B{j}")
        if i % 3 != 0:
            for t in STAMPS:
                g.add_pose(**kw, position=rng.uniform(-1, 1, 3),
                           rpy=rng.uniform(-np.pi, np.pi, 3), stamp=t, covariance=spd(rng, 1e-3))
        else:
            g.add_pose(**kw, position=rng.uniform(-1, 1, 3), rpy=rng.uniform(-np.pi, np.pi, 3),
                       covariance=spd(rng, 1e-3))
        tw = dict(point=f"f{i}", body=f"B{i}", ref_body=f"B{j}", expressed_in=f"f{i}")
        if i % 2 == 0:
            for t in STAMPS:
                g.add_twist(**tw, linear=rng.uniform(-1, 1, 3), angular=rng.uniform(-1, 1, 3),
                            stamp=t, covariance=spd(rng, 1e-2))
        else:
            g.add_twist(**tw, linear=rng.uniform(-1, 1, 3), angular=rng.uniform(-1, 1, 3),
                        covariance=spd(rng, 1e-2))
    for i in range(n + 1):
        g.add_pose(of=f"g{i}", body=f"B{i}", wrt=f"f{i}", ref_body=f"B{i}",
                   position=rng.uniform(-1, 1, 3), rpy=rng.uniform(-np.pi, np.pi, 3))
    return g, rng, parent


def random_frame(rng, n=6):
    return f"{'fg'[int(rng.integers(0, 2))]}{int(rng.integers(0, n + 1))}"


def random_queries(rng, count=4, n=6, representation="quaternion"):
    """(kind, keywords) of every kind, `count` times: the same keywords for the compiled query
    and the one-shot one. (Homogeneous poses and orientations are expressed in their reference
    frame: the representation's constraint.)"""
    out = []
    for _ in range(count):
        e, f, r = random_frame(rng, n), random_frame(rng, n), random_frame(rng, n)
        C, D = f"B{int(e[1:])}", f"B{int(rng.integers(0, n + 1))}"
        order = ["linear_angular", "angular_linear"][int(rng.integers(0, 2))]
        names = dict(of=e, wrt=f, expressed_in=r)
        rotated = names if representation == "quaternion" else dict(names, expressed_in=f)
        out += [
            ("pose", dict(rotated, covariance_order=order)),
            ("position", names),
            ("orientation", rotated),
            ("twist", dict(point=e, ref_body=D, expressed_in=r, covariance_order=order)),
            ("linear_velocity", dict(point=e, body=C, ref_body=D, expressed_in=r)),
            ("angular_velocity", dict(body=C, ref_body=D, expressed_in=r)),
        ]
    return out


def without_order(kw):
    return {k: v for k, v in kw.items() if k != "covariance_order"}


TIMES = [
    dict(),                                  # each edge's current value (its newest sample)
    dict(at="latest"),
    dict(at=0.3),                            # between samples
    dict(at=250_000_000),                    # between samples, int nanoseconds
    dict(at=1.4, max_extrapolation=0.5),     # after the last sample: extrapolated
    dict(at="latest_common"),
    dict(not_before=0.5),
]


@pytest.mark.parametrize("representation", ["quaternion", "homogeneous"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_kind_equals_the_one_shot_query(seed, representation):
    g, rng, _ = random_scene(seed, representation)
    checked = uncertain = extrapolated = 0
    for kind, kw in random_queries(rng, representation=representation):
        c = getattr(g, f"compile_{kind}_with_covariance")(**kw)
        one_shot = getattr(g, f"{kind}_with_covariance")
        for time in TIMES:
            want = one_shot(**kw, **time)
            got = c.evaluate(**time)
            assert_same(got, want)
            if time:
                extrapolated += got[0].time.extrapolated
            uncertain += bool(want[1].any())
            checked += 1
        assert repr(c).startswith(type(c).__name__ + "(")
    assert checked == 4 * 6 * len(TIMES)
    assert uncertain > checked // 2  # most queries read uncertain edges (not one body's frames)
    assert extrapolated > 0


@pytest.mark.parametrize("seed", [4, 5])
def test_compiled_queries_follow_updates_and_new_samples(seed):
    """After set_pose / set_twist with new covariances through handles and a newer sample, the
    same compiled objects still answer as the one-shot queries (now, latest, between samples)."""
    g, rng, parent = random_scene(seed)
    queries = [(getattr(g, f"compile_{kind}_with_covariance")(**kw),
                getattr(g, f"{kind}_with_covariance"), kw)
               for kind, kw in random_queries(rng, count=2)]
    before = [c.evaluate() for c, _, _ in queries]
    # f3's pose edge and f1's twist edge are timeless, f2's pose edge stamped.
    g.set_pose(g.pose_handle(of="f3", wrt=f"f{parent[3]}"), position=(0.1, 0.2, 0.3),
               rpy=(0.3, 0.2, 0.1), covariance=spd(rng, 2e-3))
    g.set_twist(g.twist_handle(point="f1", ref_body="B0"), linear=(1, 0, 0), angular=(0, 0, 1),
                covariance=spd(rng, 1e-2))
    g.add_pose(of="f2", body="B2", wrt=f"f{parent[2]}", ref_body=f"B{parent[2]}",
               position=(0.5, 0.5, 0.5), stamp=1.5, covariance=spd(rng, 1e-3))
    changed = 0
    for (c, one_shot, kw), old in zip(queries, before):
        for time in [dict(), dict(at="latest"), dict(at=0.7), dict(at=1.2, max_extrapolation=0.5)]:
            assert_same(c.evaluate(**time), one_shot(**kw, **time))
        changed += not np.array_equal(c.evaluate()[1], old[1])
    assert changed > 0


# ------------------------------------------------------------------------- by hand

def test_one_edge_by_hand():
    """One edge w -> a with S1 (edge form: (dp, dth) at a, in [w]): the position of a wrt w in
    [w] has S1's linear block, the orientation its angular block. In [a], which the edge's
    rotation moves too: p_a = R^T p, d(p_a) = R^T dp + R^T [p]x dth."""
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 2, 3),
               rotation_matrix=RZ90, covariance=S1)
    p, Sp = g.compile_position_with_covariance(of="a", wrt="w").evaluate()
    np.testing.assert_allclose(p.position, [1, 2, 3], atol=1e-15)
    np.testing.assert_allclose(Sp, S1[:3, :3], rtol=1e-12, atol=0)
    assert p.time is None
    _, So = g.compile_orientation_with_covariance(of="a", wrt="w").evaluate()
    np.testing.assert_allclose(So, S1[3:, 3:], rtol=1e-12, atol=0)
    _, Sp_a = g.compile_position_with_covariance(of="a", wrt="w", expressed_in="a").evaluate()
    J = np.hstack([RZ90.T, RZ90.T @ skew([1.0, 2, 3])])
    np.testing.assert_allclose(Sp_a, J @ S1 @ J.T, rtol=1e-12, atol=1e-15)
    assert Sp_a[0, 0] == pytest.approx(0.02 + 9 * 0.001 + 1 * 0.003, abs=1e-15)
    _, S = g.compile_pose_with_covariance(of="a", wrt="w",
                                          covariance_order="angular_linear").evaluate()
    np.testing.assert_allclose(S, np.block([[S1[3:, 3:], Z3], [Z3, S1[:3, :3]]]), atol=1e-15)


def stamped_chain(representation):
    """w -> a (Rz90, p from (1, 0, 0) at 0 s to (1, 2, 0) at 1 s, Sa0 then Sa1) -> b (the
    identity rotation, p from (2, 0, 0) to (4, 0, 0), Sb0 then Sb1); e fixed in W (Rx90,
    exact), a coordinate frame no uncertain edge moves."""
    rng = np.random.default_rng(11)
    Sa, Sb = [spd(rng, 1e-3) for _ in range(2)], [spd(rng, 1e-3) for _ in range(2)]
    g = semgraph.SceneGraph(representation=representation)
    for k, t in enumerate([0.0, 1.0]):
        g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 2 * k, 0),
                   rotation_matrix=RZ90, stamp=t, covariance=Sa[k])
        g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=(2 + 2 * k, 0, 0), stamp=t,
                   covariance=Sb[k])
    g.add_pose(of="e", body="W", wrt="w", ref_body="W", rotation_matrix=RX90)
    return g, Sa, Sb


@pytest.mark.parametrize("representation", ["quaternion", "homogeneous"])
def test_chain_of_two_stamped_edges_by_hand(representation):
    """b wrt w in [w] at 0.25 s: each edge's covariance interpolated, (1 - l) S_0 + l S_1, and
    carried by the adjoint Jacobians: dp_wb = dp_a + dth_a x (R_a p_ab) + R_a dp_b,
    dth_wb = dth_a + R_a dth_b."""
    g, Sa, Sb = stamped_chain(representation)
    lam = 0.25
    r = RZ90 @ np.array([2 + 2 * lam, 0, 0])  # b's origin from a's, in [w]
    Ja = np.block([[I3, -skew(r)], [Z3, I3]])
    Jb = np.block([[RZ90, Z3], [Z3, RZ90]])
    Sa_t, Sb_t = (1 - lam) * Sa[0] + lam * Sa[1], (1 - lam) * Sb[0] + lam * Sb[1]
    want = Ja @ Sa_t @ Ja.T + Jb @ Sb_t @ Jb.T
    c = g.compile_pose_with_covariance(of="b", wrt="w")
    X, S = c.evaluate(at=lam)
    np.testing.assert_allclose(X.position, [1, 2 * lam, 0] + r, atol=1e-12)
    np.testing.assert_allclose(S, want, rtol=1e-12, atol=1e-15)
    assert X.time.time == lam and not X.time.extrapolated
    _, Sp = g.compile_position_with_covariance(of="b", wrt="w").evaluate(at=lam)
    np.testing.assert_allclose(Sp, want[:3, :3], rtol=1e-12, atol=1e-15)
    # Expressed in [e] (exact): both blocks turned by R_we^T (homogeneous poses: only in [w]).
    _, Sp_e = g.compile_position_with_covariance(of="b", wrt="w", expressed_in="e").evaluate(at=lam)
    np.testing.assert_allclose(Sp_e, RX90.T @ want[:3, :3] @ RX90, rtol=1e-12, atol=1e-15)
    if representation == "quaternion":
        Be = np.block([[RX90.T, Z3], [Z3, RX90.T]])
        _, S_e = g.compile_pose_with_covariance(of="b", wrt="w",
                                                expressed_in="e").evaluate(at=lam)
        np.testing.assert_allclose(S_e, Be @ want @ Be.T, rtol=1e-12, atol=1e-15)
    # Now: the newest samples.
    r1 = RZ90 @ np.array([4.0, 0, 0])
    Ja1 = np.block([[I3, -skew(r1)], [Z3, I3]])
    _, S_now = c.evaluate()
    np.testing.assert_allclose(S_now, Ja1 @ Sa[1] @ Ja1.T + Jb @ Sb[1] @ Jb.T, rtol=1e-12,
                               atol=1e-15)


def test_twist_of_one_edge_by_hand():
    """A's twist (St, in [a]) seen in [w] through the edge w -> a (Rz90, S1):
    diag(R, R) St diag(R, R)^T, plus the edge's rotation perturbation turning v and w:
    Jp S1 Jp^T with Jp = [[0, -[v]x], [0, -[w]x]]."""
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 0, 0),
               rotation_matrix=RZ90, covariance=S1)
    St = np.diag([0.1, 0.2, 0.3, 0.01, 0.02, 0.03])
    g.add_twist(point="a", body="A", ref_body="W", expressed_in="a", linear=(1, 0, 0),
                angular=(0, 0, 0.5), covariance=St)
    v_w, w_w = RZ90 @ [1.0, 0, 0], RZ90 @ [0, 0, 0.5]
    B = np.block([[RZ90, Z3], [Z3, RZ90]])
    Jp = np.block([[Z3, -skew(v_w)], [Z3, -skew(w_w)]])
    want = B @ St @ B.T + Jp @ S1 @ Jp.T
    V, S = g.compile_twist_with_covariance(point="a", body="A", ref_body="W",
                                           expressed_in="w").evaluate()
    np.testing.assert_allclose(V.linear, v_w, atol=1e-12)
    np.testing.assert_allclose(S, want, rtol=1e-12, atol=1e-15)
    L, Sv = g.compile_linear_velocity_with_covariance(point="a", body="A", ref_body="W",
                                                      expressed_in="w").evaluate()
    assert type(L) is semgraph.LinearVelocity
    np.testing.assert_allclose(Sv, want[:3, :3], rtol=1e-12, atol=1e-15)
    A, Sw = g.compile_angular_velocity_with_covariance(body="A", ref_body="W",
                                                       expressed_in="w").evaluate()
    assert type(A) is semgraph.AngularVelocity
    np.testing.assert_allclose(A.angular, w_w, atol=1e-12)
    np.testing.assert_allclose(Sw, want[3:, 3:], rtol=1e-12, atol=1e-15)
    # In [a]: the twist edge's own covariance (the edge's rotation does not enter).
    _, S_a = g.compile_twist_with_covariance(point="a", body="A", ref_body="W",
                                             expressed_in="a").evaluate()
    np.testing.assert_allclose(S_a, St, rtol=1e-12, atol=1e-15)


def test_exact_edges_give_zero_covariance():
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 0, 0))
    g.add_twist(point="a", ref_body="W", expressed_in="a", linear=(1, 0, 0))
    _, S = g.compile_pose_with_covariance(of="a", wrt="w").evaluate()
    assert S.shape == (6, 6) and not S.any()
    _, S = g.compile_twist_with_covariance(point="a", ref_body="W", expressed_in="w").evaluate()
    assert S.shape == (6, 6) and not S.any()
    _, S = g.compile_angular_velocity_with_covariance(body="A", ref_body="W",
                                                      expressed_in="w").evaluate()
    assert S.shape == (3, 3) and not S.any()


# ------------------------------------------------------------------------- twists from poses

def pose_history_graph():
    """w -> a -> b, both stamped at 0 and 2 s with covariances, no twist edge."""
    rng = np.random.default_rng(21)
    g = semgraph.SceneGraph()
    for t in [0.0, 2.0]:
        g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=rng.uniform(-1, 1, 3),
                   rotation_matrix=rpy_rotation(*rng.uniform(-1, 1, 3)).as_matrix(), stamp=t,
                   covariance=spd(rng, 1e-3))
        g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=rng.uniform(-1, 1, 3),
                   rpy=rng.uniform(-1, 1, 3), stamp=t, covariance=spd(rng, 1e-3))
    return g


FROM_POSES = [
    ("twist", dict(point="b", ref_body="W", expressed_in="a", covariance_order="angular_linear")),
    ("linear_velocity", dict(point="b", body="B", ref_body="W", expressed_in="w")),
    ("angular_velocity", dict(body="B", ref_body="W", expressed_in="b")),
]


@pytest.mark.parametrize("kind,kw", FROM_POSES)
def test_twists_from_poses_equal_the_one_shot_query(kind, kw):
    g = pose_history_graph()
    c = getattr(g, f"compile_{kind}_with_covariance")(**kw, source="poses")
    one_shot = getattr(g, f"{kind}_with_covariance")
    for time in [dict(at=0.5), dict(at=1_500_000_000), dict(at="latest"),
                 dict(at="latest_common"), dict(not_before=1.0)]:
        assert_same(c.evaluate(**time), one_shot(**kw, **time, source="poses"))
    # Now: the newest samples, as the one-shot query under 'latest' (without its TimeReport, as
    # the plain compiled query).
    r, S = c.evaluate()
    r0, S0 = one_shot(**kw, at="latest", source="poses")
    assert r.time is None and r.semantics == r0.semantics
    np.testing.assert_allclose(S, S0, rtol=1e-12, atol=1e-12 * np.abs(S0).max())
    assert np.abs(S0).max() > 0
    # Beyond the samples a derivative is never extrapolated: the plain compiled query's error.
    plain = getattr(g, f"compile_{kind}")(**without_order(kw), source="poses")
    for time in [dict(at=2.5, max_extrapolation=1.0), dict(not_before=3.0)]:
        got = query_error(lambda: c.evaluate(**time))
        assert got == query_error(lambda: plain.evaluate(**time))
        assert got[0] in ("extrapolation", "stale")


def test_twist_source_errors():
    g = pose_history_graph()
    with pytest.raises(ValueError, match="source"):
        g.compile_twist_with_covariance(point="b", ref_body="W", expressed_in="a", source="bogus")
    for kind, kw in FROM_POSES:  # no twist edge: no twist path from the default source
        kw = without_order(kw)
        got = query_error(lambda: getattr(g, f"compile_{kind}_with_covariance")(**kw))
        assert got == query_error(lambda: getattr(g, f"compile_{kind}")(**kw))
        assert got[0] == "no_twist_path"


def test_twist_from_a_single_sample_raises_as_a_timed_query():
    """Now, from poses, with one sample only: no derivative; the code is the timed query's, not
    query_invalidated (the edge is there)."""
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", stamp=0.0, covariance=S1)
    c = g.compile_twist_with_covariance(point="a", ref_body="W", expressed_in="a", source="poses")
    code, _, message = query_error(c.evaluate)
    assert code == query_error(
        lambda: g.twist_with_covariance(point="a", ref_body="W", expressed_in="a",
                                        at="latest", source="poses"))[0]
    assert code != "query_invalidated"
    assert message.startswith("the compiled query TwistCoord(a|A, W, [a]) failed")


# ------------------------------------------------------------------------- errors

POSE_KINDS = ["pose", "position", "orientation"]
TWIST_KINDS = ["twist", "linear_velocity", "angular_velocity"]


@pytest.mark.parametrize("names,code,words", [
    (dict(of="nope", wrt="w"), "unknown_frame", "nope"),
    (dict(of="a", wrt="w", expressed_in="elsewhere"), "unknown_frame", "elsewhere"),
    (dict(of="a", body="Q", wrt="w"), "unknown_body", "Q"),
    (dict(of="a", wrt="w", ref_body="A"), "frame_body_mismatch", "A"),
    (dict(of="a", wrt="island"), "no_pose_path", "island"),
])
def test_compile_errors_as_the_plain_compiled_queries(names, code, words):
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", covariance=S1)
    g.add_pose(of="island", body="I", wrt="sea", ref_body="S")
    before = g.dump()
    for kind in POSE_KINDS:
        plain = query_error(lambda: getattr(g, f"compile_{kind}")(**names))
        got = query_error(lambda: getattr(g, f"compile_{kind}_with_covariance")(**names))
        assert got[0] == code and words in got[2], (kind, got)
        assert got[1] == plain[1]
        assert got[2].replace(f"compile_{kind}_with_covariance()", f"compile_{kind}()") == plain[2]
    assert g.dump() == before


@pytest.mark.parametrize("names,code,words", [
    (dict(point="nope", ref_body="W", expressed_in="w"), "unknown_frame", "nope"),
    (dict(point="a", body="A", ref_body="Nobody", expressed_in="w"), "unknown_body", "Nobody"),
    (dict(point="a", body="A", ref_body="W", expressed_in="elsewhere"), "unknown_frame",
     "elsewhere"),
    (dict(point="a", body="A", ref_body="S", expressed_in="w"), "no_twist_path", "S"),
])
def test_compile_twist_errors_as_the_plain_compiled_queries(names, code, words):
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", covariance=S1)
    g.add_twist(point="a", ref_body="W", expressed_in="a", linear=(1, 0, 0), covariance=S1)
    g.add_pose(of="island", body="I", wrt="sea", ref_body="S")
    before = g.dump()
    for kind in TWIST_KINDS:
        kw = dict(names)
        if kind == "angular_velocity":
            if kw.pop("point") == "nope":
                continue  # no point to name
        plain = query_error(lambda: getattr(g, f"compile_{kind}")(**kw))
        got = query_error(lambda: getattr(g, f"compile_{kind}_with_covariance")(**kw))
        assert got[0] == code and words in got[2], (kind, got)
        assert got[1] == plain[1]
        assert got[2].replace(f"compile_{kind}_with_covariance()", f"compile_{kind}()") == plain[2]
    assert g.dump() == before


def test_bad_keywords():
    g, _, _ = random_scene(1)
    with pytest.raises(ValueError, match="'linear_angular' or 'angular_linear'"):
        g.compile_pose_with_covariance(of="f1", wrt="f0", covariance_order="rows_first")
    with pytest.raises(TypeError, match="covariance_order must be a str"):
        g.compile_twist_with_covariance(point="f1", ref_body="B0", covariance_order=1)
    with pytest.raises(TypeError):  # only the pose and twist kinds take an order
        g.compile_position_with_covariance(of="f1", wrt="f0", covariance_order="linear_angular")
    c = g.compile_pose_with_covariance(of="f1", wrt="f0")
    with pytest.raises(TypeError):  # no time travel
        c.evaluate(at=0.5, ref_at=0.25, fixed="f0")
    with pytest.raises(ValueError, match="max_extrapolation"):
        c.evaluate(max_extrapolation=0.1)
    with pytest.raises(ValueError, match="at must be"):
        c.evaluate(at="soon")


@pytest.mark.parametrize("time", [
    dict(at=1.5),                            # beyond the samples: extrapolation
    dict(at=-1),                             # before the first sample
    dict(at=1.5, max_extrapolation=-0.1),    # invalid_number
    dict(not_before=2.0),                    # stale
])
def test_timed_errors_as_the_plain_compiled_queries(time):
    g, rng, _ = random_scene(7)
    failed = 0
    for kind, kw in random_queries(rng, count=2):
        plain = getattr(g, f"compile_{kind}")(**without_order(kw))
        c = getattr(g, f"compile_{kind}_with_covariance")(**kw)
        try:
            plain.evaluate(**time)
        except semgraph.QueryError:
            got = query_error(lambda: c.evaluate(**time))
            assert got == query_error(lambda: plain.evaluate(**time)), kind
            assert got[0] in ("extrapolation", "stale", "invalid_number")
            failed += 1
        else:  # the query reads no stamped edge
            assert c.evaluate(**time)[0].time is not None
    assert failed > 0


def test_removal_invalidates_as_the_plain_compiled_queries():
    g, rng, parent = random_scene(8)
    pairs = [(kind, getattr(g, f"compile_{kind}")(**without_order(kw)),
              getattr(g, f"compile_{kind}_with_covariance")(**kw))
             for kind, kw in random_queries(rng, count=3)]
    g.remove_pose(of="f4", wrt=f"f{parent[4]}")
    g.remove_twist(point="f5", ref_body=f"B{parent[5]}")
    invalid = 0
    for kind, plain, c in pairs:
        if plain.is_valid:
            c.evaluate()
            continue
        for time in [dict(), dict(at=0.5)]:
            got = query_error(lambda: c.evaluate(**time))
            assert got == query_error(lambda: plain.evaluate(**time)), kind
            assert got[0] == "query_invalidated" and "compile it again" in got[2]
        invalid += 1
    assert invalid > 0
    # Re-adding the edge does not revive a compiled query; a new one answers as the one-shot.
    g.add_pose(of="f4", body="B4", wrt=f"f{parent[4]}", ref_body=f"B{parent[4]}", covariance=S1)
    for kind, plain, c in pairs:
        if not plain.is_valid:
            assert query_error(c.evaluate)[0] == "query_invalidated"
    c = g.compile_position_with_covariance(of="g4", wrt="f0")
    assert_same(c.evaluate(), g.position_with_covariance(of="g4", wrt="f0"))


# ------------------------------------------------------------------------- lifetime

def test_compiled_query_keeps_its_graph_alive():
    def make():
        g, _, _ = stamped_chain("quaternion")
        return (g.compile_pose_with_covariance(of="b", wrt="w"),
                g.pose_with_covariance(of="b", wrt="w", at=0.5))

    c, want = make()
    gc.collect()
    assert_same(c.evaluate(at=0.5), want)
    assert repr(c) == "CompiledPoseWithCovariance(PoseCoord({b}|B, {w}|W, [w]))"


def test_docs_example_runs():
    """The compiled covariance example of docs/python.md runs as written; its comments hold."""
    with open(os.path.join(source_dir(), "docs", "python.md")) as f:
        (code,) = [b for b in re.findall(r"```python\n(.*?)```", f.read(), re.S)
                   if "compile_position_with_covariance" in b]
    env = {}
    exec(compile(code, "docs/python.md", "exec"), env)
    np.testing.assert_allclose(env["S3"], 3e-6 * np.eye(3), rtol=1e-12, atol=0)
    assert env["p"].time is None
    np.testing.assert_allclose(env["S3t"], 1.5e-6 * np.eye(3), rtol=1e-12, atol=0)
    assert env["pt"].time.time == 0.25
    np.testing.assert_allclose(env["pt"].position, [1, 0.25, 0], atol=1e-15)
