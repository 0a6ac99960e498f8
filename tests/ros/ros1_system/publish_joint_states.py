#!/usr/bin/env python3
"""Publishes a known motion of arm6's six revolute joints on /joint_states (rospy).

Joint i follows q_i(t) = A_i sin(2 pi f_i (t - t0) + phi_i), with t the header stamp (ROS time
in seconds) and t0 the first stamp, at RATE Hz for DURATION seconds, then exits. The values are
checked against robot_state_publisher's /tf by semgraph's forward kinematics (ros1_system_test),
so any motion works; a sinusoid makes every joint move through both signs.

    publish_joint_states.py RATE DURATION
"""
import math
import sys

import rospy
from sensor_msgs.msg import JointState

JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint"]
AMPLITUDE = [1.2, 0.8, 1.5, 2.0, 1.0, 3.0]
FREQUENCY = [0.5, 0.7, 0.3, 1.1, 0.9, 0.4]
PHASE = [0.0, 0.4, 1.0, 2.0, 0.3, 1.7]


def main():
    rate_hz, duration_s = float(sys.argv[1]), float(sys.argv[2])
    rospy.init_node("semgraph_joint_state_publisher", anonymous=True, disable_signals=True)
    pub = rospy.Publisher("/joint_states", JointState, queue_size=100)
    # Wait until robot_state_publisher and the recorder are subscribed (both are started first).
    deadline = rospy.get_time() + 20.0
    while pub.get_num_connections() < 2 and rospy.get_time() < deadline:
        rospy.sleep(0.05)
    if pub.get_num_connections() < 2:
        sys.exit("publish_joint_states.py: %d subscribers after 20 s (expected robot_state_"
                 "publisher and rosbag record)" % pub.get_num_connections())
    rate = rospy.Rate(rate_hz)
    t0 = rospy.Time.now()
    n = int(rate_hz * duration_s)
    for _ in range(n):
        stamp = rospy.Time.now()
        dt = (stamp - t0).to_sec()
        msg = JointState()
        msg.header.stamp = stamp
        msg.name = JOINTS
        msg.position = [a * math.sin(2 * math.pi * f * dt + p)
                        for a, f, p in zip(AMPLITUDE, FREQUENCY, PHASE)]
        msg.velocity = [a * 2 * math.pi * f * math.cos(2 * math.pi * f * dt + p)
                        for a, f, p in zip(AMPLITUDE, FREQUENCY, PHASE)]
        pub.publish(msg)
        rate.sleep()
    print("published %d joint states" % n)


if __name__ == "__main__":
    main()
