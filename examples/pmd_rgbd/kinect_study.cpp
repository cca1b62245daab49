// The PMD study's relative localization between recorded RGB-D frames (--kinect): each frame's
// boundary points on a VDT map of the other frames' points, reported in kinect_relative.csv.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pmd_study.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/io/point_set_map.hpp"
#include "vdtnav/rgbd_ground/camera_mount.hpp"
#include "vdtnav/rgbd_ground/ground_boundaries.hpp"
#include "vdtnav/rgbd_ground/ground_plane.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

namespace pmd_study {

using namespace vdtnav;
using namespace vdtnav::rgbd_ground;

int kinect_study(const std::string& dir, const std::string& calibration, const std::string& out) {
  camera::CameraCalibration cal;
  if (calibration.empty()) {
    cal.width = 640;
    cal.height = 480;
    cal.camera_matrix << 518.0, 0.0, 325.5, 0.0, 519.0, 253.5, 0.0, 0.0, 1.0;
  } else {
    cal = camera::read_calibration(calibration);
  }
  const std::vector<Eigen::Isometry3d> poses = read_camera_poses(dir + "/pose.txt");
  // A hand-held camera ~1.4 m up, looking forward and ~25 degrees down; the fit may move it by
  // up to 0.6 rad and 0.4 m. Indoors a carpet's edges are edges of lightness too.
  const Eigen::Isometry3d nominal =
      tilted_camera(Eigen::Vector3d(0.0, 0.0, 1.4), 0.0, 25.0 * M_PI / 180.0);
  GroundBoundaryOptions o;
  o.plane.max_tilt = 0.6;
  o.use_lightness = true;
  const GroundBoundaryExtractor ex(camera::PinholeCamera(cal), nominal, o);
  std::vector<GroundBoundaries> frames;
  std::vector<Eigen::Isometry3d> robot_in_world;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string n = std::to_string(i + 1);
    frames.push_back(ex.extract(
        read_rgbd_frame(dir + "/color/" + n + ".png", dir + "/depth/" + n + ".pgm", 1000.0)));
    if (!frames.back().plane.found) throw std::runtime_error("frame " + n + ": no floor found");
    robot_in_world.push_back(poses[i] *
                             levelled_extrinsics(nominal, frames.back().plane).inverse());
  }
  std::vector<Pose2> given;  // on the floor, robot frame of frame 1
  for (const Eigen::Isometry3d& t : robot_in_world) {
    const Eigen::Isometry3d r = robot_in_world[0].inverse() * t;
    given.emplace_back(r.translation().x(), r.translation().y(),
                       std::atan2(r.linear()(1, 0), r.linear()(0, 0)));
  }
  std::filesystem::create_directories(out);
  std::ofstream csv(out + "/kinect_relative.csv");
  csv << "frame,points,explained_pct,from_given_m,from_given_deg,from_off_m,from_off_deg\n";
  std::printf("[kinect] %zu frames of %s: each on a 2 cm map of the others' boundaries\n",
              frames.size(), dir.c_str());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::vector<Eigen::Vector2d> map_points;
    for (std::size_t j = 0; j < frames.size(); ++j) {
      if (j == i) continue;
      const Eigen::Rotation2Dd rot(given[j][2]);
      for (const BoundaryPoint& b : frames[j].points) {
        map_points.push_back(rot * b.robot + given[j].head<2>());
      }
    }
    const VdtMap2 map = VdtMap2::build(occupancy_from_points<2>(map_points, 0.02, 1.0));
    const ScanPoints obs = ex.observations(frames[i]);
    const Eigen::Rotation2Dd rot(given[i][2]);
    std::size_t near = 0;  // within 5 cm of the others' boundaries at the given pose
    for (const Eigen::Vector2d& p : obs.points) {
      near += map.value(rot * p + given[i].head<2>()).norm() < 0.05;
    }
    VdtOptimizerOptions oo;
    oo.sensor.gate = 0.1;  // five cells
    const VdtOptimizer opt(map, oo);
    const auto error_from = [&](const Pose2& start) {
      const Eigen::Vector3d e = pose_error(opt.solve(obs, start).pose, given[i]);
      return Eigen::Vector2d(e.head<2>().norm(), std::abs(e[2]) * 180.0 / M_PI);
    };
    const Eigen::Vector2d at = error_from(given[i]);
    const Eigen::Vector2d off = error_from(given[i] + Pose2(0.04, 0.03, M_PI / 180.0));
    const double pct = 100.0 * static_cast<double>(near) / static_cast<double>(obs.size());
    char line[256];
    std::snprintf(line, sizeof line, "%zu,%zu,%.1f,%.4f,%.3f,%.4f,%.3f\n", i + 1, obs.size(), pct,
                  at[0], at[1], off[0], off[1]);
    csv << line;
    std::printf(
        "  frame %zu: %zu points, %.0f %% within 5 cm of the others' map; from the given "
        "pose %.3f m %.2f deg, from 5 cm / 1 deg off %.3f m %.2f deg\n",
        i + 1, obs.size(), pct, at[0], at[1], off[0], off[1]);
  }
  std::printf("[done] %s/kinect_relative.csv\n", out.c_str());
  return 0;
}

}  // namespace pmd_study
