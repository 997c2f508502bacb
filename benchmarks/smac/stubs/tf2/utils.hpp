// Stub (navlab benchmarks/smac): tf2's planar quaternion helpers (yaw <-> quaternion), written
// from the standard formulas, as Smac's utils.hpp and the planner shell use them.
#ifndef NAVLAB_STUB_TF2_UTILS_HPP_
#define NAVLAB_STUB_TF2_UTILS_HPP_
#include <cmath>
#include "geometry_msgs/msg/types.hpp"

namespace tf2
{
class Quaternion
{
public:
  // roll, pitch, yaw [rad] (fixed axes x, y, z), as tf2::Quaternion::setRPY
  void setRPY(double roll, double pitch, double yaw)
  {
    const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
    const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
    const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
    x_ = sr * cp * cy - cr * sp * sy;
    y_ = cr * sp * cy + sr * cp * sy;
    z_ = cr * cp * sy - sr * sp * cy;
    w_ = cr * cp * cy + sr * sp * sy;
  }
  double x() const {return x_;}
  double y() const {return y_;}
  double z() const {return z_;}
  double w() const {return w_;}

private:
  double x_{0.0}, y_{0.0}, z_{0.0}, w_{1.0};
};

inline geometry_msgs::msg::Quaternion toMsg(const Quaternion & q)
{
  geometry_msgs::msg::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

// yaw [rad] of a unit quaternion (the z-y-x Euler angle tf2::getYaw returns)
inline double getYaw(const geometry_msgs::msg::Quaternion & q)
{
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}
}  // namespace tf2
#endif  // NAVLAB_STUB_TF2_UTILS_HPP_
