# Shared environment of the scripts (sourced, not run). ROS Python modules exist only for Debian's
# /usr/bin/python3, so /usr/bin goes first on PATH; logs and test results stay inside the build folder.
#
# Layout: CMake builds in build/, and catkin's devel space (executables, libraries, setup.bash) is devel/
# beside it, not inside build/: rosrun skips every executable under <package>/build/, so a devel space
# there would make `rosrun deformation_enrichment <node>` fail. `source devel/setup.bash`, then rosrun and
# roslaunch work. The sanitizer build (scripts/test --sanitize) keeps everything under build/sanitize/.
DE_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DE_BUILD="${DE_BUILD:-$DE_ROOT/build}"
DE_DEVEL="${DE_DEVEL:-$DE_ROOT/devel}"
DE_BIN="$DE_DEVEL/lib/deformation_enrichment"
export PATH=/usr/bin:$PATH
export ROS_HOME="$DE_BUILD/ros_home" ROS_HOSTNAME="${ROS_HOSTNAME:-127.0.0.1}"
mkdir -p "$ROS_HOME"
# Idle OpenMP threads sleep instead of spinning (spinning threads starve each other on 2 cores).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"

# DE_CMAKE_ARGS: extra configure arguments, a bash array (one element per argument, so values may hold spaces).
de_configure() {  # configure $DE_BUILD (log in $DE_BUILD/configure.log, printed on failure)
  mkdir -p "$DE_BUILD"
  # Ninja compiles a target's sources while the libraries it links are still being built, where Make waits for
  # them; a folder configured earlier keeps its generator.
  local generator=()
  [ -f "$DE_BUILD/CMakeCache.txt" ] || generator=(-G Ninja)
  cmake -S "$DE_ROOT" -B "$DE_BUILD" "${generator[@]}" -DCMAKE_BUILD_TYPE="${DE_BUILD_TYPE:-Release}" \
    -DCATKIN_DEVEL_PREFIX="$DE_DEVEL" "${DE_CMAKE_ARGS[@]}" >"$DE_BUILD/configure.log" 2>&1 ||
    { cat "$DE_BUILD/configure.log"; return 1; }
}

de_build() {  # de_build [extra targets...]: configure and build the package and the given targets
  de_configure || return 1
  cmake --build "$DE_BUILD" -j"$(nproc)" || return 1
  local target
  for target in "$@"; do cmake --build "$DE_BUILD" -j"$(nproc)" --target "$target" || return 1; done
}

de_build_only() {  # de_build_only targets...: configure and build only the given targets and what they need
  de_configure || return 1
  cmake --build "$DE_BUILD" -j"$(nproc)" --target "$@"
}
