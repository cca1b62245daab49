// vdtnav_active_beam: the datasets, a map and a drive through it each, and the odometry of a
// drive (active_beam_study.hpp).
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "active_beam_study.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/route_planner.hpp"

namespace active_beam_study {
namespace {

/// The planner's grid: unknown cells of a SLAM map blocked too (the robot drives where the map
/// saw free space).
OccupancyGrid<2> known_free(const RosMap& m) {
  OccupancyGrid<2> g(m.cells.size(), m.cells.frame(), 0);
  for (int y = 0; y < g.size().y(); ++y) {
    for (int x = 0; x < g.size().x(); ++x) {
      const int v = m.cells(Eigen::Vector2i(x, y));
      g(Eigen::Vector2i(x, y)) = (v < 0 || v >= 65) ? 1 : 0;
    }
  }
  return g;
}

std::vector<sim::TimedPose> drive_through(const OccupancyGrid<2>& plan_grid, int waypoints,
                                          double minutes, std::uint32_t seed) {
  sim::TrajectoryOptions t;
  t.rate_hz = 40.0;
  t.min_steps = static_cast<int>(minutes * 60.0 * t.rate_hz);
  const std::vector<Vector2d> path = sim::plan_tour(plan_grid, waypoints, 0.5, seed);
  std::vector<sim::TimedPose> drive = sim::follow_path(path, plan_grid, t);
  if (drive.size() > static_cast<std::size_t>(t.min_steps)) drive.resize(t.min_steps);
  return drive;
}

}  // namespace

/// Odometry of the drive with Table 3.2's noise read as sigmas (sim/lidar_simulator.hpp).
std::vector<OdometryStep> odometry(const std::vector<sim::TimedPose>& drive, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<OdometryStep> out(drive.size());
  for (std::size_t k = 1; k < drive.size(); ++k) {
    OdometryStep& o = out[k];
    o.dt = drive[k].t - drive[k - 1].t;
    o.v = drive[k].v + 0.05 * n01(rng);
    o.w = drive[k].w + 0.01 * n01(rng);
    o.delta = sim::unicycle_increment(o.v, o.w, o.dt);
  }
  return out;
}

std::vector<Dataset> make_datasets(const std::string& data, unsigned seed, double minutes) {
  std::vector<Dataset> datasets;
  {
    Dataset d;
    d.beam = RotatingBeamOptions::table_4_1();
    const std::string willow = data + "/ros-maps/willow-garage/willow-full.pgm";
    if (!data.empty() && std::filesystem::exists(willow)) {
      d.name = "dataset1 (Willow Garage)";
      d.world = load_occupancy_image(willow, Vector2d(54.0, 58.7), 0.1);
    } else {
      sim::FloorPlanOptions o;
      o.seed = seed;
      d.name = "dataset1 (generated floor plan)";
      d.world = sim::generate_floor_plan(o).occupancy;
    }
    d.drive = drive_through(d.world, 4, minutes, seed);
    datasets.push_back(std::move(d));
  }
  {
    Dataset d;
    d.beam = RotatingBeamOptions::table_4_3();
    const std::string office = data + "/ros-maps/fetch-office/4_26_15.yaml";
    if (!data.empty() && std::filesystem::exists(office)) {
      const RosMap m = load_ros_map(office);
      d.name = "dataset2 (fetch office)";
      d.world = occupancy(m);
      d.drive = drive_through(known_free(m), 4, minutes, seed + 1);
    } else {
      sim::FloorPlanOptions o;
      o.seed = seed + 1;
      d.name = "dataset2 (generated floor plan)";
      d.world = sim::generate_floor_plan(o).occupancy;
      d.drive = drive_through(d.world, 4, minutes, seed + 1);
    }
    datasets.push_back(std::move(d));
  }
  return datasets;
}

}  // namespace active_beam_study
