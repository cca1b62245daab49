// vdtnav_pan_tilt_3d: the figures, slices of the 3D VDT with the robot locations and Fig. 3.18's
// RMSE against the downsampling factor (pan_tilt_study.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pan_tilt_study.hpp"
#include "vdtnav/viz/viz.hpp"

namespace pan_tilt_study {
namespace {

/// |DT_v| on a plane: the points origin + i * du + j * dv, i < nu, j < nv.
Grid<float, 2> vdt_slice(const VdtMap3& vdt, const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& du, const Eigen::Vector3d& dv, int nu, int nv,
                         double cell) {
  Grid<float, 2> out(Eigen::Vector2i(nu, nv), GridFrame<2>(cell, Eigen::Vector2d::Zero()), 0.f);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      out(Eigen::Vector2i(i, j)) = static_cast<float>(vdt.value(origin + i * du + j * dv).norm());
  return out;
}

}  // namespace

/// Writes the |DT_v| slices with the robot locations marked: a horizontal one at the mean sensor
/// height (vdt_slice_horizontal.png) and two vertical ones through location 1
/// (vdt_slice_vertical.png).
void write_vdt_slices(const World& world, const VdtMap3& vdt, const PanTiltCalibration& cal,
                      const std::string& out) {
  const double res = vdt.resolution();
  const Eigen::Vector3d lo = vdt.frame().origin();
  const Eigen::Vector3d hi = lo + vdt.size().cast<double>() * res;
  const Eigen::Vector3i n = vdt.size();
  double z = 0.0;
  for (const Pose3& p : world.locations) z += sensor_z(p, cal);
  z /= static_cast<double>(world.locations.size());
  // Colour scale of a slice: 0 to its largest value, at most 2 m (the colour saturates beyond).
  const auto clip = [](const Grid<float, 2>& g) {
    return std::clamp(static_cast<double>(viz::finite_range(g).second), 0.1, 2.0);
  };
  const auto mark = [&](viz::Axes& ax, int u, int v, bool heading) {
    for (std::size_t k = 0; k < world.locations.size(); ++k) {
      const Pose3& p = world.locations[k];
      const Eigen::Vector3d s = (p * pan_tilt_laser_pose(cal, 0.0, 0.0)).translation();
      const viz::Rgb color = viz::kColorCycle[(k + 1) % viz::kColorCycle.size()];
      if (heading) {
        const Eigen::Vector3d f = s + 0.8 * p.linear().col(0);
        ax.line({s[u], f[u]}, {s[v], f[v]}, viz::Style().with_color(color).with_width(3));
      }
      ax.scatter({s[u]}, {s[v]},
                 viz::Style()
                     .with_color(color)
                     .with_marker(viz::Marker::kCircle, 14)
                     .with_label("L" + std::to_string(k + 1)));
    }
  };
  {
    const Grid<float, 2> h =
        vdt_slice(vdt, Eigen::Vector3d(lo.x() + 0.5 * res, lo.y() + 0.5 * res, z),
                  Eigen::Vector3d(res, 0, 0), Eigen::Vector3d(0, res, 0), n.x(), n.y(), res);
    const double w = hi.x() - lo.x(), d = hi.y() - lo.y();
    viz::Figure fig(1400, static_cast<int>(std::clamp(1150.0 * d / w, 500.0, 1600.0)) + 150);
    char title[160];
    std::snprintf(title, sizeof title, "%s: |DT_v| at the mean sensor height z = %.2f m",
                  world.name.c_str(), z);
    fig.title(title);
    auto& ax = fig.axes();
    ax.image(viz::heatmap(h, viz::Colormap::kViridis, 0.0, clip(h)), lo.x(), hi.x(), lo.y(), hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(h), "|DT_v| [m]")
        .xlabel("x [m]")
        .ylabel("y [m]");
    mark(ax, 0, 1, true);
    fig.save_png(out + "/vdt_slice_horizontal.png");
  }
  {
    const Eigen::Vector3d s =
        (world.locations.front() * pan_tilt_laser_pose(cal, 0.0, 0.0)).translation();
    const Grid<float, 2> xz =
        vdt_slice(vdt, Eigen::Vector3d(lo.x() + 0.5 * res, s.y(), lo.z() + 0.5 * res),
                  Eigen::Vector3d(res, 0, 0), Eigen::Vector3d(0, 0, res), n.x(), n.z(), res);
    const Grid<float, 2> yz =
        vdt_slice(vdt, Eigen::Vector3d(s.x(), lo.y() + 0.5 * res, lo.z() + 0.5 * res),
                  Eigen::Vector3d(0, res, 0), Eigen::Vector3d(0, 0, res), n.y(), n.z(), res);
    const double hz = hi.z() - lo.z(), wide = std::max(hi.x() - lo.x(), hi.y() - lo.y());
    viz::Figure fig(1400, static_cast<int>(std::clamp(2 * 1150.0 * hz / wide, 300.0, 1600.0)) + 300,
                    2, 1);
    fig.title(world.name + ": vertical |DT_v| slices through location L1");
    char t1[96], t2[96];
    std::snprintf(t1, sizeof t1, "plane y = %.2f m", s.y());
    std::snprintf(t2, sizeof t2, "plane x = %.2f m", s.x());
    auto& a = fig.axes(0, 0);
    a.image(viz::heatmap(xz, viz::Colormap::kViridis, 0.0, clip(xz)), lo.x(), hi.x(), lo.z(),
            hi.z())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(xz), "|DT_v| [m]")
        .title(t1)
        .xlabel("x [m]")
        .ylabel("z [m]");
    a.scatter({s.x()}, {s.z()},
              viz::Style()
                  .with_color(viz::kColorCycle[1])
                  .with_marker(viz::Marker::kCircle, 14)
                  .with_label("L1 sensor"));
    auto& b = fig.axes(1, 0);
    b.image(viz::heatmap(yz, viz::Colormap::kViridis, 0.0, clip(yz)), lo.y(), hi.y(), lo.z(),
            hi.z())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, clip(yz), "|DT_v| [m]")
        .title(t2)
        .xlabel("y [m]")
        .ylabel("z [m]");
    b.scatter({s.y()}, {s.z()},
              viz::Style()
                  .with_color(viz::kColorCycle[1])
                  .with_marker(viz::Marker::kCircle, 14)
                  .with_label("L1 sensor"));
    fig.save_png(out + "/vdt_slice_vertical.png");
  }
}

