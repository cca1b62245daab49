// Fig. 5.2: the least-squares B-spline approximation of the true VDT of the L-shaped room against
// the control point spacing.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "uncertain_map_study.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;
using Eigen::Vector2d;

void approximation(const sim::MappingScene& room, const std::string& out, std::vector<Row>& rows) {
  std::printf("[fig5.2] least-squares B-spline approximation of the true VDT of the %s\n",
              room.name.c_str());
  const VdtMap2 truth = VdtMap2::build(room.world);
  std::vector<Vector2d> boundary;
  for (int y = 0; y < room.world.size().y(); ++y) {
    for (int x = 0; x < room.world.size().x(); ++x) {
      if (room.world(Eigen::Vector2i(x, y))) {
        boundary.push_back(room.world.cell_center(Eigen::Vector2i(x, y)));
      }
    }
  }
  const auto vdt = [&](const Vector2d& p) -> Vector2d {
    return p - truth.nearest_occupied_point(p);
  };
  std::vector<double> hs = {0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5}, rms, mx;
  for (double h : hs) {
    mapping::UncertainMapOptions o;
    o.spacing = h;
    o.band = 1.0;
    const auto map = mapping::UncertainVdtMap::approximate(boundary, vdt, o);
    double ss = 0.0, m = 0.0;
    int n = 0;
    for (const auto& p : boundary) {
      const auto s = map.evaluate(p);
      if (!s.inside) continue;
      ss += s.value.squaredNorm();
      m = std::max(m, s.value.norm());
      ++n;
    }
    Row r;
    r.experiment = "approximation";
    r.spacing = h;
    r.control_points = map.summary().control_points;
    r.samples = map.summary().eikonal_samples;
    r.rms = std::sqrt(ss / std::max(1, n));
    r.max = m;
    r.fit_s = map.summary().fit_seconds;
    rows.push_back(r);
    rms.push_back(r.rms);
    mx.push_back(r.max);
    std::printf(
        "  h = %.2f m: %5d control points, |DT_v| at the true boundary rms %.4f m, "
        "max %.4f m\n",
        h, r.control_points, r.rms, r.max);
  }
  viz::Figure fig(1200, 700, 1, 1);
  fig.axes(0, 0)
      .title("Fig. 5.2: least-squares B-spline approximation of the true VDT (L-shaped room)")
      .xlabel("control point spacing (m)")
      .ylabel("|DT_v| at the true boundary (m)")
      .line(hs, rms, viz::Style().with_marker(viz::Marker::kCircle).with_label("rms"))
      .line(hs, mx, viz::Style().with_marker(viz::Marker::kSquare).with_label("max"))
      .legend(viz::LegendLocation::kUpperLeft);
  fig.save_png(out + "/fig5_2_approximation.png");
}

}  // namespace study
