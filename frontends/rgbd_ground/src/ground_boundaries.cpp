#include "vdtnav/rgbd_ground/ground_boundaries.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::rgbd_ground {

GroundBoundaryExtractor::GroundBoundaryExtractor(camera::PinholeCamera camera,
                                                 Eigen::Isometry3d camera_to_robot,
                                                 GroundBoundaryOptions options)
    : camera_(std::move(camera)), camera_to_robot_(camera_to_robot), options_(options) {
  VDTNAV_CHECK(options.stride >= 1, "RGB-D boundaries: stride must be >= 1");
  VDTNAV_CHECK(options.max_range > 0.0, "RGB-D boundaries: max_range must be > 0");
  VDTNAV_CHECK(options.blur_sigma >= 0.0 && options.canny_low >= 0.0 &&
                   options.canny_high >= options.canny_low,
               "RGB-D boundaries: blur_sigma >= 0 and 0 <= canny_low <= canny_high expected");
  VDTNAV_CHECK(options.prune_floor > 0.0 && options.clearance >= 0.0,
               "RGB-D boundaries: prune_floor > 0 and clearance >= 0 expected");
  VDTNAV_CHECK(options.aperture_radius > 0.0 && options.aperture_sigma >= 0.0,
               "RGB-D boundaries: aperture_radius > 0 and aperture_sigma >= 0 expected");
  VDTNAV_CHECK(
      options.noise.sigma_pixel > 0.0 && options.noise.sigma_z0 + options.noise.sigma_z2 > 0.0,
      "RGB-D boundaries: the noise model needs sigma_pixel > 0 and a depth noise > 0");
  // Every pixel's undistorted ray, once (the lens model's Newton inversion per pixel).
  const int w = camera_.width(), h = camera_.height();
  std::vector<Eigen::Vector2d> pixels;
  pixels.reserve(static_cast<std::size_t>(w) * h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) pixels.emplace_back(u, v);
  const std::vector<Eigen::Vector2d> rays = camera_.undistort(pixels);
  rays_.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) rays_[i] = rays[i].cast<float>();
}

Eigen::Vector2d GroundBoundaryExtractor::back_project(const Eigen::Vector2d& pixel, double z,
                                                      const Eigen::Isometry3d& camera_to_robot,
                                                      Eigen::Matrix<double, 2, 3>* jacobian) const {
  const Eigen::Vector2d n = camera_.undistort({pixel})[0];
  const Eigen::Vector3d pc(n.x() * z, n.y() * z, z);
  const Eigen::Vector3d pr = camera_to_robot * pc;
  if (jacobian != nullptr) {
    Eigen::Matrix2d dpix_dn;
    (void)camera_.distort(n, &dpix_dn);
    const Eigen::Matrix2d dn_dpix = dpix_dn.inverse();
    Eigen::Matrix3d dpc;  // d p_c / d(u, v, z)
    dpc.topLeftCorner<2, 2>() = z * dn_dpix;
    dpc.block<1, 2>(2, 0).setZero();
    dpc.col(2) = Eigen::Vector3d(n.x(), n.y(), 1.0);
    *jacobian = camera_to_robot.linear().topRows<2>() * dpc;
  }
  return pr.head<2>();
}

