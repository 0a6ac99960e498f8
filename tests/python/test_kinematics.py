"""Kinematics from Python (docs/kinematics.md): joints (types, axis, limits, mimic), joint states
as numpy arrays or dicts, semantic Jacobians (one-shot and compiled) and URDF models.

Expected values are independent of semgraph: a 2-link planar arm whose forward kinematics and
Jacobian are written by hand, a prismatic joint with a mimic, and the repository's 6-DOF arm
(models/urdf/arm6.urdf) whose joint table is transcribed below and chained with numpy."""

import math
import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph
from conftest import assert_rotation, source_dir

L1, L2, H = 0.7, 0.4, 0.1


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def planar_arm():
    g = semgraph.SceneGraph()
    g.add_joint("j1", type="revolute", parent="base", parent_body="Base", child="l1", child_body="L1",
                position=[0, 0, H], axis=[0, 0, 2.0], lower=-math.pi, upper=math.pi)  # axis normalized
    g.add_joint("j2", type="continuous", parent="l1", child="l2", child_body="L2", position=[L1, 0, 0],
                axis=[0, 0, 1])
    g.add_pose(of="ee", body="L2", wrt="l2", ref_body="L2", position=[L2, 0, 0])
    return g


def planar_fk(q1, q2):
    return rz(q1 + q2), np.array([L1 * math.cos(q1) + L2 * math.cos(q1 + q2),
                                  L1 * math.sin(q1) + L2 * math.sin(q1 + q2), H])


