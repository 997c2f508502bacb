// navlab benchmarks/smac: Nav2 Smac Hybrid-A* (nav2_smac_planner, built from a Nav2 checkout by
// build.sh) on one costmap, many queries; one JSON line per query on stdout.
//
// The setup follows SmacPlannerHybrid::configure and createPlan
// (nav2_smac_planner/include/nav2_smac_planner/smac_planner_hybrid_impl.hpp at the checkout):
// the same parameter defaults, the same collision checker, A* initialize(), per-query
// setFootprint / setCollisionChecker / setStart / setGoal / createPath and the conversion of
// the path to world poses. Not done: the smoother (smooth_path), costmap downsampling
// (downsample_costmap is false by default), ROS messages and publishers.
//
// Usage:
//   smac_driver --map COSTS.u8 --width W --height H --resolution R [--origin X Y]
//               --footprint "x,y;x,y;..." [--param NAME=VALUE ...]
//               [--inflation RADIUS SCALING]  < queries
// COSTS.u8: W*H bytes, row-major, row = y (Costmap2D's index my * W + mx), Nav2 costs
// (0 free, 253 inscribed, 254 lethal, 255 unknown). --param names are Smac's (without the
// plugin prefix): motion_model_for_search, reverse_penalty, ... (see configure below).
// --inflation gives the costmap an inflation layer (its radius [m] and cost_scaling_factor) so
// findCircumscribedCost returns the inflation cost at the circumscribed radius, as in a Nav2
// costmap with an inflation layer; the costs themselves must already be inflated in COSTS.u8.
// Each stdin line "sx sy syaw gx gy gyaw" [m, m, rad] is one query; each answer is one line:
// {"found":..,"wall_ms":..,"cpu_ms":..,"iterations":..,"length_m":..,"poses":[[x,y,yaw],..]}.
// The first output line describes the configuration (and the time configure took).

#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "nav2_costmap_2d/costmap_2d.hpp"
#include "nav2_costmap_2d/footprint.hpp"
#include "nav2_costmap_2d/inflation_layer_interface.hpp"
#include "nav2_smac_planner/a_star.hpp"
#include "nav2_smac_planner/collision_checker.hpp"
#include "nav2_smac_planner/utils.hpp"

