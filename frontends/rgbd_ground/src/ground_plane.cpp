#include "vdtnav/rgbd_ground/ground_plane.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

namespace vdtnav::rgbd_ground {

GroundPlane expected_ground_plane(const Eigen::Isometry3d& camera_to_robot) {
  // Robot ground z = 0: e_z . (R p + t) = 0  <=>  (R^T e_z) . p + t_z = 0 in the camera frame.
  GroundPlane g;
  g.normal = camera_to_robot.linear().transpose() * Eigen::Vector3d::UnitZ();
  g.offset = camera_to_robot.translation().z();
  return g;
}

GroundPlane fit_ground_plane(const RgbdFrame& frame, const camera::PinholeCamera& camera,
                             const Eigen::Isometry3d& camera_to_robot, const DepthNoiseModel& noise,
                             const GroundPlaneOptions& options) {
  const GroundPlane expected = expected_ground_plane(camera_to_robot);
  // Depth points on a grid of pixels; cell[] maps a grid cell to its point (or -1).
  std::vector<Eigen::Vector2d> pixels;
  std::vector<float> depths;
  const int stride = std::max(1, options.stride);
  const int gw = (frame.depth.cols + stride - 1) / stride,
            gh = (frame.depth.rows + stride - 1) / stride;
  std::vector<int> grid_of;  // grid cell of each pixel sample
  for (int v = stride / 2, gy = 0; v < frame.depth.rows; v += stride, ++gy) {
    const float* row = frame.depth.ptr<float>(v);
    for (int u = stride / 2, gx = 0; u < frame.depth.cols; u += stride, ++gx) {
      if (row[u] > 0.0f && row[u] <= options.max_range) {
        pixels.emplace_back(u, v);
        depths.push_back(row[u]);
        grid_of.push_back(gy * gw + gx);
      }
    }
  }
  GroundPlane best;
  if (pixels.size() < 3) return best;
  const std::vector<Eigen::Vector2d> rays = camera.undistort(pixels);
  std::vector<Eigen::Vector3d> pts;
  std::vector<double> tol;
  std::vector<int> cell(static_cast<std::size_t>(gw) * gh, -1);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!rays[i].allFinite()) continue;
    const double z = depths[i];
    cell[static_cast<std::size_t>(grid_of[i])] = static_cast<int>(pts.size());
    pts.emplace_back(rays[i].x() * z, rays[i].y() * z, z);
    tol.push_back(std::max(options.inlier_floor, 3.0 * noise.sigma_z(z)));
  }
  if (pts.size() < 3) return best;
  // Hypotheses are scored on an even subset of at most kScored points (the refinement below uses
  // them all).
  constexpr std::size_t kScored = 1500;
  const std::size_t score_stride = std::max<std::size_t>(1, pts.size() / kScored);
  const auto count = [&](const Eigen::Vector3d& n, double d, std::vector<int>* in,
                         std::size_t step) {
    int c = 0;
    for (std::size_t i = 0; i < pts.size(); i += step) {
      if (std::abs(n.dot(pts[i]) + d) <= tol[i]) {
        ++c;
        if (in != nullptr) in->push_back(static_cast<int>(i));
      }
    }
    return c;
  };
  // Each hypothesis: a random point and two more from its neighbourhood on the grid (within
  // kReach cells): when the first is on the ground, the others mostly are too, so a ground plane
  // that fills a sixth of the view is drawn in tens of hypotheses instead of thousands.
  constexpr int kReach = 8;
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
  std::uniform_int_distribution<int> offset(-kReach, kReach);
  // The grid cell of each point (pts is in grid order, some cells empty).
  std::vector<int> cell_of(pts.size());
  for (std::size_t c = 0; c < cell.size(); ++c) {
    if (cell[c] >= 0) cell_of[static_cast<std::size_t>(cell[c])] = static_cast<int>(c);
  }
  const auto near = [&](std::size_t i) -> int {
    const int c = cell_of[i], gx = c % gw, gy = c / gw;
    for (int attempt = 0; attempt < 8; ++attempt) {
      const int x = gx + offset(rng), y = gy + offset(rng);
      if (x < 0 || y < 0 || x >= gw || y >= gh) continue;
      const int j = cell[static_cast<std::size_t>(y) * gw + x];
      if (j >= 0 && static_cast<std::size_t>(j) != i) return j;
    }
    return -1;
  };
  const double cos_tilt = std::cos(options.max_tilt);
  int best_count = -1;
  Eigen::Vector3d best_n = expected.normal;
  double best_d = expected.offset;
  // The expected plane itself is the first hypothesis.
  for (int it = -1; it < options.iterations; ++it) {
    Eigen::Vector3d n = expected.normal;
    double d = expected.offset;
    if (it >= 0) {
      const std::size_t ia = pick(rng);
      const int ib = near(ia), ic = near(ia);
      if (ib < 0 || ic < 0 || ib == ic) continue;
      const Eigen::Vector3d& a = pts[ia];
      const Eigen::Vector3d& b = pts[static_cast<std::size_t>(ib)];
      const Eigen::Vector3d& c = pts[static_cast<std::size_t>(ic)];
      n = (b - a).cross(c - a);
      if (n.norm() < 1e-9) continue;
      n.normalize();
      if (n.dot(expected.normal) < 0.0) n = -n;
      d = -n.dot(a);
    }
    if (n.dot(expected.normal) < cos_tilt ||
        std::abs(d - expected.offset) > options.max_height_error)
      continue;
    const int c = count(n, d, nullptr, score_stride);
    if (c > best_count) {
      best_count = c;
      best_n = n;
      best_d = d;
    }
  }
  if (best_count < 1) return best;
  // Refinement: the weighted total least-squares plane of the inliers, each weighted by its
  // depth noise along the normal (sigma_i, see the header; equal weights when the model has
  // none): the smallest eigenvector of the weighted scatter about the weighted mean, the maximum
  // likelihood plane, inliers selected again at the refined plane, twice. (Unweighted, the far
  // points' noise, (8 m / 1 m)^2 = 64 times the near ones', made the plane ~3x as uncertain in
  // variance as the weighted fit: the Monte Carlo test of the covariance.)
  const auto sigma_along = [&](const Eigen::Vector3d& normal, const Eigen::Vector3d& p) {
    return std::abs(normal.dot(p / p.z())) * noise.sigma_z(p.z());
  };
  Eigen::Vector3d n = best_n;
  double d = best_d;
  std::vector<int> in;
  for (int round = 0; round < 2; ++round) {
    in.clear();
    count(n, d, &in, 1);
    if (in.size() < 3) break;
    std::vector<double> w(in.size(), 1.0);
    double wsum = 0.0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < in.size(); ++k) {
      const Eigen::Vector3d& p = pts[static_cast<std::size_t>(in[k])];
      const double sigma = sigma_along(n, p);
      if (sigma > 0.0) w[k] = 1.0 / (sigma * sigma);
      wsum += w[k];
      mean += w[k] * p;
    }
    mean /= wsum;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < in.size(); ++k) {
      const Eigen::Vector3d e = pts[static_cast<std::size_t>(in[k])] - mean;
      scatter.noalias() += w[k] * e * e.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter);
    Eigen::Vector3d m = es.eigenvectors().col(0);
    if (m.dot(expected.normal) < 0.0) m = -m;
    n = m;
    d = -n.dot(mean);
  }
  in.clear();
  best.normal = n;
  best.offset = d;
  best.inliers = count(n, d, &in, 1);
  // The fit's covariance (see the header): information of (a, b, c) over the inliers.
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  double s2 = 0.0, chi2 = 0.0;
  bool noisy = true;  // false: a noiseless model, no covariance to claim
  for (int i : in) {
    const Eigen::Vector3d& p = pts[static_cast<std::size_t>(i)];
    const double r = n.dot(p) + d;
    s2 += r * r;
    const double sigma = sigma_along(n, p);
    noisy = noisy && sigma > 0.0;
    if (!noisy) continue;
    const Eigen::Vector3d j(e1.dot(p), e2.dot(p), 1.0);
    information.noalias() += j * j.transpose() / (sigma * sigma);
    chi2 += r * r / (sigma * sigma);
  }
  best.rms = in.empty() ? 0.0 : std::sqrt(s2 / static_cast<double>(in.size()));
  if (noisy && in.size() > 3 && information.determinant() > 0.0) {
    const double scale = std::max(1.0, chi2 / static_cast<double>(in.size() - 3));
    const Eigen::Matrix3d cov = scale * information.inverse();
    Eigen::Matrix<double, 3, 2> basis;
    basis << e1, e2;
    best.normal_covariance = basis * cov.topLeftCorner<2, 2>() * basis.transpose();
    best.offset_sigma = std::sqrt(cov(2, 2));
  }
  best.found = best.inliers >= options.min_inliers && n.dot(expected.normal) >= cos_tilt &&
               std::abs(d - expected.offset) <= options.max_height_error;
  return best;
}

Eigen::Isometry3d levelled_extrinsics(const Eigen::Isometry3d& camera_to_robot,
                                      const GroundPlane& plane) {
  const GroundPlane expected = expected_ground_plane(camera_to_robot);
  // Q n_fit = n_expected (smallest rotation); R' = R Q gives R'^T e_z = Q^T n_expected = n_fit.
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(plane.normal, expected.normal);
  Eigen::Isometry3d out = camera_to_robot;
  out.linear() = camera_to_robot.linear() * q.toRotationMatrix();
  out.translation().z() = plane.offset;
  return out;
}

Eigen::Matrix2d levelled_tilt_covariance(const Eigen::Isometry3d& levelled,
                                         const GroundPlane& plane) {
  const Eigen::Matrix3d m =
      levelled.linear() * plane.normal_covariance * levelled.linear().transpose();
  Eigen::Matrix2d t;
  t << 0.0, 1.0, -1.0, 0.0;
  return t * m.topLeftCorner<2, 2>() * t.transpose();
}

}  // namespace vdtnav::rgbd_ground
