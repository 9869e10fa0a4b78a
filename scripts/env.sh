# Shared environment of the scripts (sourced, not run). ROS Python modules exist only for Debian's
# /usr/bin/python3, so /usr/bin goes first on PATH; logs and test results stay inside the build folder.
DE_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DE_BUILD="${DE_BUILD:-$DE_ROOT/build}"
export PATH=/usr/bin:$PATH
export ROS_HOME="$DE_BUILD/ros_home" ROS_HOSTNAME="${ROS_HOSTNAME:-127.0.0.1}"
mkdir -p "$ROS_HOME"
# Idle OpenMP threads sleep instead of spinning (spinning threads starve each other on 2 cores).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"

de_build() {  # de_build [extra targets...]: configure (Release) and build the package and the given targets
  mkdir -p "$DE_BUILD"
  cmake -S "$DE_ROOT" -B "$DE_BUILD" -DCMAKE_BUILD_TYPE=Release >"$DE_BUILD/configure.log" 2>&1 ||
    { cat "$DE_BUILD/configure.log"; return 1; }
  cmake --build "$DE_BUILD" -j"$(nproc)" || return 1
  local target
  for target in "$@"; do cmake --build "$DE_BUILD" -j"$(nproc)" --target "$target" || return 1; done
}
