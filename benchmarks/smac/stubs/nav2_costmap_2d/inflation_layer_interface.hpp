// Stub (navlab benchmarks/smac): shadows the checkout's header (a ROS costmap layer plugin).
// Smac's findCircumscribedCost (utils.hpp) asks the costmap for its inflation layer; the stub
// Costmap2DROS holds at most one, whose computeCost is the formula of Nav2's
// InflationLayer::computeCost (nav2_costmap_2d/inflation_layer.hpp at the checkout).
#ifndef NAVLAB_STUB_INFLATION_LAYER_INTERFACE_HPP_
#define NAVLAB_STUB_INFLATION_LAYER_INTERFACE_HPP_
#include <cmath>
#include <memory>
#include "nav2_costmap_2d/cost_values.hpp"
#include "nav2_costmap_2d/costmap_2d_ros.hpp"

namespace nav2_costmap_2d
{
class InflationLayerInterface
{
public:
  InflationLayerInterface(
    double inflation_radius, double cost_scaling_factor, double inscribed_radius,
    double resolution)
  : inflation_radius_(inflation_radius), cost_scaling_factor_(cost_scaling_factor),
    inscribed_radius_(inscribed_radius), resolution_(resolution) {}
  double getCostScalingFactor() {return cost_scaling_factor_;}
  double getInflationRadius() {return inflation_radius_;}
  // distance in cells -> cost, as InflationLayer::computeCost
  unsigned char computeCost(double distance) const
  {
    if (distance == 0) {
      return LETHAL_OBSTACLE;
    }
    if (distance * resolution_ <= inscribed_radius_) {
      return INSCRIBED_INFLATED_OBSTACLE;
    }
    const double factor =
      std::exp(-1.0 * cost_scaling_factor_ * (distance * resolution_ - inscribed_radius_));
    return static_cast<unsigned char>((INSCRIBED_INFLATED_OBSTACLE - 1) * factor);
  }
  static std::shared_ptr<InflationLayerInterface> getInflationLayer(
    std::shared_ptr<Costmap2DROS> & costmap_ros)
  {
    return costmap_ros->inflation_layer;
  }

private:
  double inflation_radius_, cost_scaling_factor_, inscribed_radius_, resolution_;
};
}  // namespace nav2_costmap_2d
#endif  // NAVLAB_STUB_INFLATION_LAYER_INTERFACE_HPP_
