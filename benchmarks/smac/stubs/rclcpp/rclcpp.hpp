// Stub (navlab benchmarks/smac): the rclcpp names Smac's core mentions; logging is a no-op.
#ifndef NAVLAB_STUB_RCLCPP_HPP_
#define NAVLAB_STUB_RCLCPP_HPP_
#include <memory>
#include <string>

namespace rclcpp
{
struct Logger {};
inline Logger get_logger(const std::string &) {return Logger{};}
struct Time {};
struct Duration
{
  Duration(int, int) {}
};
struct Clock
{
  using SharedPtr = std::shared_ptr<Clock>;
  Time now() {return Time{};}
};
}  // namespace rclcpp

// Logging macros: arguments are not evaluated (a null clock in a THROTTLE call is never touched).
#define RCLCPP_DEBUG(...) ((void)0)
#define RCLCPP_INFO(...) ((void)0)
#define RCLCPP_WARN(...) ((void)0)
#define RCLCPP_ERROR(...) ((void)0)
#define RCLCPP_FATAL(...) ((void)0)
#define RCLCPP_DEBUG_THROTTLE(...) ((void)0)
#define RCLCPP_INFO_THROTTLE(...) ((void)0)
#define RCLCPP_WARN_THROTTLE(...) ((void)0)
#define RCLCPP_ERROR_THROTTLE(...) ((void)0)
#define RCLCPP_WARN_ONCE(...) ((void)0)
#define RCLCPP_INFO_ONCE(...) ((void)0)
#endif  // NAVLAB_STUB_RCLCPP_HPP_
