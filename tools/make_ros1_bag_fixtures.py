#!/usr/bin/python3
"""Writes the ROS 1 bag fixtures of tests/data/bags/fixtures/ with ROS's own writer (Debian's
python3-rosbag, not dynid's): /usr/bin/python3 tools/make_ros1_bag_fixtures.py [OUT_DIR]
(apt install python3-rosbag python3-sensor-msgs python3-roslz4; scripts/install-deps.sh does).

joint_states_{none,bz2,lz4}.bag: 200 sensor_msgs/JointState messages on /joint_states at 1 kHz,
header stamps from 1700000000 s, joints named joint2, joint1, gripper in that order (the robot's
order differs, and one joint is not the robot's), and a std_msgs/String on /chatter every 50th
message. Joint j (1-based name number; gripper 3) at message k:
  position = 0.1 j sin(0.01 k), velocity = 0.001 j cos(0.01 k), effort = 2 j + 0.5 k.
tests/data/bags/ros1_bag_test.cpp checks these values."""
import math
import os
import sys

import rosbag
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(__file__), "..", "tests", "data", "bags", "fixtures")
numbers = {"joint2": 2, "joint1": 1, "gripper": 3}
for compression in ("none", "bz2", "lz4"):
    path = os.path.join(out, f"joint_states_{compression}.bag")
    with rosbag.Bag(path, "w", compression=compression) as bag:
        for k in range(200):
            stamp = rospy.Time(1700000000, k * 1000000)
            m = JointState()
            m.header.stamp = stamp
            m.header.frame_id = "base_link"
            m.name = list(numbers)
            m.position = [0.1 * j * math.sin(0.01 * k) for j in numbers.values()]
            m.velocity = [0.001 * j * math.cos(0.01 * k) for j in numbers.values()]
            m.effort = [2.0 * j + 0.5 * k for j in numbers.values()]
            bag.write("/joint_states", m, stamp)
            if k % 50 == 0:
                bag.write("/chatter", String(data=f"message {k}"), stamp)
    print(path, os.path.getsize(path), "bytes")
