#!/usr/bin/python3
"""Gaz et al.'s real Panda log (../shared/data/panda_gaz2019) as a ROS 1 bag, written by ROS's own
writer (Debian's python3-rosbag; scripts/install-deps.sh installs it):
  /usr/bin/python3 tools/panda_log_as_ros1_bag.py LOG_DIR OUT.bag
sensor_msgs/JointState on /franka/joint_states, one message per logged sample: header stamps
1700000000 s plus the log's time (rounded to the nanosecond), joints named joint1..joint7 like
dynid's built-in Panda but published in another order with a finger joint beside them, position
and effort from the log (no velocity: the log's is not used by examples/panda/run.sh), lz4
chunks. tests/cli/command_prepare_test.cpp prepares and identifies it as the example does."""
import sys

import rosbag
import rospy
from sensor_msgs.msg import JointState

log, out = sys.argv[1], sys.argv[2]
n = 7


def numbers(name):
    with open(f"{log}/{name}") as f:
        return [float(x) for x in f.read().split()]


t, q, tau = (numbers(f"exciting_traj_{s}.txt") for s in ("time", "positions", "torques"))
order = [6, 0, 3, 1, 5, 2, 4]  # not the robot's order
with rosbag.Bag(out, "w", compression="lz4") as bag:
    for k, seconds in enumerate(t):
        ns = round(seconds * 1e9)
        stamp = rospy.Time(1700000000 + ns // 1000000000, ns % 1000000000)
        m = JointState()
        m.header.stamp = stamp
        m.name = [f"joint{i + 1}" for i in order] + ["finger_joint1"]
        m.position = [q[k * n + i] for i in order] + [0.04]
        m.effort = [tau[k * n + i] for i in order] + [0.0]
        bag.write("/franka/joint_states", m, stamp)
