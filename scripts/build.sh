#!/usr/bin/env bash
# Configures and builds the in-repository catkin workspace (Release). Extra args go to catkin_make.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

mkdir -p "$WS/src"
ln -sfn "$REPO_ROOT" "$WS/src/cloth_sim"  # refreshed: the repository may have moved
# RViz asks rospack for the plugins of the package media_export at every start; Debian ships no
# such package, so rospack printed "[rospack] Error: no such package media_export". The real
# package is empty (it only exists to be asked): an empty one in the workspace answers.
mkdir -p "$WS/src/media_export"
cat > "$WS/src/media_export/package.xml" <<'XML'
<?xml version="1.0"?>
<package format="2">
  <name>media_export</name>
  <version>0.0.0</version>
  <description>Empty stand-in for ROS media_export, which RViz asks rospack about.</description>
  <maintainer email="nobody@example.com">cloth_sim</maintainer>
  <license>BSD</license>
  <buildtool_depend>catkin</buildtool_depend>
</package>
XML
printf 'cmake_minimum_required(VERSION 3.0.2)\nproject(media_export)\nfind_package(catkin REQUIRED)\ncatkin_package()\n' \
  > "$WS/src/media_export/CMakeLists.txt"

JOBS="${JOBS:-$(nproc)}"
catkin_make -C "$WS" \
  -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 \
  -j"$JOBS" "$@"
