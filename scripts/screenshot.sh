#!/usr/bin/env bash
# Runs the demo under Xvfb (no display needed) and saves an RViz screenshot.
#   scripts/screenshot.sh SCENE [WAIT_S] [OUT.png]
# WAIT_S (default 10) is how long the scene runs before the picture; OUT defaults to
# docs/images/SCENE.png. LAUNCH (default demo.launch) picks the launch file, e.g.
#   LAUNCH=grasp_demo.launch scripts/screenshot.sh grasp_demo 7
# Build first (make build). Uses its own ROS master port (ROS_PORT to choose it). The fold
# picture needs the pin carried over the cloth meanwhile: scripts/fold_pin.py.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
SCENE="${1:-hanging}"
LAUNCH="${LAUNCH:-demo.launch}"
WAIT="${2:-10}"
OUT="$(realpath -m "${3:-$REPO_ROOT/docs/images/$SCENE.png}")"
mkdir -p "$(dirname "$OUT")"

set +u  # setup.bash reads unset variables
source "$WS/devel/setup.bash"
set -u
PORT="${ROS_PORT:-$((11600 + RANDOM % 300))}"
export ROS_MASTER_URI="http://localhost:$PORT"
LOG="$(mktemp /tmp/cloth_sim_screenshot.XXXXXX.log)"
SCENE_FILE="$REPO_ROOT/config/scenes/$SCENE.yaml"
[ -f "$SCENE_FILE" ] || SCENE_FILE="$SCENE"
RVIZ_CONFIG="$(mktemp /tmp/cloth_sim_screenshot.XXXXXX.rviz)"
python3 "$REPO_ROOT/scripts/rviz_config.py" "$SCENE_FILE" "$RVIZ_CONFIG"
# demo.launch takes the scene's framing; another launch file brings its own RViz config.
RVIZ_ARG=""
[ "$LAUNCH" = demo.launch ] && RVIZ_ARG="rviz_config:=$RVIZ_CONFIG"

xvfb-run -a -s "-screen 0 1024x720x24" bash -c '
  roslaunch -p "$0" cloth_sim "$5" scene:="$1" rviz:=true $6 >"$4" 2>&1 &
  launch=$!
  sleep "$2"
  import -window root "$3"
  kill -INT "$launch"
  wait "$launch" || true
' "$PORT" "$SCENE" "$WAIT" "$OUT" "$LOG" "$LAUNCH" "$RVIZ_ARG"

if [ ! -s "$OUT" ]; then
  echo "[screenshot] no image; roslaunch log: $LOG" >&2
  exit 1
fi
echo "[screenshot] $OUT ($(identify -format '%wx%h' "$OUT")); roslaunch log: $LOG"
