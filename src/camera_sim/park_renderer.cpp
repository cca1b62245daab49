#include "vdtnav/camera_sim/park_renderer.hpp"

#include "vdtnav/rgbd_ground/camera_mount.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdtnav::rgbd_ground {
namespace {

/// A value in [-1, 1] fixed to ground cell (i, j) (a hash: the texture does not move).
double hash_noise(std::int64_t i, std::int64_t j, std::uint64_t salt) {
  std::uint64_t h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL ^
                    static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL ^ salt;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  return static_cast<double>(h & 0xffffff) / static_cast<double>(0x7fffff) - 1.0;
}

/// Ray (o + t d, t > 0) against an obstacle: the nearest t, or infinity.
double hit(const ParkObstacle& ob, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t_in = 0.0, t_out = std::numeric_limits<double>::infinity();
  if (ob.radius > 0.0) {
    const Eigen::Vector2d oc = o.head<2>() - ob.centre;
    const double a = d.head<2>().squaredNorm(), b = oc.dot(d.head<2>()),
                 c = oc.squaredNorm() - ob.radius * ob.radius;
    const double disc = b * b - a * c;
    if (a <= 0.0 || disc < 0.0) return std::numeric_limits<double>::infinity();
    t_in = (-b - std::sqrt(disc)) / a;
    t_out = (-b + std::sqrt(disc)) / a;
  } else {
    for (int k = 0; k < 2; ++k) {
      const double lo = ob.centre[k] - ob.half_size[k], hi = ob.centre[k] + ob.half_size[k];
      if (std::abs(d[k]) < 1e-12) {
        if (o[k] < lo || o[k] > hi) return std::numeric_limits<double>::infinity();
        continue;
      }
      const double a = (lo - o[k]) / d[k], b = (hi - o[k]) / d[k];
      t_in = std::max(t_in, std::min(a, b));
      t_out = std::min(t_out, std::max(a, b));
    }
  }
  // The vertical extent [0, height].
  if (std::abs(d.z()) > 1e-12) {
    const double a = (0.0 - o.z()) / d.z(), b = (ob.height - o.z()) / d.z();
    t_in = std::max(t_in, std::min(a, b));
    t_out = std::min(t_out, std::max(a, b));
  } else if (o.z() < 0.0 || o.z() > ob.height) {
    return std::numeric_limits<double>::infinity();
  }
  t_in = std::max(t_in, 0.0);
  return t_in <= t_out ? t_in : std::numeric_limits<double>::infinity();
}

}  // namespace

RenderOptions RenderOptions::localization_day() {
  RenderOptions r;
  r.gain = 0.7;
  r.offset = 12.0;
  r.sun = Eigen::Vector3d(-0.8, 0.1, 0.45).normalized();
  r.shadow = 0.7;
  return r;
}

camera::CameraCalibration default_rgbd_calibration() {
  camera::CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.04, 0.01, 0.0, 0.0, 0.0};
  return c;
}

Eigen::Isometry3d default_rear_camera() {
  return tilted_camera(Eigen::Vector3d(-0.4, 0.0, 1.0), 3.14159265358979323846,
                       35.0 * 3.14159265358979323846 / 180.0);
}

ParkRenderer::ParkRenderer(const ParkScene& scene, camera::CameraCalibration calibration,
                           Eigen::Isometry3d camera_to_robot)
    : scene_(scene), calibration_(std::move(calibration)), camera_to_robot_(camera_to_robot) {
  const camera::PinholeCamera camera(calibration_);
  std::vector<Eigen::Vector2d> px;
  for (int v = 0; v < calibration_.height; ++v)
    for (int u = 0; u < calibration_.width; ++u) px.emplace_back(u, v);
  for (const Eigen::Vector2d& n : camera.undistort(px)) rays_.emplace_back(n.x(), n.y(), 1.0);
}

RgbdFrame ParkRenderer::render(const Pose2& robot, const RenderOptions& o,
                               std::mt19937& rng) const {
  Eigen::Isometry3d world_from_robot = Eigen::Isometry3d::Identity();
  world_from_robot.linear() =
      Eigen::AngleAxisd(robot[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  world_from_robot.translation() = Eigen::Vector3d(robot[0], robot[1], 0.0);
  const Eigen::Isometry3d cam = world_from_robot * camera_to_robot_;
  const Eigen::Vector3d origin = cam.translation();
  // Obstacles that can be in view (within max_depth + their size of the camera).
  std::vector<const ParkObstacle*> near;
  for (const ParkObstacle& ob : scene_.obstacles) {
    if ((ob.centre - origin.head<2>()).norm() < o.max_depth + 4.0) near.push_back(&ob);
  }
  const int w = calibration_.width, h = calibration_.height;
  cv::Mat colour(h, w, CV_8UC3), depth(h, w, CV_32F);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const std::uint64_t salt = scene_.options.seed * 0x2545F4914F6CDD1DULL;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3d& ray = rays_[static_cast<std::size_t>(v) * w + u];
      const Eigen::Vector3d d = cam.linear() * ray;  // t along d is the z-depth
      double t = std::numeric_limits<double>::infinity();
      Eigen::Vector3d c(235, 206, 135);  // sky (BGR)
      bool sky = true;
      if (d.z() < 0.0) {
        t = -origin.z() / d.z();
        const Eigen::Vector3d g = origin + t * d;
        const Surface s = scene_.surface_at(g.head<2>());
        // Texture fixed to the ground: 5 cm grains, stronger on grass and gravel.
        const auto gi = static_cast<std::int64_t>(std::floor(g.x() / 0.05));
        const auto gj = static_cast<std::int64_t>(std::floor(g.y() / 0.05));
        const double tex = hash_noise(gi, gj, salt);
        switch (s) {
          case Surface::kGrass:
            c = Eigen::Vector3d(45, 130, 60) + 25.0 * tex * Eigen::Vector3d(0.5, 1.0, 0.6);
            break;
          case Surface::kPavement:
            c = Eigen::Vector3d(135, 135, 130) + 10.0 * tex * Eigen::Vector3d::Ones();
            break;
          case Surface::kGravel:
            c = Eigen::Vector3d(120, 170, 195) + 22.0 * tex * Eigen::Vector3d::Ones();
            break;
        }
        // Shadow: an obstacle between the ground point and the sun.
        for (const ParkObstacle* ob : near) {
          if ((ob->centre - g.head<2>()).norm() > ob->height * 3.0 + 1.0) continue;
          if (std::isfinite(hit(*ob, g + 1e-6 * o.sun, o.sun))) {
            c *= o.shadow;
            break;
          }
        }
        sky = false;
      }
      for (const ParkObstacle* ob : near) {
        const double th = hit(*ob, origin, d);
        if (th < t) {
          t = th;
          c = ob->colour;
          sky = false;
        }
      }
      c = o.gain * c + Eigen::Vector3d::Constant(o.offset);
      cv::Vec3b& px = colour.at<cv::Vec3b>(v, u);
      for (int k = 0; k < 3; ++k) px[k] = cv::saturate_cast<uchar>(c[k] + o.pixel_noise * n01(rng));
      double z = (!sky && t <= o.max_depth) ? t : 0.0;
      if (z > 0.0 && u01(rng) < o.holes) z = 0.0;
      if (z > 0.0) z += o.noise.sigma_z(z) * n01(rng);
      depth.at<float>(v, u) = static_cast<float>(std::max(0.0, z));
    }
  }
  return make_rgbd_frame(colour, depth, 1.0);
}

}  // namespace vdtnav::rgbd_ground
