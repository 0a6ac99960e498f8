#!/usr/bin/env python3
"""The paper's spray-painting scene (De Laet et al., IROS 2013, section V) with the semgraph
Python module: the numbers of examples/spray_painting_scene.h, the queries of
examples/spray_painting.cpp. Run from the build tree:

    PYTHONPATH=build/python /usr/bin/python3 examples/spray_painting.py

Legend: B robot base {b}, E end effector {e}, O2 spray gun {o2}, O1 cylinder {o1} with the paint
point {f1}, C camera {c}.
"""

import math

import semgraph

g = semgraph.SceneGraph()  # representation="quaternion"

# The five poses, each the pose of `of` (on `body`) relative to `wrt` (on `ref_body`), stored as
# the edge {wrt} -> {of}; rotations as roll, pitch, yaw (R = Rz(yaw) Ry(pitch) Rx(roll)).
g.add_pose(of="c", body="C", wrt="b", ref_body="B", position=[1.2, 0.4, 0.9], rpy=[0.0, 0.35, math.pi * 0.75])
g.add_pose(of="o1", body="O1", wrt="c", ref_body="C", position=[0.5, 0.2, 1.1], rpy=[0.2, -0.1, 0.3])
g.add_pose(of="f1", body="O1", wrt="o1", ref_body="O1", position=[0.02, 0.0, 0.2], rpy=[0.0, 0.0, 0.785398])
g.add_pose(of="o2", body="O2", wrt="e", ref_body="E", position=[0.0, 0.05, 0.12], rpy=[0.0, math.pi / 4, 0.0])
g.add_pose(of="e", body="E", wrt="b", ref_body="B", position=[0.55, -0.15, 0.7], rpy=[0.1, 0.4, -0.6])

# The twists: the camera is fixed to the base; the camera measures the cylinder's twist in its
# own axes [c] (converted once to a screw twist at {o1}); the gun is rigid on the end effector;
# the robot's joint velocities give the end effector's twist in [e].
g.add_twist(point="c", ref_body="B", expressed_in="b")
g.add_twist(point="o1", ref_body="C", expressed_in="c", linear=[0.2, 0.1, 0.1], angular=[0.05, 0.1, 0.2])
g.add_twist(point="o2", ref_body="E", expressed_in="o2")
g.add_twist(point="e", ref_body="B", expressed_in="e", linear=[0.04, -0.03, 0.02], angular=[0.0, 0.15, -0.1])
print(g)

# Listing 2: where is the paint point relative to the gun, and how fast does it move?
print(g.pose(of="f1", wrt="o2"))
print(g.twist(point="f1", ref_body="O2", expressed_in="o2"))
# Where the gun must point, seen by the camera.
print(g.position(of="f1", wrt="o2", expressed_in="c"))
# How fast the cylinder turns, seen from the robot base.
print(g.angular_velocity(body="O1", ref_body="B", expressed_in="b"))

# The control loop: compile once, then update the joint pose by handle and re-evaluate.
paint_point = g.compile_pose(of="f1", wrt="o2")
joints = g.pose_handle(of="e", wrt="b")
g.set_pose(joints, position=[0.6, -0.1, 0.7], rpy=[0.1, 0.45, -0.55])
print(paint_point.evaluate())

# What the graph refuses, and why.
try:
    g.add_pose(of="o1", body="O1", wrt="e", ref_body="E")  # a second pose parent for o1
except semgraph.RejectedError as e:
    print(e.code, "-", e.message)
try:
    g.pose(of="f1", body="O1", wrt="o2", ref_body="E")  # o2 is on the gun, not on E
except semgraph.QueryError as e:
    print(e.code, e.argument, "-", e.message)
