// The figures of the Table 3.3 study's first run: the trajectory (Fig. 3.3), vdt-opt's and
// vdt-ekf's errors with their 2-sigma bands (Figs. 3.4 / 3.5) and d_VCD around a true pose
// (Figs. 3.1 / 3.2).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "turtlebot_study.hpp"
#include "vdtnav/sensor/laser_scan.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/viz/viz.hpp"

namespace turtlebot_study {

using namespace vdtnav;

void draw_figures(const std::string& out, const std::string& name, const OccupancyGrid<2>& occ,
                  double resolution, const VdtMap2& vdt, const std::vector<std::string>& methods,
                  const sim::SimulatedRun& first_run, const std::vector<Trace>& first_traces) {
  std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
  const double w_m = occ.size().x() * resolution, h_m = occ.size().y() * resolution;
  const auto& run = first_run;
  {  // Fig. 3.3: trajectory with every 15th estimate
    viz::Figure fig(
        1600, static_cast<int>(std::clamp(1600.0 * h_m / w_m, 500.0, 1400.0)) * 2 / 2 + 100, 1, 1);
    fig.title("Trajectory (" + name + "): ground truth and every 15th estimate");
    auto& ax = fig.axes();
    ax.image(viz::occupancy_image(occ), 0, w_m, 0, h_m)
        .equal_aspect()
        .xlabel("x [m]")
        .ylabel("y [m]");
    std::vector<double> tx, ty;
    for (const auto& p : run.truth) tx.push_back(p[0]), ty.push_back(p[1]);
    ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(1.5).with_label("ground truth"));
    for (int m : {0, 1}) {
      std::vector<double> ex, ey;
      for (std::size_t k = 0; k < first_traces[m].estimate.size(); k += 15)
        ex.push_back(first_traces[m].estimate[k][0]), ey.push_back(first_traces[m].estimate[k][1]);
      ax.scatter(ex, ey,
                 viz::Style()
                     .with_color(viz::kColorCycle[m == 0 ? 0 : 1])
                     .with_marker(m == 0 ? viz::Marker::kCircle : viz::Marker::kCross, 6)
                     .with_label(methods[m]));
    }
    fig.save_png(out + "/trajectory.png");
  }
  for (int m : {0, 1}) {  // Figs. 3.4 / 3.5: errors with +-2 sigma
    viz::Figure fig(1600, 1000, 3, 1);
    fig.title(methods[m] + ": error of each pose component with its 2-sigma band");
    const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
    for (int c = 0; c < 3; ++c) {
      std::vector<double> t, e, lo, hi;
      for (std::size_t k = 1; k < run.size(); ++k) {
        const Eigen::Vector3d err = pose_error(first_traces[m].estimate[k], run.truth[k]);
        const double s = first_traces[m].has_cov[k]
                             ? 2.0 * std::sqrt(std::max(0.0, first_traces[m].covariance[k](c, c)))
                             : 0.0;
        t.push_back(run.times[k]);
        e.push_back(err[c]);
        lo.push_back(-s);
        hi.push_back(s);
      }
      auto& ax = fig.axes(c, 0);
      ax.band(t, lo, hi, viz::Style().with_label("+-2 sigma"))
          .line(t, e, viz::Style().with_width(1.2).with_label("error"))
          .ylabel(comp[c]);
      if (c == 2) ax.xlabel("time [s]");
    }
    fig.save_png(out + "/errors_" + std::string(m == 0 ? "vdt_opt" : "vdt_ekf") + ".png");
  }
  {  // Figs. 3.1 / 3.2: d_VCD around the true pose
    const std::size_t k = run.size() / 3;
    const Pose2 truth = run.truth[k];
    const ScanPoints pts = scan_points(run.scans[k]);
    VdtSensorModelOptions so;
    so.gate_mode = GateMode::kNone;
    const VdtSensorModel model(vdt, so);
    const int n = 61;
    const double span = 0.3;
    Grid<float, 2> land(Eigen::Vector2i(n, n),
                        GridFrame<2>(2 * span / n, Eigen::Vector2d(-span, -span)));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector2d d = land.cell_center(Eigen::Vector2i(i, j));
        land(Eigen::Vector2i(i, j)) = static_cast<float>(
            model.vector_chamfer_distance(truth + Pose2(d.x(), d.y(), 0.0), pts));
      }
    std::vector<double> a, v;
    for (int i = -60; i <= 60; ++i) {
      a.push_back(i * 0.002);
      v.push_back(model.vector_chamfer_distance(truth + Pose2(0.0, 0.0, i * 0.002), pts));
    }
    const auto range = viz::finite_range(land);
    viz::Figure fig(1600, 700, 1, 2);
    fig.font_scale(2);
    fig.title("d_VCD around the true pose (scan " + std::to_string(k) + ")");
    fig.axes(0, 0)
        .image(viz::heatmap(land, viz::Colormap::kViridis, range.first, range.second), -span, span,
               -span, span)
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, range.first, range.second, "d_VCD [m^2]")
        .title("position offset, yaw at truth (Fig. 3.1)")
        .xlabel("dx [m]")
        .ylabel("dy [m]");
    fig.axes(0, 1)
        .line(a, v, viz::Style().with_width(2))
        .title("yaw offset, position at truth (Fig. 3.2)")
        .xlabel("dyaw [rad]")
        .ylabel("d_VCD [m^2]");
    fig.save_png(out + "/vcd_landscape.png");
  }
}

}  // namespace turtlebot_study
