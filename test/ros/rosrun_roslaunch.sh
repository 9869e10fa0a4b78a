#!/usr/bin/env bash
# rosrun and roslaunch as a user runs them after `source devel/setup.bash` (ctest runs this under the devel
# space's env.sh, which sets the same environment):
#   - every executable of the package resolves, with rosrun, to exactly its file in the devel space;
#   - enrichment_node and shape_space_server_node start with rosrun against a real master;
#   - every launch file of the package starts its nodes (demo and replay run to their own end).
# Usage: rosrun_roslaunch.sh DEVEL_BIN_DIR BAG EXECUTABLE...
set -eo pipefail
devel_bin="$1" bag="$2"
shift 2
log_dir="${ROS_HOME:-/tmp}/rosrun_roslaunch"
mkdir -p "$log_dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

for exe in "$@"; do
  # --prefix echo prints the resolved command instead of running it; a non-unique name would prompt (stdin
  # is empty, so that fails too).
  resolved=$(rosrun --prefix echo deformation_enrichment "$exe" </dev/null 2>&1) || fail "rosrun: $resolved"
  [ "$resolved" = "$devel_bin/$exe" ] || fail "rosrun deformation_enrichment $exe gives '$resolved', not $devel_bin/$exe"
done
echo "rosrun resolves all $# executables in $devel_bin"

source "$(dirname "$0")/master_helpers.sh"
roscore -p "$port" >"$log_dir/roscore.log" 2>&1 &
pids+=($!)
has_service() { rosservice list 2>/dev/null | grep -qx "$1"; }

wait_for 30 rosnode list || fail "roscore did not answer on port $port (see $log_dir/roscore.log)"

rosrun deformation_enrichment enrichment_node __name:=rosrun_enrichment >"$log_dir/enrichment_node.log" 2>&1 &
node=$!
pids+=($node)
wait_for 30 has_service /rosrun_enrichment/load_example_set ||
  fail "rosrun deformation_enrichment enrichment_node did not come up (see $log_dir/enrichment_node.log)"
stop "$node"
rosrun deformation_enrichment shape_space_server_node __name:=rosrun_shape_space >"$log_dir/shape_space.log" 2>&1 &
node=$!
pids+=($node)
wait_for 30 has_service /rosrun_shape_space/compute_geodesic ||
  fail "rosrun deformation_enrichment shape_space_server_node did not come up (see $log_dir/shape_space.log)"
stop "$node"
echo "rosrun starts enrichment_node and shape_space_server_node"

launch_until_service() {  # launch_until_service SERVICE LAUNCH_FILE [ARGS...]: starts it, waits for SERVICE, stops it
  local service="$1" file="$2"
  shift 2
  roslaunch deformation_enrichment "$file" "$@" >"$log_dir/$file.log" 2>&1 &
  local launch=$!
  pids+=($launch)
  wait_for 60 has_service "$service" || fail "roslaunch deformation_enrichment $file $* did not start $service (see $log_dir/$file.log)"
  stop "$launch"
}
launch_until_service /enrichment/load_example_set enrichment.launch
launch_until_service /enrichment/load_example_set enrichment.launch nodelet:=true
launch_until_service /shape_space_server/smooth_sequence shape_space_server.launch

run_to_end() {  # run_to_end LAUNCH_FILE [ARGS...]: a launch file whose required node ends it must end, exit 0
  local file="$1"
  shift
  timeout 120 roslaunch deformation_enrichment "$file" "$@" >"$log_dir/$file.log" 2>&1 ||
    fail "roslaunch deformation_enrichment $file $* failed or did not end (see $log_dir/$file.log)"
  ! grep -q "ERROR: cannot launch node" "$log_dir/$file.log" || fail "$file: a node could not be launched"
}
run_to_end demo.launch duration:=3
run_to_end replay.launch bag:="$bag"
echo "roslaunch starts enrichment (process and nodelet), shape_space_server, demo and replay"
