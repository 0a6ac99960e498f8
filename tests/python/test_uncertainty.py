"""Covariances through the Python module (docs/uncertainty.md): add_pose / add_twist with
covariance= (timeless and stamped), and the *_with_covariance queries, of the current values
and at a time (at=, latest, latest_common, time travel, extrapolation). Every expected
covariance is J S J^T with the Jacobians derived by hand here (a pose edge's perturbation
(dp, dth) at its head, in its tail's frame: p + dp, Exp(dth) R), never read back from the
module; one time travel is also checked by Monte Carlo."""

import os
import re

import numpy as np
import pytest

import semgraph
from conftest import source_dir

RZ90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
I3, Z3 = np.eye(3), np.zeros((3, 3))
S1 = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])
S2 = np.diag([0.04, 0.05, 0.06, 0.004, 0.005, 0.006])


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def swap(S):
    return np.block([[S[3:, 3:], S[3:, :3]], [S[:3, 3:], S[:3, :3]]])


def chain(representation="quaternion"):
    """w -> a (Rz90, p = (1, 0, 0), S1) -> b (identity, p = (2, 0, 0), S2)."""
    g = semgraph.SceneGraph(representation=representation)
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 0, 0),
               rotation_matrix=RZ90, covariance=S1)
    # Given angular first (GTSAM's order): the same S2 reordered.
    g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=(2, 0, 0),
               covariance=swap(S2).tolist(), covariance_order="angular_linear")
    return g


def expected_wb():
    r = RZ90 @ np.array([2.0, 0, 0])  # b's origin from a's, in [w]
    J1 = np.block([[I3, -skew(r)], [Z3, I3]])  # dp_wb = dp1 + dth1 x r, dth_wb = dth1
    J2 = np.block([[RZ90, Z3], [Z3, RZ90]])    # a's perturbations turned into [w]
    return J1 @ S1 @ J1.T + J2 @ S2 @ J2.T


def test_two_edge_chain_by_hand():
    g = chain()
    X, S = g.pose_with_covariance(of="b", wrt="w")
    np.testing.assert_allclose(X.position, [1, 2, 0], atol=1e-12)
    assert S.shape == (6, 6)
    np.testing.assert_allclose(S, expected_wb(), atol=1e-12, rtol=0)
    # By hand: var(x) = 0.01 + 4 * 0.003 + 0.05 (b's y in [a] is x in [w]) = 0.072.
    assert S[0, 0] == pytest.approx(0.072, abs=1e-12)
    _, S_al = g.pose_with_covariance(of="b", wrt="w", covariance_order="angular_linear")
    np.testing.assert_allclose(S_al, swap(expected_wb()), atol=1e-12, rtol=0)
    p, Sp = g.position_with_covariance(of="b", wrt="w")
    np.testing.assert_allclose(p.position, [1, 2, 0], atol=1e-12)
    np.testing.assert_allclose(Sp, expected_wb()[:3, :3], atol=1e-12, rtol=0)
    _, So = g.orientation_with_covariance(of="b", wrt="w")
    np.testing.assert_allclose(So, expected_wb()[3:, 3:], atol=1e-12, rtol=0)
    # The plain query is unchanged.
    np.testing.assert_allclose(g.pose(of="b", wrt="w").position, [1, 2, 0], atol=1e-12)


def test_body_convention_by_hand():
    g = semgraph.SceneGraph()
    Sb = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])
    Sb[0, 1] = Sb[1, 0] = 0.001
    g.add_pose(of="c", body="C", wrt="w", ref_body="W", rotation_matrix=RZ90, covariance=Sb,
               convention="body")
    # X Exp(rho, phi) = (p + R rho, Exp(R phi) R) to first order.
    B = np.block([[RZ90, Z3], [Z3, RZ90]])
    _, S = g.pose_with_covariance(of="c", wrt="w")
    np.testing.assert_allclose(S, B @ Sb @ B.T, atol=1e-12, rtol=0)
    assert S[0, 0] == pytest.approx(0.02) and S[0, 1] == pytest.approx(-0.001)


def test_twist_in_another_frame_by_hand():
    g = chain()
    St = np.diag([0.1, 0.2, 0.3, 0.01, 0.02, 0.03])
    g.add_twist(point="a", body="A", ref_body="W", expressed_in="a", linear=(1, 0, 0),
                angular=(0, 0, 0.5), covariance=St)
    V, S = g.twist_with_covariance(point="a", body="A", ref_body="W", expressed_in="a")
    np.testing.assert_allclose(S, St, atol=1e-12, rtol=0)
    v_w, w_w = RZ90 @ [1.0, 0, 0], RZ90 @ [0, 0, 0.5]
    B = np.block([[RZ90, Z3], [Z3, RZ90]])
    Jp = np.block([[Z3, -skew(v_w)], [Z3, -skew(w_w)]])  # Exp(dth1) R turns v and w
    want = B @ St @ B.T + Jp @ S1 @ Jp.T
    V, S = g.twist_with_covariance(point="a", body="A", ref_body="W", expressed_in="w")
    np.testing.assert_allclose(V.linear, v_w, atol=1e-12)
    np.testing.assert_allclose(S, want, atol=1e-12, rtol=0)
    _, S_al = g.twist_with_covariance(point="a", body="A", ref_body="W", expressed_in="w",
                                      covariance_order="angular_linear")
    np.testing.assert_allclose(S_al, swap(want), atol=1e-12, rtol=0)
    _, Sv = g.linear_velocity_with_covariance(point="a", body="A", ref_body="W",
                                              expressed_in="w")
    np.testing.assert_allclose(Sv, want[:3, :3], atol=1e-12, rtol=0)
    w, Sw = g.angular_velocity_with_covariance(body="A", ref_body="W", expressed_in="w")
    np.testing.assert_allclose(w.angular, w_w, atol=1e-12)
    np.testing.assert_allclose(Sw, want[3:, 3:], atol=1e-12, rtol=0)


