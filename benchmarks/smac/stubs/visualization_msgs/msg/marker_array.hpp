// Stub (navlab benchmarks/smac): the Marker fields Smac's utils.hpp fills (debug drawing only).
#ifndef NAVLAB_STUB_VISUALIZATION_MSGS_HPP_
#define NAVLAB_STUB_VISUALIZATION_MSGS_HPP_
#include <string>
#include <vector>
#include "geometry_msgs/msg/types.hpp"
#include "rclcpp/rclcpp.hpp"

namespace visualization_msgs
{
namespace msg
{
struct Marker
{
  static constexpr int ADD = 0;
  static constexpr int LINE_LIST = 5;
  static constexpr int DELETEALL = 3;
  geometry_msgs::msg::Header header;
  std::string ns;
  int id{0}, type{0}, action{0};
  bool frame_locked{false};
  rclcpp::Duration lifetime{0, 0};
  geometry_msgs::msg::Pose pose;
  struct {double x{0}, y{0}, z{0};} scale;
  struct {float r{0}, g{0}, b{0}, a{0};} color;
  std::vector<geometry_msgs::msg::Point> points;
};
struct MarkerArray
{
  std::vector<Marker> markers;
};
}  // namespace msg
}  // namespace visualization_msgs
#endif  // NAVLAB_STUB_VISUALIZATION_MSGS_HPP_
