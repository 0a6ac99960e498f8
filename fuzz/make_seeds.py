#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz harnesses (run once; the outputs are checked in).

  fuzz/corpus/scene_ops_fuzzer/     binary op sequences, encoded for scene_ops_fuzzer.cc's decoder
  fuzz/corpus/scene_script_fuzzer/  scene scripts (first byte '\\n' = raw mode) and a few
                                    structured-mode inputs (first byte odd)

One scene_ops seed per constraint case of the paper's Figs. 2, 4 and 6 (unique body, unique
frame, frame without body, constant pose, multiple pose parents, duplicate pose path, multiple
twist parents, duplicate twist path), the W4 twist merge conflict, the spray-painting scene
of §V, repair on Figs. 4 and 6 (invert, re-root, consistency), a jointed arm (limits, mimic,
groups, Jacobians, removal) and a stamped track under every time policy (and the time options),
each on the quaternion backend and (second file) also on the homogeneous one.
The encoder below mirrors Fuzzer<B>::Step() in scene_ops_fuzzer.cc; keep them in step.

Usage: python3 fuzz/make_seeds.py   (from anywhere)
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BODIES = "ABCDEF"
FRAMES = "abcdefghijkl"


class Ops:
    """Encoder for scene_ops_fuzzer (see the file comment of scene_ops_fuzzer.cc)."""

    def __init__(self, homogeneous=False):
        self.b = bytearray([1 if homogeneous else 0])

    def byte(self, x):
        self.b.append(x & 0xFF)
        return self

    def body_name(self, name):
        return self.byte(BODIES.index(name))

    def frame_name(self, name):
        return self.byte(FRAMES.index(name))

    def body_for(self, body):  # BodyFor(): 0 omitted, 2 then a body name
        return self.byte(0) if body is None else self.byte(2).body_name(body)

    def value(self, base=0, modifier=0):  # a table index, then a modifier byte (0 = exact)
        return self.byte(base).byte(modifier)

    # ---- ops (the first byte is the op code, Step(): byte % 20)
    def body(self, name):
        return self.byte(0).body_name(name)

    def frame(self, name, body):
        self.byte(1).frame_name(name)
        return self.byte(0) if body is None else self.byte(1).body_name(body)

    def pose(self, head, head_body, tail, tail_body, rotation=(0, 0), position=(0, 0)):
        self.byte(2).frame_name(head).body_for(head_body)
        self.byte(1)  # OneIn(16) false: tail is read
        self.frame_name(tail).body_for(tail_body)
        return self.value(*rotation).value(*position)

    def readd_pose(self, edge_index, choice, rotation=(0, 0), position=(0, 0)):
        # ReAddPose(): edge index, choice (0 same value, 3 off by 1e-9, 4 position + 1e-3,
        # 5 rotation + 1e-4 rad, 6 a new value from the tables), then two "omit body" bools.
        self.byte(6).byte(edge_index).byte(choice)
        if choice == 6:
            self.value(*rotation).value(*position)
        return self.byte(1).byte(1)

    # ---- op 17, WithCovariance(): an add with a covariance. `cov` is Covariance()'s four
    # bytes: (seed, scale index 0-3 for 1e-6..1e3, kind, form). kind % 8: 0-2, 7 valid, 3 zero,
    # 4 asymmetric (bit 7: by 1e-3 max, else 1e-12), 5 NaN/Inf/-Inf/2e12 ((kind >> 1) % 4), 6 a
    # negative diagonal entry; entry (i, j) = ((kind >> 3) % 6, (kind >> 5) % 6). form: bit 0
    # angular_linear, bits 1-2 both set: the body convention.
    def covariance(self, cov):
        for x in cov:
            self.byte(x)
        return self

    def pose_cov(self, head, head_body, tail, tail_body, rotation=(0, 0), position=(0, 0),
                 cov=(1, 2, 0, 0)):
        self.byte(17).byte(0).frame_name(head).body_for(head_body)
        self.frame_name(tail).body_for(tail_body)
        return self.value(*rotation).value(*position).covariance(cov)

    def restate_pose_cov(self, edge_index, bump=False, cov=None):
        # The stored value with the stored covariance (bump: + 1e-6 on entry (0, 0)), or `cov`.
        self.byte(17).byte(2).byte(edge_index).byte(1 if bump else 0).byte(1 if cov else 0)
        if cov:
            self.covariance(cov)
        return self.body_for(None).body_for(None)

    def twist_cov(self, point, body, ref_body, coord=None, v=(1, 0), w=(2, 0), cov=(1, 2, 0, 0)):
        self.byte(17).byte(3).frame_name(point).body_for(body).body_name(ref_body)
        if coord is None:
            self.byte(0)
        else:
            self.byte(7).frame_name(coord)
        return self.value(*v).value(*w).covariance(cov)

    def update_twist_cov(self, twist_index, cov, coord=None, v=(1, 0), w=(2, 0)):
        self.byte(17).byte(5).byte(twist_index).covariance(cov)
        if coord is None:
            self.byte(0)
        else:
            self.byte(7).frame_name(coord)
        return self.value(*v).value(*w).body_for(None)

    def remove_pose(self, of, wrt):  # the "any pair" branch (needs at least one pose edge)
        return self.byte(7).byte(0).frame_name(of).byte(0).frame_name(wrt)

    def twist(self, point, body, ref_body, coord=None, v=(1, 0), w=(2, 0)):
        self.byte(8).frame_name(point).body_for(body).body_name(ref_body)
        if coord is None:
            self.byte(0)  # TwistCoord(): the point's frame
        else:
            self.byte(7).frame_name(coord)
        return self.value(*v).value(*w)

    def remove_twist(self, point, ref_body):  # the "any pair" branch (needs a twist edge)
        return self.byte(11).byte(0).frame_name(point).body_name(ref_body)

    def ask_pose(self, of, wrt, keep=False):  # edge-form pose query
        self.byte(18 if keep else 12).byte(0).frame_name(of).byte(1).body_for(None)
        return self.byte(0).frame_name(wrt).byte(1).body_for(None).byte(1)

    def ask_position(self, point, ref_point, coord):
        self.byte(12).byte(1).frame_name(point).body_for(None)
        self.byte(0).frame_name(ref_point).body_for(None)
        return self.byte(0).byte(0).frame_name(coord)

    def ask_twist(self, point, body, ref_body, kind=3, keep=False):  # 3 twist, 4 linear
        self.byte(18 if keep else 12).byte(kind).frame_name(point)
        self.byte(0).body_name(body) if body else self.byte(1)
        return self.body_name(ref_body).byte(1)

    def ask_angular(self, body, ref_body, coord):
        return self.byte(12).byte(5).frame_name(coord).byte(1).body_name(body).body_name(ref_body)

    # ---- op 16, WrenchOp(): `which` (0-2 add, 3-4 add and 5 remove of a stored pair when there
    # is one, 6 query, 7 query compiled and kept, 8 a handle kept (of a stored pair when there is one), 9 SetWrench
    # through kept handle `pick`), a stored pair's index and reverse flag (OneIn(3)), the bodies (`on`,
    # OneIn(16) false, `by`), FrameOfBody's byte, the point (FrameNear: Bool false, a frame),
    # the coordinate frame (OneIn(3) true: the point; else FrameNear again), then the values.
    def _wrench_names(self, which, on, by, point, coord, pick=0, reverse=False):
        self.byte(16).byte(which).byte(pick).byte(0 if reverse else 1)
        self.body_name(on).byte(1).body_name(by)
        self.byte(0).byte(0).frame_name(point)
        return self.byte(0) if coord == point else self.byte(1).byte(0).frame_name(coord)

    def wrench(self, on, by, point, coord, f=(1, 0), m=(2, 0)):
        return self._wrench_names(0, on, by, point, coord).value(*f).byte(1).value(*m)

    def ask_wrench(self, on, by, point, coord, keep=False):  # by None: the net wrench on `on`
        self._wrench_names(7 if keep else 6, on, by or on, point, coord)
        return self.byte(1 if by is None else 0)

    def remove_wrench(self, index, reverse=False, on="A", by="B"):  # a stored pair, else on/by
        return self._wrench_names(5, on, by, "a", "a", index, reverse)

    def wrench_handle(self, index, reverse=False, on="A", by="B"):  # a stored pair, else on/by
        return self._wrench_names(8, on, by, "a", "a", index, reverse)

    def set_wrench(self, handle_index, f=(1, 0), m=(2, 0)):  # through a kept handle
        return self._wrench_names(9, "A", "B", "a", "a", handle_index).value(*f).value(*m)


    # ---- op 15, AccelerationOp(): `which` (0 a new twist with an acceleration, 1 a stored
    # edge's update with one, 2-4 AddAcceleration, 5 a twist handle kept, 6 SetAcceleration, 7
    # SetTwist through kept handle `pick`, 8 a query, 9 a query compiled and kept), then each
    # case's bytes as read by its decoder. Values: (table index, modifier); the acceleration
    # table is AccelerationValue()'s (1: (0.5, -0.2, 0.1), 3: gravity, 5: (4, -3, 2), 7: 2e12),
    # its modifier applied only when >= 128 (0x8B: a NaN).
    def twist_acc(self, point, body, ref_body, v=(1, 0), w=(2, 0), a=(1, 0), alpha=(2, 0)):
        self.byte(15).byte(0).frame_name(point).body_for(body).body_name(ref_body)
        return self.byte(0).value(*v).value(*w).value(*a).value(*alpha)  # coord: the point

    def update_twist_acc(self, twist_index, v=(1, 0), w=(2, 0), a=(1, 0), alpha=(2, 0)):
        self.byte(15).byte(1).byte(twist_index).byte(1).byte(1)  # body omitted, its tail body
        return self.byte(0).value(*v).value(*w).value(*a).value(*alpha)

    # AddAcceleration on stored edge #twist_index: how (0-2 at the head, 3-4 a frame of its tree:
    # `near`, the index in the model's tree walk; 5 the reverse relation, 6 ref_body `other`, 7
    # random names: `point`, `ref_body`), body_choice (0 omitted, 1 the head's body, 3 `other`).
    def add_acc(self, twist_index, how=0, body_choice=1, near=0, other="A", point="a", ref_body="A",
                coord_near=None, a=(1, 0), alpha=(2, 0)):
        self.byte(15).byte(2).byte(twist_index).byte(how).byte(body_choice)
        if how == 7:
            self.frame_name(point).body_for(None).body_name(ref_body)
        else:
            if how >= 3:
                self.byte(1).byte(near)  # FrameNear: a frame of the head's tree
            if body_choice == 3:
                self.body_name(other)
            if how == 6:
                self.body_name(other)
        if coord_near is None:
            self.byte(0)  # TwistCoord: the point
        else:
            self.byte(4).byte(1).byte(coord_near)  # a frame of the point's tree
        return self.value(*a).value(*alpha)

    # A handle of stored edge #twist_index (relative to its tail body); converting: taking twists
    # in the frame of the head's tree at index `near` (FrameNear).
    def twist_handle(self, twist_index, converting=False, near=0):
        self.byte(15).byte(5).byte(twist_index).byte(2 if converting else 0).byte(1).byte(1)
        return self.byte(1).byte(near) if converting else self

    def set_acc(self, handle_index, a=(1, 0), alpha=(2, 0)):
        return self.byte(15).byte(6).byte(handle_index).value(*a).value(*alpha)

    def set_twist(self, handle_index, v=(1, 0), w=(2, 0), converting=False):
        self.byte(15).byte(7).byte(handle_index).byte(1 if converting else 0)
        return self.value(*v).value(*w)

    # A query between stored edges t1 (C: its head's body when c_head, else its tail body) and
    # t2 (D likewise), at t1's head in its frame; kind 0 acceleration, 1 linear, 2 angular.
    def ask_acc(self, t1, t2, c_head=True, d_head=False, kind=0, keep=False):
        self.byte(15).byte(9 if keep else 8).byte(t1).byte(t2).byte(kind).byte(1)
        self.byte(1 if c_head else 0).byte(1 if d_head else 0).byte(1).byte(0)  # the point: t1's head
        if kind != 2:
            self.byte(1)  # the body given
        return self.byte(1)  # coord: the point

    # Stamped accelerations (op 15, which 10-13; docs/dynamics.md §7.2). A new stamped edge's
    # sample with an acceleration (stamp: kStamps index; stamped_exist: other stamped twist edges
    # exist, so that the "new edge" branch is chosen by a byte), coord the point.
    def stamped_twist_acc(self, point, body, ref_body, stamp, v=(1, 0), w=(2, 0), a=(1, 0),
                          alpha=(2, 0), stamped_exist=False):
        self.byte(15).byte(10).byte(0)
        if stamped_exist:
            self.byte(0)  # OneIn(4) true: a new edge
        self.frame_name(point).body_for(body).body_name(ref_body).byte(0).byte(stamp)
        return self.value(*v).value(*w).value(*a).value(*alpha)

    # A sample of stamped twist edge #index (among the stamped ones) with an acceleration: at its
    # sample #sample's stamp, or (sample None) at NextStamp(newest) case `when` (0 + 0.5 s, 2 +
    # 1 ns, 3 the newest again); restate: the twist of the sample at that stamp.
    def sample_acc(self, index, sample=None, when=0, v=(1, 0), w=(2, 0), restate=False, a=(1, 0),
                   alpha=(2, 0)):
        self.byte(15).byte(10).byte(index).byte(1).byte(1).byte(0)  # its tail body; coord: point
        if sample is None:
            self.byte(0).byte(when)
        else:
            self.byte(1).byte(sample)
        return self.value(*v).value(*w).byte(1 if restate else 0).value(*a).value(*alpha)

    # AddAcceleration at a stamp on stamped twist edge #index: how as add_acc's (0 at the head, 3
    # a frame `near` of its tree, 5 the reverse relation); the stamp: its sample #sample's
    # (stamp_how 0), + 1 ns (5), or kStamps[sample] (7). restate (None: not read): when the
    # sample has an acceleration, give it again as stored.
    def stamped_add_acc(self, index, how=0, body_choice=1, near=0, sample=0, stamp_how=0, a=(1, 0),
                        alpha=(2, 0), restate=None):
        self.byte(15).byte(11).byte(index).byte(how).byte(body_choice)
        if how >= 3:
            self.byte(1).byte(near)  # FrameNear: a frame of the head's tree (index in its walk)
        self.byte(0).byte(0).byte(stamp_how).byte(sample)  # coord: the point; the stamp
        self.value(*a).value(*alpha)
        return self if restate is None else self.byte(1 if restate else 0)

    # SetAcceleration by kept handle #handle at stamped edge #index's sample #sample (stamp_how
    # as above).
    def set_acc_at(self, handle, index, sample=0, stamp_how=0, a=(1, 0), alpha=(2, 0)):
        self.byte(15).byte(12).byte(handle).value(*a).value(*alpha)
        return self.byte(index).byte(stamp_how).byte(sample)

    # An acceleration query as ask_acc's (t1 stamped) under policy 0 latest, 1 latest common,
    # 2 at a time near t1's samples: near = (sample a, sample b, case as timed_pose's); horizon:
    # kHorizons index; not_before: a kStamps index or None.
    def ask_acc_at(self, t1, t2, c_head=True, d_head=False, kind=0, policy=2, near=(0, 0, 0),
                   horizon=0, not_before=None):
        self.byte(15).byte(13).byte(t1).byte(t2).byte(kind).byte(1)
        self.byte(1 if c_head else 0).byte(1 if d_head else 0).byte(1).byte(0)
        if kind != 2:
            self.byte(1)
        self.byte(1).byte(policy)
        if policy >= 2:
            self.byte(1).byte(1).byte(near[0]).byte(near[1]).byte(near[2]).byte(horizon)
        return self.byte(1) if not_before is None else self.byte(0).byte(not_before)

    # Stamped joint states (op 15, which 14-15; docs/dynamics.md "Stamped accelerations").
    # JointStamp(): the model's joint #joint decides; how 0 its NextStamp case `arg` (0 + 0.5 s,
    # 3 the newest again), 2 its sample #arg's stamp, 3 (or a joint without samples) kStamps[arg].
    def joint_stamp(self, how=3, joint=0, arg=0):
        return self.byte(joint).byte(how).byte(arg)

    # By name: (joint index, value byte) lists as set_joints'; accelerations (joint index,
    # kValues byte: 0 0, 1 0.5, 2 -0.7, 3 1, 4 3, 5 -2.5, 6 NaN).
    def stamped_joints(self, positions, velocities=(), accelerations=(), how=3, joint=0, arg=0):
        self.byte(15).byte(14).byte(len(positions))
        for index, value in positions:
            self.byte(1).byte(index).byte(value)
        self.byte(len(velocities))
        for index, value in velocities:
            self.byte(1).byte(index).byte(value)
        if accelerations:
            self.byte(1).byte(len(accelerations) - 1)
            for index, value in accelerations:
                self.byte(1).byte(index).byte(value)
        else:
            self.byte(0)
        return self.joint_stamp(how, joint, arg)

    # A group made through op 15/15 (joint indices), or set by a real-time stamped setter: which
    # 0 positions, 1 velocities, 2 q and qdot, 3 accelerations, 4 q, qdot and qddot; values
    # (q, qdot, qddot) bytes per joint of the group.
    def stamped_group_make(self, joints):
        self.byte(15).byte(15).byte(0).byte(len(joints) - 1)
        for index in joints:
            self.byte(1).byte(index)
        return self

    def stamped_group_set(self, which, values, how=0, joint=0, arg=0):
        self.byte(15).byte(15).byte(1).byte(which)
        for q, qdot, qddot in values:
            self.byte(q).byte(qdot).byte(qddot)
        return self.joint_stamp(how, joint, arg)

    # ---- extended ops (Step(): 13, then Extended(): byte % 12). Each encoder mirrors its
    # decoder in scene_ops_fuzzer.cc; `policy` is Policy()'s byte (< 160: the default).
    def ext(self, sub):
        return self.byte(13).byte(sub)

    def repair_pose(self, head, head_body, tail, tail_body, rotation=(0, 0), position=(0, 0), policy=0):
        self.ext(0).frame_name(head).body_for(head_body).byte(1)  # OneIn(16) false: tail read
        self.byte(0).frame_name(tail).body_for(tail_body)          # FrameNear: any frame
        return self.value(*rotation).value(*position).byte(policy)

    def repair_conflict(self, edge_index, tail, tail_body, rotation=(0, 0), position=(0, 0), omit_head_body=True,
                        policy=0):  # a frame with a pose parent, posed wrt `tail`
        self.ext(1).byte(edge_index).frame_name(tail).value(*rotation)
        self.byte(1 if omit_head_body else 0).body_for(tail_body)
        return self.value(*position).byte(policy)

    def repair_determined(self, head, tail, choice=0, policy=0):
        # choice: 0 the derived value, 2 position + 1e-10, 3 position + 1e-3 (refused with the
        # discrepancy), 5 rotation + 1e-4 rad (the derived pose must exist)
        return self.ext(2).frame_name(head).byte(0).frame_name(tail).byte(choice).byte(0).byte(0).byte(policy)

    def repair_twist(self, point, ref_body, twist_index=None, case=3, choice=0, policy=0):
        # case 0: the point is twist #twist_index's head (W1 when ref_body differs); 3: as given.
        # choice (when the derived twist exists): 0 derived, 2 w + 1e-3, 4 values from the tables
        self.ext(3).frame_name(point).body_name(ref_body)
        if twist_index is not None:
            self.byte(twist_index).byte(case)
        self.byte(0).byte(0)  # BodyFor: omitted; TwistCoord: the point's frame
        if choice is not None:
            self.byte(choice)
        if choice is None or choice == 4:
            self.value(1, 0).value(2, 0)
        return self.byte(policy)

    def joint(self, name, jtype, parent, parent_body, child, child_body, rotation=0, position=0, axis=2,
              limits=0, mimic=None, have_joints=False):
        # jtype 0 revolute, 1 continuous, 2 prismatic, 3 fixed; axis: kAxes index (2 = z, 0 = x,
        # 6 = none); limits: kLimits index (0 = [-1, 1], 2 = [0, 0.5], 4 = [1, -1]); mimic:
        # (master's index among the joints, multiplier index, offset index)
        self.ext(4).byte(name).byte(jtype)
        if have_joints:
            self.byte(0)  # the parent: any frame
        self.frame_name(parent).body_for(parent_body).byte(1).frame_name(child).body_for(child_body)
        self.byte(rotation).byte(1).byte(position).byte(axis).byte(1).byte(1).byte(limits)
        if mimic is None:
            return self.byte(1)
        return self.byte(0).byte(1).byte(mimic[0]).byte(mimic[1]).byte(mimic[2])

    def set_joints(self, positions, velocities=()):
        # (joint index, value byte): < 128 kValues[b % 8] (0, 0.5, -0.7, 1, 3, -2.5, NaN, Inf);
        # >= 128 relative: 128 lower, 129 upper, 130 upper + 5e-10, 131 upper + 2e-9, 133 mid
        self.ext(5).byte(len(positions))
        for index, value in positions:
            self.byte(1).byte(index).byte(value)
        self.byte(len(velocities))
        for index, value in velocities:
            self.byte(1).byte(index).byte(value)
        return self

    def make_group(self, joints):
        self.ext(6).byte(0).byte(len(joints) - 1)
        for index in joints:
            self.byte(1).byte(index)
        return self

    def set_group(self, which, values):  # which: 0 positions, 1 velocities, 2 both; (q, qdot) bytes
        self.ext(6).byte(1).byte(which)
        for q, qdot in values:
            self.byte(q).byte(qdot)
        return self

    def jacobian(self, point, ref_body, body=None):  # at the point, in its frame
        self.ext(7).frame_name(point)
        self.byte(1) if body is None else self.byte(0).body_name(body)
        return self.body_name(ref_body).byte(1).byte(0)  # coord = point; not a joint's child

    def stamped_pose(self, head, head_body, tail, tail_body, stamp, rotation=(0, 0), position=(0, 0),
                     poses_exist=False, stamped_exist=False):
        # a new edge; stamp: kStamps index (0 1 s, 1 1.5 s, 2 2 s, 3 2.5 s, 4 3 s)
        self.ext(8).byte(stamp)
        if poses_exist:
            self.byte(1 if not stamped_exist else 0)  # the "new edge" branch
        self.frame_name(head).body_for(head_body).frame_name(tail).body_for(tail_body)
        return self.value(*rotation).value(*position)

    def next_sample(self, stamped_index, when, change):
        # the next sample of stamped pose edge #stamped_index. when: 0 newest + 0.5 s, 2 + 1 ns,
        # 3 the same stamp, 4 newest - 0.25 s (out of order), 5 + 12 s (beyond the window);
        # change: 0 the same value, 1 position moved, 2 rotated, 3 both
        return self.ext(8).byte(0).byte(1).byte(1).byte(stamped_index).byte(when).byte(change).byte(1)

    def stamped_twist(self, point, ref_body, stamp, v=(1, 0), w=(2, 0), twists_exist=False):
        self.ext(9).byte(stamp)
        if twists_exist:
            self.byte(0)  # OneIn(4) true: the arguments below (an existing edge gets a sample)
        return self.frame_name(point).byte(0).body_name(ref_body).byte(0).value(*v).value(*w)

    def timed_pose(self, focus, kind=0, to_tail=True, policy=2, near=(0, 0, 2), horizon=0, not_before=None):
        # a pose (0), position (1) or orientation (2) query from stamped edge #focus's head to its
        # tail, under policy 0 latest, 1 latest common, 2 at a time near the edge's stamps:
        # near = (sample a, sample b, case: 0 at a, 1 a + (b-a)/4, 2 halfway, 3 newest + 0.2 s,
        # 4 oldest - 0.1 s); horizon: kHorizons index (3 = 0.5 s, 4 = 2 s, 5 = -1 ns)
        self.ext(10).byte(1).byte(focus).byte(kind).byte(1 if to_tail else 0)
        if not to_tail:
            self.byte(0).frame_name("a")
        self.byte(1).byte(policy)
        if policy >= 2:
            self.byte(1).byte(1).byte(near[0]).byte(near[1]).byte(near[2]).byte(horizon)
        if not_before is None:
            return self.byte(1)
        return self.byte(0).byte(not_before)


