// The UAV study's figures: the trajectory over the map (Fig. 3.13), vdt-opt's and vdt-ekf's
// errors with their 2-sigma bands (Fig. 3.14) and one frame's edges and ground points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "study_common.hpp"
#include "uav_study.hpp"
#include "vdtnav/viz/viz.hpp"

namespace uav_study {

using namespace vdtnav;
using study::to_rgb;
using namespace vdtnav::uav_camera;

void draw_figures(const std::string& out, const Scenario& sc, double altitude,
                  const FlightRun& run) {
  const CameraCalibration& calibration = sc.calibration;
  const OccupancyGrid<2>& boundaries = sc.boundaries;
  const std::vector<UavFlightSample>& flight = sc.flight;
  const std::vector<Trace>& traces = run.traces;
  const std::vector<char>& features = run.features;
  const std::size_t shown = run.shown;
  const cv::Mat& shown_image = run.shown_image;
  const CameraFrame& shown_frame = run.shown_frame;

  std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
  const GridFrame<2>& gf = boundaries.frame();
  const double x0 = gf.origin().x(), y0 = gf.origin().y();
  const double x1 = x0 + boundaries.size().x() * gf.resolution();
  const double y1 = y0 + boundaries.size().y() * gf.resolution();
  {  // Fig. 3.13: the trajectory against the truth over the map
    viz::Figure fig(1600, static_cast<int>(1600.0 * (y1 - y0) / (x1 - x0)) + 150, 1, 1);
    fig.title("UAV trajectory: truth and vdt-opt on localized frames (Fig. 3.13)");
    auto& ax = fig.axes();
    ax.image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
        .equal_aspect()
        .xlabel("x [m]")
        .ylabel("y [m]");
    std::vector<double> tx, ty, ex, ey, gx, gy;
    for (std::size_t k = 0; k < flight.size(); ++k) {
      tx.push_back(flight[k].pose[0]);
      ty.push_back(flight[k].pose[1]);
      if (traces[0].status[k] == LocalizationStatus::kConverged) {
        ex.push_back(traces[0].estimate[k][0]);
        ey.push_back(traces[0].estimate[k][1]);
      }
      if (!features[k]) {
        gx.push_back(flight[k].pose[0]);
        gy.push_back(flight[k].pose[1]);
      }
    }
    ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(1.5).with_label("truth"));
    ax.scatter(gx, gy,
               viz::Style()
                   .with_color({160, 160, 160})
                   .with_marker(viz::Marker::kCircle, 5)
                   .with_label("feature-poor frames"));
    ax.scatter(ex, ey,
               viz::Style()
                   .with_color(viz::kColorCycle[0])
                   .with_marker(viz::Marker::kCross, 5)
                   .with_label("vdt-opt (converged)"));
    fig.save_png(out + "/trajectory.png");
  }
  for (int m : {0, 1}) {  // Fig. 3.14: x, y, yaw errors with +-2 sigma, feature-poor shaded
    viz::Figure fig(1600, 1000, 3, 1);
    fig.title(traces[m].name + ": errors with 2-sigma bands; grey: frames without features");
    const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> t, e, lo, hi, shade_lo, shade_hi;
      double span = 0.0;
      for (std::size_t k = 0; k < flight.size(); ++k) {
        const Eigen::Vector3d err = pose_error(traces[m].estimate[k], flight[k].pose);
        const double s = traces[m].has_cov[k]
                             ? 2.0 * std::sqrt(std::max(0.0, traces[m].covariance[k](c, c)))
                             : 0.0;
        t.push_back(flight[k].time);
        const bool ok = traces[m].status[k] == LocalizationStatus::kConverged;
        e.push_back(ok ? err[c] : std::nan(""));
        lo.push_back(-s);
        hi.push_back(s);
        if (ok) span = std::max(span, std::abs(err[c]) * 1.2);
        span = std::max(span, s * 1.2);
      }
      span = std::min(span, c == 2 ? 0.1 : 1.0);
      for (std::size_t k = 0; k < flight.size(); ++k) {
        shade_lo.push_back(features[k] ? 0.0 : -span);
        shade_hi.push_back(features[k] ? 0.0 : span);
      }
      auto& ax = fig.axes(c, 0);
      ax.band(t, shade_lo, shade_hi,
              viz::Style().with_color({150, 150, 150}).with_alpha(0.35).with_label("no features"))
          .band(t, lo, hi, viz::Style().with_label("+-2 sigma"))
          .line(t, e, viz::Style().with_width(1.2).with_label("error"))
          .ylim(-span, span)
          .ylabel(comp[c]);
      if (c == 2) ax.xlabel("time [s]");
    }
    fig.save_png(out + "/errors_" + std::string(m == 0 ? "vdt_opt" : "vdt_ekf") + ".png");
  }
  {  // One frame: its edges in the image, their ground points over the map
    viz::Figure fig(1800, 760, 1, 2);
    fig.title("Frame " + std::to_string(shown) +
              ": edges (left) and their ground projections at "
              "the vdt-opt estimate (right)");
    std::vector<double> eu, ev;
    for (const auto& p : shown_frame.edges) {
      eu.push_back(p.x());
      ev.push_back(calibration.height - 1 - p.y());
    }
    fig.axes(0, 0)
        .image(to_rgb(shown_image), -0.5, calibration.width - 0.5, -0.5, calibration.height - 0.5)
        .equal_aspect()
        .scatter(eu, ev,
                 viz::Style()
                     .with_color({230, 30, 30})
                     .with_marker(viz::Marker::kCircle, 3)
                     .with_label("edge pixels"))
        .xlabel("u [px]")
        .ylabel("image row from the bottom [px]");
    const Pose2 at = traces[0].estimate[shown];
    const Pose2 truth = flight[shown].pose;
    std::vector<double> gx, gy;
    const double c = std::cos(at[2]), s = std::sin(at[2]);
    for (const auto& p : shown_frame.observations.points) {
      gx.push_back(at[0] + c * p.x() - s * p.y());
      gy.push_back(at[1] + s * p.x() + c * p.y());
    }
    const double half = 1.0 * altitude;
    fig.axes(0, 1)
        .image(viz::occupancy_image(boundaries), x0, x1, y0, y1)
        .equal_aspect()
        .xlim(truth[0] - half, truth[0] + half)
        .ylim(truth[1] - 0.75 * half, truth[1] + 0.75 * half)
        .scatter(gx, gy,
                 viz::Style()
                     .with_color({230, 30, 30})
                     .with_marker(viz::Marker::kCircle, 3)
                     .with_label("ground points"))
        .xlabel("x [m]")
        .ylabel("y [m]");
    fig.save_png(out + "/frame.png");
  }
}

}  // namespace uav_study
