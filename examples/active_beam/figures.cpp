// vdtnav_active_beam: the figures of a dataset, trajectories, errors, the beam's bearing and a
// snapshot (active_beam_study.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "active_beam_study.hpp"
#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/plot.hpp"

namespace active_beam_study {
namespace {

Grid<std::uint8_t, 2> as_bytes(const OccupancyGrid<2>& g) {
  Grid<std::uint8_t, 2> out(g.size(), g.frame(), 0);
  for (int y = 0; y < g.size().y(); ++y) {
    for (int x = 0; x < g.size().x(); ++x) {
      out(Eigen::Vector2i(x, y)) = g(Eigen::Vector2i(x, y)) ? 1 : 0;
    }
  }
  return out;
}

}  // namespace

void plots(const Dataset& ds, const std::vector<Run>& runs, const std::string& prefix) {
  const Vector2d lo = ds.world.frame().origin();
  const Vector2d hi = lo + ds.world.size().cast<double>() * ds.world.resolution();
  const viz::RgbImage background = viz::occupancy_image(as_bytes(ds.world));
  const std::vector<viz::Rgb> colours = {
      {213, 94, 0}, {0, 114, 178}, {0, 158, 115}, {204, 121, 167}, {230, 159, 0}};
  {  // Fig. 4.3: trajectories over the map.
    viz::Figure fig(1400, 1100, 1, 1);
    viz::Axes& ax = fig.axes(0, 0);
    ax.title(ds.name + ": trajectories (Fig. 4.3)")
        .image(background, lo.x(), hi.x(), lo.y(), hi.y());
    std::vector<double> tx, ty;
    for (const auto& tp : ds.drive) {
      tx.push_back(tp.pose.x());
      ty.push_back(tp.pose.y());
    }
    ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(2.0).with_label("truth"));
    for (std::size_t m = 0; m < runs.size(); ++m) {
      std::vector<double> x, y;
      for (const auto& p : runs[m].estimate) {
        x.push_back(p.x());
        y.push_back(p.y());
      }
      ax.line(x, y,
              viz::Style()
                  .with_color(colours[m])
                  .with_width(1.0)
                  .with_label(to_string(runs[m].strategy)));
    }
    ax.equal_aspect().legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_trajectory.png");
  }
  {  // Fig. 4.4: active-trace's errors with +-2 sigma.
    const Run& r = runs.front();
    viz::Figure fig(1600, 1100, 3, 1);
    fig.title(ds.name + ": " + to_string(r.strategy) + " errors and +-2 sigma (Fig. 4.4)");
    const char* labels[3] = {"x error (m)", "y error (m)", "heading error (rad)"};
    for (int a = 0; a < 3; ++a) {
      const auto& e = a == 0 ? r.ex : a == 1 ? r.ey : r.ephi;
      const auto& s = a == 0 ? r.sx : a == 1 ? r.sy : r.sphi;
      std::vector<double> l(s.size()), h(s.size());
      for (std::size_t k = 0; k < s.size(); ++k) {
        l[k] = -2.0 * s[k];
        h[k] = 2.0 * s[k];
      }
      fig.axes(a, 0)
          .ylabel(labels[a])
          .xlabel("time (s)")
          .band(r.t, l, h, viz::Style().with_label("+-2 sigma"))
          .line(r.t, e, viz::Style().with_width(1.0).with_label("error"));
    }
    fig.axes(0, 0).legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_errors.png");
  }
  {  // The chosen segment and the beam's bearing over time.
    const Run& r = runs.front();
    viz::Figure fig(1600, 600, 1, 1);
    std::vector<double> deg(r.bearing.size());
    for (std::size_t k = 0; k < deg.size(); ++k) deg[k] = r.bearing[k] * 180.0 / kPi;
    fig.axes(0, 0)
        .title(ds.name + ": " + to_string(r.strategy) + ", the beam's bearing and goal segment")
        .xlabel("time (s)")
        .ylabel("bearing (deg) / goal segment")
        .line(r.t, deg, viz::Style().with_width(1.0).with_label("bearing (deg)"))
        .line(r.t, r.goal, viz::Style().with_color({213, 94, 0}).with_label("goal segment"))
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_segments.png");
  }
  {  // Figs. 4.5-4.7: a snapshot half way: pose, the sensor's range circle and the beam.
    const Run& r = runs.front();
    const std::size_t k = r.t.size() / 2;
    const Pose2 p = r.estimate[k];
    const double range = std::min(ds.beam.range_max, 6.0);
    viz::Figure fig(1100, 1000, 1, 1);
    viz::Axes& ax = fig.axes(0, 0);
    ax.title(ds.name + ": snapshot at t = " + std::to_string(static_cast<int>(r.t[k])) +
             " s (Figs. 4.5-4.7)")
        .image(background, lo.x(), hi.x(), lo.y(), hi.y());
    std::vector<double> cx, cy;
    for (int a = 0; a <= 90; ++a) {
      cx.push_back(p.x() + ds.beam.range_max * std::cos(a * 2 * kPi / 90));
      cy.push_back(p.y() + ds.beam.range_max * std::sin(a * 2 * kPi / 90));
    }
    const double b = p[2] + r.bearing[k];
    ax.line(cx, cy, viz::Style().with_color({0, 158, 115}).with_label("sensor range"))
        .line({p.x(), p.x() + ds.beam.range_max * std::cos(b)},
              {p.y(), p.y() + ds.beam.range_max * std::sin(b)},
              viz::Style().with_color({213, 94, 0}).with_width(2.0).with_label("beam"))
        .scatter({p.x()}, {p.y()},
                 viz::Style()
                     .with_color({0, 114, 178})
                     .with_marker(viz::Marker::kCircle, 10)
                     .with_label("estimated pose"))
        .xlim(p.x() - range - 1, p.x() + range + 1)
        .ylim(p.y() - range - 1, p.y() + range + 1)
        .equal_aspect()
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_snapshot.png");
  }
}

}  // namespace active_beam_study