def scene_ops_seeds():
    seeds = {}
    # Fig. 2: unique bodies, unique frames, frame attached to a body.
    seeds["fig2_unique_body"] = Ops().body("E").body("E").body("A")
    seeds["fig2_unique_frame"] = Ops().body("A").frame("a", "A").frame("a", "A").frame("f", "A").frame("f", "B")
    seeds["fig2_frame_without_body"] = Ops().body("A").frame("l", None).frame("l", "C").frame("l", "A")
    # Fig. 4: {b1},{b2}|B -> b, c; {c1},{c2}|C -> d, e; {d}|D -> f; {f}|F -> g; {a}|A -> a.
    # Wrenches (docs/dynamics.md §7): {a}|A, {b},{d}|B, {c}|C, {e}|E apart. Adds in other
    # points and frames (storage frames: the point, the coordinate frame, a frame of `on` in
    # the tree), an update, the reverse pair (duplicate_wrench), self_wrench, an unknown body,
    # wrench_not_convertible, queries of one pair, its reaction and net wrenches, a pose
    # removal that splits the tree (no_pose_path), removals.
    seeds["wrenches"] = (
        Ops().pose("b", "B", "a", "A", (3, 0), (2, 0))
        .pose("c", "C", "a", "A", (4, 0), (3, 0))
        .pose("d", "B", "b", "B", (5, 0), (1, 0))
        .body("E").frame("e", "E")
        .wrench("B", "A", "a", "c", (1, 0), (3, 0))
        .wrench("B", "C", "c", "d", (3, 0), (4, 0))
        .wrench("A", "C", "c", "c", (5, 0), (1, 0))
        .wrench("B", "A", "d", "a", (2, 0), (2, 0))   # an update: keeps its storage frame
        .wrench("A", "B", "a", "a")                   # duplicate_wrench
        .wrench("B", "B", "b", "b")                   # self_wrench
        .wrench("B", "D", "b", "b")                   # unknown_body
        .wrench("E", "A", "a", "a")                   # wrench_not_convertible
        .wrench("B", "A", "e", "e")                   # wrench_not_convertible
        .ask_wrench("B", None, "d", "a")
        .ask_wrench("B", None, "b", "c", keep=True)   # invalidated by the removal of c's pose
        .ask_wrench("A", "B", "b", "b", keep=True)    # invalidated by the removal of the wrench
        .ask_wrench("A", "B", "c", "b")
        .ask_wrench("C", None, "a", "d")
        .ask_wrench("B", "B", "a", "a")               # self_wrench
        .ask_wrench("E", None, "e", "e")              # no_wrench
        .remove_pose("c", "a")
        .ask_wrench("B", None, "b", "b")              # both stored in {d}: answered
        .ask_wrench("A", "C", "c", "c")               # stored in {a}: no_pose_path
        .wrench_handle(0)                             # the handle of the wrench on B by A
        .set_wrench(0, (4, 0), (5, 0))                # in its storage frame {d}
        .set_wrench(0, (1, 0x07), (5, 0))             # NaN: invalid_number
        .ask_wrench("B", "A", "b", "a")
        .remove_wrench(0)
        .set_wrench(0, (4, 0), (5, 0))                # its pair removed: no_wrench
        .remove_wrench(0, reverse=True)               # no_wrench
        .ask_wrench("B", "A", "a", "a"))
    # Accelerations (docs/dynamics.md §1): a chain A -> {b}|B -> {c}|C with poses, twists with
    # accelerations, queries across both edges (composition, Coriolis, the inverse), an
    # AddAcceleration at another point (converted with the edge's twist), its errors (the
    # reverse relation: no_such_edge, an unknown body, NaN, 2e12), handles (SetAcceleration,
    # SetTwist which clears it: no_acceleration), an update with one, a kept compiled query
    # invalidated by the removal of a twist edge.
    seeds["accelerations"] = (
        Ops().pose("b", "B", "a", "A", (1, 0), (1, 0))
        .pose("c", "C", "b", "B", (3, 0), (2, 0))
        .twist_acc("b", "B", "A", (1, 0), (2, 0), (1, 0), (5, 0))
        .twist_acc("c", "C", "B", (3, 0), (4, 0), (3, 0), (6, 0))
        .ask_acc(1, 0)                                  # C wrt A at c: two edges composed
        .ask_acc(0, 1, c_head=False, d_head=True)       # A wrt C: both inverted
        .ask_acc(1, 0, kind=1).ask_acc(1, 0, kind=2)
        .ask_acc(1, 0, keep=True)                       # invalidated by the removal below
        .ask_acc(0, 0, keep=True)                       # B wrt A at b: kept valid
        .add_acc(0, how=3, near=1)                      # at a frame of b's tree, converted
        .add_acc(0, how=4, near=2, coord_near=0)
        .add_acc(0, how=5)                              # the reverse relation: no_such_edge
        .add_acc(0, how=6, other="C")                   # no edge C -> b: no_such_edge
        .add_acc(0, how=0, body_choice=3, other="F")    # unknown_body
        .add_acc(0, a=(1, 0x8B))                        # NaN: invalid_number
        .add_acc(0, a=(7, 0))                           # 2e12: invalid_number
        .add_acc(0, how=7, point="k")                   # unknown_frame
        .ask_acc(1, 0)
        .twist_handle(1)
        .set_acc(0, (5, 0), (1, 0))
        .ask_acc(1, 0)
        .set_twist(0, (2, 0), (3, 0))                   # clears c's acceleration
        .ask_acc(1, 0)                                  # no_acceleration
        .update_twist_acc(1, (1, 0), (4, 0), (4, 0), (2, 0))
        .ask_acc(1, 0, kind=1)
        .twist_handle(1, converting=True, near=1)      # c's edge, taking twists in another frame
        .set_twist(0, (3, 0), (1, 0), converting=True)  # clears c's acceleration again
        .ask_acc(1, 0)                                  # no_acceleration
        .set_acc(0, (3, 0), (5, 0))
        .remove_pose("c", "b")                          # the conversion's edge (and the chain)
        .set_twist(0, converting=True)                  # query_invalidated
        .remove_twist("c", "B")
        .set_acc(0)                                     # its edge removed: no_such_edge
        .ask_acc(0, 0))
    seeds["fig4_constant_pose"] = (
        Ops().pose("b", "B", "c", "B", (3, 0), (4, 0))
        .readd_pose(0, 0)      # the same value again: accepted, kept
        .readd_pose(0, 4)      # position off by 1e-3: constant_pose_change
        .readd_pose(0, 5)      # rotation off by 1e-4 rad: constant_pose_change
        .readd_pose(0, 3)      # off by 1e-9: within tolerance, accepted
        .remove_pose("b", "c")
        .pose("b", "B", "c", "B", (4, 0), (1, 0))  # recalibrated after removal
        .ask_pose("b", "c"))
    # Covariances (docs/uncertainty.md): a between-bodies edge with a covariance (body
    # convention, angular_linear), updated with another and without one; a constant edge's
    # covariance restated (same: accepted; bumped or another: constant_pose_change); the checks
    # (NaN with a bad rotation: invalid_number first; asymmetric; negative eigenvalue; a twist
    # in the body convention); a twist converted from another frame; a re-rooted covariance.
    seeds["cov_pose_update"] = (
        Ops().pose_cov("b", "B", "a", "A", (3, 0), (4, 0), cov=(7, 2, 0, 6))
        .pose_cov("b", "B", "a", "A", (2, 0), (1, 0), cov=(9, 3, 7, 1))
        .ask_pose("b", "a")
        .readd_pose(0, 6, (1, 0), (2, 0))  # a value without one: exact again
        .ask_pose("a", "b"))
    seeds["cov_constant_restated"] = (
        Ops().pose_cov("b", "B", "c", "B", (3, 0), (4, 0), cov=(5, 1, 0, 0))
        .restate_pose_cov(0)             # the same covariance: accepted
        .restate_pose_cov(0, bump=True)  # off by 1e-6 of (0, 0): constant_pose_change
        .restate_pose_cov(0, cov=(6, 1, 0, 0))  # another: constant_pose_change
        .readd_pose(0, 0)                # without one: constant_pose_change
        .ask_pose("c", "b"))
    seeds["cov_checks"] = (
        Ops().pose_cov("b", "B", "a", "A", (3, 0x06), (4, 0), cov=(5, 2, 5, 0))  # NaN, bad q
        .pose_cov("b", "B", "a", "A", (3, 0), (4, 0), cov=(5, 2, 5 + 2 + 8, 0))   # Inf
        .pose_cov("b", "B", "a", "A", (3, 0), (4, 0), cov=(5, 2, 4 + 128 + 8, 0))  # asymmetric
        .pose_cov("b", "B", "a", "A", (3, 0), (4, 0), cov=(5, 2, 4 + 8, 0))  # by 1e-12: ok
        .pose_cov("d", "D", "a", "A", (3, 0), (4, 0), cov=(5, 2, 6 + 16, 0))  # eigenvalue < 0
        .twist_cov("b", None, "C", cov=(5, 2, 0, 6))  # a twist in the body convention
        .twist_cov("b", None, "C", cov=(5, 3, 0, 1)))
    seeds["cov_twist_converted"] = (
        Ops().pose("b", "B", "a", "A", (3, 0), (4, 0))
        .pose("c", "B", "b", "B", (2, 0), (1, 0))
        .twist_cov("b", None, "C", coord="c", cov=(11, 2, 7, 1))
        .update_twist_cov(0, (12, 1, 0, 0), coord="a")
        .update_twist_cov(0, (13, 0, 3, 0))  # a zero covariance
        .ask_twist("b", "B", "C"))
    seeds["cov_rerooted"] = (
        Ops().pose_cov("b", "B", "a", "A", (3, 0), (4, 0), cov=(21, 2, 0, 0))
        .pose_cov("c", "C", "b", "B", (2, 0), (1, 0), cov=(22, 1, 0, 1))
        .repair_pose("c", "C", "d", "D", (1, 0), (2, 0))  # inverted: {d} wrt {c}
        .pose_cov("f", "F", "e", "E", (4, 0), (3, 0), cov=(23, 2, 7, 0))
        .repair_pose("b", "B", "f", "F", (5, 0), (6, 0))  # {f}'s tree re-rooted at {f}
        .ask_pose("e", "a"))
    seeds["fig4_multiple_parents"] = (
        Ops().pose("e", "C", "f", "D", (1, 0), (2, 0))
        .pose("e", "C", "g", "F", (2, 0), (3, 0))  # multiple_pose_parents
        .pose("g", "F", "e", "C", (2, 0), (3, 0))  # the inverse is accepted (paper §VI)
        .ask_pose("g", "f"))
    seeds["fig4_duplicate_pose_path"] = (
        Ops().pose("e", "C", "f", "D", (1, 0), (2, 0))
        .pose("d", "C", "a", "A", (3, 0), (1, 0))
        .pose("b", "B", "a", "A", (4, 0), (5, 0))
        .pose("a", "A", "f", "D", (5, 0), (3, 0))  # duplicate_pose_path (C twice)
        .pose("d", "C", "e", "C", (0, 0), (4, 0))  # multiple_pose_parents
        .pose("f", "D", "e", "C", (0, 0), (4, 0))  # pose_cycle (f is the root above e)
        .ask_pose("b", "d").ask_pose("e", "f"))
    # Fig. 6: twists. c1, c2, c3 | C -> d, e, h.
    seeds["fig6_multiple_twist_parents"] = (
        Ops().twist("e", "C", "D").twist("e", "C", "F")  # multiple_twist_parents
        .twist("e", "C", "D", None, (3, 0), (4, 0))      # update
        .ask_twist("e", "C", "D").ask_twist("e", "D", "C"))
    seeds["fig6_duplicate_twist_path"] = (
        Ops().twist("d", "C", "A")
        .pose("h", "C", "d", "C", (2, 0), (1, 0))
        .twist("h", "C", "A")  # duplicate_twist_path (parallel A-C)
        .twist("h", "C", "B")
        .twist("a", "A", "B")  # cycle A-C-B-A? a not in tree: separate tree, accepted
        .ask_twist("h", "C", "A").ask_angular("C", "B", "d"))
    seeds["w4_twist_merge_conflict"] = (
        Ops().twist("d", "C", "A").twist("h", "C", "A")
        .pose("h", "C", "d", "C", (2, 0), (1, 0))  # twist_merge_conflict
        .remove_twist("h", "A")
        .pose("h", "C", "d", "C", (2, 0), (1, 0))
        .ask_twist("h", "C", "A"))
    # §V spray painting: B base {b}, E end effector {e}, O2 gun {o2}, O1 cylinder {o1},{f1}, C
    # camera {c}  ->  bodies A=B, B=E, C=O2, D=O1, E=C;  frames b=b, e=e, g=o2, h=o1, i=f1, c=c.
    spray = (lambda o: o
             .pose("c", "E", "b", "A", (6, 0), (5, 0))   # camera mounting
             .pose("h", "D", "c", "E", (3, 0), (2, 0))   # object detection
             .pose("i", "D", "h", "D", (1, 0), (4, 0))   # paint point (constant)
             .pose("g", "C", "e", "B", (7, 0), (1, 0))   # spray gun mounting
             .pose("e", "B", "b", "A", (4, 0), (3, 0))   # robot joints
             .twist("c", "E", "A", "b", (0, 0), (0, 0))  # camera static, given in [b]
             .twist("h", "D", "E", "c", (1, 0), (2, 0))  # object twist measured in [c]
             .twist("g", "C", "B", None, (0, 0), (0, 0))
             .twist("e", "B", "A", None, (3, 0), (4, 0))
             .ask_pose("i", "g", keep=True).ask_pose("g", "i")
             .ask_position("i", "g", "b")
             .ask_twist("i", "D", "C", kind=3, keep=True).ask_twist("g", "C", "D", kind=4)
             .ask_angular("D", "C", "i")
             .readd_pose(4, 6, (5, 0), (2, 0))            # joints move
             .twist("e", "B", "A", None, (5, 0), (1, 0))
             .remove_pose("h", "c").pose("h", "D", "g", "C", (0, 0), (4, 0))  # grasp
             .ask_pose("i", "b").ask_twist("i", "D", "A"))
    seeds["spray_painting"] = spray(Ops())
    # Repair (docs/repair.md), the paper's Fig. 4: {d}|D -> {c2}|C, {a}|A -> {c1}|C; c2 = c,
    # c1 = e; {f}|F. "c wrt f" is refused by P1 and added inverted; "b wrt f" then needs a
    # re-root of f's tree (2 edges reversed; the kept query over d -> c is invalidated); "d wrt
    # f" is already determined: consistent with the derived value, refused 1e-3 m off.
    seeds["repair_fig4"] = (
        Ops().pose("c", "C", "d", "D", (3, 0), (1, 0)).pose("e", "C", "a", "A", (4, 0), (2, 0))
        .pose("b", "B", "h", "E", (1, 0), (3, 0))
        .ask_pose("c", "d", keep=True)
        .repair_pose("c", None, "f", "F", (5, 0), (4, 0))      # inverted
        .repair_pose("e", None, "f", None, (1, 0), (1, 0))     # re-root refused by P3: P1 stays
        .repair_conflict(2, "f", None, (6, 0), (5, 0))         # b wrt f: re-rooted
        .repair_determined("d", "f", 0)                        # consistent
        .repair_determined("d", "f", 3)                        # refused, 1e-3 m
        .repair_determined("d", "f", 3, policy=166)            # tolerance 1e-3: at the boundary
        .repair_determined("c", "d", 5, policy=162)            # consistency checks off
        .ask_pose("b", "d").ask_pose("f", "a"))
    # Fig. 6: e|C has the twist parent D; its twist wrt F is added inverted on {f}|F; then the
    # twist of C wrt F at {g}|C is already determined (consistent, then 1e-3 rad/s off).
    seeds["repair_fig6"] = (
        Ops().pose("f", "F", "e", "C", (3, 0), (2, 0)).pose("g", "C", "e", "C", (0, 0), (4, 0))
        .twist("e", "C", "D")
        .repair_twist("e", "F", twist_index=0, case=0, choice=None)  # W1 -> inverted on f
        .repair_twist("g", "F", twist_index=0, case=3, choice=0)  # W3 -> consistent
        .repair_twist("g", "F", twist_index=0, case=3, choice=2)  # W3 -> discrepancy
        .ask_twist("g", "C", "F").ask_twist("f", "F", "D"))
    # Joints: j0 revolute a|A -> b|B about z in [-1, 1], j1 prismatic b -> c|C along x in
    # [0, 0.5], j2 continuous c -> d|D, j3 a mimic of j0 (multiplier -1, offset 0.1) d -> e|E.
    arm_joints = (lambda o: o
                  .joint(0, 0, "a", "A", "b", "B", rotation=3, position=1, axis=2, limits=0)
                  .joint(1, 2, "b", None, "c", "C", rotation=4, position=2, axis=0, limits=2,
                         have_joints=True)
                  .joint(2, 1, "c", None, "d", "D", rotation=5, position=3, axis=4, have_joints=True)
                  .joint(3, 0, "d", None, "e", "E", rotation=1, position=4, axis=1, limits=0,
                         mimic=(0, 1, 1), have_joints=True))
    arm = (lambda o: arm_joints(o)
           .joint(0, 0, "e", None, "f", "F", have_joints=True)             # duplicate_joint
           .joint(1, 0, "f", "F", "g", "A", axis=6, have_joints=True)       # invalid_model (no axis)
           .set_joints([(0, 1), (1, 130)], [(0, 3), (2, 5)])               # 0.5, upper + 5e-10
           .set_joints([(0, 131)])                                          # joint_limit
           .set_joints([(3, 1)])                                            # mimic_joint
           .jacobian("e", "A").jacobian("c", "D").ask_twist("e", "E", "A")
           .make_group([0, 1, 2]).set_group(2, [(1, 3), (133, 2), (4, 5)])
           .jacobian("e", "A", body="E").ask_pose("e", "a")
           .remove_pose("b", "a")                                           # j0 has a mimic: joint_edge
           .remove_pose("e", "d")                                           # removes j3
           .remove_pose("b", "a")                                           # removes j0
           .set_group(0, [(1, 0), (1, 0), (1, 0)])                          # unknown_joint (stale)
           .jacobian("e", "A"))
    seeds["joints_arm"] = arm(Ops())
    # Time: {o}|B stamped wrt {c}|A at 1, 1.5, 1.25 (out of order), 1.5 again (duplicate),
    # and a stamped twist; queries between samples, latest common, with and without a horizon.
    track = (lambda o: o
             .stamped_pose("b", "B", "c", "A", 0, (3, 0), (1, 0))
             .next_sample(0, 0, 2).next_sample(0, 4, 1).next_sample(0, 3, 1)
             .next_sample(0, 2, 1)          # 1.5 s + 1 ns: a 4th sample (capacity 3: the oldest goes)
             .timed_pose(0, near=(0, 1, 1))  # between the first two kept samples
             .stamped_twist("b", "A", 0, (2, 0), (3, 0))
             .stamped_twist("b", "A", 2, (1, 0), (2, 0), twists_exist=True)
             .timed_pose(0, near=(0, 1, 2)).timed_pose(0, kind=1, near=(0, 2, 1))
             .timed_pose(0, policy=1).timed_pose(0, policy=0, not_before=4)
             .timed_pose(0, near=(0, 0, 3))                           # extrapolation
             .timed_pose(0, near=(0, 0, 3), horizon=3)                # integrated with the twist
             .timed_pose(0, near=(0, 0, 4), horizon=4)                # before the first sample
             .timed_pose(0, near=(0, 0, 0), horizon=5)                # negative horizon
             .next_sample(0, 5, 3)                                    # 12 s later: older ones pruned
             .timed_pose(0, near=(0, 0, 2)).timed_pose(0, kind=2, near=(0, 1, 1)))
    seeds["time_track"] = track(Ops())
    # Stamped accelerations (docs/dynamics.md §7.2): A -> {b}|B sampled at 1, 1.5, 2 s with
    # accelerations, B -> {c}|C at 1, 1.5, 2 s (the last without one); queries between
    # samples (interpolated; across the sample without one: no_acceleration), held within a
    # horizon, latest and latest common; AddAcceleration at a sample's stamp (at the head, at a
    # frame of its tree, against the edge), at a stamp without a sample, the same one again and
    # another (a duplicate), without a stamp (stamp_mismatch); SetAcceleration at a stamp.
    seeds["time_accelerations"] = (
        Ops().pose("b", "B", "a", "A", (1, 0), (1, 0))
        .pose("c", "C", "b", "B", (3, 0), (2, 0))
        .stamped_twist_acc("b", "B", "A", 0, (1, 0), (2, 0), (1, 0), (5, 0))
        .sample_acc(0, when=0, v=(3, 0), w=(1, 0), a=(3, 0), alpha=(6, 0))  # 1.5 s
        .stamped_twist_acc("c", "C", "B", 0, (3, 0), (4, 0), (3, 0), (6, 0), stamped_exist=True)
        .sample_acc(1, when=0, v=(2, 0), w=(1, 0), a=(4, 0), alpha=(1, 0))  # 1.5 s
        .sample_acc(0, when=0, v=(2, 0), w=(3, 0), a=(5, 0), alpha=(1, 0))  # 2 s
        .stamped_twist("c", "B", 2, (1, 0), (2, 0), twists_exist=True)      # 2 s, without one
        .ask_acc_at(0, 0, near=(0, 1, 1))                                   # A -> b interpolated
        .ask_acc_at(1, 0, near=(0, 1, 2))                                   # composed, 1.25 s
        .ask_acc_at(1, 0, near=(1, 2, 2))                                   # c: no_acceleration
        .ask_acc_at(1, 0, policy=0).ask_acc_at(1, 0, policy=1)
        .ask_acc_at(0, 0, kind=1, near=(0, 0, 3), horizon=3)                # held (extrapolated)
        .ask_acc_at(0, 0, kind=2, near=(0, 0, 4), horizon=4)
        .ask_acc_at(0, 0, near=(0, 0, 3))                                   # extrapolation
        .ask_acc_at(0, 0, near=(0, 0, 0), not_before=4)                     # stale
        .stamped_add_acc(1, sample=2, a=(5, 0), alpha=(3, 0))               # c at 2 s
        .ask_acc_at(1, 0, near=(1, 2, 2))                                   # now both carry one
        .stamped_add_acc(1, sample=2, a=(5, 0), alpha=(3, 0), restate=True) # the same again
        .stamped_add_acc(1, sample=2, a=(1, 0), alpha=(3, 0), restate=False)  # another one
        .stamped_add_acc(0, how=3, near=2, sample=1, a=(4, 0), alpha=(1, 0))  # at a frame of b's tree
        .stamped_add_acc(0, how=5, sample=0)                                # against the edge, at b
        .stamped_add_acc(0, sample=0, stamp_how=5)                          # 1 s + 1 ns: no sample
        .add_acc(0)                                                         # stamp_mismatch
        .twist_handle(0)
        .set_acc_at(0, 0, sample=1, a=(6, 0), alpha=(2, 0))
        .set_acc_at(0, 0, sample=0, stamp_how=5)                            # stamp_mismatch
        .set_acc(0)                                                         # stamp_mismatch
        .ask_acc_at(0, 0, near=(0, 1, 2)).ask_acc_at(1, 0, policy=1))
    # Stamped joint states with qddot on the arm (j0 revolute, j1 prismatic, j2 continuous, j3 a
    # mimic of j0): the first stamped state by name with qddot at 1 s (j3 follows: -qddot), a
    # sample keeping qddot at 1.5 s, a real-time group set refused while j2 is not stamped
    # (stamp_mismatch), j2 stamped at 3 s, the group set with qddot at 2 s (out of order for
    # j2), SetJointAccelerations at 2 s again (replaced; a duplicate under reject), a NaN qddot,
    # unstamped sets (stamp_mismatch), acceleration queries at and between the samples.
    seeds["time_joint_accelerations"] = (
        arm_joints(Ops())
        .stamped_joints([(0, 1), (1, 133)], [(0, 3)], [(0, 3), (1, 1)], how=3, arg=0)  # 1 s
        .stamped_joints([(0, 2)], how=0, joint=0, arg=0)                                # 1.5 s
        .stamped_group_make([0, 1, 2])
        .stamped_group_set(4, [(1, 3, 3), (133, 1, 2), (4, 5, 1)], how=0, joint=0, arg=0)
        .stamped_joints([(2, 1)], [(2, 3)], [(2, 4)], how=3, arg=4)                     # j2 at 3 s
        .stamped_group_set(4, [(1, 3, 3), (133, 1, 2), (4, 5, 1)], how=0, joint=0, arg=0)  # 2 s
        .stamped_group_set(3, [(0, 0, 5), (0, 0, 2), (0, 0, 3)], how=0, joint=0, arg=3)  # 2 s
        .stamped_group_set(3, [(0, 0, 6), (0, 0, 2), (0, 0, 3)], how=0, joint=0, arg=0)  # NaN
        .stamped_group_set(2, [(2, 1, 0), (0, 1, 0), (1, 1, 0)], how=0, joint=0, arg=0)  # 2.5 s
        .set_joints([(0, 1)]).byte(1)                                 # mismatch (no qddot: 1)
        .set_group(2, [(1, 3), (133, 2), (4, 5)])                                       # mismatch
        .ask_acc_at(0, 0, near=(0, 1, 1)).ask_acc_at(3, 0, kind=2, near=(0, 1, 2))
        .ask_acc_at(1, 0, kind=1, near=(1, 2, 1)).ask_acc_at(2, 0, near=(0, 0, 0))
        .ask_acc_at(3, 1, policy=1).ask_acc_at(1, 0, policy=0))
    seeds["time_joint_accelerations_reject"] = Ops()
    seeds["time_joint_accelerations_reject"].b = bytearray(seeds["time_joint_accelerations"].b)
    seeds["time_joint_accelerations_reject"].b[0] = 4  # duplicates rejected
    for name, byte0 in (("linear", 2), ("reject", 4), ("small_window", 8)):
        seeds["time_track_" + name] = track(Ops())
        seeds["time_track_" + name].b[0] = byte0
    out = {}
    seeds["time_accelerations_reject"] = Ops()
    seeds["time_accelerations_reject"].b = bytearray(seeds["time_accelerations"].b)
    seeds["time_accelerations_reject"].b[0] = 4  # duplicates rejected
    for name, ops in seeds.items():
        out[name] = bytes(ops.b)
        homogeneous = bytearray(ops.b)
        homogeneous[0] |= 1
        out[name + "_homogeneous"] = bytes(homogeneous)
    # Invalid numbers and names on an existing scene.
    bad = spray(Ops(True))
    bad.pose("a", "A", "b", "A", (0, 8), (0, 0))   # NaN quaternion
    bad.pose("a", "A", "b", "A", (0, 6), (0, 0))   # non-unit quaternion
    bad.pose("a", "A", "b", "A", (0, 12), (0, 0))  # reflection matrix
    bad.pose("a", "A", "b", "A", (0, 0), (0, 7))   # NaN position
    bad.byte(0).byte(252)                           # body with an empty name (SpecialName 0)
    bad.byte(1).byte(253).byte(1).body_name("A")    # frame with a control character (1)
    bad.byte(0).byte(248)                           # a 300-byte body name (2)
    bad.byte(0).byte(250)                           # a 255-byte body name: valid (4)
    out["invalid_input"] = bytes(bad.b)
    return out


