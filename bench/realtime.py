#!/usr/bin/python3
"""Does every shipped scene run in real time in the node, at its own configuration?

For each scene: starts a ROS master on a free port and the node headless (demo.launch,
rviz:=false), lets it run WARMUP s, then for DURATION s records cloth/state (each frame's
wall time) and the node's /diagnostics, and reports simulated seconds per wall second, the
frame's wall time (mean, p90, max) against the 1/60 s budget, and the diagnostics' last word.
Writes bench/results/realtime.md (and prints it). Usage: bench/realtime.py [scene ...]
"""
import os
import json
import socket
import subprocess
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from cloth_sim.msg import ClothState

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["hanging", "drape", "trampoline", "gravity_well", "tablecloth", "stiff", "peer_cloth",
          "fold", "pile", "grasp_demo"]
WARMUP, DURATION = 3.0, 10.0
LEVELS = {0: "OK", 1: "WARN", 2: "ERROR", 3: "STALE"}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def machine():
    """'<CPU model>, <n> cores' as lscpu and the kernel give it."""
    model = "unknown CPU"
    for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
        if line.startswith("Model name:"):
            model = line.split(":", 1)[1].strip()
    return "%s, %d cores" % (model, os.cpu_count())


def measure(scene):
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % free_port())
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    port = env["ROS_MASTER_URI"].rsplit(":", 1)[1]
    launch = subprocess.Popen(
        ["roslaunch", "-p", port, "cloth_sim", "demo.launch", "scene:=" + scene, "rviz:=false"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        states, diagnostics = [], []
        deadline = time.time() + 30
        while True:  # the master takes a moment to come up
            try:
                rospy.init_node("realtime_probe", anonymous=True, disable_signals=True)
                break
            except Exception:
                if time.time() > deadline:
                    raise
                time.sleep(0.5)
        recording = [False]

        def on_state(msg):
            if recording[0]:
                states.append((time.time(), msg.sim_time, msg.step_wall_time, msg.status))

        def on_diag(msg):
            for status in msg.status:
                if "step" in status.name.lower() or "cloth" in status.name.lower():
                    diagnostics.append((status.level, status.message))

        rospy.Subscriber("cloth/state", ClothState, on_state, queue_size=100)
        rospy.Subscriber("/diagnostics", DiagnosticArray, on_diag, queue_size=10)
        time.sleep(WARMUP)
        recording[0] = True
        time.sleep(DURATION)
        recording[0] = False
    finally:
        launch.terminate()
        launch.wait()
    if len(states) < 2:
        return [scene, "no state received", "", "", "", "", ""]
    walls = sorted(1e3 * s[2] for s in states)
    rate = (states[-1][1] - states[0][1]) / (states[-1][0] - states[0][0])
    over = sum(1 for w in walls if w > 1e3 / 60)
    rolled = sum(1 for s in states if s[3] != "ok")
    level, message = diagnostics[-1] if diagnostics else (3, "no diagnostics")
    return [scene, "%.2f" % rate,
            "%.2f / %.2f / %.2f" % (sum(walls) / len(walls), walls[int(0.9 * (len(walls) - 1))],
                                    walls[-1]),
            "%d of %d" % (over, len(walls)), str(rolled), LEVELS.get(level, str(level)), message]


def main():
    if sys.argv[1:2] == ["--row"]:
        print(json.dumps(measure(sys.argv[2])))
        return
    scenes = sys.argv[1:] or SCENES
    load = open("/proc/loadavg").read().split()[:3]
    rows = []
    for scene in scenes:  # one process per scene: rospy joins one master per process
        print("[realtime] %s ..." % scene, flush=True)
        out = subprocess.run([sys.executable, os.path.abspath(__file__), "--row", scene],
                             capture_output=True, text=True, check=False).stdout
        lines = [line for line in out.splitlines() if line.startswith("[")]
        rows.append(json.loads(lines[-1]) if lines else [scene, "failed", "", "", "", "", ""])
    head = ["scene", "sim s per wall s", "frame wall ms (mean / p90 / max)",
            "frames over 16.7 ms", "rolled back", "diagnostics", "its message"]
    lines = ["# Real time in the node", "",
             "Each shipped scene at its own configuration, node headless, %g s after %g s of "
             "warm-up, on %s; load before: %s, after: %s (`bench/realtime.py`)." %
             (DURATION, WARMUP, machine(), " ".join(load),
              " ".join(open("/proc/loadavg").read().split()[:3])),
             "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    text = "\n".join(lines) + "\n"
    print(text)
    with open(os.path.join(REPO, "bench", "results", "realtime.md"), "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
