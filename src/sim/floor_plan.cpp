#include "vdtnav/sim/floor_plan.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "vdtnav/core/error.hpp"

namespace vdtnav::sim {
namespace {

/// Rasteriser in world metres onto the occupancy grid (origin at (0, 0)).
class Canvas {
 public:
  explicit Canvas(OccupancyGrid<2>& g) : g_(g) {}

  /// Sets cells whose centres fall in [x0, x1] x [y0, y1] to `value`.
  void rect(double x0, double y0, double x1, double y1, std::uint8_t value = 1) {
    const double r = g_.resolution();
    const int i0 = std::max(0, static_cast<int>(std::ceil(std::min(x0, x1) / r - 0.5)));
    const int i1 =
        std::min(g_.size()[0] - 1, static_cast<int>(std::floor(std::max(x0, x1) / r - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(std::min(y0, y1) / r - 0.5)));
    const int j1 =
        std::min(g_.size()[1] - 1, static_cast<int>(std::floor(std::max(y0, y1) / r - 0.5)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) g_(Eigen::Vector2i(i, j)) = value;
  }
  void disk(const Eigen::Vector2d& c, double radius, std::uint8_t value = 1) {
    const double r = g_.resolution();
    for (int j = std::max(0, static_cast<int>((c.y() - radius) / r) - 1);
         j <= std::min(g_.size()[1] - 1, static_cast<int>((c.y() + radius) / r) + 1); ++j) {
      for (int i = std::max(0, static_cast<int>((c.x() - radius) / r) - 1);
           i <= std::min(g_.size()[0] - 1, static_cast<int>((c.x() + radius) / r) + 1); ++i) {
        if ((g_.cell_center(Eigen::Vector2i(i, j)) - c).norm() <= radius)
          g_(Eigen::Vector2i(i, j)) = value;
      }
    }
  }

 private:
  OccupancyGrid<2>& g_;
};

}  // namespace

FloorPlan generate_floor_plan(const FloorPlanOptions& o) {
  VDTNAV_CHECK(o.resolution > 0.0 && o.wall_thickness >= o.resolution,
               "floor plan: wall thickness must be at least one cell");
  VDTNAV_CHECK(o.width >= 2.0 * o.max_room_width && o.height >= o.corridor_width + 6.0,
               "floor plan: the building is too small for rooms on both sides of a corridor");
  VDTNAV_CHECK(o.min_room_width > o.door_width + 1.0 && o.max_room_width >= o.min_room_width,
               "floor plan: room widths must leave space for a door");
  std::mt19937 rng(o.seed);
  auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };

  FloorPlan plan;
  const Eigen::Vector2i size(static_cast<int>(std::round(o.width / o.resolution)),
                             static_cast<int>(std::round(o.height / o.resolution)));
  plan.occupancy = OccupancyGrid<2>(size, GridFrame<2>(o.resolution, Eigen::Vector2d::Zero()), 0);
  Canvas canvas(plan.occupancy);
  const double t = o.wall_thickness, w = o.width, h = o.height;

  // Outer walls, a margin of one wall thickness inside the grid.
  canvas.rect(t, t, w - t, 2 * t);
  canvas.rect(t, h - 2 * t, w - t, h - t);
  canvas.rect(t, t, 2 * t, h - t);
  canvas.rect(w - 2 * t, t, w - t, h - t);

  // Main corridor along x, off-centre by a random amount; a cross corridor along y.
  plan.corridor_y = h / 2 + uniform(-0.1, 0.1) * h;
  const double c_lo = plan.corridor_y - o.corridor_width / 2,
               c_hi = plan.corridor_y + o.corridor_width / 2;
  plan.cross_corridor_x = w * uniform(0.4, 0.6);
  const double x_lo = plan.cross_corridor_x - o.corridor_width / 2;
  const double x_hi = plan.cross_corridor_x + o.corridor_width / 2;

