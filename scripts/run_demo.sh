#!/usr/bin/env bash
# Runs the demo (make run; SCENE=name picks config/scenes/<name>.yaml): roslaunch cloth_sim
# demo.launch with RViz when there is a display ($DISPLAY set), headless otherwise, where the
# node then logs a one-line summary of the simulation every second. Ctrl-C stops it.
# ROS_PORT=n runs it on its own ROS master at port n (default: the usual 11311, or the master
# already running there).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
SCENE="${SCENE:-hanging}"
if [ ! -f "$REPO_ROOT/config/scenes/$SCENE.yaml" ] && [ ! -f "$SCENE" ]; then
  echo "[run_demo] no scene '$SCENE'; shipped scenes:" \
       "$(cd "$REPO_ROOT/config/scenes" && ls *.yaml | sed 's/\.yaml$//' | tr '\n' ' ')" >&2
  exit 1
fi

# A scene that cannot be used stops here with its message and a failing exit status (the node
# would exit, and roslaunch with it, but with status 0).
SCENE_FILE="$REPO_ROOT/config/scenes/$SCENE.yaml"
[ -f "$SCENE_FILE" ] || SCENE_FILE="$SCENE"
if ! check=$("$WS/devel/lib/cloth_sim/cloth_sim_run" --scene "$SCENE_FILE" --check 2>&1); then
  echo "[run_demo] scene '$SCENE' cannot be used: $check" >&2
  exit 1
fi

set +u  # setup.bash reads unset variables
source "$WS/devel/setup.bash"
set -u
PORT_ARGS=()
if [ -n "${ROS_PORT:-}" ]; then
  export ROS_MASTER_URI="http://localhost:$ROS_PORT"
  PORT_ARGS=(-p "$ROS_PORT")
fi

if [ -n "${DISPLAY:-}" ] && ! xdpyinfo > /dev/null 2>&1; then
  echo "[run_demo] DISPLAY=$DISPLAY cannot be reached: running headless" >&2
  unset DISPLAY
fi
RVIZ_ARGS=()
if [ -n "${DISPLAY:-}" ]; then
  RVIZ=true SUMMARY=false
  # A camera that frames this scene (its cloth's bounds), not one view for every scene.
  RVIZ_CONFIG="$(mktemp /tmp/cloth_sim_XXXXXX.rviz)"
  python3 "$REPO_ROOT/scripts/rviz_config.py" "$SCENE_FILE" "$RVIZ_CONFIG" &&
    RVIZ_ARGS=(rviz_config:="$RVIZ_CONFIG")
else
  RVIZ=false SUMMARY=true
  echo "[run_demo] no DISPLAY: running headless, with a summary of cloth/state every second"
  echo "[run_demo] (scripts/screenshot.sh $SCENE saves an RViz picture without a display)"
fi
exec roslaunch "${PORT_ARGS[@]}" cloth_sim demo.launch scene:="$SCENE" rviz:="$RVIZ" \
  summary:="$SUMMARY" "${RVIZ_ARGS[@]}"
