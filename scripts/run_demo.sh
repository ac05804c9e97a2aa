#!/usr/bin/env bash
# Runs the default demo scene (SCENE=name picks config/scenes/<name>.yaml).
# Until the ROS node lands this is the headless core runner.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
SCENE="${SCENE:-hanging}"
exec "$WS/devel/lib/cloth_sim/cloth_sim_run" --scene "$REPO_ROOT/config/scenes/$SCENE.yaml" \
  --duration "${DURATION:-10}"
