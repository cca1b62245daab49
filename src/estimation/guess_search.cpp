#include "vdtnav/estimation/guess_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "scan_scores.hpp"

namespace vdtnav {

double explained_fraction(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& pose,
                          double distance) {
  return detail::explained_fraction_at(model, scan, PoseTraits<2>::rotation(pose), pose.head<2>(),
                                       distance);
}

double truncated_vcd(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& pose,
                     double tau) {
  return detail::truncated_vcd_at(model, scan, PoseTraits<2>::rotation(pose), pose.head<2>(), tau);
}

Pose2 search_guess(const VdtSensorModel& model, const ScanPoints& scan, const Pose2& guess,
                   const GuessSearchOptions& o, const Eigen::Matrix3d* covariance) {
  // Candidates are scored on an even subset of at most max_beams beams.
  const std::size_t stride =
      o.max_beams > 0 ? std::max<std::size_t>(1, (scan.size() + o.max_beams - 1) / o.max_beams) : 1;
  std::vector<int> subset;
  for (std::size_t i = 0; i < scan.size(); i += stride) subset.push_back(static_cast<int>(i));
  Pose2 best = guess;
  // A candidate is dropped as soon as part of its readings already scores no better than the best
  // so far (the score is a sum of non-negative terms): the same winner, fewer lookups.
  const auto score_at = [&](const Pose2& x, double stop_at) {
    return detail::truncated_vcd_at(model, scan, PoseTraits<2>::rotation(x), x.head<2>(),
                                    o.truncation, &subset, stop_at);
  };
  double best_score = score_at(guess, std::numeric_limits<double>::infinity());
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
        const double score = score_at(c, best_score);
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
