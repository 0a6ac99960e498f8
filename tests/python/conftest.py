"""Shared fixtures of the Python tests: the paper's spray-painting scene (the numbers of
examples/spray_painting_scene.h) and an independent oracle for it, built with numpy and scipy's
Rotation from the same numbers, never through semgraph.

Legend: W world (= {b}, the robot base is fixed); X_W[f] = (R_Wf, p_Wf) the pose of frame f in
W; V_W[body] = (w, v_o): angular velocity and velocity of the body's point at the world origin.
"""

import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import semgraph


def rpy_rotation(roll, pitch, yaw):
    """R = Rz(yaw) Ry(pitch) Rx(roll) (scipy: intrinsic Z-Y-X)."""
    return Rotation.from_euler("ZYX", [yaw, pitch, roll])


def wxyz(rotation):
    x, y, z, w = rotation.as_quat()
    return np.array([w, x, y, z])


# (of, body, wrt, ref_body, (roll, pitch, yaw), position): the edges X_PF in [P].
POSES = [
    ("c", "C", "b", "B", (0.0, 0.35, 3.14159265358979 * 0.75), (1.2, 0.4, 0.9)),
    ("o1", "O1", "c", "C", (0.2, -0.1, 0.3), (0.5, 0.2, 1.1)),
    ("f1", "O1", "o1", "O1", (0.0, 0.0, 0.785398), (0.02, 0.0, 0.2)),
    ("o2", "O2", "e", "E", (0.0, 1.5707963267949 / 2, 0.0), (0.0, 0.05, 0.12)),
    ("e", "E", "b", "B", (0.1, 0.4, -0.6), (0.55, -0.15, 0.7)),
]
V_CO1_c = np.array([0.2, 0.1, 0.1])
W_CO1_c = np.array([0.05, 0.1, 0.2])
V_BE_e = np.array([0.04, -0.03, 0.02])
W_BE_e = np.array([0.0, 0.15, -0.1])
BODY = {"b": "B", "c": "C", "o1": "O1", "f1": "O1", "e": "E", "o2": "O2"}


def build_spray_painting(representation="quaternion"):
    """The scene, each edge's rotation given in a different form (quaternion, matrix, rpy)."""
    g = semgraph.SceneGraph(representation=representation)
    for i, (of, body, wrt, ref_body, angles, p) in enumerate(POSES):
        rot = rpy_rotation(*angles)
        if i % 3 == 0:
            g.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=p, quaternion=wxyz(rot))
        elif i % 3 == 1:
            g.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=list(p),
                       rotation_matrix=rot.as_matrix())
        else:
            g.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=np.array(p), rpy=angles)
    g.add_twist(point="c", body="C", ref_body="B", expressed_in="b")
    g.add_twist(point="o1", body="O1", ref_body="C", expressed_in="c", linear=V_CO1_c, angular=W_CO1_c)
    g.add_twist(point="o2", body="O2", ref_body="E", expressed_in="o2")
    g.add_twist(point="e", body="E", ref_body="B", expressed_in="e", linear=V_BE_e, angular=W_BE_e)
    return g


class World:
    """World poses and twists of the scene, by hand."""

    def __init__(self, poses=POSES):
        self.R = {"b": np.eye(3)}
        self.p = {"b": np.zeros(3)}
        pending = list(poses)
        while pending:
            for edge in list(pending):
                of, _, wrt, _, angles, p = edge
                if wrt in self.R:
                    self.R[of] = self.R[wrt] @ rpy_rotation(*angles).as_matrix()
                    self.p[of] = self.p[wrt] + self.R[wrt] @ np.array(p)
                    pending.remove(edge)
        zero = (np.zeros(3), np.zeros(3))
        self.V = {"B": zero, "C": zero}
        w = self.R["c"] @ W_CO1_c
        self.V["O1"] = (w, self.R["c"] @ V_CO1_c - np.cross(w, self.p["o1"]))
        w = self.R["e"] @ W_BE_e
        self.V["E"] = (w, self.R["e"] @ V_BE_e - np.cross(w, self.p["e"]))
        self.V["O2"] = self.V["E"]

    def pose(self, e, a, f, b, r):
        """Pose (e,[a]) wrt (f,[b]) in [r]: p = R_Wr^T (p_We - p_Wf), M = R_rb R_ba R_rb^T."""
        p = self.R[r].T @ (self.p[e] - self.p[f])
        R_rb = self.R[r].T @ self.R[b]
        R_ba = self.R[b].T @ self.R[a]
        return p, R_rb @ R_ba @ R_rb.T

    def twist(self, e, C, D, r):
        """Twist of body C relative to D at point e, in [r]: (v, w)."""
        wC, vC = self.V[C]
        wD, vD = self.V[D]
        p = self.p[e]
        v = (vC + np.cross(wC, p)) - (vD + np.cross(wD, p))
        return self.R[r].T @ v, self.R[r].T @ (wC - wD)


@pytest.fixture
def spray():
    return build_spray_painting()


@pytest.fixture(scope="session")
def world():
    return World()


def assert_rotation(q_wxyz, R_expected, tol=1e-12):
    """q is unit, has w >= 0 and is the rotation R_expected."""
    q = np.asarray(q_wxyz)
    assert abs(np.linalg.norm(q) - 1.0) < tol
    assert q[0] >= 0.0
    R = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()
    np.testing.assert_allclose(R, R_expected, atol=tol, rtol=0)


def source_dir():
    return os.environ.get("SEMGRAPH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


