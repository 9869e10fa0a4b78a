#!/usr/bin/python3
"""rostest node for acquisition_driver.test: the driver against fake_coarse_sim. Two slab interactions are
recorded whole (plan, simulator, begin/end markers, a command and a settled state per step); a second run
with the same bag records nothing more; a run with another plan for that bag exits 1 naming the problem; and
de_make_examples --coarse-bag makes a two-example set naming the simulator."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest

PACKAGE = "deformation_enrichment"


def driver(bag, *parameters):
    return subprocess.run(["rosrun", PACKAGE, "acquisition_driver", "_scene:=slab", f"_bag:={bag}", *parameters],
                          capture_output=True, text=True, timeout=120)


class DriverRecordsWholeInteractions(unittest.TestCase):
    def test_record_resume_refuse_and_make_a_set(self):
        work = tempfile.mkdtemp(prefix="de_acquisition_driver_")
        try:
            bag = os.path.join(work, "train.bag")
            first = driver(bag, "_examples:=2")
            self.assertEqual(first.returncode, 0, first.stdout + first.stderr)
            topics = {}
            for topic, message, _ in rosbag.Bag(bag).read_messages():
                topics.setdefault(topic, []).append(message)
            plan = [line for line in topics["/acquisition/plan"][0].data.splitlines() if not line.startswith("#")]
            self.assertEqual(len(plan), 2)
            self.assertEqual(topics["/acquisition/simulator"][0].data, "/fake_coarse_sim")
            self.assertEqual([m.data for m in topics["/acquisition/interaction"]], ["begin 0", "end 0", "begin 1", "end 1"])
            # Indent steps, drag steps and the touching step of the slab's solve settings, per interaction.
            self.assertEqual(len(topics["/servo_cp"]), len(topics["/mesh_state"]))
            self.assertGreaterEqual(len(topics["/servo_cp"]), 2 * 3)
            again = driver(bag, "_examples:=2")
            self.assertEqual(again.returncode, 0, again.stdout + again.stderr)
            self.assertIn("0 of 2 interactions to record", again.stdout)
            other = driver(bag, "_examples:=3")
            self.assertEqual(other.returncode, 1)
            self.assertIn("driven by another plan", other.stdout + other.stderr)
            made = subprocess.run(["rosrun", PACKAGE, "de_make_examples", "--scene", "slab", "--coarse-bag", bag,
                                   "--output", os.path.join(work, "set")], capture_output=True, text=True, timeout=300)
            self.assertEqual(made.returncode, 0, made.stderr)
            manifest = json.load(open(os.path.join(work, "set", "manifest.json")))
            self.assertEqual(len(manifest["examples"]), 2)
            self.assertEqual(manifest["provenance"]["coarse_simulator"], "/fake_coarse_sim")
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    rospy.init_node("acquisition_driver_check")
    rostest.rosrun(PACKAGE, "acquisition_driver_check", DriverRecordsWholeInteractions, sys.argv)
