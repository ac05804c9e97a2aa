#!/usr/bin/python3
"""Folds the `fold` scene's cloth in a running node: carries pin 0 (the corner at (-0.5, 0.5))
in an arc over the cloth to near the opposite corner in 4 s through cloth/pin_move, then holds
it there. Used for docs/images/fold.png:

    ROS_PORT=11734 scripts/screenshot.sh fold 11 &
    ROS_MASTER_URI=http://localhost:11734 scripts/fold_pin.py   # with the workspace sourced
"""
import math
import time

import rospy
from cloth_sim.msg import PinMove

START, END = (-0.5, 0.5), (0.42, -0.42)  # m, in world
DURATION, HOLD, LIFT = 4.0, 12.0, 0.45   # s, s, m (the arc's height)


def main():
    rospy.init_node("fold_pin", anonymous=True)
    pub = rospy.Publisher("cloth/pin_move", PinMove, queue_size=10)
    time.sleep(2.5)  # let the node come up and subscribe
    t0 = time.time()
    rate = rospy.Rate(60)
    while not rospy.is_shutdown() and time.time() - t0 < DURATION + HOLD:
        s = min(1.0, (time.time() - t0) / DURATION)
        move = PinMove()
        move.id = 0
        move.target.header.frame_id = "world"
        move.target.point.x = START[0] + s * (END[0] - START[0])
        move.target.point.y = START[1] + s * (END[1] - START[1])
        # Ends two thicknesses (the scene's 3 mm) above the ground: on top of the lower layer.
        move.target.point.z = LIFT * math.sin(math.pi * s) + 0.006 * s
        pub.publish(move)
        rate.sleep()


if __name__ == "__main__":
    main()
