#!/usr/bin/python3
"""Independent oracle for scripts/covariance_chain.yaml (numpy only, no semgraph code).

Prints the expected JSON Lines of `semgraph run scripts/covariance_chain.yaml`; its output was
written once to scripts/covariance_chain.expected.jsonl. The Jacobians are derived by hand from
the meaning of a covariance (docs/uncertainty.md): a pose edge's perturbation (dp, dth) at its
head, in its tail's frame, gives p' = p + dp, R' = Exp(dth) R; first-order terms only.
  - b wrt w through a: p_wb = p_wa + R_wa p_ab. Edge w->a: dp_wb = dp1 + dth1 x (R_wa p_ab),
    dth_wb = dth1, so J1 = [[I, -[r]x], [0, I]], r = R_wa p_ab. Edge a->b: p_ab + dp2 and
    Exp(dth2) R_ab turn into R_wa dp2 and R_wa dth2: J2 = diag(R_wa, R_wa).
  - body convention: X Exp(rho, phi) = (p + R rho, R Exp(phi)) to first order = coordinates
    perturbation (R rho, R phi): Sigma = diag(R, R) S diag(R, R)^T.
  - twist of A rel. W at a: in [a] as given; in [w] V_w = R_wa V_a, so the twist edge enters
    with diag(R_wa, R_wa) and the pose edge's dth1 with (dth1 x v_w, dth1 x w_w):
    J1 = [[0, -[v_w]x], [0, -[w_w]x]] (no dp1 term: the point moves with A).
"""
import math
import os

import numpy as np

Rz90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
I3 = np.eye(3)
Z3 = np.zeros((3, 3))


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def block(a, b, c, d):
    return np.block([[a, b], [c, d]])


def swap(S):  # linear_angular <-> angular_linear
    return block(S[3:, 3:], S[3:, :3], S[:3, 3:], S[:3, :3])


def nums(M):
    return [float(x) for x in np.asarray(M).reshape(-1)]


def line(op, fields, kind, src_line):
    out = '{"op": %d, "ok": true' % op
    for key, values in fields:
        out += ', "%s": [%s]' % (key, ",".join(repr(v) for v in values))
    return out + ', "kind": "%s", "line": %d}' % (kind, src_line)


def main():
    S1 = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])
    S2 = swap(np.diag([0.004, 0.005, 0.006, 0.04, 0.05, 0.06]))  # given angular_linear
    r = Rz90 @ np.array([2.0, 0, 0])
    J1 = block(I3, -skew(r), Z3, I3)
    J2 = block(Rz90, Z3, Z3, Rz90)
    S_wb = J1 @ S1 @ J1.T + J2 @ S2 @ J2.T
    p_wb = np.array([1.0, 0, 0]) + r
    h = math.sqrt(0.5)
    q = [h, 0.0, 0.0, h]
    Sb = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])
    Sb[0, 1] = Sb[1, 0] = 0.001
    B = block(Rz90, Z3, Z3, Rz90)
    S_wc = B @ Sb @ B.T
    St = np.diag([0.1, 0.2, 0.3, 0.01, 0.02, 0.03])
    v_a, w_a = np.array([1.0, 0, 0]), np.array([0, 0, 0.5])
    v_w, w_w = Rz90 @ v_a, Rz90 @ w_a
    Jp = block(Z3, -skew(v_w), Z3, -skew(w_w))
    St_w = B @ St @ B.T + Jp @ S1 @ Jp.T
    rows = [
        (0, [], "pose", 5), (1, [], "pose", 19),
        (2, [("position", p_wb), ("quaternion", q), ("covariance", S_wb)], "query pose", 33),
        (3, [("position", p_wb), ("quaternion", q), ("covariance", swap(S_wb))], "query pose",
         34),
        (4, [("position", p_wb), ("covariance", S_wb[:3, :3])], "query position", 35),
        (5, [("quaternion", q), ("covariance", S_wb[3:, 3:])], "query orientation", 36),
        (6, [("position", p_wb), ("quaternion", q)], "query pose", 37),
        (7, [("position", p_wb), ("quaternion", q)], "query pose", 38),
        (8, [], "pose", 40),
        (9, [("position", [0, 0, 1]), ("quaternion", q), ("covariance", S_wc)], "query pose",
         56),
        (10, [], "twist", 58),
        (11, [("linear", v_a), ("angular", w_a), ("covariance", St)], "query twist", 72),
        (12, [("linear", v_w), ("angular", w_w), ("covariance", St_w)], "query twist", 73),
        (13, [("linear", v_w), ("angular", w_w), ("covariance", swap(St_w))], "query twist", 74),
        (14, [("linear", v_w), ("covariance", St_w[:3, :3])], "query linear_velocity", 76),
        (15, [("angular", w_w), ("covariance", St_w[3:, 3:])], "query angular_velocity", 78),
    ]
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "scripts", "covariance_chain.yaml"), encoding="utf-8") as f:
        op_lines = [i + 1 for i, text in enumerate(f) if text.startswith("  - ")]
    for op, fields, kind, _ in rows:
        print(line(op, [(k, nums(v)) for k, v in fields], kind, op_lines[op]))


if __name__ == "__main__":
    main()
