"""Repair from Python (docs/repair.md): add_pose / add_twist with repair=True or a RepairPolicy
return a RepairReport; a repair that does not take raises RejectedError with the original code
(and .discrepancy for a refused consistency check) and changes nothing.

The scenes are those of the paper's Fig. 4 and Fig. 6; the expected poses and twists are
composed here with numpy from the values given, never read back from semgraph."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph
from conftest import assert_rotation


class X:
    """A rigid transform (R, p) with composition and inverse, for the expected values."""

    def __init__(self, R, p):
        self.R, self.p = np.asarray(R, dtype=float), np.asarray(p, dtype=float)

    @staticmethod
    def rot(angle, axis, p):
        axis = np.asarray(axis, dtype=float)
        return X(Rotation.from_rotvec(angle * axis / np.linalg.norm(axis)).as_matrix(), p)

    def __mul__(self, o):
        return X(self.R @ o.R, self.p + self.R @ o.p)

    def inv(self):
        return X(self.R.T, -self.R.T @ self.p)

    def q(self):
        x, y, z, w = Rotation.from_matrix(self.R).as_quat()
        return [w, x, y, z]


X_DC2 = X.rot(0.3, [0, 0, 1], [1, 0, 0])
X_AC1 = X.rot(-0.2, [1, 0, 0], [0, 2, 0])
X_FC2 = X.rot(0.7, [0, 1, 1], [0.5, -1, 2])


def figure4():
    """{d}|D -> {c2}|C, {a}|A -> {c1}|C, {f}|F alone."""
    g = semgraph.SceneGraph()
    g.add_pose(of="c2", body="C", wrt="d", ref_body="D", position=X_DC2.p, quaternion=X_DC2.q())
    g.add_pose(of="c1", body="C", wrt="a", ref_body="A", position=X_AC1.p, quaternion=X_AC1.q())
    g.add_body("F")
    g.add_frame("f", "F")
    return g


def expect_pose(g, of, wrt, T):
    r = g.pose(of=of, wrt=wrt)
    np.testing.assert_allclose(r.position, T.p, atol=1e-12)
    assert_rotation(r.quaternion, T.R, 1e-12)


def test_figure4_pose_is_added_inverted():
    g = figure4()
    assert g.add_pose(of="x", body="X", wrt="d", ref_body="D") is None  # no repair asked: None
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="c2", body="C", wrt="f", ref_body="F", position=X_FC2.p, quaternion=X_FC2.q())
    assert e.value.code == "multiple_pose_parents" and e.value.discrepancy is None
    assert g.dump() == before
    report = g.add_pose(of="c2", body="C", wrt="f", ref_body="F", position=X_FC2.p,
                        rotation_matrix=X_FC2.R, repair=True)
    assert isinstance(report, semgraph.RepairReport)
    assert report.applied == "inverted" and "pose of {f}|F wrt {c2}|C" in report.change
    assert report.discrepancy is None and report.reversed_edges == 0
    assert "RepairReport(applied='inverted'" in repr(report)
    assert g.check_invariants() == ""
    expect_pose(g, "c2", "f", X_FC2)  # the refused relation is answered exactly
    expect_pose(g, "f", "d", X_DC2 * X_FC2.inv())


def test_reroot_then_invert_and_the_policy_switches():
    g = figure4()
    X_HG = X.rot(1.1, [1, 2, 3], [0, 0, 3])
    X_GF = X.rot(-0.4, [3, 1, 0], [2, 1, 0])
    g.add_pose(of="g", body="G", wrt="h", ref_body="H", position=X_HG.p, quaternion=X_HG.q())
    g.add_pose(of="f", body="F", wrt="g", ref_body="G", position=X_GF.p, quaternion=X_GF.q())
    handle = g.pose_handle(of="f", wrt="g")
    compiled = g.compile_pose(of="f", wrt="h")
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="c2", wrt="f", position=X_FC2.p, quaternion=X_FC2.q(),
                   repair=semgraph.RepairPolicy(reroot=False))
    assert e.value.code == "multiple_pose_parents"
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="c2", wrt="f", position=X_FC2.p, quaternion=X_FC2.q(),
                   repair=semgraph.RepairPolicy(invert=False))
    assert e.value.code == "multiple_pose_parents"
    assert g.dump() == before
    report = g.add_pose(of="c2", wrt="f", position=X_FC2.p, quaternion=X_FC2.q(), repair=semgraph.RepairPolicy())
    assert (report.applied, report.reversed_edges) == ("rerooted", 2)
    assert g.check_invariants() == ""
    expect_pose(g, "f", "h", X_HG * X_GF)
    expect_pose(g, "c2", "f", X_FC2)
    expect_pose(g, "h", "d", X_DC2 * X_FC2.inv() * (X_HG * X_GF).inv())
    # The reversed edges' handles and compiled queries fail cleanly.
    assert not handle.is_valid and not compiled.is_valid
    with pytest.raises(semgraph.RejectedError) as e:
        g.set_pose(handle, position=[0, 0, 0])
    assert e.value.code == "no_such_edge"
    with pytest.raises(semgraph.QueryError) as e:
        compiled.evaluate()
    assert e.value.code == "query_invalidated"


def test_determined_pose_is_consistent_or_refused_with_the_discrepancy():
    g = semgraph.SceneGraph()
    X_AB = X.rot(0.5, [1, 0, 0], [1, 2, 3])
    X_BC = X.rot(-1.0, [0, 1, 1], [0, -1, 0])
    g.add_pose(of="b", body="B", wrt="a", ref_body="A", position=X_AB.p, quaternion=X_AB.q())
    g.add_pose(of="c", body="C", wrt="b", ref_body="B", position=X_BC.p, quaternion=X_BC.q())
    X_CA = (X_AB * X_BC).inv()
    policy = semgraph.RepairPolicy(position_tolerance=1e-6, angle_tolerance=1e-6)
    assert (policy.position_tolerance, policy.invert) == (1e-6, True)
    before = g.dump()
    same = g.add_pose(of="a", wrt="c", position=X_CA.p, quaternion=X_CA.q(), repair=policy)
    assert same.applied == "consistent" and same.discrepancy[0] < 1e-12
    assert g.dump() == before
    close = g.add_pose(of="a", wrt="c", position=X_CA.p + [0.5e-6, 0, 0], quaternion=X_CA.q(), repair=policy)
    assert close.discrepancy[0] == pytest.approx(0.5e-6, abs=1e-12)
    off = X_CA * X.rot(2e-6, [0, 0, 1], [0, 0, 0])
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="a", wrt="c", position=X_CA.p + [0, 3e-3, 0], quaternion=off.q(), repair=policy)
    assert e.value.code == "pose_cycle"
    position, angle = e.value.discrepancy
    assert position == pytest.approx(3e-3, abs=1e-12) and angle == pytest.approx(2e-6, abs=1e-9)
    assert "0.003 m and 2e-06 rad" in e.value.message
    assert g.dump() == before
    with pytest.raises(semgraph.RejectedError) as e:  # without repair: the rule's refusal
        g.add_pose(of="a", wrt="c", position=X_CA.p, quaternion=X_CA.q())
    assert e.value.code == "pose_cycle" and e.value.discrepancy is None


def test_duplicate_pose_path_is_not_repaired():
    g = figure4()
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="a", wrt="d", position=[1, 1, 1], repair=True)
    assert e.value.code == "duplicate_pose_path" and e.value.discrepancy is None
    assert g.dump() == before


def test_figure6_twists_inverted_or_checked():
    g = semgraph.SceneGraph()
    X_C1C3 = X.rot(0.4, [0, 1, 0], [0.2, 0, 0.1])
    X_C2F = X.rot(0.9, [1, 1, 0], [0, 0.5, 0])
    v_AC1_c1, w_AC_c1 = np.array([0.1, 0.2, 0.3]), np.array([0, 0, 0.5])
    g.add_pose(of="c3", body="C", wrt="c1", ref_body="C", position=X_C1C3.p, quaternion=X_C1C3.q())
    g.add_twist(point="c1", body="C", ref_body="A", expressed_in="c1", linear=v_AC1_c1, angular=w_AC_c1)
    g.add_twist(point="c2", body="C", ref_body="D", expressed_in="c2", linear=[1, 0, 0], angular=[0, 0.2, 0])
    g.add_pose(of="f", body="F", wrt="c2", ref_body="C", position=X_C2F.p, quaternion=X_C2F.q())
    v, w = np.array([0.3, -0.1, 0.2]), np.array([0.1, 0.1, -0.3])
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_twist(point="c2", ref_body="F", expressed_in="c2", linear=v, angular=w)
    assert e.value.code == "multiple_twist_parents"
    assert g.dump() == before
    report = g.add_twist(point="c2", ref_body="F", expressed_in="c2", linear=v, angular=w, repair=True)
    assert report.applied == "inverted"
    T = g.twist(point="c2", ref_body="F", expressed_in="c2")
    np.testing.assert_allclose(T.linear, v, atol=1e-12)
    np.testing.assert_allclose(T.angular, w, atol=1e-12)
    # c3 wrt A follows from A ~> {c1} and X_C1C3 (by hand: moved to c3, in [c3]).
    R = X_C1C3.R.T
    w3, v3 = R @ w_AC_c1, R @ (v_AC1_c1 + np.cross(w_AC_c1, X_C1C3.p))
    ok = g.add_twist(point="c3", ref_body="A", expressed_in="c3", linear=v3, angular=w3, repair=True)
    assert ok.applied == "consistent"
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_twist(point="c3", ref_body="A", expressed_in="c3", linear=v3 + [0, 0, 0.01], angular=w3,
                    repair=semgraph.RepairPolicy())
    assert e.value.code == "duplicate_twist_path"
    assert e.value.discrepancy[0] == pytest.approx(0.01, abs=1e-12)
    assert "m/s" in e.value.message
    assert g.dump() == before


def test_repair_arguments():
    g = figure4()
    with pytest.raises(TypeError, match="repair must be a bool or a RepairPolicy"):
        g.add_pose(of="c2", wrt="f", repair="yes")
    with pytest.raises(ValueError, match="stamp= and repair="):
        g.add_twist(point="c2", ref_body="F", expressed_in="c2", stamp=1, repair=True)
    # An invalid matrix with repair: the plain add's refusal.
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="c2", wrt="f", rotation_matrix=np.diag([1.0, 1.0, -1.0]), repair=True)
    assert e.value.code == "invalid_rotation"
    assert g.dump() == before
    # repair=False is the plain add.
    with pytest.raises(semgraph.RejectedError) as e:
        g.add_pose(of="c2", wrt="f", repair=False)
    assert e.value.code == "multiple_pose_parents"
    assert "RepairPolicy(invert=True, reroot=True" in repr(semgraph.RepairPolicy())


def test_rejected_error_with_discrepancy_pickles():
    import pickle
    e = semgraph.RejectedError("pose_cycle", "m", (0.1, 0.2))
    e2 = pickle.loads(pickle.dumps(e))
    assert (e2.code, e2.message, e2.discrepancy) == ("pose_cycle", "m", (0.1, 0.2))
