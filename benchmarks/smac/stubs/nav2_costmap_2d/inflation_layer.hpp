// Stub (navlab benchmarks/smac): shadows the checkout's header (a ROS costmap layer plugin).
// NodeHybrid includes it but uses nothing from it; the inflation costs of the driver's second
// setting are computed in smac_driver.cpp with the inflation layer's formula.
#include "nav2_costmap_2d/cost_values.hpp"