I6 = "[[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]"  # a 6x6 identity covariance

SCRIPTS = {
    # Covariances (docs/uncertainty.md): both forms, both orders, the body convention, queries
    # with and without covariance_order, op errors, and malformed variants.
    "covariance.yaml": """ops:
  - {op: pose, of: a, body: A, wrt: w, ref_body: W, position: [1, 0, 0], rotation: {rpy: [0, 0, 1.5707963267948966]}, covariance: I6}
  - {op: pose, of: b, body: B, wrt: a, ref_body: A, position: [2, 0, 0], covariance: {matrix: I6, order: angular_linear}}
  - {op: pose, of: c, body: C, wrt: w, ref_body: W, covariance: {matrix: I6, convention: body}}
  - {op: twist, point: a, body: A, ref_body: W, coord: a, linear: [1, 0, 0], covariance: {matrix: I6, order: linear_angular}}
  - {op: query, kind: pose, of: b, wrt: w, covariance: true, covariance_order: angular_linear}
  - {op: query, kind: position, of: b, wrt: c, covariance: true}
  - {op: query, kind: orientation, of: b, wrt: w, covariance: false}
  - {op: query, kind: twist, point: a, body: A, ref_body: W, coord: w, covariance: true}
  - {op: query, kind: linear_velocity, point: a, body: A, ref_body: W, coord: w, covariance: true}
  - {op: query, kind: angular_velocity, body: A, ref_body: W, coord: w, covariance: true}
  - {op: pose, of: a, body: A, wrt: w, ref_body: W, covariance: [[.nan, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, -1]]}
""".replace("I6", I6),
    "bad_covariance_shape.yaml": """ops:
  - {op: pose, of: a, wrt: w, covariance: [1, 0, 0, 0, 0, 0]}
""",
    "bad_covariance_key.yaml": """ops:
  - {op: pose, of: a, wrt: w, covariance: {matrix: [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]], frame: w}}
""",
    "bad_covariance_on_body.yaml": """ops:
  - {op: body, name: W, covariance: [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]}
""",
    "bad_covariance_order.yaml": """ops:
  - {op: query, kind: position, of: a, wrt: w, covariance: true, covariance_order: angular_linear}
""",
    "spec_example.yaml": """ops:
  - {op: pose, of: c, body: C, wrt: b, ref_body: B, position: [1.0, 0.0, 0.5]}
  - {op: pose, of: o1, body: O1, wrt: c, ref_body: C, position: [0.5, 0.2, 0.0], rotation: {rpy: [0, 0, 0.3]}}
  - {op: pose, of: f1, body: O1, wrt: o1, position: [0.02, 0, 0.2], rotation: {rpy: [0, 0, 0.785398]}}
  - {op: twist, point: o1, body: O1, ref_body: C, coord: c, linear: [0.2, 0.1, 0.1], angular: [0.05, 0.1, 0.2]}
  - {op: query, kind: pose, of: f1, wrt: b}
""",
    "help_example.yaml": """representation: quaternion
ops:
  - {op: body, name: B}
  - {op: frame, name: b, body: B}
  - {op: pose, of: c, body: C, wrt: b, position: [1, 0, 0.5], rotation: {rpy: [0, 0, 0.3]}}
  - {op: twist, point: c, ref_body: B, coord: b, linear: [0.1, 0, 0], angular: [0, 0, 0.2]}
  - {op: query, kind: pose, of: c, wrt: b}
  - {op: query, kind: twist, point: c, body: C, ref_body: B, coord: c}
  - {op: remove, kind: twist, point: c, ref_body: B}
  - {op: remove, kind: pose, of: c, wrt: b}
""",
    "spray_painting.yaml": """# The paper's section V scene (examples/spray_painting_scene.h), every query kind.
ops:
  - {op: pose, of: c, body: C, wrt: b, ref_body: B, position: [1.2, 0.4, 0.9], rotation: {rpy: [0, 0.35, 2.35619449019]}}
  - {op: pose, of: o1, body: O1, wrt: c, ref_body: C, position: [0.5, 0.2, 1.1], rotation: {rpy: [0.2, -0.1, 0.3]}}
  - {op: pose, of: f1, body: O1, wrt: o1, position: [0.02, 0.0, 0.2], rotation: {rpy: [0, 0, 0.785398]}}
  - {op: pose, of: o2, body: O2, wrt: e, ref_body: E, position: [0.0, 0.05, 0.12], rotation: {rpy: [0, 0.785398163, 0]}}
  - {op: pose, of: e, body: E, wrt: b, position: [0.55, -0.15, 0.7], rotation: {quaternion: [0.9, 0.1, 0.3, -0.3]}}
  - {op: twist, point: c, ref_body: B, coord: b}
  - {op: twist, point: o1, body: O1, ref_body: C, coord: c, linear: [0.2, 0.1, 0.1], angular: [0.05, 0.1, 0.2]}
  - {op: twist, point: o2, ref_body: E, coord: o2}
  - {op: twist, point: e, ref_body: B, coord: e, linear: [0.04, -0.03, 0.02], angular: [0.0, 0.15, -0.1]}
  - {op: query, kind: pose, of: f1, wrt: o2}
  - {op: query, kind: pose, point: f1, orientation: o1, ref_point: o2, ref_orientation: e, coord: b}
  - {op: query, kind: position, point: f1, ref_point: o2, coord: b}
  - {op: query, kind: orientation, orientation: f1, ref_orientation: o2, coord: c}
  - {op: query, kind: twist, point: f1, body: O1, ref_body: O2, coord: o2}
  - {op: query, kind: linear_velocity, point: f1, body: O1, ref_body: O2, coord: b}
  - {op: query, kind: angular_velocity, body: O1, ref_body: O2, coord: o2}
  - {op: remove, kind: pose, of: o1, wrt: c}
  - {op: pose, of: o1, wrt: o2, position: [0, 0, 0.1], rotation: {matrix: [[1, 0, 0], [0, 0, -1], [0, 1, 0]]}}
  - {op: query, kind: pose, of: f1, wrt: b}
""",
    "homogeneous.yaml": """representation: homogeneous
ops:
  - {op: pose, of: a, body: A, wrt: w, ref_body: W, position: [1, 2, 3], rotation: {quaternion: [0.5, 0.5, 0.5, 0.5]}}
  - {op: pose, of: b, body: B, wrt: a, position: [0, 1, 0]}
  - {op: query, kind: pose, of: b, wrt: w}
  - {op: query, kind: pose, of: b, wrt: w, coord: a}
  - {op: query, kind: orientation, orientation: b, ref_orientation: w, coord: a}
  - {op: query, kind: position, point: b, ref_point: w, coord: a}
""",
    "paper_constraints.yaml": """# Figs. 2, 4 and 6 of the paper, and W4: every constraint rejects once.
ops:
  - {op: body, name: E}
  - {op: body, name: E}
  - {op: frame, name: a, body: A}
  - {op: frame, name: z}
  - {op: body, name: B}
  - {op: pose, of: b1, body: B, wrt: b2, ref_body: B, position: [0, 0, 1]}
  - {op: pose, of: b1, wrt: b2, position: [0, 0, 2]}
  - {op: pose, of: c2, body: C, wrt: d, ref_body: D}
  - {op: pose, of: c2, wrt: f, ref_body: F}
  - {op: pose, of: c1, body: C, wrt: a, ref_body: A}
  - {op: pose, of: a, wrt: d}
  - {op: twist, point: c2, ref_body: D, coord: c2}
  - {op: twist, point: c2, ref_body: F, coord: c2}
  - {op: twist, point: c1, ref_body: A, coord: c1}
  - {op: pose, of: c3, body: C, wrt: c1}
  - {op: twist, point: c3, ref_body: A, coord: c3}
  - {op: twist, point: x1, body: X, ref_body: A, coord: x1}
  - {op: twist, point: x2, body: X, ref_body: A, coord: x2}
  - {op: pose, of: x2, wrt: x1}
  - {op: remove, kind: pose, of: c3, wrt: c1}
  - {op: remove, kind: pose, of: c3, wrt: c1}
  - {op: query, kind: twist, point: c1, body: C, ref_body: A, coord: c1}
""",
    "names_and_numbers.yaml": """ops:
  - {op: body, name: ""}
  - {op: body, name: "tab\\there"}
  - {op: frame, name: f}
  - {op: pose, of: a, body: A, wrt: b, ref_body: B, position: [.nan, 0, 0]}
  - {op: pose, of: a, body: A, wrt: b, ref_body: B, position: [0, -.inf, 0]}
  - {op: pose, of: a, body: A, wrt: b, ref_body: B, rotation: {quaternion: [1, 1, 0, 0]}}
  - {op: pose, of: a, body: A, wrt: b, ref_body: B, rotation: {matrix: [[-1, 0, 0], [0, 1, 0], [0, 0, 1]]}}
  - {op: pose, of: a, body: A, wrt: b, ref_body: B, rotation: {rpy: [.nan, 0, 0]}}
  - {op: query, kind: pose, of: a, wrt: b}
""",
    "aliases.yaml": """anchors:
ops:
  - &p {op: pose, of: a, body: A, wrt: b, ref_body: B, position: &v [1, 2, 3]}
  - *p
  - {op: twist, point: a, ref_body: B, coord: a, linear: *v}
""",
    "bad_yaml.yaml": "ops: [ {op: body, name: A}\n",
    "bad_unknown_op.yaml": "ops:\n  - {op: teleport, name: A}\n",
    "bad_missing_field.yaml": "ops:\n  - {op: twist, point: a, ref_body: B}\n",
    "bad_array_length.yaml": "ops:\n  - {op: pose, of: a, body: A, wrt: b, ref_body: B, position: [1, 2]}\n",
    "bad_two_rotations.yaml": "ops:\n  - {op: pose, of: a, body: A, wrt: b, ref_body: B, rotation: {rpy: [0, 0, 0], quaternion: [1, 0, 0, 0]}}\n",
    "bad_representation.yaml": "representation: euler\nops: []\n",
    "bad_deep_nesting.yaml": "ops: " + "[" * 200 + "]" * 200 + "\n",
    # Four levels of 64 aliases: 64^4 copies of a 17-unit scalar, far above the 32 MiB expanded
    # limit, in under 1 KB; refused at an alias of the last level.
    "bad_alias_bomb.yaml": "a: &a [" + "xxxxxxxxxxxxxxxx," * 16 + "]\nb: &b [" + "*a," * 64 +
                           "]\nc: &c [" + "*b," * 64 + "]\nd: &d [" + "*c," * 64 + "]\nops: [" +
                           "*d," * 64 + "]\n",
    # Time: stamps, every query time field, the errors (docs/scene-script.md, Time).
    "time.yaml": """time: {interpolation: screw, duplicate_stamp: replace, window: 10}
ops:
  - {op: pose, of: o, body: O, wrt: w, ref_body: W, stamp: 1}
  - {op: pose, of: o, wrt: w, position: [2, 0, 0], rotation: {rpy: [0, 0, 1.5707963267948966]}, stamp: 2}
  - {op: twist, point: o, ref_body: W, coord: o, linear: [1.57, -1.57, 0], angular: [0, 0, 1.57], stamp: 1}
  - {op: twist, point: o, ref_body: W, coord: o, linear: [1.57, -1.57, 0], angular: [0, 0, 1.57], stamp: 2}
  - {op: pose, of: s, body: S, wrt: w, position: [0, 0, 1], stamp: 1}
  - {op: pose, of: s, wrt: w, position: [0, 0, 2], stamp: 1.25}
  - {op: query, kind: pose, of: o, wrt: w, at: 1.5}
  - {op: query, kind: twist, point: o, ref_body: W, coord: o, at: 1.5, source: poses}
  - {op: query, kind: pose, of: o, wrt: w, at: 2.5, max_extrapolation: 0.5}
  - {op: query, kind: pose, of: o, wrt: s, at: latest_common}
  - {op: query, kind: position, of: o, wrt: s, at: 1.5, ref_at: 1.125, fixed: w}
  - {op: query, kind: angular_velocity, body: O, ref_body: W, coord: w, not_before: 1.5}
  - {op: joint, name: j, type: revolute, parent: base, parent_body: Base, child: l1, child_body: L1, axis: [0, 0, 1], lower: -3, upper: 3}
  - {op: joints, positions: {j: 0.2}, velocities: {j: 0.5}, stamp: 1}
  - {op: joints, positions: {j: 0.6}, stamp: 2}
  - {op: joints, positions: {j: 0.1}}
  - {op: query, kind: orientation, of: l1, wrt: base, at: 1.5}
""",
    "time_errors.yaml": """time: {window: 0.5, duplicate_stamp: reject, interpolation: linear}
ops:
  - {op: pose, of: o, body: O, wrt: w, ref_body: W, stamp: 1}
  - {op: pose, of: o, wrt: w, position: [1, 0, 0], stamp: 2}
  - {op: pose, of: o, wrt: w, stamp: 1.4}
  - {op: pose, of: o, wrt: w, position: [1, 0, 1], stamp: 2}
  - {op: pose, of: o, wrt: w, position: [5, 0, 0]}
  - {op: pose, of: o, wrt: w, stamp: .nan}
  - {op: twist, point: o, ref_body: W, coord: o, stamp: 1e10}
  - {op: query, kind: pose, of: o, wrt: w, at: .inf}
  - {op: query, kind: pose, of: o, wrt: w, at: 1.75, max_extrapolation: -0.001}
  - {op: query, kind: pose, of: o, wrt: w, at: 1.75, ref_at: 1.8, fixed: nowhere}
""",
    "bad_time_field.yaml": "ops:\n  - {op: body, name: B, stamp: 1}\n",
    "bad_time_window.yaml": "time: {window: -1}\nops: []\n",
    "bad_time_travel.yaml": "ops:\n  - {op: query, kind: pose, of: a, wrt: b, at: latest_common, ref_at: 1, fixed: b}\n",
    # Aliased ops within the limit: each alias is one op, read as a copy.
    "alias_ops.yaml": "ops: [&o {op: body, name: B}, *o, *o, *o, &f {op: frame, name: f, body: B}, *f]\n",
}


