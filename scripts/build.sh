#!/usr/bin/env bash
# Configures and builds the in-repository catkin workspace (Release). Extra args go to catkin_make.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

mkdir -p "$WS/src"
if [ ! -L "$WS/src/cloth_sim" ]; then ln -sfn "$REPO_ROOT" "$WS/src/cloth_sim"; fi

JOBS="${JOBS:-$(nproc)}"
catkin_make -C "$WS" \
  -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -j"$JOBS" "$@"
