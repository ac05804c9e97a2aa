#!/usr/bin/env python3
"""Writes an RViz config that frames one scene: rviz/demo.rviz with the orbit camera's focal
point and distance set from where the cloth is and goes (one fixed camera cut some scenes off
and showed others small).

    scripts/rviz_config.py SCENE_FILE OUT.rviz

The cloth's bounding box is taken after 0.5 s and after 3 s of simulation (cloth_sim_run
--positions), so a cloth that falls or swings stays in view; the camera looks at its centre
from far enough for its diagonal to fill about 80 % of RViz's 45-degree view.
"""
import math
import os
import re
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNNER = os.path.join(REPO, ".catkin_ws", "devel", "lib", "cloth_sim", "cloth_sim_run")
TEMPLATE = os.path.join(REPO, "rviz", "demo.rviz")
FOV = math.radians(45.0)  # RViz's orbit view, vertical
FILL = 0.8                # share of the view the cloth's diagonal takes


def positions(scene, duration, frame):
    """Particle positions after `duration` s with frames of `frame` s (rows of x, y, z)."""
    with tempfile.NamedTemporaryFile(suffix=".csv") as out:
        args = [RUNNER, "--scene", scene, "--duration", str(duration), "--quiet",
                "--positions", out.name]
        if frame:
            args += ["--dt", str(frame)]
        subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
        rows = open(out.name).read().split("\n")[1:]
        return [tuple(float(v) for v in r.split(",")[1:]) for r in rows if r]


def frame_view(points):
    """(focal point, distance) for the bounding box of `points`."""
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    center = [(a + b) / 2 for a, b in zip(lo, hi)]
    diagonal = math.dist(lo, hi)
    return center, max(0.5, diagonal / 2 / FILL / math.tan(FOV / 2))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    scene, out = sys.argv[1], sys.argv[2]
    points = positions(scene, 0.5, None) + positions(scene, 3.0, None)
    center, distance = frame_view(points)
    text = open(TEMPLATE).read()
    text = re.sub(r"(\n      Distance: )[-0-9.e]+", r"\g<1>%.3f" % distance, text, count=1)
    focal = "\n      Focal Point:\n        X: %.3f\n        Y: %.3f\n        Z: %.3f" % tuple(center)
    text = re.sub(r"\n      Focal Point:\n        X: [-0-9.e]+\n        Y: [-0-9.e]+\n"
                  r"        Z: [-0-9.e]+", focal, text, count=1)
    with open(out, "w") as f:
        f.write(text)
    print("[rviz_config] %s: focal point (%.2f, %.2f, %.2f) m, distance %.2f m"
          % (os.path.basename(scene), center[0], center[1], center[2], distance))


if __name__ == "__main__":
    main()
