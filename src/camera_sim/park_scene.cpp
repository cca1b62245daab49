#include "vdtnav/camera_sim/park_scene.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "vdtnav/core/error.hpp"

namespace vdtnav::rgbd_ground {
namespace {

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

}  // namespace

Surface ParkScene::surface_at(const Eigen::Vector2d& p) const {
  const double half = 0.5 * options.path_width;
  if ((p - plaza).norm() <= options.plaza_radius) return Surface::kGravel;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    if (segment_distance(p, loop[i], loop[(i + 1) % loop.size()]) <= half)
      return Surface::kPavement;
  }
  for (const auto& [a, b] : gravel_paths) {
    if (segment_distance(p, a, b) <= half) return Surface::kGravel;
  }
  return Surface::kGrass;
}

OccupancyGrid<2> ParkScene::boundary_map(double resolution) const {
  VDTNAV_CHECK(resolution > 0.0, "park: the map resolution must be > 0");
  const Eigen::Vector2i size(static_cast<int>(std::ceil(options.width / resolution)),
                             static_cast<int>(std::ceil(options.depth / resolution)));
  OccupancyGrid<2> grid(size, GridFrame<2>(resolution, Eigen::Vector2d::Zero()), 0);
  std::vector<Surface> s(static_cast<std::size_t>(size.x()) * size.y());
  for (int y = 0; y < size.y(); ++y)
    for (int x = 0; x < size.x(); ++x)
      s[static_cast<std::size_t>(y) * size.x() + x] = surface_at(grid.cell_center({x, y}));
  // Both cells of every 4-neighbour pair on different surfaces are boundary cells: the boundary
  // runs between their centres, so the band's middle is on it (one cell per side would put the
  // map's boundary half a cell to that side).
  for (int y = 0; y < size.y(); ++y) {
    for (int x = 0; x < size.x(); ++x) {
      const Surface here = s[static_cast<std::size_t>(y) * size.x() + x];
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        const int xx = x + dx, yy = y + dy;
        if (xx >= size.x() || yy >= size.y()) continue;
        if (s[static_cast<std::size_t>(yy) * size.x() + xx] != here) {
          grid({x, y}) = 1;
          grid({xx, yy}) = 1;
        }
      }
    }
  }
  return grid;
}

ParkScene generate_park(const ParkSceneOptions& o) {
  VDTNAV_CHECK(o.width >= 20.0 && o.depth >= 16.0, "park: at least 20 m x 16 m");
  ParkScene p;
  p.options = o;
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  // The paved loop: a rounded rectangle 6 m inside the park's edge, its corners cut at 45 deg,
  // the sides bent a little (seeded).
  const double m = 6.0, c = 5.0, w = o.width, d = o.depth;
  p.loop = {{m + c, m},
            {0.5 * w + 2.0 * jitter(rng), m + 1.5 * jitter(rng)},
            {w - m - c, m},
            {w - m, m + c},
            {w - m + 1.5 * jitter(rng), 0.5 * d},
            {w - m, d - m - c},
            {w - m - c, d - m},
            {0.5 * w + 2.0 * jitter(rng), d - m + 1.5 * jitter(rng)},
            {m + c, d - m},
            {m, d - m - c},
            {m + 1.5 * jitter(rng), 0.5 * d},
            {m, m + c}};
  p.plaza = Eigen::Vector2d(0.5 * w + 2.0 * jitter(rng), 0.5 * d + 1.5 * jitter(rng));
  // Gravel paths from the plaza to the middles of the loop's four sides.
  for (const std::size_t k : {1u, 4u, 7u, 10u}) p.gravel_paths.emplace_back(p.plaza, p.loop[k]);
  // Lamp posts beside the loop, one every ~12 m, 1.8 m off its centre line (alternating sides).
  double along = 0.0;
  int side = 1;
  for (std::size_t i = 0; i < p.loop.size(); ++i) {
    const Eigen::Vector2d a = p.loop[i], b = p.loop[(i + 1) % p.loop.size()];
    const double len = (b - a).norm();
    const Eigen::Vector2d t = (b - a) / len, n(-t.y(), t.x());
    for (double s = std::fmod(12.0 - along, 12.0); s < len; s += 12.0) {
      const Eigen::Vector2d lp = a + s * t + side * (0.5 * o.path_width + 0.6) * n;
      p.lamp_posts.push_back(lp);
      p.obstacles.push_back({lp, 0.08, Eigen::Vector2d::Zero(), 4.0, Eigen::Vector3d(40, 40, 40)});
      side = -side;
    }
    along = std::fmod(along + len, 12.0);
  }
  // Benches on the grass beside the loop (boxes 1.6 x 0.5, 0.8 tall, brown), bins, and people
  // on the paths (cylinders 0.25 m, 1.7 m, clothes of random colours).
  std::uniform_int_distribution<std::size_t> seg(0, p.loop.size() - 1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int k = 0; k < o.benches; ++k) {
    const std::size_t i = seg(rng);
    const Eigen::Vector2d a = p.loop[i], b = p.loop[(i + 1) % p.loop.size()];
    const Eigen::Vector2d t = (b - a).normalized(), n(-t.y(), t.x());
    const Eigen::Vector2d at = a + (0.2 + 0.6 * u01(rng)) * (b - a) +
                               (u01(rng) < 0.5 ? -1.0 : 1.0) * (0.5 * o.path_width + 1.0) * n;
    const bool along_x = std::abs(t.x()) > std::abs(t.y());
    p.obstacles.push_back({at, 0.0,
                           along_x ? Eigen::Vector2d(0.8, 0.25) : Eigen::Vector2d(0.25, 0.8), 0.8,
                           Eigen::Vector3d(30, 70, 120)});
  }
  for (int k = 0; k < o.people; ++k) {
    const std::size_t i = seg(rng);
    const Eigen::Vector2d a = p.loop[i], b = p.loop[(i + 1) % p.loop.size()];
    const Eigen::Vector2d t = (b - a).normalized(), n(-t.y(), t.x());
    const Eigen::Vector2d at = a + u01(rng) * (b - a) + (u01(rng) < 0.5 ? -0.8 : 0.8) * n;
    p.obstacles.push_back({at, 0.25, Eigen::Vector2d::Zero(), 1.7,
                           Eigen::Vector3d(255 * u01(rng), 255 * u01(rng), 255 * u01(rng))});
  }
  return p;
}

}  // namespace vdtnav::rgbd_ground
