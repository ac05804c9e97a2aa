#!/usr/bin/python3
"""pinch_demo.test: launch/pinch_demo.launch as users run it, headless. Its scripted gripper
(tools/gripper/pinch_gripper.py) publishes the URDF fingers' frames and unpauses the node; the
fingers close on the cloth's edge and lift it 0.5 m by friction alone (mu = 1): at 5 s of
simulated time the cloth's centre of mass hangs well above the table."""
import sys
import threading
import time
import unittest

import rospy
import rostest

from cloth_sim.msg import ClothState, FrameState

TOP = 0.75  # m: the table top of config/scenes/pinch.yaml


class PinchDemo(unittest.TestCase):
    def test_the_scripted_gripper_lifts_the_cloth(self):
        lock = threading.Lock()
        seen = {"frame": None, "colliders": None}

        def on_frame(f):
            with lock:
                if seen["frame"] is None and f.sim_time >= 5.0:
                    seen["frame"] = f

        def on_state(s):
            with lock:
                seen["colliders"] = sorted(c.name for c in s.colliders)

        rospy.Subscriber("cloth/frame_state", FrameState, on_frame, queue_size=200)
        rospy.Subscriber("cloth/state", ClothState, on_state)
        deadline = time.time() + 120.0  # wall s: the node runs at real time once unpaused
        while not rospy.is_shutdown() and time.time() < deadline:
            with lock:
                if seen["frame"] is not None:
                    break
            time.sleep(0.1)
        with lock:
            frame, colliders = seen["frame"], seen["colliders"]
        self.assertIsNotNone(frame, "the node never reached 5 s of simulated time")
        z = frame.positions[2::3]
        com = sum(z) / len(z)
        sys.stdout.write("[measured] pinch demo at %.3f s: the cloth's centre of mass %.3f m above "
                         "the table; colliders %s\n" % (frame.sim_time, com - TOP, colliders))
        self.assertEqual(colliders, ["finger_lower", "finger_upper", "table"])
        self.assertGreater(com - TOP, 0.2)  # the rostest pinch measures 0.345 m at 5 s


if __name__ == "__main__":
    rospy.init_node("pinch_demo_test")
    rostest.rosrun("cloth_sim", "pinch_demo_test", PinchDemo)