def planar_jacobian(q1, q2):
    """At the end effector, relative to Base, in [base]: rows v_x v_y v_z w_x w_y w_z."""
    s1, c1 = math.sin(q1), math.cos(q1)
    s12, c12 = math.sin(q1 + q2), math.cos(q1 + q2)
    return np.array([[-L1 * s1 - L2 * s12, -L2 * s12],
                     [L1 * c1 + L2 * c12, L2 * c12],
                     [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [1.0, 1.0]])


def test_planar_arm_forward_kinematics_and_jacobian():
    g = planar_arm()
    assert g.joint_names == ["j1", "j2"] and g.num_joints == 2
    for q1, q2 in [(0.3, -1.1), (2.0, 0.5), (-0.7, 2.9)]:
        qdot = np.array([0.4, -1.3])
        g.set_joints(np.array([q1, q2]), qdot)
        np.testing.assert_array_equal(g.joint_positions(), [q1, q2])
        np.testing.assert_array_equal(g.joint_velocities(), qdot)
        R, p = planar_fk(q1, q2)
        X = g.pose(of="ee", wrt="base")
        np.testing.assert_allclose(X.position, p, atol=1e-14)
        assert_rotation(X.quaternion, R)
        J = g.jacobian(point="ee", ref_body="Base", expressed_in="base")
        assert J.joints == ["j1", "j2"]
        assert J.matrix.shape == (6, 2) and J.matrix.dtype == np.float64
        np.testing.assert_allclose(J.matrix, planar_jacobian(q1, q2), atol=1e-14)
        np.testing.assert_array_equal(J.linear, J.matrix[:3])
        np.testing.assert_array_equal(J.angular, J.matrix[3:])
        # Full twist semantics: J qdot is the twist query, in any frame and at any point.
        T = g.twist(point="ee", ref_body="Base", expressed_in="base")
        np.testing.assert_allclose(J.matrix @ qdot, np.concatenate([T.linear, T.angular]), atol=1e-14)
        J_ee = g.jacobian(point="ee", ref_body="Base", expressed_in="ee").matrix  # Pinocchio's LOCAL
        np.testing.assert_allclose(J_ee[:3], R.T @ planar_jacobian(q1, q2)[:3], atol=1e-14)
        np.testing.assert_allclose(J_ee[3:], R.T @ planar_jacobian(q1, q2)[3:], atol=1e-14)
        # At the point of L2 at the base's origin: v_i = z x (0 - p_joint_i).
        J_o = g.jacobian(point="base", body="L2", ref_body="Base", expressed_in="base").matrix
        np.testing.assert_allclose(J_o[:3, 0], [0, 0, 0], atol=1e-14)
        np.testing.assert_allclose(J_o[:3, 1], [L1 * math.sin(q1), -L1 * math.cos(q1), 0], atol=1e-14)
        # Relative to L1: only j2 is on the twist path.
        J_rel = g.jacobian(point="ee", ref_body="L1", expressed_in="base")
        assert J_rel.joints == ["j2"]
        np.testing.assert_allclose(J_rel.matrix[:, 0], planar_jacobian(q1, q2)[:, 1], atol=1e-14)
    assert "Jacobian(TwistCoord(ee|L2, Base, [base]), joints=['j1', 'j2'], shape=(6, 2))" == repr(
        g.jacobian(point="ee", ref_body="Base", expressed_in="base"))


def test_compiled_jacobian_follows_the_joint_state():
    g = planar_arm()
    c = g.compile_jacobian(point="ee", ref_body="Base", expressed_in="base")
    assert c.joints == ["j1", "j2"] and c.is_valid
    for q in [(0.1, 0.2), (1.5, -2.0)]:
        g.set_joints({"j1": q[0], "j2": q[1]})
        np.testing.assert_allclose(c.evaluate().matrix, planar_jacobian(*q), atol=1e-14)
    g.remove_pose(of="l2", wrt="l1")  # removes the joint j2
    assert not c.is_valid
    with pytest.raises(semgraph.QueryError) as e:
        c.evaluate()
    assert e.value.code == "query_invalidated"
    assert g.joint_names == ["j1"]


def prismatic_with_mimic():
    g = semgraph.SceneGraph()
    g.add_joint("p1", type="prismatic", parent="base", parent_body="Base", child="car", child_body="Car",
                axis=[0, 1, 0], lower=-0.5, upper=0.5)
    g.add_joint("p2", type="prismatic", parent="car", child="finger", child_body="Finger", axis=[1, 0, 0],
                lower=-10, upper=10, mimic="p1", multiplier=2.0, offset=0.1)
    return g


def test_prismatic_joint_and_mimic():
    g = prismatic_with_mimic()
    assert g.joint_names == ["p1"] and g.num_joints == 2  # the mimic follows p1
    g.set_joints([0.3], [0.5])
    np.testing.assert_allclose(g.position(of="finger", wrt="base").position, [2 * 0.3 + 0.1, 0.3, 0], atol=1e-15)
    np.testing.assert_allclose(g.joint_positions(), [0.3])
    J = g.jacobian(point="finger", ref_body="Base", expressed_in="base")
    assert J.joints == ["p1"]
    np.testing.assert_allclose(J.matrix[:, 0], [2, 1, 0, 0, 0, 0], atol=1e-15)
    T = g.twist(point="finger", ref_body="Base", expressed_in="base")
    np.testing.assert_allclose(T.linear, [1.0, 0.5, 0], atol=1e-15)
    grp = g.joint_group(["p1"])
    assert len(grp) == 1 and grp.names == ["p1"] and repr(grp) == "JointGroup(['p1'])"
    g.set_joints([-0.2], names=grp)
    np.testing.assert_allclose(g.joint_positions(grp), [-0.2])
    np.testing.assert_allclose(g.joint_velocities(["p1"]), [0.5])  # kept: not given


@pytest.mark.parametrize("code, words, op", [
    ("joint_limit", ["p1"], lambda g: g.set_joints([0.6])),
    ("joint_limit", ["p1"], lambda g: g.set_joints({"p1": -0.51})),
    ("invalid_number", [], lambda g: g.set_joints([math.nan])),
    ("invalid_number", [], lambda g: g.set_joints(None, {"p1": math.inf})),
    ("mimic_joint", ["p2"], lambda g: g.set_joints({"p2": 0.1})),
    ("unknown_joint", ["nope"], lambda g: g.set_joints({"nope": 0.0})),
    ("unknown_joint", ["nope"], lambda g: g.set_joints([0.0], names=["nope"])),
    ("mimic_joint", ["p2"], lambda g: g.joint_group(["p2"])),
    ("duplicate_joint", ["p1"], lambda g: g.add_joint("p1", type="fixed", parent="car", child="x", child_body="X")),
    ("invalid_model", ["axis"], lambda g: g.add_joint("z", type="revolute", parent="base", child="z", child_body="Z",
                                                      axis=[0, 0, 0], lower=-1, upper=1)),
    ("invalid_model", [], lambda g: g.add_joint("z", type="revolute", parent="base", child="z", child_body="Z",
                                                lower=1, upper=-1)),
    ("invalid_model", [], lambda g: g.add_joint("z", type="revolute", parent="base", child="z", child_body="Z",
                                                mimic="none_such")),
    ("joint_edge", [], lambda g: g.add_pose(of="car", wrt="base", position=[0, 0, 0])),
    ("multiple_pose_parents", [], lambda g: g.add_joint("z", type="fixed", parent="base", child="finger")),
])
def test_refused_joint_operations_change_nothing(code, words, op):
    g = prismatic_with_mimic()
    g.set_joints([0.25], [0.1])
    before = g.dump()
    with pytest.raises(semgraph.RejectedError) as e:
        op(g)
    assert e.value.code == code, e.value.message
    for w in words:
        assert w in e.value.message
    assert g.dump() == before
    np.testing.assert_array_equal(g.joint_positions(), [0.25])


def test_wrong_python_arguments_of_the_joint_calls():
    g = prismatic_with_mimic()
    before = g.dump()
    with pytest.raises(ValueError, match="positions must have shape \\(1,\\)"):
        g.set_joints([0.1, 0.2])
    with pytest.raises(ValueError, match="type must be"):
        g.add_joint("z", type="ball", parent="base", child="z", child_body="Z")
    with pytest.raises(TypeError, match="lower must be a number"):
        g.add_joint("z", type="revolute", parent="base", child="z", child_body="Z", lower="low")
    with pytest.raises(TypeError, match="all be dicts"):
        g.set_joints({"p1": 0.1}, [0.0])
    with pytest.raises(TypeError, match="names must be"):
        g.set_joints([0.1], names="p1")
    with pytest.raises(TypeError, match="positions\\['p1'\\] must be a number"):
        g.set_joints({"p1": "x"})
    other = prismatic_with_mimic()
    with pytest.raises(ValueError, match="another SceneGraph"):
        g.set_joints([0.1], names=other.joint_group(["p1"]))
    assert g.dump() == before


def planar_acceleration(q, qd, qdd):
    """The end effector's classical acceleration relative to Base in [base], and alpha, by hand."""
    q1, q12 = q[0], q[0] + q[1]
    w1, w12, d1, d12 = qd[0], qd[0] + qd[1], qdd[0], qdd[0] + qdd[1]
    a = np.array([-L1 * (math.cos(q1) * w1 ** 2 + math.sin(q1) * d1)
                  - L2 * (math.cos(q12) * w12 ** 2 + math.sin(q12) * d12),
                  L1 * (-math.sin(q1) * w1 ** 2 + math.cos(q1) * d1)
                  + L2 * (-math.sin(q12) * w12 ** 2 + math.cos(q12) * d12), 0.0])
    return a, np.array([0.0, 0.0, d12])


def test_planar_arm_joint_accelerations():
    g = planar_arm()
    q, qd = [0.3, -1.1], [0.4, -1.3]
    g.set_joints(q, qd)
    with pytest.raises(semgraph.QueryError) as e:  # never given: no acceleration, not a zero
        g.acceleration(point="ee", ref_body="Base", expressed_in="base")
    assert e.value.code == "no_acceleration" and "l2" in e.value.message
    assert np.isnan(g.joint_accelerations()).all()
    qdd = [0.9, -0.35]
    g.set_joints(accelerations=np.array(qdd))
    np.testing.assert_array_equal(g.joint_accelerations(), qdd)
    r = g.acceleration(point="ee", ref_body="Base", expressed_in="base")
    a, alpha = planar_acceleration(q, qd, qdd)
    np.testing.assert_allclose(r.linear, a, atol=1e-13)
    np.testing.assert_allclose(r.angular, alpha, atol=1e-15)
    # Velocities later, or positions with accelerations: what is not given is kept.
    g.set_joints(velocities=[-0.8, 2.0])
    a, _ = planar_acceleration(q, [-0.8, 2.0], qdd)
    np.testing.assert_allclose(
        g.linear_acceleration(point="ee", ref_body="Base", expressed_in="base"), a, atol=1e-13)
    g.set_joints([1.2, 0.4], accelerations=[0.1, 0.2])
    np.testing.assert_array_equal(g.joint_velocities(), [-0.8, 2.0])
    a, _ = planar_acceleration([1.2, 0.4], [-0.8, 2.0], [0.1, 0.2])
    np.testing.assert_allclose(
        g.linear_acceleration(point="ee", ref_body="Base", expressed_in="base"), a, atol=1e-13)
    # By name, and in a group's layout.
    g.set_joints(None, {"j2": 0.5}, {"j1": -1.0})
    np.testing.assert_array_equal(g.joint_accelerations(["j2", "j1"]), [0.2, -1.0])
    g.set_joints(velocities=[0.0, 1.0], accelerations=[3.0, 4.0], names=g.joint_group(["j2", "j1"]))
    np.testing.assert_array_equal(g.joint_velocities(), [1.0, 0.0])
    np.testing.assert_array_equal(g.joint_accelerations(), [4.0, 3.0])
    a, alpha = planar_acceleration([1.2, 0.4], [1.0, 0.0], [4.0, 3.0])
    r = g.acceleration(point="ee", ref_body="Base", expressed_in="base")
    np.testing.assert_allclose(r.linear, a, atol=1e-13)
    np.testing.assert_allclose(r.angular, alpha, atol=1e-15)


@pytest.mark.parametrize("error, code, words, op", [
    (semgraph.RejectedError, "invalid_number", ["acceleration"], lambda g: g.set_joints(accelerations=[0, math.nan])),
    (semgraph.RejectedError, "invalid_number", ["acceleration of joint j1"],
     lambda g: g.set_joints(accelerations={"j1": math.inf})),
    (semgraph.RejectedError, "unknown_joint", ["nope"], lambda g: g.set_joints(accelerations={"nope": 1.0})),
    (semgraph.RejectedError, "joint_limit", ["j1"], lambda g: g.set_joints([4.0, 0.0], accelerations=[1.0, 1.0])),
    (ValueError, None, ["accelerations must have shape (2,)"], lambda g: g.set_joints(accelerations=[1.0])),
    (TypeError, None, ["all be dicts"], lambda g: g.set_joints({"j1": 0.1}, accelerations=[0.0, 0.0])),
    (TypeError, None, ["accelerations['j1'] must be a number"], lambda g: g.set_joints(accelerations={"j1": "x"})),
])
def test_refused_joint_accelerations_change_nothing(error, code, words, op):
    g = planar_arm()
    g.set_joints([0.3, -1.1], [0.4, -1.3], [0.5, 0.6])
    before = g.dump()
    with pytest.raises(error) as e:
        op(g)
    if code is not None:
        assert e.value.code == code, e.value.message
    for w in words:
        assert w in str(e.value)
    assert g.dump() == before


# arm6.urdf, transcribed: (joint, parent link, child link, origin xyz, origin rpy, axis)
ARM6 = [
    ("shoulder_pan_joint", "base_link", "shoulder_link", (0, 0, 0.089159), (0, 0, 0), (0, 0, 1)),
    ("shoulder_lift_joint", "shoulder_link", "upper_arm_link", (0, 0.13585, 0), (0, 1.570796325, 0), (0, 1, 0)),
    ("elbow_joint", "upper_arm_link", "forearm_link", (0, -0.1197, 0.425), (0, 0, 0), (0, 1, 0)),
    ("wrist_1_joint", "forearm_link", "wrist_1_link", (0, 0, 0.39225), (0, 1.570796325, 0), (0, 1, 0)),
    ("wrist_2_joint", "wrist_1_link", "wrist_2_link", (0, 0.093, 0), (0, 0, 0), (0, 0, 1)),
    ("wrist_3_joint", "wrist_2_link", "wrist_3_link", (0, 0, 0.09465), (0, 0, 0), (0, 1, 0)),
]
TOOL0 = ((0, 0.0823, 0), (-1.570796325, 0, 0))  # ee_fixed_joint: wrist_3_link -> tool0


def rpy_matrix(rpy):
    return Rotation.from_euler("ZYX", [rpy[2], rpy[1], rpy[0]]).as_matrix()


def arm6_fk(q):
    """Frames of every child link and tool0 in base_link: (R, p), and the joint axes in base."""
    R, p = np.eye(3), np.zeros(3)
    frames, axes = {}, []
    for (name, parent, child, xyz, rpy, axis), qi in zip(ARM6, q):
        p = p + R @ np.array(xyz, dtype=float)
        R = R @ rpy_matrix(rpy)
        u = np.array(axis, dtype=float)
        R = R @ Rotation.from_rotvec(u * qi).as_matrix()
        frames[child] = (R, p)
        axes.append((R @ u, p))
    p_tool = p + R @ np.array(TOOL0[0])
    frames["tool0"] = (R @ rpy_matrix(TOOL0[1]), p_tool)
    return frames, axes


def arm6_path():
    return os.path.join(source_dir(), "models", "urdf", "arm6.urdf")


needs_models = pytest.mark.skipif(not semgraph._semgraph._has_models, reason="built without the models layer")


@needs_models
def test_urdf_arm_matches_hand_computed_kinematics():
    g = semgraph.SceneGraph()
    robot = g.load_urdf(arm6_path(), prefix="r/")
    assert robot.name == "arm6" and robot.prefix == "r/" and robot.root == "r/base_link"
    assert robot.joints == ["r/" + j[0] for j in ARM6]
    assert robot.fixed_joints == ["r/ee_fixed_joint"] and robot.mimic_joints == []
    assert robot.group.names == robot.joints and g.joint_names == robot.joints
    assert "r/tool0" in robot.links and robot.links[0] == "r/base_link"
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(-3.0, 3.0, 6)
        qdot = rng.uniform(-1.0, 1.0, 6)
        g.set_joints(q, qdot, names=robot.group)
        frames, axes = arm6_fk(q)
        for link in ["shoulder_link", "forearm_link", "wrist_3_link", "tool0"]:
            X = g.pose(of="r/" + link, wrt="r/base_link")
            np.testing.assert_allclose(X.position, frames[link][1], atol=1e-12)
            assert_rotation(X.quaternion, frames[link][0], tol=1e-12)
        # Revolute columns: [z_i x (p_tool - p_i); z_i], all in base_link.
        p_tool = frames["tool0"][1]
        J_hand = np.array([np.concatenate([np.cross(z, p_tool - o), z]) for z, o in axes]).T
        J = g.jacobian(point="r/tool0", ref_body="r/base_link", expressed_in="r/base_link")
        assert J.joints == robot.joints
        np.testing.assert_allclose(J.matrix, J_hand, atol=1e-12)
        T = g.twist(point="r/tool0", ref_body="r/base_link", expressed_in="r/base_link")
        np.testing.assert_allclose(J.matrix @ qdot, np.concatenate([T.linear, T.angular]), atol=1e-12)
    # A second robot of the same model, side by side, attached with an ordinary pose.
    g.add_pose(of="r/base_link", wrt="world", ref_body="World", position=[1, 0, 0])
    left = g.load_urdf_string(open(arm6_path()).read(), prefix="l/")
    assert left.root == "l/base_link" and len(g.joint_names) == 12


@needs_models
def test_urdf_load_errors_change_nothing():
    g = semgraph.SceneGraph()
    g.load_urdf(arm6_path(), prefix="r/")
    data = os.path.join(source_dir(), "tests", "models", "data")
    before = g.dump()
    for code, op in [
        ("invalid_model", lambda: g.load_urdf(os.path.join(data, "no_such_file.urdf"))),
        ("invalid_model", lambda: g.load_urdf(os.path.join(data, "planar.urdf"))),
        ("invalid_model", lambda: g.load_urdf(os.path.join(data, "malformed.urdf"))),
        ("invalid_model", lambda: g.load_urdf_string("<robot name='x'><link name=''/></robot>")),
        ("duplicate_joint", lambda: g.load_urdf(arm6_path(), prefix="r/")),
    ]:
        with pytest.raises(semgraph.RejectedError) as e:
            op()
        assert e.value.code == code, e.value.message
        assert g.dump() == before
    with pytest.raises(TypeError):
        g.load_urdf(42)


@pytest.mark.skipif(semgraph._semgraph._has_models, reason="built with the models layer")
def test_urdf_without_the_models_layer_raises():
    with pytest.raises(RuntimeError, match="without robot models"):
        semgraph.SceneGraph().load_urdf(arm6_path())


def test_compiled_jacobian_and_groups_keep_their_graph_alive():
    import gc
    g = planar_arm()
    c = g.compile_jacobian(point="ee", ref_body="Base", expressed_in="base")
    group = g.joint_group(["j2", "j1"])
    J = g.jacobian(point="ee", ref_body="Base", expressed_in="base")
    del g
    gc.collect()
    np.testing.assert_allclose(c.evaluate().matrix, planar_jacobian(0.0, 0.0), atol=1e-15)
    assert group.names == ["j2", "j1"] and "TwistCoord(ee|L2, Base, [base])" in J.semantics
