#include "vdtnav/estimation/lost_detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

void LostDetectionOptions::validate() const {
  VDTNAV_CHECK(window >= 1, "lost detection: window must be >= 1 scan");
  VDTNAV_CHECK(std::isfinite(lost_fraction) && lost_fraction >= 0.0 && lost_fraction <= 1.0,
               "lost detection: lost_fraction must be in [0, 1]");
  VDTNAV_CHECK(
      std::isfinite(found_fraction) && found_fraction >= lost_fraction && found_fraction <= 1.0,
      "lost detection: found_fraction must be in [lost_fraction, 1]");
  VDTNAV_CHECK(std::isfinite(drop) && drop > 0.0, "lost detection: drop must be > 0");
  VDTNAV_CHECK(std::isfinite(sigmas) && sigmas >= 0.0, "lost detection: sigmas must be >= 0");
  VDTNAV_CHECK(baseline_scans >= 1, "lost detection: baseline_scans must be >= 1");
}

LostDetector::LostDetector(const LostDetectionOptions& options) : options_(options) {
  options_.validate();
}

bool LostDetector::update(double explained) {
  if (!std::isfinite(explained)) explained = 0.0;  // nothing measured: nothing explained
  window_.push_back(explained);
  sum_ += explained;
  double leaving = std::numeric_limits<double>::quiet_NaN();
  if (static_cast<int>(window_.size()) > options_.window) {
    leaving = window_.front();
    sum_ -= leaving;
    window_.pop_front();
  }
  // Only a full window decides (one poorly explained first scan is not a lost track).
  if (static_cast<int>(window_.size()) < options_.window) return lost_;
  const double mean = window_mean();
  if (lost_) {
    lost_ = mean < options_.found_fraction;  // found again without an acquisition
    if (!lost_) restart_baseline();
    return lost_;
  }
  if (std::isnan(baseline_)) {
    restart_baseline();
    return lost_;
  }
  const double margin = std::max(options_.drop, options_.sigmas * spread());
  if (mean < options_.lost_fraction || baseline_ - mean > margin) {
    lost_ = true;
    return lost_;
  }
  // The track holds: the scan leaving the window joins its baseline and spread (exponential
  // weights). Scans join only once they are past the window, so that a fall the window is
  // still testing never lowers the baseline nor widens the spread it is tested against.
  if (!std::isnan(leaving)) {
    const double a = 1.0 / options_.baseline_scans, d = leaving - baseline_;
    baseline_ += a * d;
    variance_ = (1.0 - a) * (variance_ + a * d * d);
  }
  return lost_;
}

void LostDetector::reset() {
  window_.clear();
  sum_ = 0.0;
  baseline_ = variance_ = std::numeric_limits<double>::quiet_NaN();
  lost_ = false;
}

void LostDetector::restart_baseline() {
  baseline_ = window_mean();
  double v = 0.0;
  for (double e : window_) v += (e - baseline_) * (e - baseline_);
  variance_ = v / static_cast<double>(window_.size());
}

double LostDetector::spread() const noexcept { return std::sqrt(variance_); }

double LostDetector::window_mean() const noexcept {
  return window_.empty() ? 1.0 : sum_ / static_cast<double>(window_.size());
}

}  // namespace vdtnav
