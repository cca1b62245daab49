#include "vdtnav/estimation/lost_detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

void LostDetectionOptions::validate() const {
  VDTNAV_CHECK(window >= 1, "lost detection: window must be >= 1 scan");
  const auto fraction = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  VDTNAV_CHECK(fraction(lost_contradiction) && lost_contradiction > 0.0,
               "lost detection: lost_contradiction must be in (0, 1]");
  VDTNAV_CHECK(fraction(found_contradiction) && found_contradiction < lost_contradiction,
               "lost detection: found_contradiction must be in [0, lost_contradiction)");
  VDTNAV_CHECK(fraction(doubt_contradiction) && doubt_contradiction <= lost_contradiction,
               "lost detection: doubt_contradiction must be in [0, lost_contradiction]");
  VDTNAV_CHECK(fraction(min_judged), "lost detection: min_judged must be in [0, 1]");
  VDTNAV_CHECK(std::isfinite(doubt_rise) && doubt_rise > 0.0,
               "lost detection: doubt_rise must be > 0");
  VDTNAV_CHECK(std::isfinite(sigmas) && sigmas >= 0.0, "lost detection: sigmas must be >= 0");
  VDTNAV_CHECK(fraction(scan_doubt_contradiction),
               "lost detection: scan_doubt_contradiction must be in [0, 1]");
  VDTNAV_CHECK(baseline_scans >= 1, "lost detection: baseline_scans must be >= 1");
}

LostDetector::LostDetector(const LostDetectionOptions& options) : options_(options) {
  options_.validate();
}

bool LostDetector::update(const ScanAgreement& scan) {
  window_.push_back(scan);
  sum_ += scan;
  if (static_cast<int>(window_.size()) > options_.window) {
    sum_ -= window_.front();
    window_.pop_front();
  }
  // Only a full window that the map judges enough of decides; otherwise the state is kept.
  const auto judged_enough = [&](const ScanAgreement& a) {
    return a.judged() > 0 && a.judged() >= options_.min_judged * a.readings;
  };
  const bool full = static_cast<int>(window_.size()) >= options_.window;
  decided_ = full && judged_enough(sum_);
  unjudged_ = full && !decided_ ? unjudged_ + 1 : 0;
  if (!decided_) {
    doubt_ = false;
    return lost_;
  }
  const double c = sum_.contradiction();
  // A lost track is found again by a window of scans the map judges each, not by one scan that
  // outweighs the window's unjudged ones (a dead-reckoned track that wanders onto a look-alike
  // place: one scan explained there is no evidence of where the robot is).
  lost_ = lost_ ? c > options_.found_contradiction ||
                      !std::all_of(window_.begin(), window_.end(), judged_enough)
                : c >= options_.lost_contradiction;
  const bool risen = !std::isnan(baseline_) &&
                     c - baseline_ > std::max(options_.doubt_rise, options_.sigmas * spread());
  const bool scan_contradicted =
      scan.judged() > 0 && scan.contradiction() >= options_.scan_doubt_contradiction;
  doubt_ = !lost_ && (c >= options_.doubt_contradiction || risen || scan_contradicted);
  // The track's own windows join its baseline W windows after they were tested, and only those
  // of a track in good standing.
  if (lost_ || doubt_) {
    tested_.clear();
  } else {
    tested_.push_back(c);
    if (static_cast<int>(tested_.size()) > options_.window) {
      const double joining = tested_.front();
      tested_.pop_front();
      if (std::isnan(baseline_)) {
        baseline_ = joining;
        variance_ = 0.0;
      } else {
        const double a = 1.0 / options_.baseline_scans, d = joining - baseline_;
        baseline_ += a * d;
        variance_ = (1.0 - a) * (variance_ + a * d * d);
      }
    }
  }
  return lost_;
}

double LostDetector::spread() const noexcept { return std::sqrt(variance_); }

void LostDetector::reset() {
  window_.clear();
  tested_.clear();
  sum_ = ScanAgreement{};
  baseline_ = variance_ = std::numeric_limits<double>::quiet_NaN();
  lost_ = doubt_ = decided_ = false;
  unjudged_ = 0;
}

}  // namespace vdtnav
