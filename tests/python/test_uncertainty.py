"""Covariances through the Python module (docs/uncertainty.md): add_pose / add_twist with
covariance=, and the *_with_covariance queries. Every expected covariance is J S J^T with the
Jacobians derived by hand here (a pose edge's perturbation (dp, dth) at its head, in its tail's
frame: p + dp, Exp(dth) R), never read back from the module."""

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


def chain():
    """w -> a (Rz90, p = (1, 0, 0), S1) -> b (identity, p = (2, 0, 0), S2)."""
    g = semgraph.SceneGraph()
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
