#include "plots.hpp"

#include <algorithm>
#include <cmath>

#include "vdtnav/viz/viz.hpp"

namespace vdtnav::tools {

namespace {

void map_background(viz::Axes& ax, const RosMap& map) {
  const auto& f = map.cells.frame();
  const double x0 = f.origin().x(), y0 = f.origin().y();
  const double x1 = x0 + map.cells.size().x() * f.resolution();
  const double y1 = y0 + map.cells.size().y() * f.resolution();
  ax.image(viz::occupancy_image(map.cells), x0, x1, y0, y1)
      .equal_aspect()
      .xlabel("x [m]")
      .ylabel("y [m]");
}

}  // namespace

bool plots_available() { return true; }

void plot_trajectories(const std::string& png, const RosMap& map,
                       const std::vector<PlotTrack>& tracks, const std::string& title, int every) {
  viz::Figure fig(1400, 1200);
  viz::Axes& ax = fig.axes();
  map_background(ax, map);
  ax.title(title);
  for (std::size_t k = 0; k < tracks.size(); ++k) {
    std::vector<double> xs, ys;
    for (const Pose2& p : tracks[k].poses) {
      xs.push_back(p[0]);
      ys.push_back(p[1]);
    }
    const viz::Rgb c = viz::kColorCycle[k % viz::kColorCycle.size()];
    ax.line(xs, ys,
            viz::Style{}
                .with_color(c)
                .with_width(2.0)
                .with_dashes(tracks[k].dashed)
                .with_label(tracks[k].label));
    if (k == 0 && every > 0) {
      std::vector<double> mx, my;
      for (std::size_t i = 0; i < tracks[k].poses.size(); i += static_cast<std::size_t>(every)) {
        mx.push_back(xs[i]);
        my.push_back(ys[i]);
      }
      ax.scatter(mx, my, viz::Style{}.with_color(c).with_marker(viz::Marker::kCircle, 7.0));
    }
  }
  ax.legend(viz::LegendLocation::kUpperRight);
  fig.save_png(png);
}

void plot_reprojected_scans(const std::string& png, const RosMap& map,
                            const std::vector<Pose2>& poses, const std::vector<LaserScan>& scans,
                            const std::string& title) {
  viz::Figure fig(1400, 1200);
  viz::Axes& ax = fig.axes();
  map_background(ax, map);
  ax.title(title);
  std::vector<double> xs, ys;
  for (std::size_t k = 0; k < poses.size() && k < scans.size(); ++k) {
    const ScanPoints pts = scan_points(scans[k]);
    for (const auto& p : pts.points) {
      const Eigen::Vector2d q = transform_point(poses[k], p);
      xs.push_back(q.x());
      ys.push_back(q.y());
    }
  }
  ax.scatter(xs, ys,
             viz::Style{}
                 .with_color(viz::kColorCycle[1])
                 .with_marker(viz::Marker::kCircle, 2.0)
                 .with_alpha(0.35)
                 .with_label("scan endpoints from the estimated poses"));
  std::vector<double> tx, ty;
  for (const Pose2& p : poses) {
    tx.push_back(p[0]);
    ty.push_back(p[1]);
  }
  ax.line(tx, ty,
          viz::Style{}.with_color(viz::kColorCycle[0]).with_width(1.5).with_label("estimate"));
  ax.legend(viz::LegendLocation::kUpperRight);
  fig.save_png(png);
}

void plot_errors(const std::string& png, const std::vector<double>& t,
                 const std::vector<Eigen::Vector3d>& error,
                 const std::vector<Eigen::Vector3d>& two_sigma, const std::string& title) {
  viz::Figure fig(1400, 1100, 3, 1);
  fig.title(title);
  const char* names[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
  for (int c = 0; c < 3; ++c) {
    viz::Axes& ax = fig.axes(c, 0);
    std::vector<double> e, lo, hi;
    for (std::size_t k = 0; k < error.size(); ++k) {
      e.push_back(error[k][c]);
      if (!two_sigma.empty()) {
        lo.push_back(-two_sigma[k][c]);
        hi.push_back(two_sigma[k][c]);
      }
    }
    if (!two_sigma.empty()) {
      ax.band(t, lo, hi, viz::Style{}.with_color(viz::kColorCycle[0]).with_label("+-2 sigma"));
    }
    ax.line(t, e, viz::Style{}.with_color(viz::kColorCycle[1]).with_width(1.5).with_label("error"));
    ax.hline(0.0, viz::Style{}.with_color({0, 0, 0}).with_width(1.0));
    ax.ylabel(names[c]).grid(true);
    if (c == 2) ax.xlabel("time [s]");
    ax.legend(c == 0 ? viz::LegendLocation::kUpperRight : viz::LegendLocation::kNone);
  }
  fig.save_png(png);
}

}  // namespace vdtnav::tools
