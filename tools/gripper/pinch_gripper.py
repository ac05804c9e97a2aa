#!/usr/bin/python3
"""A scripted parallel-jaw gripper for cloth_sim's pinch demo (launch/pinch_demo.launch).

Publishes the tf frames of config/robots/parallel_gripper.urdf's links (gripper_palm,
finger_upper, finger_lower) in simulated time on a 1/480 s grid, the whole ~duration at once
(the node keeps ~tf_buffer_duration, 120 s, of it), then unpauses the node (started paused, so
that the fingers are there from its first frame): the node makes each finger's <collision> box
a collider on its frame (~robot_links) and looks the frames up at every substep. The lower jaw lies flush with the table top under the
cloth's overhanging edge; the upper jaw closes onto it (0.5 s to 1.5 s) to a 9 mm gap, which
squeezes the cloth 1 mm into the fingers' 5 mm margins; the gripper then lifts 0.5 m (2 s to 4 s)
and holds. No grasp service: friction alone (~robot_friction) holds the cloth.
"""
import time

import rospy
from geometry_msgs.msg import TransformStamped
from std_srvs.srv import Trigger
from tf2_msgs.msg import TFMessage

TOP, X, GAP, OPEN = 0.75, 0.33, 0.009, 0.08  # m: table top, fingers' x, closed gap, opening


def smooth(s):
    s = min(max(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def frames_at(t):
    """{link: (x, y, z)} at simulated time t (s): the same script as test/node/pinch_test.cpp."""
    lift = 0.5 * smooth((t - 2.0) / 2.0)
    lower = TOP + lift
    upper = lower + GAP + OPEN * (1.0 - smooth((t - 0.5) / 1.0))
    return {"finger_lower": (X, 0.0, lower), "finger_upper": (X, 0.0, upper),
            "gripper_palm": (X + 0.04, 0.0, 0.5 * (lower + upper))}


def main():
    rospy.init_node("pinch_gripper")
    period = 1.0 / 480.0
    duration = float(rospy.get_param("~duration", 10.0))
    pub = rospy.Publisher("/tf", TFMessage, queue_size=1, latch=True)
    rospy.wait_for_service("cloth/unpause")
    start = rospy.Time(1)  # the node's simulated time 0 (names::kSimTimeOriginSec)
    msg = TFMessage()
    for k in range(int(duration / period) + 1):
        t = k * period
        for link, (x, y, z) in frames_at(t).items():
            tf = TransformStamped()
            tf.header.frame_id = "world"
            tf.header.stamp = start + rospy.Duration.from_sec(t)
            tf.child_frame_id = link
            tf.transform.translation.x, tf.transform.translation.y = x, y
            tf.transform.translation.z = z
            tf.transform.rotation.w = 1.0
            msg.transforms.append(tf)
    while pub.get_num_connections() == 0 and not rospy.is_shutdown():
        time.sleep(0.05)  # wall time: the simulated clock stands still while the node is paused
    pub.publish(msg)
    time.sleep(1.0)  # into the node's buffer
    rospy.loginfo("pinch_gripper: %.0f s of finger frames published; %s", duration,
                  rospy.ServiceProxy("cloth/unpause", Trigger)().message)
    rospy.spin()


if __name__ == "__main__":
    try:
        main()
    except rospy.ROSInterruptException:
        pass
