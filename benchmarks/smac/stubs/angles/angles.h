// Stub (navlab benchmarks/smac): the one function of ROS's angles package that Smac's
// node_lattice.cpp calls (lattice node only; the Hybrid-A* benchmark never reaches it).
#ifndef NAVLAB_STUB_ANGLES_H_
#define NAVLAB_STUB_ANGLES_H_
#include <cmath>

namespace angles
{
// the signed angle [rad] in [-pi, pi) that turns from angle `from` to angle `to`
inline double shortest_angular_distance(double from, double to)
{
  const double d = std::fmod(to - from + M_PI, 2.0 * M_PI);
  return (d < 0.0 ? d + 2.0 * M_PI : d) - M_PI;
}
}  // namespace angles
#endif  // NAVLAB_STUB_ANGLES_H_
