#include "vdtnav/estimation/guess_search.hpp"

#include <algorithm>
#include <cmath>

namespace vdtnav {

double explained_fraction(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& pose,
                          double distance) {
  if (scan.size() == 0) return 0.0;
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  const double d2 = distance * distance;
  std::size_t n = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    bool inlier = false;
    const Eigen::Vector2d d = model.disparity_value(pose, c, s, scan.points[i], &inlier);
    n += inlier && d.squaredNorm() < d2;
  }
  return static_cast<double>(n) / static_cast<double>(scan.size());
}

namespace {

/// The truncated VCD over every `stride`-th beam.
double truncated_vcd_strided(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& pose,
                             double tau, std::size_t stride) {
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  const double t2 = tau * tau;
  double sum = 0.0;
  for (std::size_t i = 0; i < scan.size(); i += stride) {
    bool inlier = false;
    const Eigen::Vector2d d = model.disparity_value(pose, c, s, scan.points[i], &inlier);
    sum += inlier ? std::min(d.squaredNorm(), t2) : t2;
  }
  return sum;
}

}  // namespace

double truncated_vcd(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& pose,
                     double tau) {
  return truncated_vcd_strided(model, scan, pose, tau, 1);
}

Pose2 search_guess(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& guess,
                   const GuessSearchOptions& o, const Eigen::Matrix3d* covariance) {
  // Candidates are scored on an even subset of at most max_beams beams.
  const std::size_t stride =
      o.max_beams > 0 ? std::max<std::size_t>(1, (scan.size() + o.max_beams - 1) / o.max_beams) : 1;
  Pose2 best = guess;
  double best_score = truncated_vcd_strided(model, scan, guess, o.truncation, stride);
  int hxy = std::max(0, o.steps_xy / 2), hyaw = std::max(0, o.steps_yaw / 2);
  const double sxy = hxy > 0 ? o.window_xy / hxy : 0.0;
  const double syaw = hyaw > 0 ? o.window_yaw / hyaw : 0.0;
  if (covariance != nullptr && covariance->allFinite()) {
    // Grow the half-widths to window_sigmas sigma at the base spacing.
    const double wxy =
        std::min(o.max_window_xy,
                 o.window_sigmas * std::sqrt(std::max((*covariance)(0, 0), (*covariance)(1, 1))));
    const double wyaw =
        std::min(o.max_window_yaw, o.window_sigmas * std::sqrt((*covariance)(2, 2)));
    if (sxy > 0.0 && wxy > o.window_xy) hxy = static_cast<int>(std::ceil(wxy / sxy));
    if (syaw > 0.0 && wyaw > o.window_yaw) hyaw = static_cast<int>(std::ceil(wyaw / syaw));
  }
  for (int a = -hyaw; a <= hyaw; ++a) {
    for (int i = -hxy; i <= hxy; ++i) {
      for (int j = -hxy; j <= hxy; ++j) {
        if (a == 0 && i == 0 && j == 0) continue;
        const Pose2 c(guess[0] + i * sxy, guess[1] + j * sxy, wrap_angle(guess[2] + a * syaw));
        const double score = truncated_vcd_strided(model, scan, c, o.truncation, stride);
        if (score < best_score) {
          best_score = score;
          best = c;
        }
      }
    }
  }
  return best;
}

}  // namespace vdtnav
