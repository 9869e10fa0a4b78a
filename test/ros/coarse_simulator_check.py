#!/usr/bin/python3
"""rostest node for coarse_simulator.test: examples made against another coarse simulator over ROS
(docs/coarse_simulator.md), with Bullet's deformable body (bullet_coarse_sim_node, started by the launch file).

acquisition_driver records the slab's first N automatic-plan interactions and M random held-out ones (a seed
used for no setting) from Bullet; de_make_examples --coarse-bag makes the set; de_evaluate --coarse-bag scores
it on the held-out Bullet states against the fine truth, beside the package's own-SNH set of the same
interactions (the first N of the nested slab set that ctest acquired, DE_TEST_SLAB_AUTO_SET) on the very same
Bullet states. Passes when the Bullet set's mean ratio is at most its bound and below the own set's.

Parameters (~): examples (12), held_out (8), seed, bound (0.9).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest

PACKAGE = "deformation_enrichment"


def run(command, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        raise AssertionError(f"{' '.join(command)} exited {result.returncode}:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}")
    return result


def tool(name):
    prefix = run(["rosrun", "--prefix", "echo", PACKAGE, name]).stdout.strip()
    return prefix if prefix.endswith(name) else name


class ExamplesFromAnotherSimulator(unittest.TestCase):
    def test_bullet_set_beats_the_own_set_on_bullet_states(self):
        examples, held_out = rospy.get_param("~examples", 12), rospy.get_param("~held_out", 8)
        seed, bound = rospy.get_param("~seed", 2718), rospy.get_param("~bound", 0.9)
        own_set = os.environ["DE_TEST_SLAB_AUTO_SET"]
        work = tempfile.mkdtemp(prefix="de_coarse_simulator_")
        try:
            train, test = os.path.join(work, "train.bag"), os.path.join(work, "held_out.bag")
            driver = ["rosrun", PACKAGE, "acquisition_driver", "_scene:=slab"]
            log = run(driver + [f"_examples:={examples}", f"_bag:={train}"]).stdout
            # One node name for both runs, as a user types them: the first run's ~examples must not stay.
            self.assertFalse(rospy.has_param("/acquisition_driver/examples"))
            run(driver + [f"_held_out:={held_out}", f"_seed:={seed}", f"_bag:={test}"])
            print(log[-1500:])
            bullet_set = os.path.join(work, "bullet_set")
            run([tool("de_make_examples"), "--scene", "slab", "--coarse-bag", train, "--output", bullet_set])
            manifest = json.load(open(os.path.join(bullet_set, "manifest.json")))
            self.assertEqual(len(manifest["examples"]), examples)
            self.assertIn("bullet", manifest["provenance"]["coarse_simulator"])
            self.assertIn("train.bag", manifest["provenance"]["file_hashes"])
            # The own-SNH set's first N examples (its learning curve at N) are the Bullet set's interactions.
            score = json.loads(run([tool("de_evaluate"), "--scene", "slab", "--coarse-bag", test, "--examples", own_set,
                                    "--learning-curve", str(examples), "--also-examples", bullet_set]).stdout)
            own, bullet = score["learning_curve"][0], score["also"][0]
            print(f"{held_out} held-out Bullet interactions (seed {seed}): the set made against Bullet, mean ratio "
                  f"{bullet['mean_ratio']:.3f} (worst {bullet['worst_ratio']:.3f}, oracle {bullet['oracle_mean_ratio']:.3f}); "
                  f"the own-SNH set's first {examples}, "
                  f"{own['mean_ratio']:.3f} (worst {own['worst_ratio']:.3f})")
            self.assertGreater(bullet["oracle_mean_ratio"], 0.0)  # the bounds are computed for every row
            self.assertLessEqual(bullet["mean_ratio"], bound)
            self.assertLess(bullet["mean_ratio"], own["mean_ratio"])
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    rospy.init_node("coarse_simulator_check")
    rostest.rosrun(PACKAGE, "coarse_simulator_check", ExamplesFromAnotherSimulator, sys.argv)
