#!/usr/bin/python3
"""rostest node for demo.test: with an example set loaded, the demo's enrichment adds detail where the tool
touches the slab. Passes when, within the time limit, states with the tool in contact arrive whose status
reports touched vertices and a confidence above zero, and whose enriched positions differ from the coarse
input of the same stamp (while every output stays finite)."""
import sys
import unittest

import numpy as np
import rospy
import rostest
from deformation_enrichment.msg import EnrichmentStatus
from sensor_msgs.msg import PointCloud2

WANTED = 10  # enriched states with detail, at 30 Hz a third of a second of contact


def xyz(cloud):
    points = np.frombuffer(cloud.data, dtype=np.uint8).reshape(cloud.height * cloud.width, cloud.point_step)
    offsets = {f.name: f.offset for f in cloud.fields}
    return np.stack([points[:, offsets[a]:offsets[a] + 4].copy().view(np.float32)[:, 0] for a in "xyz"], axis=1)


class DemoAddsDetail(unittest.TestCase):
    def test_detail_appears_at_the_contact(self):
        inputs, detail_stamps, changed, non_finite = {}, set(), [], []

        def on_input(cloud):
            inputs[cloud.header.stamp] = xyz(cloud)
            while len(inputs) > 200:
                inputs.pop(next(iter(inputs)))

        def on_status(status):
            if status.tool_ids and status.vertices_touched > 0 and status.confidence > 0.0:
                detail_stamps.add(status.header.stamp)

        def on_output(cloud):
            out = xyz(cloud)
            if not np.isfinite(out).all():
                non_finite.append(cloud.header.stamp)
            coarse = inputs.get(cloud.header.stamp)
            if cloud.header.stamp in detail_stamps and coarse is not None:
                changed.append(float(np.abs(out - coarse).max()))

        rospy.Subscriber("mesh_state", PointCloud2, on_input, queue_size=20)
        rospy.Subscriber("enrichment/status", EnrichmentStatus, on_status, queue_size=20)
        rospy.Subscriber("enriched_mesh_state", PointCloud2, on_output, queue_size=20)
        deadline = rospy.Time.now() + rospy.Duration(rospy.get_param("~time_limit", 60.0))
        while not rospy.is_shutdown() and rospy.Time.now() < deadline and len([c for c in changed if c > 0]) < WANTED:
            rospy.sleep(0.1)
        self.assertEqual(non_finite, [], "non-finite enriched states")
        moved = [c for c in changed if c > 0]
        self.assertGreaterEqual(len(moved), WANTED,
                                f"only {len(moved)} enriched states differ from their coarse input "
                                f"({len(detail_stamps)} statuses reported detail)")
        # The slab's detail is sub-millimetre to millimetres; a metre would be a broken stamp.
        self.assertLess(max(moved), 0.01)


if __name__ == "__main__":
    rospy.init_node("demo_detail_check")
    rostest.rosrun("deformation_enrichment", "demo_detail_check", DemoAddsDetail, sys.argv)