/// Fig. 3.18: RMSE per scenario against the downsampling factor, with the success rate and the
/// solve time (x: log10 of the factor, which the plots cannot put on a log axis themselves).
void write_rmse_figure(const std::vector<std::vector<Cell>>& cells, const std::string& title,
                       const std::string& path) {
  viz::Figure fig(1600, 1100, 2, 2);
  fig.title(title);
  std::vector<double> xs;
  for (int f : kFactors) xs.push_back(std::log10(static_cast<double>(f)));
  const char* xlabel = "log10(factor k), k = 1, 2, 5, 10, 100";
  const viz::Marker markers[4] = {viz::Marker::kCircle, viz::Marker::kSquare,
                                  viz::Marker::kTriangle, viz::Marker::kCross};
  const auto series = [&](viz::Axes& ax, double (Cell::*metric)() const) {
    for (std::size_t s = 0; s < kScenarios.size(); ++s) {
      std::vector<double> ys;
      for (std::size_t f = 0; f < kFactors.size(); ++f) ys.push_back((cells[s][f].*metric)());
      ax.line(xs, ys,
              viz::Style()
                  .with_color(viz::kColorCycle[s])
                  .with_marker(markers[s], 10)
                  .with_label(std::string("scenario ") + kScenarios[s].name));
    }
    ax.xlabel(xlabel);
  };
  series(fig.axes(0, 0), &Cell::pos_rmse);
  fig.axes(0, 0)
      .hline(0.02, viz::Style().with_dashes().with_label("target at factor 1"))
      .title("position RMSE (converged trials)")
      .ylabel("RMSE [m]")
      .legend(viz::LegendLocation::kUpperLeft);
  series(fig.axes(0, 1), &Cell::att_rmse);
  fig.axes(0, 1)
      .hline(0.01, viz::Style().with_dashes().with_label("target at factor 1"))
      .title("attitude RMSE (converged trials)")
      .ylabel("RMSE [rad]")
      .legend(viz::LegendLocation::kUpperLeft);
  series(fig.axes(1, 0), &Cell::success_pct);
  fig.axes(1, 0)
      .title("success: < 0.1 m and < 0.05 rad")
      .ylabel("success [%]")
      .ylim(0.0, 105.0)
      .legend(viz::LegendLocation::kLowerLeft);
  series(fig.axes(1, 1), &Cell::ms_mean);
  fig.axes(1, 1)
      .title("solve time")
      .ylabel("ms per solve")
      .legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

}  // namespace pan_tilt_study
