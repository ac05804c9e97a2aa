#!/usr/bin/env bash
# Builds and runs every test (gtest without a master, rostest with a real one), then gates on
# catkin_test_results: `catkin_make run_tests` itself exits 0 even when tests fail.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

rm -rf "$WS/build/test_results"
"$REPO_ROOT/scripts/build.sh"
# The Python test nodes import the workspace's generated messages: catkin's cached environment
# (written at the first configure, before they existed) lacks their path, so the tests run in a
# shell that sourced the workspace. The build above ran unsourced (CONTRIBUTING.md).
set +u  # setup.bash reads unset variables
source "$WS/devel/setup.bash"
set -u
"$REPO_ROOT/scripts/build.sh" run_tests
catkin_test_results --verbose "$WS/build/test_results"
