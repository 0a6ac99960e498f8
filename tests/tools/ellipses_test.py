#!/usr/bin/env python3
"""Test of `semgraph ellipses` (tools/semgraph/ellipse_writer.h) on scripts/covariance_chain.yaml.

  ellipses_test.py TOOL

The expected 3x3 position covariances of a, b and c relative to w are derived by hand (as in
covariance_oracle.py: a pose edge's perturbation (dp, dth) at its head in its tail's frame), then
projected on the plane and decomposed here with numpy; each SVG ellipse must carry those
semi-axes (times sigma) and that axis direction, at the frame's position, and its drawn radii
must be the semi-axes times the drawing's scale."""
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "scripts", "covariance_chain.yaml")
RZ90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
SVG = "{http://www.w3.org/2000/svg}"


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def expected():
    """frame -> (position in [w], 3x3 position covariance in [w])."""
    S1 = np.diag([0.01, 0.02, 0.03, 0.001, 0.002, 0.003])
    S2 = np.diag([0.04, 0.05, 0.06, 0.004, 0.005, 0.006])
    r = RZ90 @ np.array([2.0, 0, 0])
    # b: dp = dp1 + dth1 x r + R dp2 -> S1p + [r]x S1th [r]x^T + R S2p R^T
    Sb = S1[:3, :3] + skew(r) @ S1[3:, 3:] @ skew(r).T + RZ90 @ S2[:3, :3] @ RZ90.T
    Sc_body = np.diag([0.01, 0.02, 0.03])
    Sc_body[0, 1] = Sc_body[1, 0] = 0.001
    return {"a": ([1.0, 0, 0], S1[:3, :3]), "b": ([1.0, 2, 0], Sb),
            "c": ([0.0, 0, 1], RZ90 @ Sc_body @ RZ90.T)}


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def check(tool, plane, sigma):
    axes = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}[plane]
    out = subprocess.run([tool, "ellipses", SCRIPT, "--root", "w", "--plane", plane, "--sigma",
                          str(sigma)], capture_output=True, timeout=60)
    if out.returncode != 0:
        fail("exit %d: %s" % (out.returncode, out.stderr.decode()))
    root = ET.fromstring(out.stdout)
    scale = float(root.get("data-scale"))
    ellipses = {e.get("data-frame"): e for e in root.iter(SVG + "ellipse")}
    if sorted(ellipses) != ["a", "b", "c"]:  # w is the root: exact, no ellipse
        fail("ellipses of %s" % sorted(ellipses))
    labels = [t.text for t in root.iter(SVG + "text")]
    if sorted(labels) != ["{a}", "{b}", "{c}", "{w}"]:
        fail("labels %s" % labels)
    for frame, (p, S) in expected().items():
        e = ellipses[frame]
        C = S[np.ix_(axes, axes)]
        lam, vec = np.linalg.eigh(C)
        major, minor = sigma * math.sqrt(lam[1]), sigma * math.sqrt(lam[0])
        got = {k: float(e.get("data-" + k)) for k in ("x", "y", "major", "minor", "angle")}
        want = {"x": p[axes[0]], "y": p[axes[1]], "major": major, "minor": minor}
        for k, v in want.items():
            if abs(got[k] - v) > 1e-9:
                fail("%s %s %s: %r, expected %r" % (plane, frame, k, got[k], v))
        a = got["angle"]
        u = np.array([math.cos(a), math.sin(a)])
        if lam[1] - lam[0] > 1e-12 and abs(abs(u @ vec[:, 1]) - 1) > 1e-9:
            fail("%s %s: major axis %r, expected along %r" % (plane, frame, u, vec[:, 1]))
        # The ellipse as a matrix: R diag(major^2, minor^2) R^T = sigma^2 C.
        Rm = np.array([[u[0], -u[1]], [u[1], u[0]]])
        back = Rm @ np.diag([got["major"] ** 2, got["minor"] ** 2]) @ Rm.T
        if np.abs(back - sigma ** 2 * C).max() > 1e-9:
            fail("%s %s: ellipse %r, expected %r" % (plane, frame, back, sigma ** 2 * C))
        for attr, v in (("rx", major), ("ry", minor)):
            if abs(float(e.get(attr)) - v * scale) > 1e-6:
                fail("%s %s %s: %s, expected %r" % (plane, frame, attr, e.get(attr), v * scale))
        degrees = float(e.get("transform").split("(")[1].split()[0])
        if abs(degrees + math.degrees(a)) > 1e-9:
            fail("%s %s: transform %s for angle %r" % (plane, frame, e.get("transform"), a))


def main():
    tool = sys.argv[1]
    for plane, sigma in (("xy", 1.0), ("xz", 2.0), ("yz", 3.0)):
        check(tool, plane, sigma)
    bad = subprocess.run([tool, "ellipses", SCRIPT, "--root", "nope"], capture_output=True)
    if bad.returncode != 2 or b"no frame named 'nope'" not in bad.stderr or bad.stdout:
        fail("unknown root: exit %d, %r" % (bad.returncode, bad.stderr))
    bad = subprocess.run([tool, "ellipses", SCRIPT, "--root", "w", "--plane", "xw"],
                         capture_output=True)
    if bad.returncode != 2 or bad.stdout:
        fail("bad plane: exit %d" % bad.returncode)
    print("ok")


if __name__ == "__main__":
    main()
