#!/usr/bin/env python3
"""Independent oracle for examples/spray_painting.yaml (plain Python math, no semgraph code).

Prints the expected JSON Lines of `semgraph run examples/spray_painting.yaml`; its output was
written once to tests/tools/scripts/spray_painting.expected.jsonl. It recomputes everything from
first principles: every frame's pose in the base frame [b] as (R, p), every twist as (v, w) of a
body relative to another at a point, in [b], moved with v(q) = v(p) + w x (q - p), summed along
the body chain O1 - C - B - E - O2 and rotated into the asked frame.
If you change the example, change the numbers below identically and regenerate.
"""
import json
import math


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def mat_mul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(A, v):
    return [sum(A[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]


def add(a, b):
    return [x + y for x, y in zip(a, b)]


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def neg(a):
    return [-x for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rpy(roll, pitch, yaw):
    # R = Rz(yaw) Ry(pitch) Rx(roll), as docs/scene-script.md says.
    return mat_mul(rot_z(yaw), mat_mul(rot_y(pitch), rot_x(roll)))


def quaternion(R):
    """[w, x, y, z] of a rotation matrix (Shepperd), with w >= 0."""
    t = R[0][0] + R[1][1] + R[2][2]
    if t > 0:
        s = math.sqrt(t + 1.0) * 2
        q = [0.25 * s, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s]
    elif R[0][0] > R[1][1] and R[0][0] > R[2][2]:
        s = math.sqrt(1.0 + R[0][0] - R[1][1] - R[2][2]) * 2
        q = [(R[2][1] - R[1][2]) / s, 0.25 * s, (R[0][1] + R[1][0]) / s, (R[0][2] + R[2][0]) / s]
    elif R[1][1] > R[2][2]:
        s = math.sqrt(1.0 + R[1][1] - R[0][0] - R[2][2]) * 2
        q = [(R[0][2] - R[2][0]) / s, (R[0][1] + R[1][0]) / s, 0.25 * s, (R[1][2] + R[2][1]) / s]
    else:
        s = math.sqrt(1.0 + R[2][2] - R[0][0] - R[1][1]) * 2
        q = [(R[1][0] - R[0][1]) / s, (R[0][2] + R[2][0]) / s, (R[1][2] + R[2][1]) / s, 0.25 * s]
    return q if q[0] >= 0 else neg(q)


# ---- poses: frame -> (parent, R_parent_frame, p in parent)
edges = {
    "c": ("b", rpy(0.0, 0.5, 2.5), [1.2, 0.0, 1.0]),
    "o1": ("c", rpy(0.1, -0.2, 0.3), [0.4, 0.1, 0.6]),
    "f1": ("o1", rpy(0.0, 0.0, 0.785398), [0.02, 0.0, 0.2]),
    "e": ("b", rpy(0.0, 1.2, 0.4), [0.7, 0.2, 0.5]),
    "o2": ("e", rpy(0.0, -0.2, 0.0), [0.0, 0.0, 0.12]),
}


def world(frame):
    """(R_bF, p_bF): frame F in the base frame b."""
    if frame == "b":
        return [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0]
    parent, R, p = edges[frame]
    R_bP, p_bP = world(parent)
    return mat_mul(R_bP, R), add(p_bP, mat_vec(R_bP, p))


def pose(of, wrt, coord=None):
    """Pose of frame `of` wrt frame `wrt`: position expressed in [coord] (default [wrt]),
    orientation R_wrt_of (for coord == wrt)."""
    R_a, p_a = world(of)
    R_b, p_b = world(wrt)
    R_r, _ = world(coord or wrt)
    return mat_mul(transpose(R_b), R_a), mat_vec(transpose(R_r), sub(p_a, p_b))


# ---- twists: (moving body, reference body, point frame h, coord frame of the given values, v, w)
twist_edges = [
    ("C", "B", "c", "b", [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
    ("O1", "C", "o1", "c", [0.2, 0.1, 0.1], [0.05, 0.1, 0.2]),
    ("O2", "E", "o2", "o2", [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
    ("E", "B", "e", "e", [0.05, -0.02, 0.03], [0.1, 0.0, -0.15]),
]


def edge_twist_in_b(moving, ref, point):
    """Twist of `moving` relative to `ref` at `point`, in [b], from one edge (either way)."""
    for (H, D, h, r, v, w) in twist_edges:
        if {H, D} != {moving, ref}:
            continue
        R_r, _ = world(r)
        w_b = mat_vec(R_r, w)
        v_b = mat_vec(R_r, v)  # velocity of the point h of H, in [b]
        _, p_h = world(h)
        _, p_e = world(point)
        v_e = add(v_b, cross(w_b, sub(p_e, p_h)))
        return (v_e, w_b) if (H, D) == (moving, ref) else (neg(v_e), neg(w_b))
    raise KeyError((moving, ref))


chain = ["O1", "C", "B", "E", "O2"]  # the only path between the bodies in TG


def twist(point, body, ref_body, coord):
    i, j = chain.index(body), chain.index(ref_body)
    step = 1 if j > i else -1
    v, w = [0.0] * 3, [0.0] * 3
    for k in range(i, j, step):
        dv, dw = edge_twist_in_b(chain[k], chain[k + step], point)
        v, w = add(v, dv), add(w, dw)
    R_r, _ = world(coord)
    return mat_vec(transpose(R_r), v), mat_vec(transpose(R_r), w)


lines = [{"op": i, "ok": True} for i in range(20)]
R, p = pose("f1", "o2")
lines.append({"op": 20, "ok": True, "position": p, "quaternion": quaternion(R)})
v, w = twist("f1", "O1", "O2", "o2")
lines.append({"op": 21, "ok": True, "linear": v, "angular": w})
v, w = twist("f1", "O2", "O1", "o2")
lines.append({"op": 22, "ok": True, "linear": v, "angular": w})
R, p = pose("f1", "b")
lines.append({"op": 23, "ok": True, "position": p, "quaternion": quaternion(R)})
_, p = pose("f1", "o2", coord="b")
lines.append({"op": 24, "ok": True, "position": p})
R, _ = pose("o2", "o1")
lines.append({"op": 25, "ok": True, "quaternion": quaternion(R)})
v, _ = twist("f1", "O1", "B", "b")
lines.append({"op": 26, "ok": True, "linear": v})
_, w = twist("o1", "O2", "O1", "o1")
lines.append({"op": 27, "ok": True, "angular": w})

for line in lines:
    print(json.dumps(line, separators=(", ", ": ")).replace(", ", ",").replace(',"', ', "'))
