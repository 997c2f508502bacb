// Stub (navlab benchmarks/smac).
#include "rclcpp/rclcpp.hpp"
