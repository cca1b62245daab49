#include "vdtnav/camera_sim/landmark_detections.hpp"

#include <cmath>

namespace vdtnav::rgbd_ground {

std::vector<BearingDetection> detect_landmarks(const ParkScene& scene, const Pose2& robot,
                                               const DetectionOptions& o, std::mt19937& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<BearingDetection> out;
  for (const Eigen::Vector2d& l : scene.lamp_posts) {
    const Eigen::Vector2d rel = l - robot.head<2>();
    const double bearing = wrap_angle(std::atan2(rel.y(), rel.x()) - robot[2]);
    if (rel.norm() > o.max_range || rel.norm() < 0.5 || std::abs(bearing) > o.half_fov) continue;
    if (u01(rng) < o.miss_probability) continue;
    out.push_back({wrap_angle(bearing + o.sigma * n01(rng)), o.sigma, 0});
  }
  std::poisson_distribution<int> false_count(o.false_per_frame);
  for (int k = false_count(rng); k > 0; --k) {
    out.push_back({o.half_fov * (2.0 * u01(rng) - 1.0), o.sigma, 0});
  }
  return out;
}

std::vector<Landmark2> park_landmarks(const ParkScene& scene) {
  std::vector<Landmark2> out;
  for (const Eigen::Vector2d& l : scene.lamp_posts) out.push_back({l, 0});
  return out;
}

}  // namespace vdtnav::rgbd_ground
