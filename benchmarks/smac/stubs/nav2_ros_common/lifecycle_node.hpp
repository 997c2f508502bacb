// Stub (navlab benchmarks/smac): nav2::LifecycleNode as far as Smac's core uses it; every
// parameter read returns the default it is declared with.
#ifndef NAVLAB_STUB_NAV2_LIFECYCLE_NODE_HPP_
#define NAVLAB_STUB_NAV2_LIFECYCLE_NODE_HPP_
#include <memory>
#include <string>
#include "rclcpp/rclcpp.hpp"

namespace nav2
{
class LifecycleNode
{
public:
  using SharedPtr = std::shared_ptr<LifecycleNode>;
  using WeakPtr = std::weak_ptr<LifecycleNode>;
  rclcpp::Clock::SharedPtr get_clock() {return std::make_shared<rclcpp::Clock>();}
  rclcpp::Logger get_logger() {return rclcpp::Logger{};}
  template<typename T>
  T declare_or_get_parameter(const std::string &, const T & default_value) {return default_value;}
};
}  // namespace nav2
#endif  // NAVLAB_STUB_NAV2_LIFECYCLE_NODE_HPP_