def test_exact_values_have_zero_covariance():
    g = semgraph.SceneGraph()
    g.add_pose(of="a", wrt="w", body="A", ref_body="W", position=(1, 0, 0))
    _, S = g.pose_with_covariance(of="a", wrt="w")
    assert np.array_equal(S, np.zeros((6, 6)))


@pytest.mark.parametrize("matrix,code", [
    (np.diag([np.nan, 1, 1, 1, 1, 1]), "invalid_number"),
    (np.diag([1, 1, 1, 1, 1, 2e12]), "invalid_number"),
    (np.eye(6) + np.triu(np.full((6, 6), 0.5), 1), "invalid_covariance"),   # not symmetric
    (np.diag([1, 1, 1, 1, 1, -1.0]), "invalid_covariance"),                # eigenvalue -1
])
def test_refused_covariances_raise_and_change_nothing(matrix, code):
    g = chain()
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=(3, 0, 0), covariance=matrix)
    assert info.value.code == code
    assert g.dump() == before
    np.testing.assert_allclose(g.pose_with_covariance(of="b", wrt="w")[1], expected_wb(),
                               atol=1e-12)


def test_body_convention_needs_the_edge_form():
    g = chain()
    with pytest.raises(semgraph.RejectedError) as info:
        g.add_pose(of="c", body="C", wrt="w", ref_body="W", expressed_in="a",
                   covariance=np.eye(6), convention="body")
    assert info.value.code == "invalid_covariance"


def test_constant_pose_restated_with_another_covariance():
    g = semgraph.SceneGraph()
    g.add_pose(of="s", body="W", wrt="w", ref_body="W", covariance=np.eye(6))
    g.add_pose(of="s", body="W", wrt="w", ref_body="W", covariance=np.eye(6))  # the same: fine
    with pytest.raises(semgraph.RejectedError) as info:
        g.add_pose(of="s", body="W", wrt="w", ref_body="W", covariance=2 * np.eye(6))
    assert info.value.code == "constant_pose_change"


@pytest.mark.parametrize("kwargs,error,words", [
    (dict(covariance=np.eye(5)), ValueError, "covariance"),
    (dict(covariance=list(range(36))), ValueError, "covariance"),
    (dict(covariance=np.eye(6), covariance_order="rotation_first"), ValueError,
     "'linear_angular' or 'angular_linear'"),
    (dict(covariance=np.eye(6), convention="left"), ValueError, "'coordinates' or 'body'"),
    (dict(covariance=np.eye(6), convention=1), TypeError, "convention"),
    (dict(covariance_order="angular_linear"), ValueError, "need covariance="),
    (dict(covariance=np.eye(6), repair=True), ValueError, "repair"),
])
def test_bad_keywords(kwargs, error, words):
    g = semgraph.SceneGraph()
    with pytest.raises(error) as info:
        g.add_pose(of="a", body="A", wrt="w", ref_body="W", **kwargs)
    assert words in str(info.value)
    assert g.num_frames == 0


def test_twist_takes_no_convention():
    g = chain()
    with pytest.raises(TypeError):
        g.add_twist(point="a", ref_body="W", expressed_in="a", covariance=np.eye(6),
                    convention="body")


def test_query_errors_as_the_plain_query():
    g = chain()
    with pytest.raises(semgraph.QueryError) as info:
        g.pose_with_covariance(of="nope", wrt="w")
    assert info.value.code == "unknown_frame"
    with pytest.raises(ValueError):
        g.pose_with_covariance(of="b", wrt="w", covariance_order="xyz")


def test_docs_example_runs():
    """The Python block of docs/uncertainty.md runs as written."""
    with open(os.path.join(source_dir(), "docs", "uncertainty.md")) as f:
        (code,) = re.findall(r"```python\n(.*?)```", f.read(), re.S)
    env = {}
    exec(compile(code, "docs/uncertainty.md", "exec"), env)
    assert env["S"].shape == (6, 6) and env["S3"].shape == (3, 3)
    np.testing.assert_allclose(env["S3"], np.diag([4e-6, 4e-6, 2.5e-5]), atol=1e-15)
    np.testing.assert_allclose(env["St"], 1.5e-6 * np.eye(6), atol=1e-18)  # 0.75 S0 + 0.25 S1
    assert env["Xt"].time.time == 0.25


