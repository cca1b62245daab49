// vdtnav_intel_lab: the figures, the trajectories over the map, the scans reprojected from the
// estimated poses and the errors over time (intel_study.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "intel_study.hpp"
#include "vdtnav/viz/viz.hpp"

namespace intel_study {
namespace {

void map_axes(viz::Axes& ax, const Grid<std::int8_t, 2>& cells) {
  const auto& f = cells.frame();
  ax.image(viz::occupancy_image(cells), f.origin().x(),
           f.origin().x() + cells.size().x() * f.resolution(), f.origin().y(),
           f.origin().y() + cells.size().y() * f.resolution())
      .equal_aspect()
      .xlabel("x [m]")
      .ylabel("y [m]");
}

}  // namespace

void write_figures(const std::string& out, const mapping::OccupancyMap& map, const Localization& in,
                   const std::vector<Row>& rows) {
  const JoinedLogs& logs = in.logs;
  const std::size_t split = in.split;
  const std::vector<double>& times = in.times;
  const eval::Trajectory2& reference = in.reference;
  {
    viz::Figure fig(1400, 1300);
    viz::Axes& ax = fig.axes();
    map_axes(ax, map.cells);
    ax.title("Intel lab: trajectories over the map built from the last third");
    std::vector<double> rx, ry;
    for (const auto& s : reference) {
      rx.push_back(s.pose[0]);
      ry.push_back(s.pose[1]);
    }
    ax.line(rx, ry,
            viz::Style{}.with_color({0, 0, 0}).with_width(2.5).with_dashes().with_label(
                "corrected (GMapping)"));
    for (std::size_t k = 1; k < rows.size(); ++k) {
      std::vector<double> xs, ys;
      for (const Pose2& p : rows[k].poses) {
        xs.push_back(p[0]);
        ys.push_back(p[1]);
      }
      ax.line(xs, ys, viz::Style{}.with_width(1.5).with_label(rows[k].method));
    }
    ax.legend(viz::LegendLocation::kUpperRight);
    fig.save_png(out + "/trajectories.png");
  }
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const Row& r = rows[k];
    if (r.method != "vdt-opt" && r.method != "vdt-ekf") continue;
    viz::Figure fig(1400, 1300);
    viz::Axes& ax = fig.axes();
    map_axes(ax, map.cells);
    ax.title("scans reprojected from the " + r.method + " poses (scans 0.." +
             std::to_string(split - 1) + ")");
    std::vector<double> xs, ys;
    for (std::size_t i = 0; i < r.poses.size(); ++i) {
      for (const auto& p : scan_points(logs.raw.lasers[i].scan).points) {
        const Eigen::Vector2d q = transform_point(r.poses[i], p);
        xs.push_back(q.x());
        ys.push_back(q.y());
      }
    }
    ax.scatter(xs, ys,
               viz::Style{}
                   .with_color(viz::kColorCycle[1])
                   .with_marker(viz::Marker::kCircle, 2.0)
                   .with_alpha(0.3));
    fig.save_png(out + "/scans_" + r.method + ".png");

    viz::Figure ef(1400, 1100, 3, 1);
    ef.title(r.method + ": error against the corrected poses, with +-2 sigma");
    const char* names[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> t, e, lo, hi;
      for (std::size_t i = 0; i < r.poses.size(); ++i) {
        t.push_back(times[i] - times[0]);
        e.push_back(pose_error(r.poses[i], reference[i].pose)[c]);
        const double s2 = 2.0 * std::sqrt(std::max(0.0, r.cov[i](c, c)));
        lo.push_back(-s2);
        hi.push_back(s2);
      }
      viz::Axes& ax2 = ef.axes(c, 0);
      ax2.band(t, lo, hi, viz::Style{}.with_color(viz::kColorCycle[0]).with_label("+-2 sigma"));
      ax2.line(t, e,
               viz::Style{}.with_color(viz::kColorCycle[1]).with_width(1.5).with_label("error"));
      ax2.ylabel(names[c]).grid(true);
      if (c == 2) ax2.xlabel("time [s]");
      ax2.legend(c == 0 ? viz::LegendLocation::kUpperRight : viz::LegendLocation::kNone);
    }
    ef.save_png(out + "/errors_" + r.method + ".png");
  }
}

}  // namespace intel_study
