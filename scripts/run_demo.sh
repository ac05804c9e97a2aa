#!/usr/bin/env bash
# Runs the demo (make run; SCENE=name picks config/scenes/<name>.yaml): roslaunch cloth_sim
# demo.launch with RViz when there is a display ($DISPLAY set), headless otherwise, where the
# node then logs a one-line summary of the simulation every second. Ctrl-C stops it.
# ROS_PORT=n runs it on its own ROS master at port n (default: the usual 11311, or the master
# already running there). A scene that needs its script runs through its own launch file:
# fold with its pin script (launch/fold_demo.launch), grasp_demo with its scripted gripper
# (launch/grasp_demo.launch) and pinch with its URDF gripper (launch/pinch_demo.launch); fold
# and grasp_demo loop. DRY_RUN=1 prints the roslaunch command instead of running it.
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
# A scene is run as it is meant to be seen: with its script where it has one.
case "$SCENE" in
  fold)
    LAUNCH=(cloth_sim fold_demo.launch scene:="$SCENE" rviz:="$RVIZ" summary:="$SUMMARY" "${RVIZ_ARGS[@]}") ;;
  grasp_demo)  # its own RViz config (the gripper frame, the force arrow); again every 3 s
    LAUNCH=(cloth_sim grasp_demo.launch rviz:="$RVIZ" summary:="$SUMMARY" loop:=3 start_delay:=2) ;;
  pinch)
    LAUNCH=(cloth_sim pinch_demo.launch rviz:="$RVIZ") ;;
  *)
    LAUNCH=(cloth_sim demo.launch scene:="$SCENE" rviz:="$RVIZ" summary:="$SUMMARY" "${RVIZ_ARGS[@]}") ;;
esac
if [ -n "${DRY_RUN:-}" ]; then
  echo roslaunch "${PORT_ARGS[@]}" "${LAUNCH[@]}"
  exit 0
fi
exec roslaunch "${PORT_ARGS[@]}" "${LAUNCH[@]}"
