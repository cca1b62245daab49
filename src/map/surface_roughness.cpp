#include "vdtnav/map/surface_roughness.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/traits.hpp"

namespace vdtnav {

template <int Dim>
SurfaceRoughness measure_surface_roughness(const OccupancyGrid<Dim>& occupied,
                                           const SurfaceRoughnessOptions& options) {
  using Index = typename SpaceTraits<Dim>::Index;
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  VDTNAV_CHECK(options.radius >= 1, "surface roughness: radius must be >= 1 cell");
  const int min_cells = options.min_cells > 0 ? options.min_cells : options.radius + 1;
  const double h = occupied.resolution();

  // Surface cells and the faces they expose (bit 2d: free at -e_d, bit 2d+1: free at +e_d).
  Grid<std::int32_t, Dim> slot(occupied.size(), occupied.frame(), -1);
  std::vector<Index> cells;
  std::vector<unsigned> faces;
  for (std::size_t c = 0; c < occupied.num_cells(); ++c) {
    if (!occupied[c]) continue;
    const Index i = occupied.index_of(static_cast<std::ptrdiff_t>(c));
    unsigned f = 0;
    for (int d = 0; d < Dim; ++d) {
      for (int side = 0; side < 2; ++side) {
        Index j = i;
        j[d] += side == 0 ? -1 : 1;
        if (occupied.contains(j) && !occupied(j)) f |= 1U << (2 * d + side);
      }
    }
    if (f == 0) continue;  // interior
    slot[c] = static_cast<std::int32_t>(cells.size());
    cells.push_back(i);
    faces.push_back(f);
  }

  // Per window (a surface cell and one face it exposes; a one-cell wall's cells expose both):
  // the smallest eigenvalue of its cells' scatter, in cells squared.
  std::vector<double> spread;
  spread.reserve(cells.size());
  const int r = options.radius;
  std::vector<Vector> pts;
  std::vector<std::size_t> stack;
  std::vector<std::size_t> seen_at(cells.size(), 0);  // the window that last reached a cell
  std::size_t window = 0;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    for (unsigned face = 0; face < 2 * Dim; ++face) {
      const unsigned bit = 1U << face;
      if ((faces[k] & bit) == 0) continue;
      // The surface through cell k facing this way: cells exposing the same face, linked within
      // two cells (a jag of a cell either way leaves a gap of one), inside the disc of radius r:
      // one face of a wall, not its other face, the wall across a corner or the shelf beside it.
      ++window;
      pts.clear();
      stack.assign(1, k);
      seen_at[k] = window;
      while (!stack.empty()) {
        const std::size_t m = stack.back();
        stack.pop_back();
        pts.push_back((cells[m] - cells[k]).template cast<double>());
        Index lo = cells[m].array() - 2, hi = cells[m].array() + 2, j = lo;
        while (true) {
          if (occupied.contains(j) && (j - cells[k]).squaredNorm() <= r * r) {
            const std::int32_t s = slot(j);
            if (s >= 0 && seen_at[static_cast<std::size_t>(s)] != window &&
                (faces[static_cast<std::size_t>(s)] & bit) != 0) {
              seen_at[static_cast<std::size_t>(s)] = window;
              stack.push_back(static_cast<std::size_t>(s));
            }
          }
          int d = 0;
          for (; d < Dim; ++d) {
            if (++j[d] <= hi[d]) break;
            j[d] = lo[d];
          }
          if (d == Dim) break;
        }
      }
      if (static_cast<int>(pts.size()) < min_cells) continue;
      Vector mean = Vector::Zero();
      for (const Vector& p : pts) mean += p;
      mean /= static_cast<double>(pts.size());
      Matrix scatter = Matrix::Zero();
      for (const Vector& p : pts) scatter += (p - mean) * (p - mean).transpose();
      scatter /= static_cast<double>(pts.size());
      Eigen::SelfAdjointEigenSolver<Matrix> eig(scatter, Eigen::EigenvaluesOnly);
      spread.push_back(std::max(0.0, eig.eigenvalues()[0]));
    }
  }

  SurfaceRoughness out;
  out.windows = spread.size();
  if (!spread.empty()) {
    double sum = 0.0;
    for (const double v : spread) sum += v;
    out.sigma = std::sqrt(sum / static_cast<double>(spread.size())) * h;
  }
  out.floor = std::max(out.sigma, h / std::sqrt(12.0));
  return out;
}

template SurfaceRoughness measure_surface_roughness<2>(const OccupancyGrid<2>&,
                                                       const SurfaceRoughnessOptions&);
template SurfaceRoughness measure_surface_roughness<3>(const OccupancyGrid<3>&,
                                                       const SurfaceRoughnessOptions&);

}  // namespace vdtnav