# yaml_tree_fuzzer: byte 0 even = the script limits, odd = tiny limits (8 levels, 64 nodes,
# 300 expanded bytes). Every YAML feature the tree handles, and every way it refuses a text.
YAML_SEEDS = {
    "block.yaml": (0, b"ops:\n  - op: body\n    name: B\n  - op: frame\n    name: f\n    body:\n"),
    "flow.yaml": (0, b"{a: [1, -2.5e3, .inf, .nan, ~, null, true], 'b c': \"d\", e: {}, f: []}\n"),
    "scalars.yaml": (0, b"a: |\n  two\n  lines\nb: >\n  folded\n  text\nc: 'it''s'\nd: \"tab\\there\"\n"),
    "escapes.yaml": (0, b'[\"\\N\", \"\\_\", \"\\L\", \"\\P\", \"\\u00A0\", \"\\x85\", \"\\U0001F600\", \"\\0\", \"\\e\", \"x\\_y\\Nz\"]\n'),
    "bad_surrogate.yaml": (0, b'a: \"\\uD800\"\n'),
    "bad_above_max.yaml": (0, b'a: \"\\U00110000\"\n'),
    "tags.yaml": (0, b"[!!int 1, !!float 2, !!str 3, !custom x, ! y]\n"),
    "complex_keys.yaml": (0, b"? [a, b]\n: c\n? {d: e}\n: f\ng:\n"),
    "duplicate_keys.yaml": (0, b"{a: 1, a: 2}\n"),
    "anchors.yaml": (0, b"base: &b {x: &v [1, 2, 3]}\nuse: [*b, *v, *b]\nscalar: &s text\nagain: *s\n"),
    "alias_cycle.yaml": (0, b"a: &a [1, *a]\n"),
    "unknown_alias.yaml": (0, b"a: *nowhere\n"),
    "alias_bomb_tiny.yaml": (1, b"a: &a [x, x, x, x]\nb: &b [*a, *a, *a, *a]\nc: &c [*b, *b, *b, *b]\nd: [*c, *c]\n"),
    "alias_bomb.yaml": (0, b"a: &a [" + b"xxxxxxxxxxxxxxxx," * 200 + b"]\nb: &b [" + b"*a," * 200 + b"]\nc: [" + b"*b," * 200 + b"]\n"),
    "deep_tiny.yaml": (1, b"[" * 9 + b"]" * 9),
    "deep.yaml": (0, b"[" * 70 + b"]" * 70),
    "many_nodes_tiny.yaml": (1, b"[" + b"1," * 70 + b"]"),
    "two_documents.yaml": (0, b"a: 1\n---\nb: 2\n"),
    "document_end.yaml": (0, b"%YAML 1.2\n---\na: 1\n...\n"),
    "empty.yaml": (0, b""),
    "comment_only.yaml": (0, b"# nothing\n"),
    "invalid_utf8.yaml": (0, b"a: caf\xe9\n"),
    "nul.yaml": (0, b"a: b\x00c\n"),
    "leading_nul.yaml": (0, b"\x00a\x00:\x00 \x00b\x00\n"),
    "utf16_bom.yaml": (0, b"\xff\xfea\x00:\x00"),
    "utf8_bom.yaml": (0, b"\xef\xbb\xbfa: b\n"),
    "broken.yaml": (0, b"a: [1, 2\nb: }\n"),
}


