// Stub (navlab benchmarks/smac).
#include "nav2_ros_common/lifecycle_node.hpp"
