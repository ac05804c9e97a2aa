#!/usr/bin/python3
"""grasp_demo.test: the demo's gripper grasps a corner of the cloth, the cloth pulls on it, and
after the release the corner lies over the opposite one (the cloth is folded in half)."""
import math
import sys
import threading
import unittest

import rospy
import rostest

from cloth_sim.msg import ClothState
from sensor_msgs import point_cloud2
from sensor_msgs.msg import PointCloud2

WEIGHT = 0.6 * 0.6 * 0.2 * 9.81  # N: config/scenes/grasp_demo.yaml, 0.6 m square at 0.2 kg/m^2
SIDE = 20                        # particles along each side of the grid


class GraspDemo(unittest.TestCase):
    def test_gripper_folds_the_cloth_corner_to_corner(self):
        lock = threading.Lock()
        seen = {"max_force": 0.0, "vertex": None, "released_at": None, "last": None}

        def on_state(s):
            with lock:
                seen["last"] = s
                for g in s.grasps:
                    f = g.wrench.force
                    seen["max_force"] = max(seen["max_force"], math.sqrt(f.x ** 2 + f.y ** 2 + f.z ** 2))
                    seen["vertices"] = list(g.vertices)
                    seen["vertex"] = g.vertices[0]
                if seen["vertex"] is not None and not s.grasps and seen["released_at"] is None:
                    seen["released_at"] = s.sim_time

        rospy.Subscriber("cloth/state", ClothState, on_state)
        deadline = rospy.get_time() + 30.0  # simulated s: the script lasts 6.5
        while not rospy.is_shutdown() and rospy.get_time() < deadline:
            with lock:
                done = seen["released_at"] is not None and seen["last"].sim_time > seen["released_at"] + 1.5
            if done:
                break
            rospy.sleep(0.1)
        with lock:
            self.assertIsNotNone(seen["vertex"], "the gripper never grasped")
            self.assertIsNotNone(seen["released_at"], "the gripper never released")
            # Carried over the fold line, the grasp holds about half the cloth's weight.
            self.assertGreater(seen["max_force"], 0.3 * WEIGHT)
            held = seen["vertices"]
        cloud = rospy.wait_for_message("cloth/points", PointCloud2, timeout=10.0)
        points = list(point_cloud2.read_points(cloud, field_names=("x", "y", "z")))
        # Each held particle against the one diagonally opposite it (grid index row * SIDE + col):
        # the corner lands on the opposite corner.
        def gap(v):
            row, col = divmod(v, SIDE)
            opposite = (SIDE - 1 - row) * SIDE + (SIDE - 1 - col)
            return math.hypot(points[v][0] - points[opposite][0], points[v][1] - points[opposite][1]), opposite
        distance, vertex, opposite = min(gap(v) + (v,) for v in held)[0], None, None
        for v in held:
            if gap(v)[0] == distance:
                vertex, opposite = v, gap(v)[1]
        z = points[vertex][2]
        sys.stdout.write("[measured] grasped particle %d ends %.3f m (in x, y) from particle %d diagonally "
                         "opposite, z = %.3f m; max grasp force %.3f N (weight %.3f N)\n"
                         % (vertex, distance, opposite, z, seen["max_force"], WEIGHT))
        self.assertLess(distance, 0.15)  # folded corner to corner (the sheet is 0.85 m across)
        self.assertLess(z, 0.1)


if __name__ == "__main__":
    rospy.init_node("grasp_demo_test")
    rostest.rosrun("cloth_sim", "grasp_demo_test", GraspDemo)