def main():
    ops_dir = os.path.join(HERE, "corpus", "scene_ops_fuzzer")
    script_dir = os.path.join(HERE, "corpus", "scene_script_fuzzer")
    os.makedirs(ops_dir, exist_ok=True)
    os.makedirs(script_dir, exist_ok=True)
    for name, data in scene_ops_seeds().items():
        with open(os.path.join(ops_dir, "seed_" + name), "wb") as f:
            f.write(data)
    for name, text in SCRIPTS.items():
        with open(os.path.join(script_dir, "seed_" + name), "wb") as f:
            f.write(b"\n" + text.encode())  # byte 0 even: raw mode
    yaml_dir = os.path.join(HERE, "corpus", "yaml_tree_fuzzer")
    os.makedirs(yaml_dir, exist_ok=True)
    for name, (mode, text) in YAML_SEEDS.items():
        with open(os.path.join(yaml_dir, "seed_" + name), "wb") as f:
            f.write(bytes([mode]) + text)
    # Structured mode (byte 0 odd): a few fixed byte strings.
    for i, data in enumerate([bytes([1, 0, 23]) + bytes(range(0, 250, 3)),
                              bytes([3, 1, 20]) + bytes(range(250, 0, -7)) * 2,
                              bytes([5, 0, 12]) + bytes([2, 0, 1, 2, 1, 3, 2, 1, 0, 1, 0, 7] * 6),
                              # with a time map and many time decisions (stamps, at, travel)
                              bytes([7, 0, 0, 1, 0, 1, 22]) + bytes([2, 3, 0, 1, 2, 3, 4, 0, 1, 0, 6, 0, 1, 2, 0, 3] * 8),
                              bytes([9, 1, 0, 0, 1, 0, 23]) + bytes(range(7, 250, 5)) * 2]):
        with open(os.path.join(script_dir, "seed_structured_%d" % i), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
