#!/usr/bin/python3
"""Independent oracle for examples/spray_painting_uncertainty.yaml (numpy, no semgraph code).

Prints the expected JSON Lines of `semgraph run examples/spray_painting_uncertainty.yaml`; its
output was written once to scripts/spray_painting_uncertainty.expected.jsonl. Only the edge
c -> o1 carries a covariance S (rows (dp, dth) at o1's origin in [c]): p_co1 + dp and
Exp(dth) R_co1 move f1 by dp + dth x q in [c], q = R_co1 p_o1f1, and turn it by dth. So, in
a frame [x] with R_xc the rotation of [c] in [x]: J = [[R_xc, -R_xc [q]x], [0, R_xc]] and the
answer's covariance is J S J^T (its top-left 3x3 for a position).
"""
import math
import os

import numpy as np


def rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), \
        math.sin(y)
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return Rz @ Ry @ Rx


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def quaternion(R):  # w >= 0 (the tool's sign rule), Shepperd's method
    t = np.trace(R)
    if t > 0:
        s = math.sqrt(t + 1) * 2
        q = [s / 4, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(1 + R[i, i] - R[j, j] - R[k, k]) * 2
        q = [0.0] * 4
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = s / 4
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    return [-x for x in q] if q[0] < 0 else q


def main():
    R_bc, p_bc = rpy(0, 0.5, 2.5), np.array([1.2, 0, 1.0])
    R_co1, p_co1 = rpy(0.1, -0.2, 0.3), np.array([0.4, 0.1, 0.6])
    R_o1f1, p_o1f1 = rpy(0, 0, 0.785398), np.array([0.02, 0, 0.2])
    R_be, p_be = rpy(0, 1.2, 0.4), np.array([0.7, 0.2, 0.5])
    R_eo2, p_eo2 = rpy(0, -0.2, 0), np.array([0, 0, 0.12])
    S = np.diag([4e-6, 4e-6, 2.5e-5, 1e-4, 1e-4, 1e-4])
    R_bo2, p_bo2 = R_be @ R_eo2, p_be + R_be @ p_eo2
    R_bf1 = R_bc @ R_co1 @ R_o1f1
    p_bf1 = p_bc + R_bc @ (p_co1 + R_co1 @ p_o1f1)
    q = R_co1 @ p_o1f1

    def J(R_xc):
        Z = np.zeros((3, 3))
        return np.block([[R_xc, -R_xc @ skew(q)], [Z, R_xc]])

    J_o2 = J(R_bo2.T @ R_bc)
    S_o2 = J_o2 @ S @ J_o2.T
    J_b = J(R_bc)
    S_b = J_b @ S @ J_b.T
    p_o2f1 = R_bo2.T @ (p_bf1 - p_bo2)
    q_o2f1 = quaternion(R_bo2.T @ R_bf1)

    def fmt(v):
        return "[" + ",".join(repr(float(x)) for x in np.asarray(v).reshape(-1)) + "]"

    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "..", "examples", "spray_painting_uncertainty.yaml")) as f:
        lines = [i + 1 for i, t in enumerate(f) if t.startswith("  - ")]
    for op in range(5):
        print('{"op": %d, "ok": true, "kind": "pose", "line": %d}' % (op, lines[op]))
    print('{"op": 5, "ok": true, "position": %s, "quaternion": %s, "covariance": %s, '
          '"kind": "query pose", "line": %d}' % (fmt(p_o2f1), fmt(q_o2f1), fmt(S_o2), lines[5]))
    print('{"op": 6, "ok": true, "position": %s, "covariance": %s, "kind": "query position", '
          '"line": %d}' % (fmt(p_o2f1), fmt(S_o2[:3, :3]), lines[6]))
    print('{"op": 7, "ok": true, "position": %s, "covariance": %s, "kind": "query position", '
          '"line": %d}' % (fmt(p_bf1), fmt(S_b[:3, :3]), lines[7]))
    # For the README: the standard deviations of the paint point's position in [o2], in mm.
    sd = np.sqrt(np.diag(S_o2[:3, :3])) * 1000
    print("# sd_mm_o2 %.3f %.3f %.3f" % tuple(sd), file=__import__("sys").stderr)


if __name__ == "__main__":
    main()