GroundBoundaries GroundBoundaryExtractor::extract(const RgbdFrame& frame) const {
  VDTNAV_CHECK(frame.colour.cols == camera_.width() && frame.colour.rows == camera_.height() &&
                   frame.depth.size() == frame.colour.size() && frame.depth.type() == CV_32F &&
                   frame.colour.type() == CV_8UC3,
               "RGB-D boundaries: the frame must be " + std::to_string(camera_.width()) + " x " +
                   std::to_string(camera_.height()) +
                   " (the camera's size), BGR colour and CV_32F depth (make_rgbd_frame)");
  GroundBoundaries out;
  out.plane = fit_ground_plane(frame, camera_, camera_to_robot_, options_.noise, options_.plane);
  if (!out.plane.found) return out;  // no ground in view: no boundaries to trust
  const Eigen::Isometry3d extrinsics = levelled_extrinsics(camera_to_robot_, out.plane);
  out.tilt_covariance = levelled_tilt_covariance(extrinsics, out.plane);

  // Chroma edges (and lightness edges on request).
  cv::Mat blurred, lab;
  if (options_.blur_sigma > 0.0) {
    cv::GaussianBlur(frame.colour, blurred, cv::Size(0, 0), options_.blur_sigma);
  } else {
    blurred = frame.colour;
  }
  cv::cvtColor(blurred, lab, cv::COLOR_BGR2Lab);
  std::array<cv::Mat, 3> channels;
  cv::split(lab, channels.data());
  cv::Mat edges = cv::Mat::zeros(lab.size(), CV_8U), e;
  for (int c = options_.use_lightness ? 0 : 1; c < 3; ++c) {
    cv::Canny(channels[static_cast<std::size_t>(c)], e, options_.canny_low, options_.canny_high, 3,
              true);
    edges |= e;
  }

  const GroundPlane& plane = out.plane;
  const int w = frame.depth.cols, h = frame.depth.rows;
  const double fx = std::abs(camera_.calibration().camera_matrix(0, 0));
  const auto point_at = [&](int u, int v, double z) {
    const Eigen::Vector2f& r = rays_[static_cast<std::size_t>(v) * w + u];
    return Eigen::Vector3d(r.x() * z, r.y() * z, z);
  };
  const auto prune_tol = [&](double z) {
    return std::max(options_.prune_floor, 3.0 * options_.noise.sigma_z(z));
  };
  static constexpr std::array<std::array<int, 2>, 8> kDirs{
      {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {1, -1}, {-1, 1}}};
  const double s2p = options_.noise.sigma_pixel * options_.noise.sigma_pixel;
  int seen = 0;
  for (int v = 0; v < h; ++v) {
    const std::uint8_t* erow = edges.ptr<std::uint8_t>(v);
    const float* drow = frame.depth.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      if (erow[u] == 0) continue;
      const double z = drow[u];
      if (!(z > 0.0) || z > options_.max_range) continue;
      ++out.edge_pixels;
      // Ground here and all around?
      bool ground = std::abs(plane.distance(point_at(u, v, z))) <= prune_tol(z);
      const int reach = std::clamp(static_cast<int>(std::ceil(fx * options_.clearance / z)), 1, 60);
      for (const auto& d : kDirs) {
        if (!ground) break;
        for (const int step : {reach, (reach + 1) / 2}) {
          const int uu = u + d[0] * step, vv = v + d[1] * step;
          if (uu < 0 || vv < 0 || uu >= w || vv >= h) continue;
          const double zz = frame.depth.at<float>(vv, uu);
          if (!(zz > 0.0)) continue;  // a hole says nothing
          if (std::abs(plane.distance(point_at(uu, vv, zz))) > prune_tol(zz)) {
            ground = false;
            break;
          }
        }
      }
      if (!ground) {
        ++out.pruned;
        out.pruned_pixels.emplace_back(u, v);
        continue;
      }
      if (seen++ % options_.stride != 0) continue;
      BoundaryPoint p;
      p.pixel = Eigen::Vector2i(u, v);
      p.camera = point_at(u, v, z);
      Eigen::Matrix<double, 2, 3> j;
      p.robot = back_project(Eigen::Vector2d(u, v), z, extrinsics, &j);
      const double sz = options_.noise.sigma_z(z);
      p.covariance = j * Eigen::Vector3d(s2p, s2p, sz * sz).asDiagonal() * j.transpose();
      const double vz = (extrinsics.linear() * p.camera).z();
      p.tilt_jacobian << 0.0, vz, -vz, 0.0;
      out.points.push_back(p);
    }
  }
  estimate_edge_tangents(out.points, options_.aperture_radius);
  return out;
}

