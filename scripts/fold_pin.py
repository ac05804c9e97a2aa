#!/usr/bin/python3
"""Folds the `fold` scene's cloth in a running node: carries pin 0 (the corner at (-0.5, 0.5))
in an arc over the cloth to near the opposite corner in 4 s through cloth/pin_move, then holds
it there; with --loop, resets the cloth (cloth/reset) after the hold and folds again, until
Ctrl-C (`make run SCENE=fold` starts it so). Used for docs/images/fold.png:

    ROS_PORT=11734 scripts/screenshot.sh fold 11 &
    ROS_MASTER_URI=http://localhost:11734 scripts/fold_pin.py   # with the workspace sourced
"""
import math
import sys
import time

import rospy
from cloth_sim.msg import PinMove
from std_srvs.srv import Trigger

START, END = (-0.5, 0.5), (0.42, -0.42)  # m, in world
DURATION, HOLD, LIFT = 4.0, 12.0, 0.45   # s, s, m (the arc's height)


def fold(pub):
    """One fold: the arc in DURATION s, then HOLD s holding the pin there."""
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


def main():
    rospy.init_node("fold_pin", anonymous=True)
    loop = "--loop" in rospy.myargv(sys.argv)[1:]
    pub = rospy.Publisher("cloth/pin_move", PinMove, queue_size=10)
    time.sleep(2.5)  # let the node come up and subscribe
    fold(pub)
    while loop and not rospy.is_shutdown():
        rospy.wait_for_service("cloth/reset")
        rospy.loginfo("fold_pin: again: %s", rospy.ServiceProxy("cloth/reset", Trigger)().message)
        time.sleep(1.0)
        fold(pub)


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
