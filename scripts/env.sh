# Sourced by the other scripts: workspace location, and /usr/bin first on PATH (below).
# The catkin workspace lives inside the repository (.catkin_ws/, ignored by git); its src/
# holds one symlink back to the repository root, which is the cloth_sim package.
REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS="${CLOTH_SIM_WS:-$REPO_ROOT/.catkin_ws}"
# Debian's ROS Python modules live under /usr/bin/python3; a pyenv python3 first on PATH breaks
# catkin (no catkin_pkg) and pluginlib (no ament_package).
export PATH="/usr/bin:$PATH"
