#include "kidnapping.hpp"

#include <chrono>
#include <cmath>
#include <random>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/recovering_localizer.hpp"

namespace kidnap {

using namespace vdtnav;

bool right(const Pose2& estimate, const Pose2& truth) {
  return (estimate.head<2>() - truth.head<2>()).norm() <= 0.3 &&
         std::abs(wrap_angle(estimate[2] - truth[2])) <= 0.1;
}

bool elsewhere(const Pose2& estimate, const Pose2& truth) {
  return (estimate.head<2>() - truth.head<2>()).norm() > 1.0 ||
         std::abs(wrap_angle(estimate[2] - truth[2])) > 0.5;
}

std::vector<Outcome> run(const Drive& drive, Localizer2D& localizer, const Options& options,
                         Trace* trace) {
  const int n = static_cast<int>(drive.scans.size());
  VDTNAV_CHECK(n > options.every, "kidnapping: the drive has " + std::to_string(n) +
                                      " scans, fewer than the " + std::to_string(options.every) +
                                      " between teleports");
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - options.every);
  // Segment starts: each teleport lands at least min_jump from where the robot was.
  std::vector<int> starts{pick(rng)};
  while (static_cast<int>(starts.size()) <= options.kidnappings) {
    const Pose2& from = drive.truth[static_cast<std::size_t>(starts.back() + options.every - 1)];
    int s = pick(rng);
    for (int tries = 0;
         tries < 1000 &&
         (drive.truth[static_cast<std::size_t>(s)].head<2>() - from.head<2>()).norm() <
             options.min_jump;
         ++tries) {
      s = pick(rng);
    }
    starts.push_back(s);
  }
  const auto* recovering = dynamic_cast<const RecoveringLocalizer*>(&localizer);
  const Pose2& p0 = drive.truth[static_cast<std::size_t>(starts.front())];
  localizer.reset(p0, Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
  std::vector<Outcome> outcomes;
  int index = 0;
  for (std::size_t seg = 0; seg < starts.size(); ++seg) {
    std::vector<LocalizationResult> results;
    std::vector<Pose2> truth;
    int unrecognizable = 0, other_refusals = 0;
    for (int j = 0; j < options.every; ++j, ++index) {
      const auto k = static_cast<std::size_t>(starts[seg] + j);
      // The first scan of the drive starts where the localizer was reset: no motion into it.
      const OdometryStep step = seg == 0 && j == 0 ? OdometryStep{} : drive.odometry[k];
      const int ambiguous_before = recovering != nullptr ? recovering->ambiguous() : 0;
      const auto t0 = std::chrono::steady_clock::now();
      results.push_back(localizer.update(step, drive.scans[k]));
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      if (seg > 0 && j < options.within) {
        if (drive.scans[k].size() < 10) {
          ++unrecognizable;
        } else if (recovering != nullptr && recovering->ambiguous() > ambiguous_before) {
          // Two distinct candidates passed the verification: is the truth among them?
          bool among = false;
          for (const Pose2& a : recovering->ambiguous_poses())
            among = among || right(a, drive.truth[k]);
          if (among) {
            ++unrecognizable;
          } else {
            ++other_refusals;
          }
        }
      }
      truth.push_back(drive.truth[k]);
      if (trace != nullptr) {
        trace->error.push_back((results.back().pose.head<2>() - truth.back().head<2>()).norm());
        trace->status.push_back(results.back().status);
        trace->ms.push_back(ms);
        if (j == 0 && seg > 0) trace->teleports.push_back(index);
      }
    }
    if (seg == 0) continue;  // the start, not a kidnapping
    Outcome o;
    o.unrecognizable = unrecognizable > 0 && other_refusals == 0;
    // A pose the default outputs hold (converged, or bridged across what looks like a gap of
    // the map: published_by_default()) is accepted, right or wrong.
    const auto accepted = [&](int j) {
      return published_by_default(results[static_cast<std::size_t>(j)].status);
    };
    const auto ok = [&](int j) {
      return right(results[static_cast<std::size_t>(j)].pose, truth[static_cast<std::size_t>(j)]);
    };
    const auto away = [&](int j) {
      return elsewhere(results[static_cast<std::size_t>(j)].pose,
                       truth[static_cast<std::size_t>(j)]);
    };
    for (int j = options.every - 1; j >= 0; --j) {  // back to the last converged-elsewhere scan
      if (accepted(j) && away(j)) break;
      if (accepted(j) && ok(j)) o.scans_to_recover = j;
    }
    for (int j = 0; j < options.every; ++j) {
      const LocalizationResult& r = results[static_cast<std::size_t>(j)];
      const bool wrong = accepted(j) && away(j);
      if (wrong && j >= options.window) o.wrong_accepted = true;
      if (wrong && j < options.window) ++o.converged_wrong_early;
      if (o.scans_to_recover >= 0 && j > o.scans_to_recover && accepted(j) && !ok(j) && !away(j))
        ++o.converged_off;
      o.lost_scans += r.status == LocalizationStatus::kLost;
      o.global_searches += r.work.global_searches;
    }
    outcomes.push_back(o);
  }
  return outcomes;
}

}  // namespace kidnap
