// The PMD study's figures: the trajectories over the map (Fig. 3.24), vdt-ekf's and
// vdt-ekf+bearings' errors with their 2-sigma bands (Fig. 3.23) and one frame with the ground
// boundaries kept.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "pmd_study.hpp"
#include "study_common.hpp"
#include "vdtnav/viz/viz.hpp"

namespace pmd_study {

using namespace vdtnav;
using study::to_rgb;
using namespace vdtnav::rgbd_ground;

void draw_figures(const std::string& out, const Scenario& sc, const FilterRun& run) {
  const OccupancyGrid<2>& boundaries = sc.boundaries;
  const ScooterDrive& drive = sc.drive;
  const std::size_t n = sc.n;
  const std::vector<Trace>& traces = run.traces;
  const std::vector<Landmark2>& landmarks = run.landmarks;
  const std::size_t shown = run.shown;
  const cv::Mat& shown_colour = run.shown_colour;
  const GroundBoundaries& shown_boundaries = run.shown_boundaries;

  // ------------------------------------------------------------------ figures
  std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
  const GridFrame<2>& gf = boundaries.frame();
  const double x0 = gf.origin().x(), y0 = gf.origin().y();
  const double x1 = x0 + boundaries.size().x() * gf.resolution();
  const double y1 = y0 + boundaries.size().y() * gf.resolution();
  {  // Fig. 3.24: trajectories over the map
    viz::Figure fig(1600, static_cast<int>(1600.0 * (y1 - y0) / (x1 - x0)) + 150, 1, 1);
    fig.title("PMD trajectories over the boundary map (Fig. 3.24)");
    auto& ax = fig.axes();
    ax.image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
        .equal_aspect()
        .xlabel("x [m]")
        .ylabel("y [m]");
    std::vector<double> tx, ty;
    for (std::size_t k = 0; k < n; ++k) {
      tx.push_back(drive.truth[k][0]);
      ty.push_back(drive.truth[k][1]);
    }
    ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(2.0).with_label("truth"));
    for (std::size_t m = 0; m < traces.size(); ++m) {
      std::vector<double> ex, ey;
      for (const Pose2& p : traces[m].estimate) {
        ex.push_back(p[0]);
        ey.push_back(p[1]);
      }
      ax.line(
          ex, ey,
          viz::Style().with_color(viz::kColorCycle[m]).with_width(1.2).with_label(traces[m].name));
    }
    std::vector<double> lx, ly;
    for (const Landmark2& l : landmarks) {
      lx.push_back(l.position.x());
      ly.push_back(l.position.y());
    }
    ax.scatter(lx, ly,
               viz::Style()
                   .with_color({200, 30, 30})
                   .with_marker(viz::Marker::kCross, 9)
                   .with_label("landmarks"));
    fig.save_png(out + "/trajectories.png");
  }
  {  // Fig. 3.23: errors with +-2 sigma of vdt-ekf and vdt-ekf+bearings
    viz::Figure fig(1600, 1000, 3, 1);
    fig.title("vdt-ekf (boundaries) and vdt-ekf+bearings: errors with 2-sigma bands (Fig. 3.23)");
    const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
    for (int c = 0; c < 3; ++c) {
      auto& ax = fig.axes(c, 0);
      double span = 0.0;
      for (std::size_t m : {0u, 1u}) {
        std::vector<double> t, e, lo, hi;
        for (std::size_t k = 0; k < n; ++k) {
          const Eigen::Vector3d err = pose_error(traces[m].estimate[k], drive.truth[k]);
          const double s = 2.0 * std::sqrt(std::max(0.0, traces[m].covariance[k](c, c)));
          t.push_back(drive.time[k]);
          e.push_back(err[c]);
          lo.push_back(-s);
          hi.push_back(s);
          span = std::max({span, 1.2 * std::abs(err[c]), 1.2 * s});
        }
        ax.band(t, lo, hi,
                viz::Style()
                    .with_color(viz::kColorCycle[m])
                    .with_alpha(0.25)
                    .with_label(traces[m].name + " +-2 sigma"))
            .line(t, e,
                  viz::Style()
                      .with_color(viz::kColorCycle[m])
                      .with_width(1.2)
                      .with_label(traces[m].name));
      }
      span = std::min(span, c == 2 ? 0.2 : 1.0);
      ax.ylim(-span, span).ylabel(comp[c]);
      if (c == 2) ax.xlabel("time [s]");
    }
    fig.save_png(out + "/errors.png");
  }
  if (!shown_colour.empty()) {  // one frame: kept boundary pixels over the colour image
    viz::Figure fig(1000, 820, 1, 1);
    fig.title("Frame " + std::to_string(shown) + ": ground boundaries kept (" +
              std::to_string(shown_boundaries.points.size()) + ") and pruned (" +
              std::to_string(shown_boundaries.pruned) + ")");
    const int h = shown_colour.rows;
    std::vector<double> ku, kv;
    for (const BoundaryPoint& p : shown_boundaries.points) {
      ku.push_back(p.pixel.x());
      kv.push_back(h - 1 - p.pixel.y());
    }
    fig.axes()
        .image(to_rgb(shown_colour), -0.5, shown_colour.cols - 0.5, -0.5, h - 0.5)
        .equal_aspect()
        .scatter(ku, kv,
                 viz::Style()
                     .with_color({30, 230, 30})
                     .with_marker(viz::Marker::kCircle, 3)
                     .with_label("kept boundary pixels"))
        .xlabel("u [px]")
        .ylabel("image row from the bottom [px]");
    fig.save_png(out + "/frame.png");
  }
}

}  // namespace pmd_study
