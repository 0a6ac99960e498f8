#!/usr/bin/env python3
"""Independent expected values for examples/robot_arm.yaml (tests/tools/scripts/robot_arm.*).

Forward kinematics of models/urdf/arm7.urdf with 4x4 matrices (xml.etree + numpy, no semgraph
code), and the geometric Jacobian of the flange's origin: column i = [z_i x (p_e - o_i); z_i]
for revolute joint i with axis z_i through o_i (all in the table frame), then rotated into the
cup's frame. Prints the query lines of the expected output (the ops before are plain "ok").
  /usr/bin/python3 tests/tools/robot_arm_oracle.py > tests/tools/scripts/robot_arm.expected.jsonl
"""
import math
import os
import xml.etree.ElementTree as ET

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
URDF = os.path.join(HERE, "..", "..", "models", "urdf", "arm7.urdf")


def rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def T(R, p):
    M = np.eye(4)
    M[:3, :3] = R
    M[:3, 3] = p
    return M


def axis_angle(u, a):
    u = np.asarray(u, float) / np.linalg.norm(u)
    K = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K


def quaternion(R):  # [w, x, y, z], w >= 0
    w = math.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return [w, x, y, z]


def nums(v):
    return "[" + ",".join(repr(float(x)) for x in v) + "]"


q = [0.3, -0.5, 0.2, -2.0, 0.1, 1.8, 0.7]
qdot = [0.1, 0.2, -0.1, 0.3, 0.0, -0.2, 0.5]
T_table_base = T(np.eye(3), [0.5, 0, 0])
T_table_camera = T(rpy(math.pi, 0, 0), [1.1, 0.1, 1.0])
T_camera_cup = T(rpy(0, 0, 0.4), [0.05, -0.1, 0.85])
T_table_cup = T_table_camera @ T_camera_cup

joints = ET.parse(URDF).getroot().findall("joint")
M = T_table_base.copy()
origins, axes = [], []
i = 0
for j in joints:
    o = j.find("origin")
    xyz = [float(x) for x in o.get("xyz", "0 0 0").split()]
    r = [float(x) for x in o.get("rpy", "0 0 0").split()]
    M = M @ T(rpy(*r), xyz)
    if j.get("type") == "revolute":
        u = [float(x) for x in j.find("axis").get("xyz").split()]
        origins.append(M[:3, 3].copy())
        axes.append(M[:3, :3] @ (np.array(u) / np.linalg.norm(u)))
        M = M @ T(axis_angle(u, q[i]), [0, 0, 0])
        i += 1
T_table_flange = M
p_e = T_table_flange[:3, 3]
J = np.zeros((6, 7))
for k in range(7):
    J[:3, k] = np.cross(axes[k], p_e - origins[k])
    J[3:, k] = axes[k]
R_cup = T_table_cup[:3, :3]
J_cup = np.vstack([R_cup.T @ J[:3], R_cup.T @ J[3:]])
V = J_cup @ np.array(qdot)

X = np.linalg.inv(T_table_cup) @ T_table_flange
cup_in_base = (np.linalg.inv(T_table_base) @ T_table_cup)[:3, 3]

lines = [
    '{"op": 0, "ok": true, "kind": "urdf", "line": 6}',
    '{"op": 1, "ok": true, "kind": "pose", "line": 8}',
    '{"op": 2, "ok": true, "kind": "twist", "line": 9}',
    '{"op": 3, "ok": true, "kind": "pose", "line": 11}',
    '{"op": 4, "ok": true, "kind": "pose", "line": 13}',
    '{"op": 5, "ok": true, "kind": "joints", "line": 15}',
    '{"op": 6, "ok": true, "position": %s, "quaternion": %s, "kind": "query pose", "line": 19}'
    % (nums(X[:3, 3]), nums(quaternion(X[:3, :3]))),
    '{"op": 7, "ok": true, "position": %s, "kind": "query position", "line": 21}' % nums(cup_in_base),
    '{"op": 8, "ok": true, "joints": [%s], "linear": [%s], "angular": [%s], "kind": "query jacobian", "line": 24}'
    % (", ".join('"arm/joint%d"' % (k + 1) for k in range(7)),
       ", ".join(nums(J_cup[r]) for r in range(3)), ", ".join(nums(J_cup[3 + r]) for r in range(3))),
    '{"op": 9, "ok": true, "linear": %s, "angular": %s, "kind": "query twist", "line": 25}' % (nums(V[:3]), nums(V[3:])),
]
print("\n".join(lines))
