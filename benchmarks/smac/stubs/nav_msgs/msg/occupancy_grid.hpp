// Stub (navlab benchmarks/smac): the OccupancyGrid fields Costmap2D's constructor reads.
#ifndef NAVLAB_STUB_NAV_MSGS_OCCUPANCY_GRID_HPP_
#define NAVLAB_STUB_NAV_MSGS_OCCUPANCY_GRID_HPP_
#include <cstdint>
#include <vector>
#include "geometry_msgs/msg/types.hpp"

namespace nav_msgs
{
namespace msg
{
struct MapMetaData
{
  float resolution{0.0f};
  uint32_t width{0}, height{0};
  geometry_msgs::msg::Pose origin;
};
struct OccupancyGrid
{
  geometry_msgs::msg::Header header;
  MapMetaData info;
  std::vector<int8_t> data;
};
}  // namespace msg
}  // namespace nav_msgs
#endif  // NAVLAB_STUB_NAV_MSGS_OCCUPANCY_GRID_HPP_
