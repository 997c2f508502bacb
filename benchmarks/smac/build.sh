#!/usr/bin/env bash
# Build Nav2 Smac's Hybrid-A* core and navlab's driver (smac_driver) from a Nav2 checkout.
#
#   benchmarks/smac/build.sh NAV2_CHECKOUT [BUILD_DIR]     (BUILD_DIR default: ./build-smac)
#
# Compiles, from the checkout's own files (nothing of Nav2 is copied into navlab):
#   nav2_smac_planner/src/{collision_checker,node_hybrid,obstacle_heuristic,distance_heuristic,
#     node_lattice}.cpp (A*, analytic expansion and goal manager are header templates; the
#     distance heuristic's explicit NodeLattice instantiation pulls in node_lattice.cpp)
#   nav2_costmap_2d/src/{costmap_2d,footprint_collision_checker,footprint,costmap_math}.cpp
#   nav2_util/src/array_parser.cpp (footprint.cpp calls it)
# with headers from nav2_smac_planner/include, nav2_costmap_2d/include, nav2_util/include,
# nav2_core/include, and navlab's ROS stubs (benchmarks/smac/stubs, searched first).
# Written against Nav2 commit a3a97043 (2026-08-21):
#   git --git-dir=/path/to/navigation2.git archive a3a97043 nav2_smac_planner nav2_costmap_2d \
#     nav2_util nav2_core | tar -x -C /tmp/nav2
# Needs g++ (C++17), OMPL 1.5 headers and library (libompl-dev), Eigen 3 (libeigen3-dev),
# nlohmann json (nlohmann-json3-dev; Smac's utils.hpp includes it). Not run by CI.
# OMPL_SRC=/path/to/ompl (a checkout at the installed version, 1.5.2 for Debian's libompl-dev
# 1.5.2+ds1): its DubinsStateSpace.cpp and ReedsSheppStateSpace.cpp are compiled with -DNDEBUG
# into the driver, whose definitions take the place of the library's: Debian's libompl keeps
# assert() on and aborts in dubinsRSL on some of Smac's queries (a rounding check;
# ROS's release builds of OMPL have NDEBUG). OMPL_SRC=none links the library as it is.
#   git --git-dir=/path/to/ompl.git archive 1.5.2 src/ompl/base/spaces/src | tar -x -C /tmp/ompl
# Flags: -O2 -DNDEBUG (Nav2's own CMakeLists.txt adds -O3); OPT="-O3" build.sh ... overrides.
set -euo pipefail

NAV2=${1:?usage: build.sh NAV2_CHECKOUT [BUILD_DIR]}
BUILD=${2:-build-smac}
HERE=$(cd "$(dirname "$0")" && pwd)
OPT=${OPT:--O2}

SMAC_SRC="collision_checker node_hybrid obstacle_heuristic distance_heuristic node_lattice"
COSTMAP_SRC="costmap_2d footprint_collision_checker footprint costmap_math"
for f in $SMAC_SRC; do
  [[ -f "$NAV2/nav2_smac_planner/src/$f.cpp" ]] || {
    echo "build.sh: $NAV2/nav2_smac_planner/src/$f.cpp missing: NAV2_CHECKOUT must be a Nav2 checkout (commit a3a97043) with nav2_smac_planner, nav2_costmap_2d, nav2_util, nav2_core" >&2
    exit 1
  }
done
for f in $COSTMAP_SRC; do
  [[ -f "$NAV2/nav2_costmap_2d/src/$f.cpp" ]] || {
    echo "build.sh: $NAV2/nav2_costmap_2d/src/$f.cpp missing: NAV2_CHECKOUT must be a Nav2 checkout (commit a3a97043) with nav2_smac_planner, nav2_costmap_2d, nav2_util, nav2_core" >&2
    exit 1
  }
done
[[ -f "$NAV2/nav2_util/src/array_parser.cpp" ]] || { echo "build.sh: $NAV2/nav2_util/src/array_parser.cpp missing" >&2; exit 1; }
for d in nav2_util/include nav2_core/include; do
  [[ -d "$NAV2/$d" ]] || { echo "build.sh: $NAV2/$d missing (needed for headers)" >&2; exit 1; }
done
OMPL_INC=$(ls -d /usr/include/ompl-1.* 2>/dev/null | head -1)
[[ -n "$OMPL_INC" ]] || { echo "build.sh: OMPL headers (/usr/include/ompl-1.*) missing: apt-get install libompl-dev" >&2; exit 1; }
[[ -d /usr/include/eigen3 ]] || { echo "build.sh: /usr/include/eigen3 missing: apt-get install libeigen3-dev" >&2; exit 1; }
[[ -f /usr/include/nlohmann/json.hpp ]] || { echo "build.sh: /usr/include/nlohmann/json.hpp missing: apt-get install nlohmann-json3-dev" >&2; exit 1; }

OMPL_SRC=${OMPL_SRC:?"set OMPL_SRC to an OMPL checkout at the installed version (git archive 1.5.2 src/ompl/base/spaces/src), or OMPL_SRC=none"}
OMPL_OWN=()
if [[ "$OMPL_SRC" != none ]]; then
  for f in DubinsStateSpace ReedsSheppStateSpace; do
    [[ -f "$OMPL_SRC/src/ompl/base/spaces/src/$f.cpp" ]] || {
      echo "build.sh: $OMPL_SRC/src/ompl/base/spaces/src/$f.cpp missing (OMPL_SRC: an OMPL checkout, or none)" >&2
      exit 1
    }
    OMPL_OWN+=("$f")
  done
fi

mkdir -p "$BUILD"
INC=(-I"$HERE/stubs" -I"$NAV2/nav2_smac_planner/include" -I"$NAV2/nav2_costmap_2d/include"
     -I"$NAV2/nav2_util/include" -I"$NAV2/nav2_core/include" -I"$OMPL_INC" -I/usr/include/eigen3)
FLAGS=(-std=c++17 $OPT -DNDEBUG -fPIC -w)
objects=()
compile() {  # source file -> object in BUILD, in the background
  local obj="$BUILD/$2.o"
  objects+=("$obj")
  g++ "${FLAGS[@]}" "${INC[@]}" -c "$1" -o "$obj" &
}
for f in $SMAC_SRC; do compile "$NAV2/nav2_smac_planner/src/$f.cpp" "smac_$f"; done
for f in $COSTMAP_SRC; do compile "$NAV2/nav2_costmap_2d/src/$f.cpp" "costmap_$f"; done
compile "$NAV2/nav2_util/src/array_parser.cpp" util_array_parser
for f in "${OMPL_OWN[@]}"; do compile "$OMPL_SRC/src/ompl/base/spaces/src/$f.cpp" "ompl_$f"; done
compile "$HERE/smac_driver.cpp" smac_driver
for job in $(jobs -p); do wait "$job"; done
g++ "${FLAGS[@]}" "${objects[@]}" -lompl -o "$BUILD/smac_driver"
# only a work tree whose top is the checkout itself names Nav2's commit: an archive unpacked inside
# another repository (navlab's, say) would otherwise report that repository's
top=$(git -C "$NAV2" rev-parse --show-toplevel 2>/dev/null || true)
if [[ -n "$top" && "$(cd "$top" && pwd -P)" == "$(cd "$NAV2" && pwd -P)" ]]; then
  commit=$(git -C "$NAV2" rev-parse --short HEAD)
else
  commit="unknown (not a git work tree: an archive; the README's is a3a97043)"
fi
echo "built $BUILD/smac_driver from $NAV2 (commit $commit) with g++ ${FLAGS[*]}; OMPL state spaces from ${OMPL_SRC}"