namespace
{

using nav2_smac_planner::AStarAlgorithm;
using nav2_smac_planner::NodeHybrid;

double thread_cpu_seconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

[[noreturn]] void fail(const std::string & message)
{
  std::cerr << "smac_driver: " << message << std::endl;
  std::exit(2);
}

// The plugin's parameters: Smac's defaults (configure()) unless given with --param.
class Params
{
public:
  void set(const std::string & assignment)
  {
    auto eq = assignment.find('=');
    if (eq == std::string::npos) {
      fail("--param wants NAME=VALUE, got " + assignment);
    }
    values_[assignment.substr(0, eq)] = assignment.substr(eq + 1);
  }
  double number(const std::string & name, double fallback)
  {
    used_[name] = true;
    auto it = values_.find(name);
    return it == values_.end() ? fallback : std::stod(it->second);
  }
  bool flag(const std::string & name, bool fallback)
  {
    used_[name] = true;
    auto it = values_.find(name);
    return it == values_.end() ? fallback : (it->second == "true" || it->second == "1");
  }
  std::string text(const std::string & name, const std::string & fallback)
  {
    used_[name] = true;
    auto it = values_.find(name);
    return it == values_.end() ? fallback : it->second;
  }
  void check_all_used()
  {
    for (const auto & kv : values_) {
      if (!used_.count(kv.first)) {
        fail("unknown --param " + kv.first);
      }
    }
  }

private:
  std::map<std::string, std::string> values_;
  std::map<std::string, bool> used_;
};

struct Planner
{
  // configure()'s members
  std::shared_ptr<nav2::LifecycleNode> node = std::make_shared<nav2::LifecycleNode>();
  std::shared_ptr<nav2_costmap_2d::Costmap2DROS> costmap_ros;
  nav2_costmap_2d::Costmap2D * costmap = nullptr;
  nav2_smac_planner::SearchInfo search_info;
  nav2_smac_planner::MotionModel motion_model;
  nav2_smac_planner::GoalHeadingMode goal_heading_mode;
  std::unique_ptr<AStarAlgorithm<NodeHybrid>> a_star;
  nav2_smac_planner::GridCollisionChecker collision_checker{nullptr, 1, nullptr};
  double angle_bin_size = 0.0;
  unsigned int angle_quantizations = 0;
  float tolerance = 0.0f;
  bool allow_unknown = true;
  int max_iterations = 0, max_on_approach_iterations = 0, terminal_checking_interval = 0;
  int coarse_search_resolution = 1;
  double max_planning_time = 0.0, lookup_table_size = 0.0, minimum_turning_radius = 0.0;
  float lookup_table_dim = 0.0f;
};

// SmacPlannerHybridT<NodeHybrid>::configure, the parts that set up the search (parameter
// defaults as there; downsampling, smoother and publishers left out).
void configure(Planner & p, Params & params)
{
  const double resolution = p.costmap->getResolution();
  const int downsampling_factor = 1;  // downsample_costmap: false (the default)
  const int bins = static_cast<int>(params.number("angle_quantization_bins", 72));
  p.angle_bin_size = 2.0 * M_PI / bins;
  p.angle_quantizations = static_cast<unsigned int>(bins);
  p.tolerance = static_cast<float>(params.number("tolerance", 0.25));
  p.allow_unknown = params.flag("allow_unknown", true);
  p.max_iterations = static_cast<int>(params.number("max_iterations", 1000000));
  p.max_on_approach_iterations = static_cast<int>(params.number("max_on_approach_iterations", 1000));
  p.terminal_checking_interval = static_cast<int>(params.number("terminal_checking_interval", 5000));
  p.minimum_turning_radius = params.number("minimum_turning_radius", 0.4);
  auto & s = p.search_info;
  s.allow_primitive_interpolation = params.flag("allow_primitive_interpolation", true);
  s.cache_obstacle_heuristic = params.flag("cache_obstacle_heuristic", false);
  s.reverse_penalty = params.number("reverse_penalty", 2.0);
  s.change_penalty = params.number("change_penalty", 0.0);
  s.non_straight_penalty = params.number("non_straight_penalty", 1.2);
  s.cost_penalty = params.number("cost_penalty", 2.0);
  s.retrospective_penalty = params.number("retrospective_penalty", 0.015);
  s.analytic_expansion_ratio = params.number("analytic_expansion_ratio", 3.5);
  s.analytic_expansion_max_cost = params.number("analytic_expansion_max_cost", 200.0);
  s.analytic_expansion_max_cost_override =
    params.flag("analytic_expansion_max_cost_override", false);
  s.use_quadratic_cost_penalty = params.flag("use_quadratic_cost_penalty", false);
  s.downsample_obstacle_heuristic = params.flag("downsample_obstacle_heuristic", true);
  s.analytic_expansion_max_length =
    params.number("analytic_expansion_max_length", 3.0) / resolution;
  p.max_planning_time = params.number("max_planning_time", 5.0);
  p.lookup_table_size = params.number("lookup_table_size", 20.0);
  p.motion_model = nav2_smac_planner::fromString(
    params.text("motion_model_for_search", "DUBIN"));
  p.goal_heading_mode = nav2_smac_planner::fromStringToGH(
    params.text("goal_heading_mode", "DEFAULT"));
  p.coarse_search_resolution = static_cast<int>(params.number("coarse_search_resolution", 1));
  params.check_all_used();
  if (p.motion_model != nav2_smac_planner::MotionModel::DUBIN &&
    p.motion_model != nav2_smac_planner::MotionModel::REEDS_SHEPP)
  {
    fail("motion_model_for_search must be DUBIN or REEDS_SHEPP here");
  }
  if (p.max_on_approach_iterations <= 0) {
    p.max_on_approach_iterations = std::numeric_limits<int>::max();
  }
  if (p.max_iterations <= 0) {
    p.max_iterations = std::numeric_limits<int>::max();
  }
  if (p.minimum_turning_radius < resolution * downsampling_factor) {
    p.minimum_turning_radius = resolution * downsampling_factor;
  }
  s.minimum_turning_radius = p.minimum_turning_radius / (resolution * downsampling_factor);
  p.lookup_table_dim = static_cast<float>(p.lookup_table_size) /
    static_cast<float>(resolution * downsampling_factor);
  p.lookup_table_dim = static_cast<float>(static_cast<int>(p.lookup_table_dim));
  if (static_cast<int>(p.lookup_table_dim) % 2 == 0) {
    p.lookup_table_dim += 1.0f;
  }

  p.collision_checker = nav2_smac_planner::GridCollisionChecker(
    p.costmap_ros, p.angle_quantizations, p.node);
  p.collision_checker.setFootprint(
    p.costmap_ros->getRobotFootprint(), p.costmap_ros->getUseRadius(),
    nav2_smac_planner::findCircumscribedCost(p.costmap_ros));

  p.a_star = std::make_unique<AStarAlgorithm<NodeHybrid>>(p.motion_model, p.search_info);
  p.a_star->initialize(
    p.allow_unknown, p.max_iterations, p.max_on_approach_iterations,
    p.terminal_checking_interval, p.max_planning_time, p.lookup_table_dim,
    p.angle_quantizations);
}

unsigned int heading_bin(double yaw, const Planner & p)
{
  // createPlan's quantisation of the start and goal headings
  double bin = std::round(yaw / p.angle_bin_size);
  while (bin < 0.0) {
    bin += static_cast<float>(p.angle_quantizations);
  }
  if (bin >= static_cast<float>(p.angle_quantizations)) {
    bin -= static_cast<float>(p.angle_quantizations);
  }
  return static_cast<unsigned int>(bin);
}

struct Answer
{
  bool found = false;
  std::string reason;
  int iterations = 0;
  std::vector<std::array<double, 3>> poses;
};

// SmacPlannerHybridT<NodeHybrid>::createPlan without the smoother and the publishers.
Answer create_plan(Planner & p, const double s[3], const double g[3])
{
  Answer a;
  nav2_costmap_2d::Costmap2D * costmap = p.costmap;
  p.collision_checker.setFootprint(
    p.costmap_ros->getRobotFootprint(), p.costmap_ros->getUseRadius(),
    nav2_smac_planner::findCircumscribedCost(p.costmap_ros));
  p.a_star->setCollisionChecker(&p.collision_checker);

  float mx_start, my_start, mx_goal, my_goal;
  if (!costmap->worldToMapContinuous(s[0], s[1], mx_start, my_start)) {
    a.reason = "StartOutsideMapBounds";
    return a;
  }
  const unsigned int start_bin = heading_bin(s[2], p);
  p.a_star->setStart(mx_start, my_start, start_bin);
  if (!costmap->worldToMapContinuous(g[0], g[1], mx_goal, my_goal)) {
    a.reason = "GoalOutsideMapBounds";
    return a;
  }
  const unsigned int goal_bin = heading_bin(g[2], p);
  p.a_star->setGoal(mx_goal, my_goal, goal_bin, p.goal_heading_mode, p.coarse_search_resolution);

  if (std::floor(mx_start) == std::floor(mx_goal) && std::floor(my_start) == std::floor(my_goal) &&
    start_bin == goal_bin)
  {
    a.found = true;
    a.poses.push_back({s[0], s[1], g[2]});
    return a;
  }

  NodeHybrid::CoordinateVector path;
  int num_iterations = 0;
  try {
    if (!p.a_star->createPath(
        path, num_iterations, p.tolerance / static_cast<float>(costmap->getResolution()),
        []() {return false;}, nullptr))
    {
      a.iterations = num_iterations;
      a.reason = num_iterations == 1 ? "StartOccupied" :
        num_iterations < p.a_star->getMaxIterations() ? "NoValidPathCouldBeFound" :
        "PlannerTimedOut (max_iterations)";
      return a;
    }
  } catch (const std::exception & e) {
    a.iterations = num_iterations;
    a.reason = e.what();
    return a;
  }
  a.iterations = num_iterations;
  a.found = true;
  a.poses.reserve(path.size());
  for (int i = static_cast<int>(path.size()) - 1; i >= 0; --i) {
    geometry_msgs::msg::Pose pose = nav2_smac_planner::getWorldCoords(path[i].x, path[i].y, costmap);
    pose.orientation = nav2_smac_planner::getWorldOrientation(path[i].theta);
    a.poses.push_back({pose.position.x, pose.position.y, tf2::getYaw(pose.orientation)});
  }
  return a;
}

std::vector<geometry_msgs::msg::Point> parse_footprint(const std::string & text)
{
  std::vector<geometry_msgs::msg::Point> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ';')) {
    geometry_msgs::msg::Point pt;
    if (std::sscanf(item.c_str(), "%lf,%lf", &pt.x, &pt.y) != 2) {
      fail("bad --footprint vertex " + item);
    }
    out.push_back(pt);
  }
  if (out.size() < 3) {
    fail("--footprint needs at least 3 vertices");
  }
  return out;
}

}  // namespace

