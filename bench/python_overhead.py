#!/usr/bin/env python3
"""Per-call cost of the semgraph Python module (not a test; see docs/performance.md).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--repeat 7] [--batch 1000]

Measures, on the paper's spray-painting scene (examples/spray_painting_scene.h), the wall time
per call from Python of: a one-shot pose query (f1 wrt o2, a 5-edge path), the same query
compiled and evaluated, a twist query one-shot and compiled, set_pose through a handle, and a
PoseBatch.set of N edges from one (N, 7) array (per call and per edge); with time, the same
pose query at a time between two samples of a stamped edge (one-shot and compiled) and a
stamped set_pose; with kinematics, the Jacobian of the 6-DOF arm of models/urdf/arm6.urdf
(one-shot and compiled) and set_joints from an array. Each figure is the
best of --repeat runs of a timeit loop (best, not mean: the machine is shared), with the cost of
an empty Python call printed for reference.
"""

import argparse
import math
import os
import timeit

import numpy as np

import semgraph


def rpy(roll, pitch, yaw):
    return [roll, pitch, yaw]


# The scene of examples/spray_painting_scene.h.
POSES = [
    ("c", "C", "b", "B", rpy(0.0, 0.35, math.pi * 0.75), [1.2, 0.4, 0.9]),
    ("o1", "O1", "c", "C", rpy(0.2, -0.1, 0.3), [0.5, 0.2, 1.1]),
    ("f1", "O1", "o1", "O1", rpy(0.0, 0.0, 0.785398), [0.02, 0.0, 0.2]),
    ("o2", "O2", "e", "E", rpy(0.0, math.pi / 4, 0.0), [0.0, 0.05, 0.12]),
    ("e", "E", "b", "B", rpy(0.1, 0.4, -0.6), [0.55, -0.15, 0.7]),
]


def scene():
    g = semgraph.SceneGraph()
    for of, body, wrt, ref_body, angles, p in POSES:
        g.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=p, rpy=angles)
    g.add_twist(point="c", ref_body="B", expressed_in="b")
    g.add_twist(point="o1", ref_body="C", expressed_in="c", linear=[0.2, 0.1, 0.1], angular=[0.05, 0.1, 0.2])
    g.add_twist(point="o2", ref_body="E", expressed_in="o2")
    g.add_twist(point="e", ref_body="B", expressed_in="e", linear=[0.04, -0.03, 0.02], angular=[0.0, 0.15, -0.1])
    return g


