// Global localization from one scan with no prior on one map: branch and bound against random
// sampling at the same time budget, each trial judged against the true pose; the table rows, the
// success map and the time histogram.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "kidnapped_study.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/viz/image.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;

namespace {

enum class Outcome { kSuccess, kAmbiguous, kRefused, kWrong };

struct Tally {
  std::vector<double> seconds;
  std::vector<Outcome> outcome;
  [[nodiscard]] int count(Outcome o) const {
    return static_cast<int>(std::count(outcome.begin(), outcome.end(), o));
  }
};

using kidnap::right;  // within 0.3 m and 0.1 rad (kidnapping.hpp)

Outcome judge(const GlobalLocalizationResult& r, const Pose2& truth) {
  if (r.result.status == LocalizationStatus::kConverged) {
    return right(r.result.pose, truth) ? Outcome::kSuccess : Outcome::kWrong;
  }
  if (r.ambiguous) {
    bool among = right(r.result.pose, truth);
    for (const Pose2& a : r.alternatives) among = among || right(a, truth);
    if (among) return Outcome::kAmbiguous;
  }
  return Outcome::kRefused;
}

Grid<std::uint8_t, 2> as_bytes(const OccupancyGrid<2>& g) {
  Grid<std::uint8_t, 2> out(g.size(), g.frame(), 0);
  for (std::size_t k = 0; k < g.num_cells(); ++k) out[k] = g[k] ? 1 : 0;
  return out;
}

void success_map(const Case& c, const Tally& t, const std::string& path) {
  const Eigen::Vector2d lo = c.grid.frame().origin();
  const Eigen::Vector2d hi =
      lo + c.grid.size().cast<double>() * c.grid.resolution();  // axis-aligned maps here
  viz::Figure fig(1400, 1000, 1, 1);
  viz::Axes& ax = fig.axes(0, 0);
  ax.title(c.map + ": branch and bound from one scan, by outcome")
      .image(viz::occupancy_image(as_bytes(c.grid)), lo.x(), hi.x(), lo.y(), hi.y());
  const struct {
    Outcome o;
    const char* label;
    viz::Rgb colour;
  } kinds[] = {{Outcome::kSuccess, "success", {0, 158, 115}},
               {Outcome::kAmbiguous, "ambiguous (refused)", {230, 159, 0}},
               {Outcome::kRefused, "refused", {86, 180, 233}},
               {Outcome::kWrong, "wrong pose accepted", {213, 94, 0}}};
  for (const auto& k : kinds) {
    std::vector<double> xs, ys;
    for (std::size_t i = 0; i < t.outcome.size(); ++i) {
      if (t.outcome[i] != k.o) continue;
      xs.push_back(c.truth[i].x());
      ys.push_back(c.truth[i].y());
    }
    if (xs.empty()) continue;
    ax.scatter(
        xs, ys,
        viz::Style().with_color(k.colour).with_marker(viz::Marker::kCircle, 7).with_label(k.label));
  }
  ax.equal_aspect().legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

}  // namespace

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

Histogram global_trials(const Case& c, const VdtMap2& map, unsigned seed, const std::string& out,
                        std::ofstream& csv, std::ofstream& md) {
  const GlobalLocalizer loc(map, c.grid);
  std::printf("[%s] %zu x %zu cells of %.3f m, %zu %s scans\n", c.map.c_str(),
              static_cast<std::size_t>(c.grid.size().x()),
              static_cast<std::size_t>(c.grid.size().y()), c.grid.resolution(),
              c.observations.size(), c.scans.c_str());
  std::fflush(stdout);
  Tally bb, rs;
  for (std::size_t k = 0; k < c.observations.size(); ++k) {
    const GlobalLocalizationResult a = loc.localize(c.observations[k]);
    bb.seconds.push_back(a.seconds);
    bb.outcome.push_back(judge(a, c.truth[k]));
    // Random sampling with the time branch and bound took on this scan.
    const GlobalLocalizationResult b =
        loc.localize_random(c.observations[k], a.seconds, seed + static_cast<unsigned>(k));
    rs.seconds.push_back(b.seconds);
    rs.outcome.push_back(judge(b, c.truth[k]));
  }
  for (const auto& [name, t] : {std::pair<const char*, const Tally&>{"branch-and-bound", bb},
                                std::pair<const char*, const Tally&>{"random-sampling", rs}}) {
    const int n = static_cast<int>(t.outcome.size());
    const int ok = t.count(Outcome::kSuccess), amb = t.count(Outcome::kAmbiguous);
    const double pct = 100.0 * ok / n;
    const double pct_clear = n > amb ? 100.0 * ok / (n - amb) : 0.0;
    char line[512];
    std::snprintf(line, sizeof line, "%s,%s,%s,%d,%.1f,%.4f,%.4f\n", c.map.c_str(), c.scans.c_str(),
                  name, n, pct, quantile(t.seconds, 0.5), quantile(t.seconds, 0.95));
    csv << line;
    std::snprintf(
        line, sizeof line, "| %s | %s | %s | %d | %.1f | %d | %d | %d | %.1f | %.3f | %.3f |\n",
        c.map.c_str(), c.scans.c_str(), name, n, pct, amb, t.count(Outcome::kRefused),
        t.count(Outcome::kWrong), pct_clear, quantile(t.seconds, 0.5), quantile(t.seconds, 0.95));
    md << line;
    std::printf(
        "  %-16s success %.1f %% (%.1f %% outside %d ambiguous), %d refused, %d wrong "
        "accepted; median %.3f s, p95 %.3f s\n",
        name, pct, pct_clear, amb, t.count(Outcome::kRefused), t.count(Outcome::kWrong),
        quantile(t.seconds, 0.5), quantile(t.seconds, 0.95));
    std::fflush(stdout);
  }
  success_map(c, bb, out + "/" + c.map + "_success.png");
  std::vector<double> centres, counts;
  const double top = std::max(quantile(bb.seconds, 1.0), 1e-3);
  const int bins = 20;
  for (int b = 0; b < bins; ++b) {
    centres.push_back((b + 0.5) * top / bins);
    counts.push_back(0.0);
  }
  for (double s : bb.seconds) {
    counts[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(s / top * bins)))] += 1;
  }
  return Histogram{std::move(centres), std::move(counts)};
}

}  // namespace study
