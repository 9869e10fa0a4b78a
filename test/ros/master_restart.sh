#!/usr/bin/env bash
# The ROS master restarts while enrichment.launch runs (process form, then nodelet form): the node sees that
# the new master does not know it, writes its parameters to the new master, shuts down, and the launch file's
# respawn brings it back registered, so states flow again and its ~scene is still set. ctest runs this under
# the devel space's env.sh.
set -eo pipefail
log_dir="${ROS_HOME:-/tmp}/master_restart"
mkdir -p "$log_dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

source "$(dirname "$0")/master_helpers.sh"
start_master() {  # start_master NAME: a roscore on $port; its pid in $master
  roscore -p "$port" >"$log_dir/roscore_$1.log" 2>&1 &
  master=$!
  pids+=($master)
  wait_for 30 rosnode list || fail "roscore did not answer on port $port (see $log_dir/roscore_$1.log)"
}
start_simulator() {  # start_simulator NAME: Bullet's coarse slab at rest, publishing mesh_state and rest_mesh
  rosrun deformation_enrichment bullet_coarse_sim_node __name:=coarse_sim _scene:=slab _rate:=20 \
    >"$log_dir/simulator_$1.log" 2>&1 &
  simulator=$!
  pids+=($simulator)
}
states_flow() { timeout 5 rostopic echo -n 1 /enriched_mesh_state/header; }

for form in process nodelet; do
  start_master "${form}_first"
  roslaunch deformation_enrichment enrichment.launch scene:=slab nodelet:=$([ $form = nodelet ] && echo true || echo false) \
    >"$log_dir/launch_$form.log" 2>&1 &
  launch=$!
  pids+=($launch)
  start_simulator "${form}_first"
  wait_for 90 states_flow || fail "$form: no enriched state before the restart (see $log_dir)"

  stop "$master"
  stop "$simulator"  # deaf as well after the restart; a user's simulator restarts with its master too
  sleep 2
  start_master "${form}_second"
  start_simulator "${form}_second"
  wait_for 90 states_flow || fail "$form: no enriched state after the master restarted (see $log_dir/launch_$form.log)"
  grep -q "does not know node" "$log_dir/launch_$form.log" || fail "$form: the node did not say why it shut down"
  [ "$(rosparam get /enrichment/scene 2>/dev/null)" = "slab" ] ||
    fail "$form: the respawned node's parameters are not on the new master"
  echo "$form: the master restarted; the node said why, was respawned with its parameters, and enriches again"
  stop "$simulator"
  stop "$launch"
  stop "$master"
done
