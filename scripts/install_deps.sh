#!/usr/bin/env bash
# Installs the Debian 12 packages cloth_sim needs (ROS 1 from Debian's own archive, no ROS apt repo).
# Idempotent: does nothing when everything is already installed. Uses sudo only when not root.
# Usage: install_deps.sh [bench]; "bench" adds what only the benchmark uses (make bench): Bullet,
# the peer of `cloth_sim_bench peers` (optional at build time: make run and make test do without).
set -euo pipefail

PACKAGES=(
  # build tools and ROS 1 core (Debian 12 names: ROS 1 comes from the Debian archive)
  build-essential cmake catkin ros-core-dev libroscpp-dev python3-rostest librostest-dev
  python3-roslaunch rosbash ros-message-generation ros-message-runtime
  # message packages and tf2
  libstd-msgs-dev libstd-srvs-dev libgeometry-msgs-dev libvisualization-msgs-dev
  libsensor-msgs-dev libros-rosgraph-msgs-dev
  libtf2-ros-dev tf2-tools libtf2-eigen-dev
  # node extras
  libinteractive-markers-dev libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libdiagnostic-updater-dev rviz librviz-dev
  # the robot's body as colliders (URDF) and the cloth/step_frames action
  liburdf-dev liburdfdom-dev libactionlib-dev libactionlib-msgs-dev ros-actionlib-msgs
  python3-actionlib python3-actionlib-msgs
  # Python message modules, so rostopic / rosservice can show the node's topics and services
  python3-visualization-msgs python3-std-srvs python3-diagnostic-msgs
  # the grasp demo's scripted gripper and its test (Python, /usr/bin/python3)
  python3-rospy python3-tf2-ros python3-tf2-msgs python3-geometry-msgs python3-sensor-msgs python3-yaml
  # core libraries
  libeigen3-dev libyaml-cpp-dev libtinyobjloader-dev libcli11-dev libsuitesparse-dev
  # optimized BLAS for CHOLMOD's supernodal factorization (Newton): 3-4x the reference BLAS
  libopenblas-dev
  # tests
  libgtest-dev libgmock-dev python3-nose
  # Markdown check of README.md and docs/ (test/docs/markdown_test.py)
  cmark
  # headless RViz, screenshots, benchmark plot
  xvfb xauth imagemagick x11-utils mesa-utils python3-matplotlib
)

if [ "${1:-}" = bench ]; then
  PACKAGES+=(libbullet-dev)  # Bullet's implicit deformable solver (docs/benchmark.md)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[install_deps] all ${#PACKAGES[@]} Debian packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "[install_deps] installing ${#missing[@]} missing packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