void estimate_edge_tangents(std::vector<BoundaryPoint>& points, double radius) {
  VDTNAV_CHECK(radius > 0.0, "edge tangents: the radius must be > 0");
  // The neighbourhood of a point: the points within `radius`, or within the distance of its
  // kNeighbours-th nearest when fewer lie there (far from the camera a pixel row spans
  // z^2 / (f h) on the ground, and the kept pixels thin out), at most kGrowth radii.
  constexpr int kNeighbours = 6, kGrowth = 4;
  // Points hashed into square buckets of side `radius`.
  const auto cell = [radius](double v) {
    return static_cast<std::int64_t>(std::floor(v / radius));
  };
  const auto key = [](std::int64_t x, std::int64_t y) { return x * 2000003 + y; };
  std::unordered_map<std::int64_t, std::vector<std::size_t>> buckets;
  buckets.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    buckets[key(cell(points[i].robot.x()), cell(points[i].robot.y()))].push_back(i);
  }
  std::vector<std::pair<double, std::size_t>> near;
  for (BoundaryPoint& p : points) {
    const std::int64_t bx = cell(p.robot.x()), by = cell(p.robot.y());
    // Rings of buckets until kNeighbours points lie within the ring's inner distance.
    near.clear();
    double reach = radius;
    for (std::int64_t ring = 0; ring <= kGrowth; ++ring) {
      for (std::int64_t dx = -ring; dx <= ring; ++dx) {
        for (std::int64_t dy = -ring; dy <= ring; ++dy) {
          if (std::max(std::abs(dx), std::abs(dy)) != ring) continue;
          const auto it = buckets.find(key(bx + dx, by + dy));
          if (it == buckets.end()) continue;
          for (const std::size_t j : it->second) {
            near.emplace_back((points[j].robot - p.robot).squaredNorm(), j);
          }
        }
      }
      if (ring >= 1 && near.size() > static_cast<std::size_t>(kNeighbours)) {
        std::nth_element(near.begin(), near.begin() + kNeighbours, near.end());
        const double dk = std::sqrt(near[kNeighbours].first);
        if (dk <= static_cast<double>(ring) * radius) {  // no closer point in a farther ring
          reach = std::max(radius, dk);
          break;
        }
      }
      reach = std::max(radius, static_cast<double>(ring + 1) * radius);
    }
    reach = std::min(reach, kGrowth * radius);
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    int n = 0;
    for (const auto& [d2, j] : near) {
      if (d2 > reach * reach) continue;
      const Eigen::Vector2d d = points[j].robot - p.robot;
      mean += d;
      scatter.noalias() += d * d.transpose();
      ++n;
    }
    if (n < 4) {
      p.straightness = 0.0;
      continue;
    }
    mean /= n;
    scatter = scatter / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    const double l1 = eig.eigenvalues()[1], l2 = std::max(0.0, eig.eigenvalues()[0]);
    p.tangent = eig.eigenvectors().col(1).normalized();
    p.straightness = l1 > 0.0 ? (l1 - l2) / (l1 + l2) : 0.0;
  }
}

ScanPoints GroundBoundaryExtractor::observations(const GroundBoundaries& boundaries) const {
  ScanPoints s;
  const bool shared = !boundaries.tilt_covariance.isZero(0.0);
  if (shared) s.shared_covariance = boundaries.tilt_covariance;
  for (std::size_t i = 0; i < boundaries.points.size(); ++i) {
    const BoundaryPoint& p = boundaries.points[i];
    const double a = p.straightness * options_.aperture_sigma;
    const ScanPoints::SharedJacobian g = p.tilt_jacobian;
    s.add_point(p.robot, p.covariance + (a * a) * p.tangent * p.tangent.transpose(), i,
                shared ? &g : nullptr);
  }
  return s;
}

}  // namespace vdtnav::rgbd_ground