def per_call(stmt, number, repeat, env):
    times = timeit.repeat(stmt, number=number, repeat=repeat, globals=env)
    return min(times) / number


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--number", type=int, default=100000)
    parser.add_argument("--batch", type=int, default=1000, help="edges in the batch update")
    args = parser.parse_args()

    g = scene()
    q = g.compile_pose(of="f1", wrt="o2")
    t = g.compile_twist(point="f1", ref_body="O2", expressed_in="o2")
    h = g.pose_handle(of="e", wrt="b")
    p = np.array([0.55, -0.15, 0.7])
    quat = np.array([1.0, 0.0, 0.0, 0.0])

    # A chain of N joints for the batch: j0 -> j1 -> ... each on its own body.
    n = args.batch
    chain = semgraph.SceneGraph()
    for i in range(n):
        chain.add_pose(of=f"j{i + 1}", body=f"L{i + 1}", wrt=f"j{i}", ref_body=f"L{i}", position=[0.1, 0, 0])
    batch = chain.pose_batch([chain.pose_handle(of=f"j{i + 1}", wrt=f"j{i}") for i in range(n)])
    values = np.zeros((n, 7))
    values[:, 0] = 0.1
    angles = np.linspace(0.0, 1.0, n)
    values[:, 3] = np.cos(angles / 2)
    values[:, 6] = np.sin(angles / 2)

    def noop(**kwargs):
        return None

    # Time: the same scene with e wrt b stamped (100 samples, 10 ms apart).
    gt = semgraph.SceneGraph()
    for of, body, wrt, ref_body, angles, pos in POSES:
        if of == "e":
            for k in range(100):
                gt.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=pos, rpy=angles,
                            stamp=k * 10_000_000)
        else:
            gt.add_pose(of=of, body=body, wrt=wrt, ref_body=ref_body, position=pos, rpy=angles)
    qt = gt.compile_pose(of="f1", wrt="o2")
    ht = gt.pose_handle(of="e", wrt="b")
    stamps = iter(range(1_000_000_000, 10**18, 1000))

    # Kinematics: the 6-DOF arm.
    urdf = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "urdf", "arm6.urdf")
    arm = semgraph.SceneGraph()
    robot = arm.load_urdf(urdf)
    arm.set_joints(np.array([0.1, -0.5, 0.9, -0.4, 0.3, 0.2]))
    cj = arm.compile_jacobian(point="tool0", ref_body="base_link", expressed_in="base_link")
    qj = np.array([0.2, -0.4, 1.0, -0.3, 0.2, 0.1])

    env = dict(g=g, q=q, t=t, h=h, p=p, quat=quat, batch=batch, values=values, noop=noop, gt=gt, qt=qt, ht=ht,
               stamps=stamps, arm=arm, cj=cj, qj=qj, group=robot.group)
    rows = [
        ("empty Python call noop(of=, wrt=)", 'noop(of="f1", wrt="o2")', args.number),
        ("one-shot g.pose(of=, wrt=) (5 edges)", 'g.pose(of="f1", wrt="o2")', args.number),
        ("one-shot g.pose(...).position", 'g.pose(of="f1", wrt="o2").position', args.number),
        ("compiled q.evaluate()", "q.evaluate()", args.number),
        ("one-shot g.twist(point=, ref_body=, expressed_in=)",
         'g.twist(point="f1", ref_body="O2", expressed_in="o2")', args.number),
        ("compiled twist t.evaluate()", "t.evaluate()", args.number),
        ("g.set_pose(h, position=ndarray, quaternion=ndarray)", "g.set_pose(h, position=p, quaternion=quat)", args.number),
        ("g.set_pose(h, position=list, quaternion=list)",
         "g.set_pose(h, position=[0.55, -0.15, 0.7], quaternion=[1.0, 0.0, 0.0, 0.0])", args.number),
        (f"batch.set((N, 7) array), N = {n}", "batch.set(values)", max(1, args.number // n)),
        ("stamped one-shot gt.pose(of=, wrt=, at=0.505) (float s)", 'gt.pose(of="f1", wrt="o2", at=0.505)',
         args.number),
        ("stamped one-shot gt.pose(of=, wrt=, at=505_000_000) (int ns)",
         'gt.pose(of="f1", wrt="o2", at=505_000_000)', args.number),
        ("stamped one-shot gt.pose(of=, wrt=, at='latest')", 'gt.pose(of="f1", wrt="o2", at="latest")',
         args.number),
        ("compiled qt.evaluate(at=0.505)", "qt.evaluate(at=0.505)", args.number),
        ("stamped gt.set_pose(ht, ..., stamp=int) (in order)",
         "gt.set_pose(ht, position=p, quaternion=quat, stamp=next(stamps))", args.number),
        ("arm.jacobian(point=, ref_body=, expressed_in=) (6 DOF)",
         'arm.jacobian(point="tool0", ref_body="base_link", expressed_in="base_link")', args.number // 2),
        ("arm.jacobian(...).matrix (a new (6, 6) array)",
         'arm.jacobian(point="tool0", ref_body="base_link", expressed_in="base_link").matrix', args.number // 2),
        ("compiled cj.evaluate() (6 DOF)", "cj.evaluate()", args.number),
        ("arm.set_joints(ndarray (6,), names=group)", "arm.set_joints(qj, names=group)", args.number),
        ("arm.set_joints(ndarray (6,)) (names looked up)", "arm.set_joints(qj)", args.number),
    ]
    print(f"semgraph {semgraph.__version__}, best of {args.repeat} runs")
    print(f"{'call':58s} {'per call':>12s}")
    for label, stmt, number in rows:
        seconds = per_call(stmt, number, args.repeat, env)
        extra = f"   ({seconds / n * 1e9:.1f} ns per edge)" if label.startswith("batch") else ""
        print(f"{label:58s} {seconds * 1e6:9.3f} us{extra}")


if __name__ == "__main__":
    main()
