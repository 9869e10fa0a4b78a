#!/usr/bin/env bash
# The README's "own catkin workspace" path, as a user follows it: the package's files (as a clone has them)
# go into catkin_ws/src/deformation_enrichment of a fresh workspace outside the package folder, catkin_make
# configures the workspace and builds the enrichment node, and after `source devel/setup.bash` rosrun finds
# the node in that workspace's devel space and roslaunch resolves every launch file of the package.
# Usage: catkin_workspace.sh SOURCE_DIR   (needs catkin_make and ninja on PATH; builds Release, tests off).
# Ninja, as the package's own build: the node's sources compile while the layers below it still build.
set -eo pipefail
source_dir="$1"
workspace=$(mktemp -d /tmp/de_catkin_ws.XXXXXX)
trap 'rm -rf "$workspace"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

mkdir -p "$workspace/src/deformation_enrichment"
# What a clone holds: everything but build output.
tar -C "$source_dir" --exclude=./build --exclude=./devel --exclude=./.git -cf - . |
  tar -C "$workspace/src/deformation_enrichment" -xf -
cd "$workspace"
export PATH=/usr/bin:$PATH
catkin_make --use-ninja -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=OFF -DDE_BUILD_BENCHMARKS=OFF \
  -j"$(nproc)" enrichment_node >"$workspace/catkin_make.log" 2>&1 || { tail -40 "$workspace/catkin_make.log"; fail "catkin_make"; }
# Sourcing the workspace replaces the package paths of the caller's environment with the workspace's.
source devel/setup.bash
expected="$workspace/devel/lib/deformation_enrichment/enrichment_node"
resolved=$(rosrun --prefix echo deformation_enrichment enrichment_node </dev/null 2>&1) || fail "rosrun: $resolved"
[ "$resolved" = "$expected" ] || fail "rosrun deformation_enrichment enrichment_node gives '$resolved', not $expected"
for launch in "$workspace"/src/deformation_enrichment/launch/*.launch; do
  name=$(basename "$launch")
  args=()
  [ "$name" = replay.launch ] && args=(bag:=/tmp/any.bag)
  roslaunch --nodes deformation_enrichment "$name" "${args[@]}" >/dev/null 2>&1 || fail "roslaunch cannot resolve $name"
done
echo "catkin_make in $workspace: rosrun finds $expected; roslaunch resolves every launch file"