# ---------------------------------------------------------------------------------------------
# At a time (docs/uncertainty.md, "Covariances and time"): the time keywords of the plain
# queries. Each sample carries its own covariance; between samples i and i+1 at lambda the edge's
# covariance is (1 - lambda) S_i + lambda S_i+1 in the edge form (a definition); a time travel's
# two sides are independent. Values are kept with constant rotations between samples so that
# the interpolated value (hence every Jacobian) is known by hand.

def spd(seed, scale):
    """A dense symmetric positive definite 6x6 matrix (random, fixed seed)."""
    A = np.random.default_rng(seed).normal(size=(6, 6))
    return scale * (A @ A.T + 6 * np.eye(6))


SA0, SA1 = spd(1, 1e-3), spd(2, 1e-3)
SB0, SB1 = spd(3, 1e-3), spd(4, 1e-3)
RX90 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])
# w -> a (body A): R = Rz90, p from (1, 0, 0) at 0 s to (1, 2, 0) at 1 s.
# w -> b (body B): R = Rx90, p from (0, 0, 1) at 0 s to (2, 0, 1) at 1 s.
PA0, PA1 = np.array([1.0, 0, 0]), np.array([1.0, 2, 0])
PB0, PB1 = np.array([0.0, 0, 1]), np.array([2.0, 0, 1])


def report(r):
    t = r.time
    return (t.time_ns, t.ref_time_ns, t.oldest_ns, t.newest_ns, t.extrapolated)


def stamped_graph(representation="quaternion"):
    g = semgraph.SceneGraph(representation=representation)
    # The stamps in both spellings: int nanoseconds and float seconds.
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=PA0, rotation_matrix=RZ90,
               stamp=0, covariance=SA0)
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=PA1, rotation_matrix=RZ90,
               stamp=1.0, covariance=swap(SA1), covariance_order="angular_linear")
    g.add_pose(of="b", body="B", wrt="w", ref_body="W", position=PB0, rotation_matrix=RX90,
               stamp=0.0, covariance=SB0)
    g.add_pose(of="b", body="B", wrt="w", ref_body="W", position=PB1, rotation_matrix=RX90,
               stamp=1_000_000_000, covariance=SB1)
    return g


@pytest.mark.parametrize("at,lam", [(0.5, 0.5), (250_000_000, 0.25), (0.0, 0.0), (1.0, 1.0)])
def test_interpolated_covariance_of_one_edge(at, lam):
    g = stamped_graph()
    want = (1 - lam) * SA0 + lam * SA1  # edge form: {a} wrt {w} in [w]
    X, S = g.pose_with_covariance(of="a", wrt="w", at=at)
    np.testing.assert_allclose(X.position, (1 - lam) * PA0 + lam * PA1, atol=1e-12)
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
    assert report(X) == report(g.pose(of="a", wrt="w", at=at))
    _, S_al = g.pose_with_covariance(of="a", wrt="w", at=at, covariance_order="angular_linear")
    np.testing.assert_allclose(S_al, swap(want), atol=1e-15, rtol=1e-12)
    P, Sp = g.position_with_covariance(of="a", wrt="w", at=at)
    np.testing.assert_allclose(Sp, want[:3, :3], atol=1e-15, rtol=1e-12)
    assert report(P) == report(g.position(of="a", wrt="w", at=at))
    O, So = g.orientation_with_covariance(of="a", wrt="w", at=at)
    np.testing.assert_allclose(So, want[3:, 3:], atol=1e-15, rtol=1e-12)
    assert report(O) == report(g.orientation(of="a", wrt="w", at=at))


def test_latest_and_untimed_read_the_newest_sample():
    g = stamped_graph()
    X, S = g.pose_with_covariance(of="a", wrt="w", at="latest")
    np.testing.assert_allclose(S, SA1, atol=1e-15, rtol=1e-12)
    assert report(X) == report(g.pose(of="a", wrt="w", at="latest"))
    U, S = g.pose_with_covariance(of="a", wrt="w")
    np.testing.assert_allclose(S, SA1, atol=1e-15, rtol=1e-12)
    assert U.time is None
    X, S = g.pose_with_covariance(of="a", wrt="w", not_before=0.5)
    np.testing.assert_allclose(S, SA1, atol=1e-15, rtol=1e-12)
    assert report(X) == report(g.pose(of="a", wrt="w", not_before=0.5))


def test_latest_common_is_at_the_oldest_newest_stamp():
    g = stamped_graph()
    g.add_pose(of="c", body="C", wrt="w", ref_body="W", stamp=0.0)
    g.add_pose(of="c", body="C", wrt="w", ref_body="W", stamp=0.75)
    # c has no covariance (zero); a at 0.75.
    X, S = g.position_with_covariance(of="a", wrt="c", at="latest_common")
    assert X.time.time == 0.75
    assert report(X) == report(g.position(of="a", wrt="c", at="latest_common"))
    np.testing.assert_allclose(S, (0.25 * SA0 + 0.75 * SA1)[:3, :3], atol=1e-15, rtol=1e-12)


def expected_chain(lam, R_we):
    """{e'} (exact, p = (2, 0, 0) in [a]) wrt {w} in [e]: a's edge at lambda moves e' rigidly."""
    r = RZ90 @ np.array([2.0, 0, 0])  # e' from a's origin, in [w]
    J = np.block([[I3, -skew(r)], [Z3, I3]])
    B = np.block([[R_we.T, Z3], [Z3, R_we.T]])  # [w] -> [e]
    return B @ J @ ((1 - lam) * SA0 + lam * SA1) @ J.T @ B.T


