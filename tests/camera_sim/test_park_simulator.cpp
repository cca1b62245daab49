// The PMD study's simulator: the park's boundary map against its surfaces, a rendered frame's
// depth against the analytic ground and obstacle intersections, the drive on the paths at the
// requested length and speeds, and the landmark detector's bearings, misses and false positives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "vdtnav/camera_sim/landmark_detections.hpp"
#include "vdtnav/camera_sim/park_renderer.hpp"
#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/camera_sim/scooter_drive.hpp"

namespace vdtnav::rgbd_ground {
namespace {

const ParkScene& park() {
  static const ParkScene p = generate_park({});
  return p;
}

TEST(ParkScene, BoundaryCellsAreExactlyThoseBesideAnotherSurface) {
  const OccupancyGrid<2> map = park().boundary_map(0.1);
  int boundary = 0, checked = 0;
  for (int y = 1; y + 1 < map.size().y(); y += 3) {
    for (int x = 1; x + 1 < map.size().x(); x += 3) {
      const Surface here = park().surface_at(map.cell_center({x, y}));
      bool differs = false;
      for (const auto& [dx, dy] :
           {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
        differs |= park().surface_at(map.cell_center({x + dx, y + dy})) != here;
      EXPECT_EQ(map({x, y}) != 0, differs) << x << " " << y;
      boundary += differs;
      ++checked;
    }
  }
  EXPECT_GT(boundary, 100);
  EXPECT_LT(boundary, checked / 5);
  // The loop's centre line is pavement, 2 m beside a straight stretch is grass.
  EXPECT_EQ(park().surface_at(0.5 * (park().loop[2] + park().loop[3])), Surface::kPavement);
  EXPECT_EQ(park().surface_at(park().plaza), Surface::kGravel);
}

TEST(ParkRenderer, DepthIsTheAnalyticIntersection) {
  RenderOptions o;
  o.noise.sigma_z2 = 0.0;
  o.holes = 0.0;
  o.pixel_noise = 0.0;
  const camera::CameraCalibration cal = default_rgbd_calibration();
  const Eigen::Isometry3d mount = default_rear_camera();
  const ParkRenderer r(park(), cal, mount);
  const ScooterDrive d = simulate_scooter_drive(park(), {});
  const Pose2 pose = d.truth[40];
  std::mt19937 rng(1);
  const RgbdFrame f = r.render(pose, o, rng);
  const camera::PinholeCamera cam(cal);
  Eigen::Isometry3d world_robot = Eigen::Isometry3d::Identity();
  world_robot.linear() = Eigen::AngleAxisd(pose[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_robot.translation() = Eigen::Vector3d(pose[0], pose[1], 0.0);
  const Eigen::Isometry3d world_cam = world_robot * mount;
  int ground = 0;
  for (int v = 300; v < 480; v += 30) {
    for (int u = 20; u < 640; u += 60) {
      const Eigen::Vector2d n = cam.undistort({Eigen::Vector2d(u, v)})[0];
      const Eigen::Vector3d dir = world_cam.linear() * Eigen::Vector3d(n.x(), n.y(), 1.0);
      const double t = -world_cam.translation().z() / dir.z();  // z-depth of the ground hit
      const Eigen::Vector3d g = world_cam.translation() + t * dir;
      // Only pixels whose ray surely meets the ground first: its ground track from the camera
      // passes no obstacle's bounding circle.
      bool blocked = false;
      const Eigen::Vector2d a = world_cam.translation().head<2>(), b = g.head<2>();
      for (const ParkObstacle& ob : park().obstacles) {
        const double reach = std::max(ob.radius, ob.half_size.norm()) + 0.05;
        const double s = std::clamp((ob.centre - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        blocked |= (a + s * (b - a) - ob.centre).norm() < reach;
      }
      if (blocked) continue;
      EXPECT_NEAR(f.depth.at<float>(v, u), t, 1e-4 * t) << u << " " << v;
      ++ground;
    }
  }
  EXPECT_GT(ground, 20);
}

TEST(ScooterDrive, StaysOnThePathsAtTheRequestedLengthAndSpeeds) {
  ScooterDriveOptions o;
  const ScooterDrive d = simulate_scooter_drive(park(), o);
  double length = 0.0;
  for (std::size_t k = 0; k < d.truth.size(); ++k) {
    EXPECT_NE(park().surface_at(d.truth[k].head<2>()), Surface::kGrass) << k;
    if (k == 0) continue;
    const double step = (d.truth[k].head<2>() - d.truth[k - 1].head<2>()).norm();
    length += step;
    EXPECT_LE(step * o.frame_rate, o.max_speed + 1e-9);
    EXPECT_GE(step * o.frame_rate, 0.8 * o.min_speed);  // corners cut the chord
  }
  EXPECT_NEAR(length, o.length, 5.0);
}

TEST(LandmarkDetections, BearingsMissesAndFalsePositivesFollowTheirOptions) {
  DetectionOptions exact;
  exact.sigma = 1e-12;
  exact.miss_probability = 0.0;
  exact.false_per_frame = 0.0;
  const ScooterDrive d = simulate_scooter_drive(park(), {});
  std::mt19937 rng(2);
  const std::vector<Landmark2> lm = park_landmarks(park());
  int visible = 0;
  for (std::size_t k = 0; k < d.truth.size(); k += 50) {
    for (const BearingDetection& z : detect_landmarks(park(), d.truth[k], exact, rng)) {
      double best = 1e9;
      for (const Landmark2& l : lm)
        best = std::min(
            best,
            std::abs(wrap_angle(z.bearing - predicted_bearing(d.truth[k], l.position,
                                                              Eigen::Vector2d::Zero(), nullptr))));
      EXPECT_LT(best, 1e-9);
      ++visible;
    }
  }
  ASSERT_GT(visible, 20);
  // 2000 frames at one pose: misses and false positives at their rates.
  DetectionOptions o;
  const Pose2 at = d.truth[100];
  const std::size_t seen = detect_landmarks(park(), at, exact, rng).size();
  ASSERT_GT(seen, 0u);
  double total = 0.0;
  for (int k = 0; k < 2000; ++k)
    total += static_cast<double>(detect_landmarks(park(), at, o, rng).size());
  const double expected =
      static_cast<double>(seen) * (1.0 - o.miss_probability) + o.false_per_frame;
  EXPECT_NEAR(total / 2000.0, expected, 0.05 * expected + 0.05);
}

}  // namespace
}  // namespace vdtnav::rgbd_ground
