// The figures of a fitted map: the DT_x, DT_y and sigma fields (Fig. 5.4) and the zero contour
// against the observations and the truth (Fig. 5.5).

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "uncertain_map_study.hpp"
#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;
using Eigen::Vector2d;

void plot_map(const mapping::UncertainVdtMap& map, const std::vector<Vector2d>& truth,
              const std::string& prefix, const std::string& title) {
  const Vector2d lo = map.origin();
  const Vector2d hi = lo + map.cells().cast<double>() * map.spacing();
  const double res = std::max(0.01, (hi - lo).maxCoeff() / 1200.0);
  const Eigen::Vector2i size = ((hi - lo) / res).array().ceil().cast<int>().matrix();
  Grid<float, 2> fx(size, GridFrame<2>(res, lo), NAN), fy = fx, fs = fx;
  std::vector<double> zx, zy;
  for (int y = 0; y < size.y(); ++y) {
    for (int x = 0; x < size.x(); ++x) {
      const Vector2d c = fx.frame().cell_center(Eigen::Vector2i(x, y));
      const mapping::UncertainMapSample s = map.evaluate(c);
      if (!s.inside) continue;
      fx(Eigen::Vector2i(x, y)) = static_cast<float>(s.value.x());
      fy(Eigen::Vector2i(x, y)) = static_cast<float>(s.value.y());
      fs(Eigen::Vector2i(x, y)) = static_cast<float>(std::sqrt(s.covariance.trace()));
      // The zero contour: where DT_v is shorter than half a pixel and points across it.
      if (s.value.norm() < 0.5 * res) {
        zx.push_back(c.x());
        zy.push_back(c.y());
      }
    }
  }
  const double band = 1.0;
  const double shi = std::min(0.1, viz::finite_range(fs).second);
  {
    viz::Figure fig(1800, 650, 1, 3);
    fig.title(title + ": the fitted map (Fig. 5.4)");
    fig.axes(0, 0)
        .image(viz::heatmap(fx, viz::Colormap::kBlueWhiteRed, -band, band), lo.x(), hi.x(), lo.y(),
               hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kBlueWhiteRed, -band, band, "DT_x (m)")
        .title("DT_x");
    fig.axes(0, 1)
        .image(viz::heatmap(fy, viz::Colormap::kBlueWhiteRed, -band, band), lo.x(), hi.x(), lo.y(),
               hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kBlueWhiteRed, -band, band, "DT_y (m)")
        .title("DT_y");
    fig.axes(0, 2)
        .image(viz::heatmap(fs, viz::Colormap::kViridis, 0.0, shi), lo.x(), hi.x(), lo.y(), hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, shi, "sigma (m)")
        .title("sqrt(trace cov DT_v)");
    fig.save_png(prefix + "_fields.png");
  }
  {
    viz::Figure fig(1400, 1100, 1, 1);
    std::vector<double> ox, oy, tx, ty;
    for (const auto& p : map.observed_points()) {
      ox.push_back(p.x());
      oy.push_back(p.y());
    }
    const std::size_t step = std::max<std::size_t>(1, truth.size() / 20000);
    for (std::size_t k = 0; k < truth.size(); k += step) {
      tx.push_back(truth[k].x());
      ty.push_back(truth[k].y());
    }
    fig.axes(0, 0)
        .title(title + ": zero contour of the fitted VDT (Fig. 5.5)")
        .scatter(ox, oy,
                 viz::Style()
                     .with_color({0, 114, 178})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_alpha(0.35)
                     .with_label("observations (given poses)"))
        .scatter(tx, ty,
                 viz::Style()
                     .with_color({0, 0, 0})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_label("true boundary"))
        .scatter(zx, zy,
                 viz::Style()
                     .with_color({213, 94, 0})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_label("fitted DT_v = 0"))
        .xlim(lo.x(), hi.x())
        .ylim(lo.y(), hi.y())
        .equal_aspect()
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_zero_contour.png");
  }
}

}  // namespace study