  // Rooms: partition [2t, x_lo] and [x_hi, w - 2t] into widths in [min, max] on both sides.
  auto partition = [&](double a, double b) {
    std::vector<double> cuts{a};
    while (b - cuts.back() > 2 * o.max_room_width)
      cuts.push_back(cuts.back() + uniform(o.min_room_width, o.max_room_width));
    const double rest = b - cuts.back();
    if (rest > o.max_room_width) cuts.push_back(cuts.back() + rest / 2);
    cuts.push_back(b);
    return cuts;
  };
  for (int side = 0; side < 2; ++side) {
    const double y0 = side == 0 ? 2 * t : c_hi, y1 = side == 0 ? c_lo : h - 2 * t;
    const double wall_y = side == 0 ? c_lo : c_hi;  // corridor wall of this side
    // Cross-corridor walls on this side.
    canvas.rect(x_lo - t, y0, x_lo, y1);
    canvas.rect(x_hi, y0, x_hi + t, y1);
    for (const auto& span : {std::pair{2 * t, x_lo - t}, std::pair{x_hi + t, w - 2 * t}}) {
      const auto cuts = partition(span.first, span.second);
      // The corridor wall along the whole span, doors cut later.
      canvas.rect(span.first, wall_y - t / 2, span.second, wall_y + t / 2);
      for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
        const double rx0 = cuts[k], rx1 = cuts[k + 1];
        if (k > 0) canvas.rect(rx0 - t / 2, y0, rx0 + t / 2, y1);  // wall between rooms
        Room room;
        room.min_corner = {rx0, y0};
        room.max_corner = {rx1, y1};
        const double door_x = uniform(rx0 + o.door_width / 2 + 0.4, rx1 - o.door_width / 2 - 0.4);
        room.door = {door_x, wall_y};
        room.centre = {(rx0 + rx1) / 2, (y0 + y1) / 2};
        plan.rooms.push_back(room);
      }
      // Doors between some neighbouring rooms.
      for (std::size_t k = 1; k + 1 < cuts.size(); ++k) {
        if (uniform(0, 1) < 0.4) {
          const double dy = uniform(y0 + 0.8, y1 - o.door_width - 0.8);
          canvas.rect(cuts[k] - t, dy, cuts[k] + t, dy + o.door_width, 0);
        }
      }
    }
  }
  // Clutter: furniture against walls or free-standing, never in front of a door or at the centre.
  for (const Room& room : plan.rooms) {
    const int items = std::uniform_int_distribution<int>(1, std::max(1, o.clutter_per_room))(rng);
    for (int k = 0; k < items; ++k) {
      for (int attempt = 0; attempt < 20; ++attempt) {
        const double sx = uniform(0.4, 1.6), sy = uniform(0.4, 1.0);
        const Eigen::Vector2d lo(uniform(room.min_corner.x() + t, room.max_corner.x() - t - sx),
                                 uniform(room.min_corner.y() + t, room.max_corner.y() - t - sy));
        const Eigen::Vector2d hi = lo + Eigen::Vector2d(sx, sy);
        auto clear_of = [&](const Eigen::Vector2d& p, double r) {
          const Eigen::Vector2d q = p.cwiseMax(lo).cwiseMin(hi);
          return (q - p).norm() > r;
        };
        // Keep the door, the centre and the tour's way in (door -> 1 m inside -> centre) free.
        const double inward = room.centre.y() > plan.corridor_y ? 1.0 : -1.0;
        const Eigen::Vector2d way_in(room.door.x(), room.door.y() + inward);
        bool clear = clear_of(room.door, 1.4) && clear_of(room.centre, 1.0);
        for (double s = 0.0; s <= 1.0 && clear; s += 0.05)
          clear = clear_of((1 - s) * way_in + s * room.centre, 0.6);
        if (!clear) continue;
        if (uniform(0, 1) < 0.3) {
          canvas.disk((lo + hi) / 2, std::min(sx, sy) / 2);  // round table
        } else {
          canvas.rect(lo.x(), lo.y(), hi.x(), hi.y());
        }
        break;
      }
    }
  }
  // Doors onto the corridor (cut after clutter so nothing blocks them).
  for (const Room& room : plan.rooms) {
    canvas.rect(room.door.x() - o.door_width / 2, room.door.y() - t,
                room.door.x() + o.door_width / 2, room.door.y() + t, 0);
  }
  // Pillars along the main corridor walls.
  for (double x = 3.0; x < w - 3.0; x += uniform(5.0, 9.0)) {
    if (std::abs(x - plan.cross_corridor_x) < o.corridor_width) continue;
    bool near_door = false;
    for (const Room& room : plan.rooms) near_door |= std::abs(room.door.x() - x) < o.door_width;
    if (!near_door) canvas.disk({x, c_lo + 0.2}, 0.12);
  }

  // Tour: west to east along the corridor visiting every second room, then back west along the
  // corridor into the remaining ones.
  std::vector<const Room*> order;
  for (const Room& r : plan.rooms) order.push_back(&r);
  std::sort(order.begin(), order.end(),
            [](const Room* a, const Room* b) { return a->door.x() < b->door.x(); });
  const double x_start = 2 * t + 1.2;
  plan.tour.emplace_back(x_start, plan.corridor_y);
  auto visit = [&](const Room& r) {
    const double inward = r.centre.y() > plan.corridor_y ? 1.0 : -1.0;
    plan.tour.emplace_back(r.door.x(), plan.corridor_y);
    plan.tour.emplace_back(r.door.x(), r.door.y() + inward * 1.0);
    plan.tour.push_back(r.centre);
    plan.tour.emplace_back(r.door.x(), r.door.y() + inward * 1.0);
    plan.tour.emplace_back(r.door.x(), plan.corridor_y);
  };
  for (std::size_t k = 0; k < order.size(); k += 2) visit(*order[k]);
  plan.tour.emplace_back(w - 2 * t - 1.2, plan.corridor_y);
  for (std::size_t k = order.size(); k-- > 0;) {
    if (k % 2 == 1) visit(*order[k]);
  }
  plan.tour.emplace_back(x_start, plan.corridor_y);
  return plan;
}

}  // namespace vdtnav::sim
