#include "vdtnav/camera_sim/scooter_drive.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "vdtnav/core/error.hpp"

namespace vdtnav::rgbd_ground {

ScooterDrive simulate_scooter_drive(const ParkScene& scene, const ScooterDriveOptions& o) {
  VDTNAV_CHECK(
      o.length > 0.0 && o.frame_rate > 0.0 && o.min_speed > 0.0 && o.max_speed >= o.min_speed,
      "scooter drive: length, frame rate and speeds must be > 0");
  // The route: the loop's centre line, and every second lap in via one gravel path over the
  // plaza and out via the opposite one (loop vertices 1 and 7 are where they meet the loop).
  std::vector<Eigen::Vector2d> lap(scene.loop.begin(), scene.loop.end());
  lap.push_back(scene.loop[0]);
  std::vector<Eigen::Vector2d> detour;
  for (std::size_t i = 0; i <= 1; ++i) detour.push_back(scene.loop[i]);
  detour.push_back(scene.plaza);
  for (std::size_t i = 7; i <= scene.loop.size(); ++i)
    detour.push_back(scene.loop[i % scene.loop.size()]);
  std::vector<Eigen::Vector2d> route;
  for (int k = 0; route.size() < 2 || k < 20; ++k) {
    const auto& part = (k % 2 == 1) ? detour : lap;
    route.insert(route.end(), part.begin() + (route.empty() ? 0 : 1), part.end());
  }
  // Smooth the corners: pieces of at most 1 m, then Chaikin's corner cutting, three rounds (which
  // then rounds each corner within ~0.5 m of it, on the path).
  {
    std::vector<Eigen::Vector2d> dense{route.front()};
    for (std::size_t i = 0; i + 1 < route.size(); ++i) {
      const int pieces = std::max(1, static_cast<int>(std::ceil((route[i + 1] - route[i]).norm())));
      for (int k = 1; k <= pieces; ++k)
        dense.push_back(route[i] + (route[i + 1] - route[i]) * (static_cast<double>(k) / pieces));
    }
    route = dense;
  }

  for (int round = 0; round < 3; ++round) {
    std::vector<Eigen::Vector2d> s{route.front()};
    for (std::size_t i = 0; i + 1 < route.size(); ++i) {
      s.push_back(0.75 * route[i] + 0.25 * route[i + 1]);
      s.push_back(0.25 * route[i] + 0.75 * route[i + 1]);
    }
    s.push_back(route.back());
    route = s;
  }
  std::mt19937_64 rng(o.seed * 31 + 7);
  std::normal_distribution<double> n01(0.0, 1.0);
  ScooterDrive d;
  double s = 0.0, time = 0.0;
  std::size_t seg = 0;
  double seg_pos = 0.0;  // metres along route[seg] -> route[seg + 1]
  const double dt = 1.0 / o.frame_rate;
  const auto pose_at = [&]() {
    const Eigen::Vector2d a = route[seg], b = route[seg + 1];
    const Eigen::Vector2d t = (b - a).normalized();
    const Eigen::Vector2d p = a + seg_pos * t;
    return Pose2(p.x(), p.y(), std::atan2(t.y(), t.x()));
  };
  while (s <= o.length && seg + 1 < route.size()) {
    d.time.push_back(time);
    d.truth.push_back(pose_at());
    const double speed = 0.5 * (o.min_speed + o.max_speed) +
                         0.5 * (o.max_speed - o.min_speed) * std::sin(2.0 * M_PI * time / 40.0);
    double step = speed * dt;
    s += step;
    time += dt;
    while (step > 0.0 && seg + 1 < route.size()) {
      const double left = (route[seg + 1] - route[seg]).norm() - seg_pos;
      if (step < left) {
        seg_pos += step;
        step = 0.0;
      } else {
        step -= left;
        ++seg;
        seg_pos = 0.0;
      }
    }
    if (seg + 1 >= route.size()) break;
  }
  d.odometry.resize(d.truth.size());
  for (std::size_t k = 1; k < d.truth.size(); ++k) {
    const Pose2 delta = between(d.truth[k - 1], d.truth[k]);
    const double dist = delta.head<2>().norm();
    OdometryStep st;
    st.dt = dt;
    st.delta = Pose2(delta[0] + o.odometry_sigma_per_m * dist * n01(rng),
                     delta[1] + o.odometry_sigma_per_m * dist * n01(rng),
                     delta[2] + (o.odometry_sigma_yaw_per_rad * std::abs(delta[2]) +
                                 o.odometry_sigma_yaw_per_m * dist) *
                                    n01(rng));
    st.v = dist / dt;
    st.w = delta[2] / dt;
    d.odometry[k] = st;
  }
  return d;
}

MotionNoise drive_odometry_noise(const ScooterDriveOptions& o) {
  MotionNoise n;
  n.a_tt = o.odometry_sigma_per_m;
  n.a_tr = 0.0;
  n.a_rr = o.odometry_sigma_yaw_per_rad;
  n.a_rt = o.odometry_sigma_yaw_per_m;
  n.floor_t = 1e-4;
  n.floor_r = 1e-4;
  return n;
}

}  // namespace vdtnav::rgbd_ground
