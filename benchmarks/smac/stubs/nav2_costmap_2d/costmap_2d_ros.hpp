// Stub (navlab benchmarks/smac): shadows the checkout's Costmap2DROS (a ROS lifecycle node).
// Smac's core asks it for the costmap, the robot footprint and (findCircumscribedCost) the
// inflation layer and the footprint's circumscribed radius.
#ifndef NAVLAB_STUB_COSTMAP_2D_ROS_HPP_
#define NAVLAB_STUB_COSTMAP_2D_ROS_HPP_
#include <memory>
#include <utility>
#include <vector>
#include "geometry_msgs/msg/types.hpp"
#include "nav2_costmap_2d/costmap_2d.hpp"
#include "nav2_costmap_2d/cost_values.hpp"
#include "nav2_ros_common/lifecycle_node.hpp"

namespace nav2_costmap_2d
{
class Costmap2DPublisher;
class InflationLayerInterface;
class Layer;  // named in findCircumscribedCost (an unused local), never defined

class LayeredCostmap
{
public:
  explicit LayeredCostmap(double circumscribed_radius)
  : circumscribed_radius_(circumscribed_radius) {}
  double getCircumscribedRadius() {return circumscribed_radius_;}

private:
  double circumscribed_radius_;
};

class Costmap2DROS
{
public:
  Costmap2DROS(
    Costmap2D * costmap, std::vector<geometry_msgs::msg::Point> footprint,
    double circumscribed_radius)
  : costmap_(costmap), footprint_(std::move(footprint)), layered_(circumscribed_radius) {}
  Costmap2D * getCostmap() {return costmap_;}
  std::vector<geometry_msgs::msg::Point> getRobotFootprint() {return footprint_;}
  bool getUseRadius() {return false;}
  LayeredCostmap * getLayeredCostmap() {return &layered_;}
  std::shared_ptr<InflationLayerInterface> inflation_layer;  // null: no inflation layer

private:
  Costmap2D * costmap_;
  std::vector<geometry_msgs::msg::Point> footprint_;
  LayeredCostmap layered_;
};
}  // namespace nav2_costmap_2d
#endif  // NAVLAB_STUB_COSTMAP_2D_ROS_HPP_
