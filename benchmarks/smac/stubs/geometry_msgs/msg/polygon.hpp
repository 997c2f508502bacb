// Stub (navlab benchmarks/smac).
#include "geometry_msgs/msg/types.hpp"
