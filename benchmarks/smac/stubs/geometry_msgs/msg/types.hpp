// Stub (navlab benchmarks/smac): geometry_msgs as plain structs with the fields Smac's core reads.
#ifndef NAVLAB_STUB_GEOMETRY_MSGS_HPP_
#define NAVLAB_STUB_GEOMETRY_MSGS_HPP_
#include <string>
#include <vector>
#include "rclcpp/rclcpp.hpp"

namespace geometry_msgs
{
namespace msg
{
struct Point
{
  double x{0.0}, y{0.0}, z{0.0};
  bool operator==(const Point & o) const {return x == o.x && y == o.y && z == o.z;}
  bool operator!=(const Point & o) const {return !(*this == o);}
};
struct Point32
{
  float x{0.0f}, y{0.0f}, z{0.0f};
};
struct Quaternion
{
  double x{0.0}, y{0.0}, z{0.0}, w{1.0};
};
struct Pose
{
  Point position;
  Quaternion orientation;
};
struct Header
{
  rclcpp::Time stamp;
  std::string frame_id;
};
struct PoseStamped
{
  Header header;
  Pose pose;
};
struct Polygon
{
  std::vector<Point32> points;
};
struct PolygonStamped
{
  Header header;
  Polygon polygon;
};
}  // namespace msg
}  // namespace geometry_msgs
#endif  // NAVLAB_STUB_GEOMETRY_MSGS_HPP_
