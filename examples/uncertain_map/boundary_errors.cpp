// The errors of a fitted map at the true boundary (Fig. 5.6): measured along the fitted normal,
// with their sigma, and plotted.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "uncertain_map_study.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;
using Eigen::Vector2d;

BoundaryErrors boundary_errors(const mapping::UncertainVdtMap& map,
                               const std::vector<Vector2d>& truth, std::size_t max_points) {
  BoundaryErrors out;
  const std::size_t step = std::max<std::size_t>(1, truth.size() / max_points);
  for (std::size_t k = 0; k < truth.size(); k += step) {
    const mapping::UncertainMapSample s = map.evaluate(truth[k]);
    if (!s.inside || !s.covariance.allFinite()) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 *
                                                            (s.jacobian + s.jacobian.transpose()));
    const int i = std::abs(es.eigenvalues()[1]) >= std::abs(es.eigenvalues()[0]) ? 1 : 0;
    const Vector2d n = es.eigenvectors().col(i);
    out.add(n.dot(s.value), std::sqrt(std::max(0.0, n.dot(s.covariance * n))));
  }
  return out;
}

void plot_boundary_errors(const BoundaryErrors& e, const std::string& path,
                          const std::string& title) {
  std::vector<double> lo(e.sigma.size()), hi(e.sigma.size());
  for (std::size_t k = 0; k < e.sigma.size(); ++k) {
    lo[k] = -2.0 * e.sigma[k];
    hi[k] = 2.0 * e.sigma[k];
  }
  viz::Figure fig(1600, 600, 1, 1);
  fig.axes(0, 0)
      .title(title)
      .xlabel("true boundary point")
      .ylabel("fitted DT_v along the normal (m)")
      .band(e.index, lo, hi, viz::Style().with_label("+-2 sigma"))
      .line(e.index, e.error, viz::Style().with_width(1.0).with_label("error"))
      .legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

}  // namespace study
