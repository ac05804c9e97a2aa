#!/usr/bin/python3
"""A scripted gripper for cloth_sim: publishes a tf frame along waypoints and grasps/releases.

Reads ~waypoints (a YAML file, see config/grasp_demo_waypoints.yaml). Between two waypoints the
frame moves on a straight line with a smoothstep profile (zero speed at each waypoint, so the
cloth is not jerked). Each transform is published once, on a fixed grid of ~sample_period, up to
~lookahead ahead of the current ROS time, so cloth_sim_node (which looks the frame up at every
substep's simulated time) always has the two samples around it; with /use_sim_time it follows
the simulated time. At a waypoint's time its action runs: cloth/grasp (the frame, a radius) or
cloth/release (the last grasp).
"""
import math
import sys

import rospy
import tf2_ros
import yaml
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

from cloth_sim.srv import AddGrasp, AddGraspRequest, ReleaseGrasp
from std_srvs.srv import Trigger


def load_waypoints(path):
    with open(path) as f:
        doc = yaml.safe_load(f)
    points = doc.get("waypoints") or []
    if len(points) < 2:
        raise ValueError("%s: 'waypoints' needs at least two entries" % path)
    last = -math.inf
    for i, w in enumerate(points):
        t, p = w.get("t"), w.get("position")
        if not isinstance(t, (int, float)) or not math.isfinite(t) or t <= last:
            raise ValueError("%s: waypoints[%d].t = %r must be a number above the previous one" % (path, i, t))
        if not (isinstance(p, list) and len(p) == 3 and all(isinstance(c, (int, float)) and math.isfinite(c) for c in p)):
            raise ValueError("%s: waypoints[%d].position = %r must be [x, y, z] in m" % (path, i, p))
        if w.get("action") not in (None, "grasp", "release"):
            raise ValueError("%s: waypoints[%d].action = %r must be grasp or release" % (path, i, w.get("action")))
        last = t
    return doc.get("frame_id", "world"), doc.get("child_frame_id", "gripper"), points


def position_at(points, t):
    """The gripper's position (m) at t s: smoothstep between the two waypoints around t."""
    if t <= points[0]["t"]:
        return points[0]["position"]
    for a, b in zip(points, points[1:]):
        if t <= b["t"]:
            u = (t - a["t"]) / (b["t"] - a["t"])
            s = u * u * (3.0 - 2.0 * u)
            return [pa + s * (pb - pa) for pa, pb in zip(a["position"], b["position"])]
    return points[-1]["position"]


def main():
    rospy.init_node("scripted_gripper")
    frame, child, points = load_waypoints(rospy.get_param("~waypoints"))
    period = float(rospy.get_param("~sample_period", 1.0 / 120.0))
    lookahead = float(rospy.get_param("~lookahead", 0.1))
    # ~loop: s to wait after the last waypoint before cloth/reset and the script again (0: once).
    # ~start_delay: s (simulated) before the first waypoint, so a viewer has time to come up.
    loop = float(rospy.get_param("~loop", 0.0))
    start_delay = float(rospy.get_param("~start_delay", 0.0))
    pub = rospy.Publisher("/tf", TFMessage, queue_size=100)
    rospy.wait_for_service("cloth/grasp")
    grasp = rospy.ServiceProxy("cloth/grasp", AddGrasp)
    release = rospy.ServiceProxy("cloth/release", ReleaseGrasp)
    reset = rospy.ServiceProxy("cloth/reset", Trigger)
    while not rospy.is_shutdown() and rospy.Time.now().is_zero():
        rospy.sleep(0.01)  # with /use_sim_time: wait for the first /clock
    if start_delay > 0.0:
        rospy.sleep(start_delay)
    start = rospy.Time.now()
    next_sample = 0  # index of the next sample on the grid k * period
    actions = [w for w in points if w.get("action")]
    grasp_id = None
    rate = rospy.Rate(200)
    while not rospy.is_shutdown():
        now = (rospy.Time.now() - start).to_sec()
        msg = TFMessage()
        while next_sample * period <= now + lookahead:
            t = next_sample * period
            tf = TransformStamped()
            tf.header.frame_id = frame
            tf.header.stamp = start + rospy.Duration.from_sec(t)
            tf.child_frame_id = child
            tf.transform.translation.x, tf.transform.translation.y, tf.transform.translation.z = position_at(points, t)
            tf.transform.rotation.w = 1.0
            msg.transforms.append(tf)
            next_sample += 1
        if msg.transforms:
            pub.publish(msg)
        while actions and actions[0]["t"] <= now:
            w = actions.pop(0)
            if w["action"] == "grasp":
                req = AddGraspRequest(frame_id=child, radius=float(w.get("radius", 0.0)))
                res = grasp(req)
                rospy.loginfo("scripted_gripper: t = %.2f s: grasp: %s", now, res.message)
                grasp_id = res.id if res.success else None
            elif grasp_id is not None:
                res = release(grasp_id)
                rospy.loginfo("scripted_gripper: t = %.2f s: release: %s", now, res.message)
                grasp_id = None
        if not actions and now > points[-1]["t"] + lookahead + loop:
            if loop <= 0.0:
                rospy.loginfo("scripted_gripper: done")
                rospy.spin()  # keep the last transforms in the buffers of late listeners
                return
            # Again from the start: the cloth back to the scene's initial state, the same script.
            rospy.loginfo("scripted_gripper: done; again: %s", reset().message)
            start = rospy.Time.now()
            next_sample = 0
            actions = [w for w in points if w.get("action")]
            grasp_id = None
        rate.sleep()


if __name__ == "__main__":
    try:
        main()
    except (ValueError, OSError) as e:
        sys.stderr.write("scripted_gripper: %s\n" % e)
        sys.exit(1)
    except rospy.ROSInterruptException:
        pass
