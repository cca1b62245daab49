#include "vdtnav/sim/mapping_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {

MappingRun simulate_mapping_run(const OccupancyGrid<2>& world, const std::vector<Pose2>& truth,
                                const LidarOptions& lidar, const MappingNoise& noise,
                                std::uint32_t seed) {
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  VDTNAV_CHECK(!truth.empty(), "simulate_mapping_run: no pose");
  VDTNAV_CHECK(std::isfinite(lidar.fov) && lidar.fov > 0.0 && lidar.fov <= kTwoPi &&
                   std::isfinite(lidar.angular_resolution) && lidar.angular_resolution > 0.0,
               "simulate_mapping_run: lidar fov must be in (0, 2 pi] and its resolution > 0");
  VDTNAV_CHECK(
      lidar.range_min >= 0.0 && lidar.range_max > lidar.range_min && std::isfinite(lidar.range_max),
      "simulate_mapping_run: lidar ranges must satisfy 0 <= range_min < range_max < inf");
  for (double s : {noise.sigma_xy, noise.sigma_phi, noise.sigma_range, lidar.sigma_range}) {
    VDTNAV_CHECK(std::isfinite(s) && s >= 0.0, "simulate_mapping_run: noise sigmas must be >= 0");
  }
  std::seed_seq range_seq{seed, 0x52414e47u}, pose_seq{seed, 0x504f5345u};
  std::mt19937_64 range_rng(range_seq), pose_rng(pose_seq);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Matrix3d pose_cov =
      Eigen::Vector3d(noise.sigma_xy * noise.sigma_xy, noise.sigma_xy * noise.sigma_xy,
                      noise.sigma_phi * noise.sigma_phi)
          .asDiagonal();
  const int beams = lidar.num_beams();

  MappingRun run;
  run.truth = truth;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const Pose2& x = truth[k];
    VDTNAV_CHECK(x.allFinite(),
                 "simulate_mapping_run: pose " + std::to_string(k) + " is not finite");
    mapping::MapScan scan;
    scan.pose = x;
    scan.pose[0] += noise.sigma_xy * normal(pose_rng);
    scan.pose[1] += noise.sigma_xy * normal(pose_rng);
    scan.pose[2] = wrap_angle(scan.pose[2] + noise.sigma_phi * normal(pose_rng));
    scan.pose_covariance = pose_cov;
    scan.points.sigma_range = noise.sigma_range > 0.0 ? noise.sigma_range : lidar.sigma_range;
    scan.points.range_max = lidar.range_max;
    const Pose2 sensor = compose(x, lidar.mount);
    for (int b = 0; b < beams; ++b) {
      const double theta = -0.5 * lidar.fov + b * lidar.angular_resolution;
      const double eps = normal(range_rng);  // one draw per beam, hit or not
      const Eigen::Vector2d u_world(std::cos(sensor[2] + theta), std::sin(sensor[2] + theta));
      const double r0 =
          cast_ray<2>(world, sensor.head<2>(), u_world, lidar.range_max, RaySurface::kCellCentre);
      if (!std::isfinite(r0) || r0 < lidar.range_min) continue;
      const double r = std::max(0.0, r0 + noise.sigma_range * eps);
      const Eigen::Vector2d u_robot =
          Eigen::Rotation2Dd(lidar.mount[2]) * Eigen::Vector2d(std::cos(theta), std::sin(theta));
      scan.points.add(lidar.mount.head<2>(), u_robot, r, static_cast<std::size_t>(b));
      run.true_boundary.push_back(sensor.head<2>() + r0 * u_world);
    }
    run.scans.push_back(std::move(scan));
  }
  return run;
}

MappingScene l_shaped_room(double resolution) {
  VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0.0 && resolution <= 0.5,
               "l_shaped_room: resolution must be in (0, 0.5] m");
  constexpr double kPi = 3.14159265358979323846;
  MappingScene scene;
  scene.name = "L-shaped room";
  // Cell centres on whole multiples of the resolution from -0.5 m, so the walls (at 0, 3 and 6 m)
  // run through them and the world's VDT is zero on them.
  const int n = static_cast<int>(std::lround(7.0 / resolution)) + 1;
  scene.world = OccupancyGrid<2>(
      Eigen::Vector2i(n, n),
      GridFrame<2>(resolution, Eigen::Vector2d::Constant(-0.5 - 0.5 * resolution)));
  const std::vector<Eigen::Vector2d> corners = {{0, 0}, {6, 0}, {6, 3}, {3, 3}, {3, 6}, {0, 6}};
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % corners.size()];
    const int steps = static_cast<int>(std::ceil((b - a).norm() / (0.25 * resolution)));
    for (int k = 0; k <= steps; ++k) {
      scene.world(scene.world.cell_of(a + (b - a) * (static_cast<double>(k) / steps))) = 1;
    }
  }
  scene.poses = {Pose2(4.8, 1.5, kPi), Pose2(1.5, 4.8, -0.5 * kPi), Pose2(1.2, 1.2, 0.25 * kPi)};
  return scene;
}

std::vector<TimedPose> mapping_drive(const MappingScene& scene) {
  VDTNAV_CHECK(scene.path.size() >= 2, "mapping_drive: the scene has no path");
  TrajectoryOptions o;
  o.rate_hz = 10.0;
  o.min_steps = 2;
  return follow_path(scene.path, scene.world, o);
}

MappingScene scene_along(std::string name, OccupancyGrid<2> world,
                         std::vector<Eigen::Vector2d> path) {
  MappingScene scene;
  scene.name = std::move(name);
  scene.world = std::move(world);
  scene.path = std::move(path);
  for (const TimedPose& tp : mapping_drive(scene)) {
    if (scene.poses.empty() || (tp.pose.head<2>() - scene.poses.back().head<2>()).norm() >= 0.5 ||
        std::abs(wrap_angle(tp.pose[2] - scene.poses.back()[2])) >= 0.3) {
      scene.poses.push_back(tp.pose);
    }
  }
  return scene;
}

MappingScene generated_corridor(std::uint32_t seed) {
  FloorPlanOptions o;
  o.seed = seed;
  FloorPlan plan = generate_floor_plan(o);
  std::vector<Eigen::Vector2d> path = {Eigen::Vector2d(3.0, plan.corridor_y),
                                       Eigen::Vector2d(o.width - 3.0, plan.corridor_y)};
  return scene_along("generated floor plan, main corridor", std::move(plan.occupancy),
                     std::move(path));
}

}  // namespace vdtnav::sim
