#!/usr/bin/env bash
# Configures and builds the in-repository catkin workspace (Release). Extra args go to catkin_make.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

mkdir -p "$WS/src"
ln -sfn "$REPO_ROOT" "$WS/src/cloth_sim"  # refreshed: the repository may have moved

JOBS="${JOBS:-$(nproc)}"
catkin_make -C "$WS" \
  -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -j"$JOBS" "$@"