int main(int argc, char ** argv)
{
  std::string map_path, footprint_text;
  unsigned int width = 0, height = 0;
  double resolution = 0.0, origin_x = 0.0, origin_y = 0.0;
  double inflation_radius = -1.0, cost_scaling_factor = 0.0;
  Params params;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    auto next = [&]() -> std::string {
        if (i + 1 >= argc) {fail(arg + " needs a value");}
        return argv[++i];
      };
    if (arg == "--map") {map_path = next();} else if (arg == "--width") {
      width = std::stoul(next());
    } else if (arg == "--height") {height = std::stoul(next());} else if (arg == "--resolution") {
      resolution = std::stod(next());
    } else if (arg == "--origin") {
      origin_x = std::stod(next());
      origin_y = std::stod(next());
    } else if (arg == "--footprint") {footprint_text = next();} else if (arg == "--param") {
      params.set(next());
    } else if (arg == "--inflation") {
      inflation_radius = std::stod(next());
      cost_scaling_factor = std::stod(next());
    } else {
      fail("unknown argument " + arg);
    }
  }
  if (map_path.empty() || !width || !height || resolution <= 0.0 || footprint_text.empty()) {
    fail("need --map, --width, --height, --resolution and --footprint");
  }
  std::vector<unsigned char> costs(static_cast<size_t>(width) * height);
  std::ifstream in(map_path, std::ios::binary);
  if (!in.read(reinterpret_cast<char *>(costs.data()), costs.size())) {
    fail("could not read " + std::to_string(costs.size()) + " bytes from " + map_path);
  }

  nav2_costmap_2d::Costmap2D costmap(width, height, resolution, origin_x, origin_y, 0);
  std::memcpy(costmap.getCharMap(), costs.data(), costs.size());
  auto footprint = parse_footprint(footprint_text);
  // inscribed and circumscribed radius as LayeredCostmap::setFootprint computes them
  const auto radii = nav2_costmap_2d::calculateMinAndMaxDistances(footprint);

  Planner p;
  p.costmap = &costmap;
  p.costmap_ros = std::make_shared<nav2_costmap_2d::Costmap2DROS>(&costmap, footprint, radii.second);
  if (inflation_radius >= 0.0) {
    p.costmap_ros->inflation_layer = std::make_shared<nav2_costmap_2d::InflationLayerInterface>(
      inflation_radius, cost_scaling_factor, radii.first, resolution);
  }
  const auto w0 = std::chrono::steady_clock::now();
  configure(p, params);
  const double configure_ms = std::chrono::duration<double, std::milli>(
    std::chrono::steady_clock::now() - w0).count();
  std::printf(
    "{\"configured\":true,\"configure_ms\":%.3f,\"motion\":\"%s\",\"bins\":%u,"
    "\"circumscribed_cost\":%.1f,\"inscribed_radius\":%.4f,\"circumscribed_radius\":%.4f,"
    "\"reverse_penalty\":%g,\"change_penalty\":%g,\"non_straight_penalty\":%g,\"cost_penalty\":%g,"
    "\"retrospective_penalty\":%g,\"analytic_expansion_ratio\":%g,"
    "\"analytic_expansion_max_length_cells\":%g,\"minimum_turning_radius_cells\":%g,"
    "\"allow_primitive_interpolation\":%s,\"downsample_obstacle_heuristic\":%s,"
    "\"max_iterations\":%d,\"max_planning_time\":%g,\"tolerance\":%g,\"lookup_table_dim\":%g}\n",
    configure_ms, nav2_smac_planner::toString(p.motion_model).c_str(), p.angle_quantizations,
    nav2_smac_planner::findCircumscribedCost(p.costmap_ros), radii.first, radii.second,
    p.search_info.reverse_penalty, p.search_info.change_penalty, p.search_info.non_straight_penalty,
    p.search_info.cost_penalty, p.search_info.retrospective_penalty,
    p.search_info.analytic_expansion_ratio, p.search_info.analytic_expansion_max_length,
    p.search_info.minimum_turning_radius,
    p.search_info.allow_primitive_interpolation ? "true" : "false",
    p.search_info.downsample_obstacle_heuristic ? "true" : "false",
    p.max_iterations, p.max_planning_time, p.tolerance, p.lookup_table_dim);
  std::fflush(stdout);

  std::string line;
  while (std::getline(std::cin, line)) {
    double s[3], g[3];
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf", &s[0], &s[1], &s[2], &g[0], &g[1],
      &g[2]) != 6)
    {
      if (line.find_first_not_of(" \t\r") == std::string::npos) {continue;}
      fail("bad query line: " + line);
    }
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_seconds();
    Answer a = create_plan(p, s, g);
    const double cpu_ms = 1000.0 * (thread_cpu_seconds() - cpu0);
    const double wall_ms = std::chrono::duration<double, std::milli>(
      std::chrono::steady_clock::now() - wall0).count();
    double length = 0.0;
    for (size_t i = 1; i < a.poses.size(); ++i) {
      length += std::hypot(a.poses[i][0] - a.poses[i - 1][0], a.poses[i][1] - a.poses[i - 1][1]);
    }
    std::ostringstream out;
    out.precision(9);
    out << "{\"found\":" << (a.found ? "true" : "false") << ",\"reason\":\"" << a.reason
        << "\",\"wall_ms\":" << wall_ms << ",\"cpu_ms\":" << cpu_ms << ",\"iterations\":"
        << a.iterations << ",\"length_m\":" << length << ",\"poses\":[";
    for (size_t i = 0; i < a.poses.size(); ++i) {
      out << (i ? "," : "") << "[" << a.poses[i][0] << "," << a.poses[i][1] << "," <<
        a.poses[i][2] << "]";
    }
    out << "]}\n";
    std::fputs(out.str().c_str(), stdout);
    std::fflush(stdout);
  }
  return 0;
}
