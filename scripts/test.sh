#!/usr/bin/env bash
# Builds and runs every test (gtest without a master, rostest with a real one), then gates on
# catkin_test_results: `catkin_make run_tests` itself exits 0 even when tests fail.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

rm -rf "$WS/build/test_results"
"$REPO_ROOT/scripts/build.sh" run_tests
catkin_test_results --verbose "$WS/build/test_results"
