#!/usr/bin/python3
"""rostest node for demo_simulator_truth.test: the fine truth that demo_scene_node publishes beside a simulator
that stamps its own states. Collects servo_cp and fine_state until 90 fine states (3 s of taps) have
arrived (the taps' fine paths are solved in the background first), and passes when every fine state has the stamp
of a command, the scene's display-vertex count of finite points, and some are dented (more than 1 mm from the
first one)."""
import sys
import unittest

import numpy as np
import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2

FINE_STATES = 90


def xyz(cloud):
    return np.array(list(point_cloud2.read_points(cloud, field_names=("x", "y", "z"))), dtype=np.float64).reshape(-1, 3)


class TruthOfEachCommand(unittest.TestCase):
    def test_fine_states_carry_command_stamps(self):
        commands, fine = set(), []
        rospy.Subscriber("servo_cp", PoseStamped, lambda pose: commands.add(pose.header.stamp))
        rospy.Subscriber("fine_state", PointCloud2, lambda cloud: fine.append((cloud.header.stamp, xyz(cloud))))
        deadline = rospy.Time.now() + rospy.Duration(90.0)
        while len(fine) < FINE_STATES and rospy.Time.now() < deadline and not rospy.is_shutdown():
            rospy.sleep(0.1)
        rospy.sleep(0.2)  # the commands of the last fine states
        self.assertGreaterEqual(len(fine), FINE_STATES, "too few fine states in 90 s")
        vertices = rospy.get_param("~display_vertices")
        first = fine[0][1]
        dented = 0
        for stamp, points in fine:
            self.assertIn(stamp, commands, "a fine state without the stamp of a servo_cp command")
            self.assertEqual(points.shape, (vertices, 3))
            self.assertTrue(np.isfinite(points).all())
            dented += np.linalg.norm(points - first, axis=1).max() > 1e-3
        self.assertGreater(dented, 0, "no fine state dented by the tool")


if __name__ == "__main__":
    rospy.init_node("demo_simulator_truth_check")
    rostest.rosrun("deformation_enrichment", "demo_simulator_truth", TruthOfEachCommand, sys.argv)