def chain_graph():
    g = stamped_graph()
    g.add_pose(of="t", body="A", wrt="a", ref_body="A", position=(2, 0, 0))  # exact, same body
    g.add_pose(of="e", body="W", wrt="w", ref_body="W", rotation_matrix=RX90)  # exact, [e]
    return g


def test_chain_of_a_stamped_and_an_exact_edge_expressed_elsewhere():
    g = chain_graph()
    want = expected_chain(0.25, RX90)
    X, S = g.pose_with_covariance(of="t", wrt="w", expressed_in="e", at=0.25)
    p_w = 0.75 * PA0 + 0.25 * PA1 + RZ90 @ [2.0, 0, 0]
    np.testing.assert_allclose(X.position, RX90.T @ p_w, atol=1e-12)
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
    assert report(X) == report(g.pose(of="t", wrt="w", expressed_in="e", at=0.25))
    _, Sp = g.position_with_covariance(of="t", wrt="w", expressed_in="e", at=0.25)
    np.testing.assert_allclose(Sp, want[:3, :3], atol=1e-15, rtol=1e-12)
    _, So = g.orientation_with_covariance(of="t", wrt="w", expressed_in="e", at=0.25)
    np.testing.assert_allclose(So, want[3:, 3:], atol=1e-15, rtol=1e-12)


def travel_expected(t, ref_t):
    """b at t relative to a at ref_t, in [a], through the fixed world: the two edges' independent
    perturbations (dp, dth at the head, in [w]): p_ab = R_a^T (p_b - p_a), R_ab = R_a^T R_b."""
    pa, pb = (1 - ref_t) * PA0 + ref_t * PA1, (1 - t) * PB0 + t * PB1
    Ja = np.block([[-RZ90.T, RZ90.T @ skew(pb - pa)], [Z3, -RZ90.T]])
    Jb = np.block([[RZ90.T, Z3], [Z3, RZ90.T]])
    Sa = (1 - ref_t) * SA0 + ref_t * SA1
    Sb = (1 - t) * SB0 + t * SB1
    return Ja @ Sa @ Ja.T + Jb @ Sb @ Jb.T, Ja, Jb, Sa, Sb, pa, pb


