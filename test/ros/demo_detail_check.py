#!/usr/bin/python3
"""rostest node for demo.test: with an example set loaded, the demo's enrichment adds detail wherever the tool
touches the slab. Watches one full cycle of the demo's taps (4 taps every 3 s) from the first contact and
passes when at least 90 % of the states with the tool in contact (the scene's `contacts`) have a status that
reports touched vertices and a confidence above zero and an enriched state that differs from its coarse input,
by at most 1 cm, while every output stays finite."""
import sys
import unittest

import numpy as np
import rospy
import rostest
from deformation_enrichment.msg import EnrichmentStatus, ToolContactArray
from sensor_msgs.msg import PointCloud2

CYCLE = rospy.Duration(12.0)  # demo.launch: 4 held-out taps, one every 3 s
SHARE = 0.9


def xyz(cloud):
    points = np.frombuffer(cloud.data, dtype=np.uint8).reshape(cloud.height * cloud.width, cloud.point_step)
    offsets = {f.name: f.offset for f in cloud.fields}
    return np.stack([points[:, offsets[a]:offsets[a] + 4].copy().view(np.float32)[:, 0] for a in "xyz"], axis=1)


class DemoAddsDetail(unittest.TestCase):
    def test_detail_appears_at_every_contact(self):
        inputs, contact_stamps, detail_stamps, changed, non_finite = {}, set(), set(), {}, []

        def on_input(cloud):
            inputs[cloud.header.stamp] = xyz(cloud)
            while len(inputs) > 200:
                inputs.pop(next(iter(inputs)))

        def on_contacts(contacts):
            if contacts.contacts:
                contact_stamps.add(contacts.header.stamp)

        def on_status(status):
            if status.tool_ids and status.vertices_touched > 0 and status.confidence > 0.0:
                detail_stamps.add(status.header.stamp)

        def on_output(cloud):
            out = xyz(cloud)
            if not np.isfinite(out).all():
                non_finite.append(cloud.header.stamp)
            coarse = inputs.get(cloud.header.stamp)
            if coarse is not None:
                changed[cloud.header.stamp] = float(np.abs(out - coarse).max())

        rospy.Subscriber("mesh_state", PointCloud2, on_input, queue_size=20)
        rospy.Subscriber("contacts", ToolContactArray, on_contacts, queue_size=20)
        rospy.Subscriber("enrichment/status", EnrichmentStatus, on_status, queue_size=20)
        rospy.Subscriber("enriched_mesh_state", PointCloud2, on_output, queue_size=20)
        deadline = rospy.Time.now() + rospy.Duration(rospy.get_param("~time_limit", 60.0))
        while not rospy.is_shutdown() and rospy.Time.now() < deadline and not contact_stamps:
            rospy.sleep(0.1)
        self.assertTrue(contact_stamps, "the tool never touched the slab")
        start = min(contact_stamps)
        while not rospy.is_shutdown() and rospy.Time.now() < min(deadline, start + CYCLE + rospy.Duration(1.0)):
            rospy.sleep(0.1)
        self.assertEqual(non_finite, [], "non-finite enriched states")
        window = [t for t in contact_stamps if t <= start + CYCLE and t in changed]
        detailed = [t for t in window if t in detail_stamps and changed[t] > 0.0]
        print(f"{len(detailed)} of {len(window)} states in contact got detail")
        self.assertGreater(len(window), 100, f"only {len(window)} states in contact in one cycle of taps")
        self.assertGreaterEqual(len(detailed), SHARE * len(window),
                                f"{len(detailed)} of {len(window)} states in contact got detail")
        # The slab's detail is sub-millimetre to millimetres; a centimetre would be a broken stamp.
        self.assertLess(max(changed[t] for t in detailed), 0.01)


if __name__ == "__main__":
    rospy.init_node("demo_detail_check")
    rostest.rosrun("deformation_enrichment", "demo_detail_check", DemoAddsDetail, sys.argv)