@pytest.mark.parametrize("representation", ["quaternion", "homogeneous"])
def test_time_travel_sums_two_independent_sides(representation):
    g = stamped_graph(representation)
    want, *_ = travel_expected(0.25, 0.75)
    X, S = g.pose_with_covariance(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    plain = g.pose(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    np.testing.assert_allclose(X.position, plain.position, atol=1e-15)
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
    assert report(X) == report(plain) and X.time.ref_time == 0.75
    P, Sp = g.position_with_covariance(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    np.testing.assert_allclose(Sp, want[:3, :3], atol=1e-15, rtol=1e-12)
    assert report(P) == report(g.position(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w"))
    O, So = g.orientation_with_covariance(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    np.testing.assert_allclose(So, want[3:, 3:], atol=1e-15, rtol=1e-12)
    assert report(O) == report(g.orientation(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w"))
    # Not the same as both sides at one time.
    _, S_same = g.pose_with_covariance(of="b", wrt="a", at=0.25)
    np.testing.assert_allclose(S_same, travel_expected(0.25, 0.25)[0], atol=1e-15, rtol=1e-12)


def test_time_travel_monte_carlo():
    """The first-order answer against the sample covariance of exactly perturbed values (covariances
    of order 1e-6, as the specification's truth for tests): each side's edge drawn from its
    covariance at its own time, independently, composed in numpy."""
    from scipy.spatial.transform import Rotation
    g = semgraph.SceneGraph()
    scale = 1e-3  # SA*, SB* are ~1e-2: scaled to ~1e-5 .. 1e-6
    for k, (t, pa, pb, sa, sb) in enumerate([(0, PA0, PB0, SA0, SB0), (1.0, PA1, PB1, SA1, SB1)]):
        g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=pa, rotation_matrix=RZ90,
                   stamp=t, covariance=scale * sa)
        g.add_pose(of="b", body="B", wrt="w", ref_body="W", position=pb, rotation_matrix=RX90,
                   stamp=t, covariance=scale * sb)
    _, S = g.pose_with_covariance(of="b", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    _, _, _, Sa, Sb, pa, pb = travel_expected(0.25, 0.75)
    n = 40000
    rng = np.random.default_rng(7)
    da = rng.multivariate_normal(np.zeros(6), scale * Sa, size=n)
    db = rng.multivariate_normal(np.zeros(6), scale * Sb, size=n)
    Ra = Rotation.from_rotvec(da[:, 3:]) * Rotation.from_matrix(RZ90)
    Rb = Rotation.from_rotvec(db[:, 3:]) * Rotation.from_matrix(RX90)
    p = Ra.inv().apply((pb + db[:, :3]) - (pa + da[:, :3]))
    R0 = RZ90.T @ RX90
    dth = (Ra.inv() * Rb * Rotation.from_matrix(R0).inv()).as_rotvec()
    d = np.hstack([p - RZ90.T @ (pb - pa), dth])
    S_mc = np.cov(d.T)
    # Sampling error of each entry: sqrt((S_ii S_jj + S_ij^2) / n); allow 4 of them.
    sd = np.sqrt((np.outer(np.diag(S), np.diag(S)) + S ** 2) / n)
    assert np.all(np.abs(S_mc - S) < 4 * sd), np.max(np.abs(S_mc - S) / sd)


def stamped_twist_graph(representation="quaternion"):
    g = chain(representation)  # timeless w -> a (S1) -> b (S2)
    St0 = np.diag([0.1, 0.2, 0.3, 0.01, 0.02, 0.03])
    St1 = spd(5, 1e-2)
    for t, St in [(0, St0), (1.0, St1)]:
        g.add_twist(point="a", body="A", ref_body="W", expressed_in="a", linear=(1, 0, 0),
                    angular=(0, 0, 0.5), stamp=t, covariance=St)
    return g, St0, St1


@pytest.mark.parametrize("representation", ["quaternion", "homogeneous"])
def test_twist_at_a_time_by_hand(representation):
    g, St0, St1 = stamped_twist_graph(representation)
    St = 0.75 * St0 + 0.25 * St1
    kw = dict(point="a", body="A", ref_body="W")
    V, S = g.twist_with_covariance(**kw, expressed_in="a", at=0.25)
    np.testing.assert_allclose(S, St, atol=1e-15, rtol=1e-12)
    assert report(V) == report(g.twist(**kw, expressed_in="a", at=0.25))
    # In [w]: the twist turned by the timeless w -> a edge, whose rotation turns v and w too.
    v_w, w_w = RZ90 @ [1.0, 0, 0], RZ90 @ [0, 0, 0.5]
    B = np.block([[RZ90, Z3], [Z3, RZ90]])
    Jp = np.block([[Z3, -skew(v_w)], [Z3, -skew(w_w)]])
    want = B @ St @ B.T + Jp @ S1 @ Jp.T
    V, S = g.twist_with_covariance(**kw, expressed_in="w", at=0.25)
    np.testing.assert_allclose(V.linear, v_w, atol=1e-12)
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
    assert report(V) == report(g.twist(**kw, expressed_in="w", at=0.25))
    _, S_al = g.twist_with_covariance(**kw, expressed_in="w", at=0.25,
                                      covariance_order="angular_linear")
    np.testing.assert_allclose(S_al, swap(want), atol=1e-15, rtol=1e-12)
    L, Sv = g.linear_velocity_with_covariance(**kw, expressed_in="w", at=0.25)
    np.testing.assert_allclose(Sv, want[:3, :3], atol=1e-15, rtol=1e-12)
    assert report(L) == report(g.linear_velocity(**kw, expressed_in="w", at=0.25))
    A, Sw = g.angular_velocity_with_covariance(body="A", ref_body="W", expressed_in="w", at=0.25)
    np.testing.assert_allclose(Sw, want[3:, 3:], atol=1e-15, rtol=1e-12)
    assert report(A) == report(g.angular_velocity(body="A", ref_body="W", expressed_in="w",
                                                  at=0.25))


def test_twist_held_beyond_its_samples_keeps_its_covariance():
    g, _, St1 = stamped_twist_graph()
    kw = dict(point="a", body="A", ref_body="W", expressed_in="a")
    V, S = g.twist_with_covariance(**kw, at=1.5, max_extrapolation=1.0)
    np.testing.assert_allclose(S, St1, atol=1e-15, rtol=1e-12)
    assert report(V) == report(g.twist(**kw, at=1.5, max_extrapolation=1.0))
    V, S = g.twist_with_covariance(**kw, at="latest")
    np.testing.assert_allclose(S, St1, atol=1e-15, rtol=1e-12)


POSE_FUNCTIONS = ["pose", "position", "orientation"]
TWIST_FUNCTIONS = ["twist", "linear_velocity", "angular_velocity"]


def twist_names(name):
    if name == "angular_velocity":
        return dict(body="A", ref_body="W", expressed_in="a")
    return dict(point="a", body="A", ref_body="W", expressed_in="a")


def query_error(call):
    """(code, argument, message), the message with a "*_with_covariance()" prefix written as the
    plain query's (argument errors name the function called)."""
    with pytest.raises(semgraph.QueryError) as info:
        call()
    message = re.sub(r"^(\w+)_with_covariance\(\)", r"\1()", info.value.message)
    return info.value.code, info.value.argument, message


@pytest.mark.parametrize("time", [
    dict(at=1.5),                                    # beyond the samples: extrapolation
    dict(at=-1),                                     # 1 ns before the first sample
    dict(at=1.5, max_extrapolation=0.1),             # beyond the horizon
    dict(at=1.5, max_extrapolation=-0.1),            # invalid_number
    dict(at=float("nan")),                           # invalid_number
    dict(not_before=2.0),                            # stale
    dict(at=0.5, not_before=2_000_000_000),          # stale
])
def test_timed_query_errors_as_the_plain_queries(time):
    g = stamped_graph()
    before = g.dump()
    for name in POSE_FUNCTIONS:
        plain = query_error(lambda: getattr(g, name)(of="b", wrt="a", **time))
        got = query_error(lambda: getattr(g, name + "_with_covariance")(of="b", wrt="a", **time))
        assert got == plain, name
        assert got[0] in ("extrapolation", "stale", "invalid_number")
    travel = dict(time, ref_at=0.5, fixed="w") if "at" in time else None
    if travel is not None:
        for name in POSE_FUNCTIONS:
            plain = query_error(lambda: getattr(g, name)(of="b", wrt="a", **travel))
            got = query_error(
                lambda: getattr(g, name + "_with_covariance")(of="b", wrt="a", **travel))
            assert got == plain, name
    assert g.dump() == before
    g, _, _ = stamped_twist_graph()
    before = g.dump()
    for name in TWIST_FUNCTIONS:
        plain = query_error(lambda: getattr(g, name)(**twist_names(name), **time))
        got = query_error(
            lambda: getattr(g, name + "_with_covariance")(**twist_names(name), **time))
        assert got == plain, name
    assert g.dump() == before


def test_extrapolation_message_names_the_edge_and_its_range():
    g = stamped_graph()
    code, _, message = query_error(lambda: g.pose_with_covariance(of="b", wrt="w", at=1.5))
    assert code == "extrapolation" and "{b}" in message and "1.000" in message


@pytest.mark.parametrize("kwargs,error,words", [
    (dict(at="soon"), ValueError, "at must be"),
    (dict(at=[1.0]), TypeError, "at must be a time"),
    (dict(at=True), TypeError, "at"),
    (dict(max_extrapolation=0.1), ValueError, "max_extrapolation"),
    (dict(not_before="now"), TypeError, "not_before"),
    (dict(at=1.0, ref_at=0.5), ValueError, "ref_at"),
    (dict(ref_at=0.5, fixed="w"), ValueError, "time travel needs at="),
    (dict(at=0.5, ref_at=0.5, fixed=3), TypeError, "fixed"),
])
def test_bad_time_keywords_as_the_plain_queries(kwargs, error, words):
    g = stamped_graph()
    before = g.dump()
    for name in POSE_FUNCTIONS:
        with pytest.raises(error) as plain:
            getattr(g, name)(of="b", wrt="a", **kwargs)
        with pytest.raises(error) as got:
            getattr(g, name + "_with_covariance")(of="b", wrt="a", **kwargs)
        assert words in str(got.value)
        fn = name + "_with_covariance"
        assert str(got.value).replace(fn + "()", name + "()") == str(plain.value), name
    assert g.dump() == before


def test_twist_kinds_take_no_time_travel():
    g, _, _ = stamped_twist_graph()
    before = g.dump()
    for name in TWIST_FUNCTIONS:
        for fn in (name, name + "_with_covariance"):
            with pytest.raises(TypeError):  # as twist(): no ref_at / fixed keyword at all
                getattr(g, fn)(**twist_names(name), at=1.0, ref_at=0.5, fixed="w")
        with pytest.raises(ValueError, match="max_extrapolation"):
            getattr(g, name + "_with_covariance")(**twist_names(name), max_extrapolation=0.1)
        with pytest.raises(TypeError, match="at must be a time"):
            getattr(g, name + "_with_covariance")(**twist_names(name), at=[1.0])
    assert g.dump() == before


def test_time_travel_edge_on_both_sides_contributes_twice():
    """{t} (exact in A) at 0.25 s relative to {a} at 0.75 s through {w}: the one stamped edge
    w -> a is on both sides, read at each side's time, two independent perturbations."""
    g = chain_graph()
    pa_t, pa_ref = 0.75 * PA0 + 0.25 * PA1, 0.25 * PA0 + 0.75 * PA1
    r = RZ90 @ np.array([2.0, 0, 0])  # t from a's origin, in [w]
    B = np.block([[RZ90.T, Z3], [Z3, RZ90.T]])  # [w] -> [a]
    J_point = B @ np.block([[I3, -skew(r)], [Z3, I3]])
    J_ref = np.block([[-RZ90.T, RZ90.T @ skew(pa_t + r - pa_ref)], [Z3, -RZ90.T]])
    want = (J_point @ (0.75 * SA0 + 0.25 * SA1) @ J_point.T +
            J_ref @ (0.25 * SA0 + 0.75 * SA1) @ J_ref.T)
    X, S = g.pose_with_covariance(of="t", wrt="a", at=0.25, ref_at=0.75, fixed="w")
    np.testing.assert_allclose(X.position, RZ90.T @ (pa_t + r - pa_ref), atol=1e-12)
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
    assert report(X) == report(g.pose(of="t", wrt="a", at=0.25, ref_at=0.75, fixed="w"))
    # Untimed: one edge, one value: {t} is rigid in [a], exactly.
    assert np.array_equal(g.pose_with_covariance(of="t", wrt="a")[1], np.zeros((6, 6)))


def test_extrapolated_pose_edge_propagates_its_integration_twist():
    """w -> a has one sample (S0) at 0 s; A's twist (v, 0) at {a} in [a] (St, timeless) integrates
    it to dt = 0.2 s: X = X_0 Exp(dt (v, 0)), p = p_0 + R v dt. By hand, to first order: the
    sample's (dp, dth) in [w]: p + dp + dth x (R v dt), Exp(dth) R; the twist's (dv, dw) in [a]:
    Exp(dt (v + dv, dw)) = (dt (v + dv) + dt^2/2 dw x v, Exp(dt dw)), then turned by R."""
    g = semgraph.SceneGraph()
    v, dt = np.array([1.0, 0.5, 0.0]), 0.2
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=PA0, rotation_matrix=RZ90,
               stamp=0, covariance=SA0)
    St = spd(6, 1e-3)
    g.add_twist(point="a", body="A", ref_body="W", expressed_in="a", linear=v, covariance=St)
    X, S = g.pose_with_covariance(of="a", wrt="w", at=dt, max_extrapolation=0.5)
    np.testing.assert_allclose(X.position, PA0 + RZ90 @ v * dt, atol=1e-12)
    assert X.time.extrapolated
    assert report(X) == report(g.pose(of="a", wrt="w", at=dt, max_extrapolation=0.5))
    J_sample = np.block([[I3, -skew(RZ90 @ v * dt)], [Z3, I3]])
    J_twist = np.block([[dt * RZ90, -0.5 * dt * dt * RZ90 @ skew(v)], [Z3, dt * RZ90]])
    want = J_sample @ SA0 @ J_sample.T + J_twist @ St @ J_twist.T
    np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-10)


def test_stamped_covariances_are_checked_and_refusals_change_nothing():
    g = stamped_graph()
    before = g.dump()
    for bad, code in [(np.diag([1, 1, 1, 1, 1, -1.0]), "invalid_covariance"),
                      (np.diag([np.nan, 1, 1, 1, 1, 1]), "invalid_number")]:
        with pytest.raises(semgraph.RejectedError) as info:
            g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=PA0,
                       rotation_matrix=RZ90, stamp=0.5, covariance=bad)
        assert info.value.code == code
        with pytest.raises(semgraph.RejectedError) as info:
            g.add_twist(point="b", body="B", ref_body="W", expressed_in="b", stamp=0.5,
                        covariance=bad)
        assert info.value.code == code
    assert g.dump() == before
    np.testing.assert_allclose(g.pose_with_covariance(of="a", wrt="w", at=0.5)[1],
                               0.5 * SA0 + 0.5 * SA1, atol=1e-15, rtol=1e-12)
    # Another covariance at a stored stamp is another value: refused under 'reject'.
    r = semgraph.SceneGraph(duplicate_stamp="reject")
    r.add_pose(of="a", body="A", wrt="w", ref_body="W", stamp=0, covariance=SA0)
    before = r.dump()
    with pytest.raises(semgraph.RejectedError) as info:
        r.add_pose(of="a", body="A", wrt="w", ref_body="W", stamp=0, covariance=SA1)
    assert info.value.code == "duplicate_stamp"
    assert r.dump() == before


# ---------------------------------------------------------------- handles with a covariance

def test_set_pose_and_set_twist_with_covariance_through_handles():
    """Untimed and stamped updates through handles carry their covariances (by hand: the edge
    form as given; between two samples (1 - l) S_i + l S_i+1; a rotation matrix too; the body
    convention turned into coordinates by diag(R, R)); refusals change nothing."""
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 0, 0))
    g.add_pose(of="s", body="S", wrt="w", ref_body="W", position=(0, 0, 0), stamp=0.0)
    g.add_twist(point="s", ref_body="W", expressed_in="s", linear=(1, 0, 0), stamp=0.0)
    a = g.pose_handle(of="a", wrt="w")
    s = g.pose_handle(of="s", wrt="w")
    t = g.twist_handle(point="s", ref_body="W")
    g.set_pose(a, position=(2, 0, 0), rotation_matrix=RZ90, covariance=S1)
    _, S = g.pose_with_covariance(of="a", wrt="w")
    np.testing.assert_allclose(S, S1, atol=1e-15, rtol=0)
    g.set_pose(a, position=(2, 0, 0), rotation_matrix=RZ90, covariance=S1, convention="body")
    B = np.block([[RZ90, Z3], [Z3, RZ90]])
    _, S = g.pose_with_covariance(of="a", wrt="w")
    np.testing.assert_allclose(S, B @ S1 @ B.T, atol=1e-15, rtol=0)
    g.set_pose(a, position=(2, 0, 0))  # exact again
    _, S = g.pose_with_covariance(of="a", wrt="w")
    assert not S.any()
    # Stamped: the first sample had none (zero), then S1 at 1 s and S2 at 2 s (angular first).
    g.set_pose(s, position=(1, 0, 0), stamp=1.0, covariance=S1)
    g.set_pose(s, position=(2, 0, 0), stamp=2.0, covariance=swap(S2),
               covariance_order="angular_linear")
    g.set_twist(t, linear=(2, 0, 0), stamp=1.0, covariance=S1)
    g.set_twist(t, linear=(3, 0, 0), stamp=2.0, covariance=S2)
    X, S = g.pose_with_covariance(of="s", wrt="w", at=1.25)
    np.testing.assert_allclose(X.position, [1.25, 0, 0], atol=1e-12)
    np.testing.assert_allclose(S, 0.75 * S1 + 0.25 * S2, atol=1e-15, rtol=1e-12)
    _, S = g.pose_with_covariance(of="s", wrt="w", at=0.5)
    np.testing.assert_allclose(S, 0.5 * S1, atol=1e-15, rtol=1e-12)
    V, S = g.twist_with_covariance(point="s", ref_body="W", expressed_in="s", at=1.5)
    np.testing.assert_allclose(V.linear, [2.5, 0, 0], atol=1e-12)
    np.testing.assert_allclose(S, 0.5 * S1 + 0.5 * S2, atol=1e-15, rtol=1e-12)
    # Refused: a bad matrix, a twist with a convention keyword (not taken), a stamp on a
    # timeless edge; nothing changed.
    before = g.dump()
    bad = S1.copy()
    bad[0, 1] = 1.0
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(s, position=(3, 0, 0), stamp=3.0, covariance=bad)
    assert e.value.code == "invalid_covariance"
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_twist(t, linear=(3, 0, 0), stamp=3.0, covariance=-S1)
    assert e.value.code == "invalid_covariance"
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(a, position=(3, 0, 0), stamp=3.0, covariance=S1)
    assert e.value.code == "stamp_mismatch"
    with pytest.raises(TypeError):
        g.set_twist(t, linear=(3, 0, 0), stamp=3.0, covariance=S1, convention="body")
    with pytest.raises(ValueError):
        g.set_pose(a, position=(3, 0, 0), covariance=np.eye(5))
    with pytest.raises(ValueError):
        g.set_pose(a, position=(3, 0, 0), covariance_order="angular_linear")
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(a, position=(3, 0, 0), rotation_matrix=2 * RZ90, covariance=S1)
    assert e.value.code == "invalid_rotation"
    assert g.dump() == before


def pose_history_graph():
    """w -> a: X_0 = (Rz90, 0) at 0 s with S1, X_1 = (Rz90, (1, 0, 0)) at 2 s with S2."""
    g = semgraph.SceneGraph()
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", rotation_matrix=RZ90, stamp=0.0,
               covariance=S1)
    g.add_pose(of="a", body="A", wrt="w", ref_body="W", position=(1, 0, 0),
               rotation_matrix=RZ90, stamp=2.0, covariance=S2)
    return g


def test_twist_from_poses_by_hand():
    """source='poses' (screw, the default): the derivative Log(X_0^-1 X_1) / dt with equal
    rotations R: rho = R^T d, v = (rho + R^T (dp_1 - dp_0) + [rho]x R^T (dth_0 + dth_1) / 2) / dt,
    w = R^T (dth_1 - dth_0) / dt (to first order: X_1's rotation perturbation turns the segment
    about X_1's origin, hence the half lever arm), each sample independent."""
    g = pose_history_graph()
    dt, d = 2.0, np.array([1.0, 0, 0])
    Rt, rho = RZ90.T, RZ90.T @ d
    J0 = -np.block([[Rt, -0.5 * skew(rho) @ Rt], [Z3, Rt]]) / dt
    J1 = np.block([[Rt, 0.5 * skew(rho) @ Rt], [Z3, Rt]]) / dt
    want = J0 @ S1 @ J0.T + J1 @ S2 @ J1.T
    kw = dict(point="a", body="A", ref_body="W", expressed_in="a", source="poses")
    for time in [dict(at=0.5), dict(at="latest"), dict()]:
        V, S = g.twist_with_covariance(**kw, **time)
        np.testing.assert_allclose(V.linear, rho / dt, atol=1e-12)
        np.testing.assert_allclose(S, want, atol=1e-15, rtol=1e-12)
        assert report(V) == report(g.twist(**kw, **time))
        _, Sv = g.linear_velocity_with_covariance(**kw, **time)
        np.testing.assert_allclose(Sv, want[:3, :3], atol=1e-15, rtol=1e-12)
        kw_w = dict(body="A", ref_body="W", expressed_in="a", source="poses")
        _, Sw = g.angular_velocity_with_covariance(**kw_w, **time)
        np.testing.assert_allclose(Sw, want[3:, 3:], atol=1e-15, rtol=1e-12)
    # Source twists: no twist edge, no twist path, as the plain query.
    plain = query_error(lambda: g.twist(**dict(kw, source="twists"), at=0.5))
    got = query_error(lambda: g.twist_with_covariance(**dict(kw, source="twists"), at=0.5))
    assert got == plain


@pytest.mark.parametrize("time", [dict(at=2.5), dict(at=2.5, max_extrapolation=1.0),
                                  dict(at=-1.0), dict(not_before=3.0)])
def test_twist_from_poses_errors_as_the_plain_query(time):
    g = pose_history_graph()
    before = g.dump()
    kw = dict(point="a", body="A", ref_body="W", expressed_in="a", source="poses")
    for name in TWIST_FUNCTIONS:
        names = dict(kw)
        if name == "angular_velocity":
            del names["point"]
        plain = query_error(lambda: getattr(g, name)(**names, **time))
        got = query_error(lambda: getattr(g, name + "_with_covariance")(**names, **time))
        assert got == plain, name
    with pytest.raises(ValueError):
        g.twist_with_covariance(**dict(kw, source="bogus"), at=0.5)
    assert g.dump() == before
