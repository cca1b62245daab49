#include "vdtnav/sim/room3d.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::sim {
namespace {

using Box = Eigen::AlignedBox3d;

/// Snaps lengths to whole cells so that every face lies on a cell-centre plane.
class Snap {
 public:
  explicit Snap(double resolution) : r_(resolution) {}
  [[nodiscard]] double operator()(double x) const { return std::round(x / r_) * r_; }
  [[nodiscard]] Box box(double x0, double y0, double z0, double x1, double y1, double z1) const {
    return Box(Eigen::Vector3d((*this)(x0), (*this)(y0), (*this)(z0)),
               Eigen::Vector3d((*this)(x1), (*this)(y1), (*this)(z1)));
  }

 private:
  double r_;
};

/// Sets every cell whose centre lies in `box` (closed, with a rounding slack).
void rasterise(OccupancyGrid<3>& grid, const Box& box) {
  const auto& frame = grid.frame();
  const double slack = 1e-6;
  const Eigen::Vector3d lo = frame.continuous_index(box.min()).array() - slack;
  const Eigen::Vector3d hi = frame.continuous_index(box.max()).array() + slack;
  Eigen::Vector3i i0, i1;
  for (int d = 0; d < 3; ++d) {
    i0[d] = std::max(0, static_cast<int>(std::ceil(lo[d])));
    i1[d] = std::min(grid.size()[d] - 1, static_cast<int>(std::floor(hi[d])));
  }
  for (int k = i0.z(); k <= i1.z(); ++k)
    for (int j = i0.y(); j <= i1.y(); ++j)
      for (int i = i0.x(); i <= i1.x(); ++i) grid(Eigen::Vector3i(i, j, k)) = 1;
}

/// Footprint (x, y) rectangles of placed furniture, kept apart by a margin.
struct Footprint {
  Eigen::Vector2d min, max;
  [[nodiscard]] bool overlaps(const Footprint& o, double margin) const {
    return min.x() < o.max.x() + margin && o.min.x() < max.x() + margin &&
           min.y() < o.max.y() + margin && o.min.y() < max.y() + margin;
  }
};

}  // namespace

Room3d generate_room3d(const Room3dOptions& o) {
  VDTNAV_CHECK(std::isfinite(o.resolution) && o.resolution > 0.0,
               "room3d: resolution must be finite and > 0");
  VDTNAV_CHECK(o.wall_thickness >= 2.0 * o.resolution - 1e-12,
               "room3d: wall_thickness must be at least 2 cells");
  VDTNAV_CHECK(o.length >= 3.0 && o.width >= 3.0 && o.height >= 2.0,
               "room3d: the room must be at least 3 m x 3 m x 2 m");
  VDTNAV_CHECK(o.boxes >= 0 && o.tables >= 0 && o.pillars >= 0,
               "room3d: furniture counts must be >= 0");
  const bool partition = o.partition_x > 0.0;
  if (partition) {
    VDTNAV_CHECK(o.partition_x >= 1.0 && o.partition_x <= o.length - 1.0,
                 "room3d: partition_x must leave 1 m on both sides");
    VDTNAV_CHECK(o.door_width > 0.0 && o.door_width <= o.width - 1.0 && o.door_height > 0.0 &&
                     o.door_height < o.height,
                 "room3d: the doorway must fit in the partition");
  }

  const double r = o.resolution;
  const Snap snap(r);
  const double length = snap(o.length), width = snap(o.width), height = snap(o.height);
  const double wall = snap(o.wall_thickness) - r;  // centre-to-centre thickness of the solids
  // Cell centres at integer multiples of r: the cell of centre -wall is cell 0.
  const Eigen::Vector3d origin = Eigen::Vector3d::Constant(-wall - 0.5 * r);
  const Eigen::Vector3i size(static_cast<int>(std::lround((length + 2 * wall) / r)) + 1,
                             static_cast<int>(std::lround((width + 2 * wall) / r)) + 1,
                             static_cast<int>(std::lround((height + 2 * wall) / r)) + 1);

  Room3d room;
  room.occupancy = OccupancyGrid<3>(size, GridFrame<3>(r, origin), 0);
  room.interior_min = Eigen::Vector3d::Zero();
  room.interior_max = Eigen::Vector3d(length, width, height);
  auto& solids = room.solids;
  const double x0 = -wall, x1 = length + wall, y0 = -wall, y1 = width + wall, z0 = -wall,
               z1 = height + wall;
  solids.push_back(snap.box(x0, y0, z0, x1, y1, 0.0));     // floor
  solids.push_back(snap.box(x0, y0, height, x1, y1, z1));  // ceiling
  solids.push_back(snap.box(x0, y0, z0, 0.0, y1, z1));     // wall x = 0
  solids.push_back(snap.box(length, y0, z0, x1, y1, z1));  // wall x = length
  solids.push_back(snap.box(x0, y0, z0, x1, 0.0, z1));     // wall y = 0
  solids.push_back(snap.box(x0, width, z0, x1, y1, z1));   // wall y = width

  std::mt19937 rng(o.seed);
  auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };

  // Partition: two side pieces and a lintel over the doorway, 0.1 m thick.
  std::vector<Footprint> placed;
  const double margin = 0.6;  // free space kept between furniture, walls and the doorway
  if (partition) {
    const double px = snap(o.partition_x), pt = snap(0.1);
    const double door_w = snap(o.door_width), door_h = snap(o.door_height);
    const double dy = snap(uniform(0.5, width - 0.5 - door_w));
    solids.push_back(snap.box(px, 0.0, 0.0, px + pt, dy, height));
    solids.push_back(snap.box(px, dy + door_w, 0.0, px + pt, width, height));
    solids.push_back(snap.box(px, 0.0, door_h, px + pt, width, height));
    room.doorway = Box(Eigen::Vector3d(px, dy, 0.0), Eigen::Vector3d(px + pt, dy + door_w, door_h));
    placed.push_back({{px, 0.0}, {px + pt, width}});
    // Keep the doorway approach clear on both sides.
    placed.push_back({{px - 1.0, dy}, {px + pt + 1.0, dy + door_w}});
  }

  // Furniture: rejection-sample footprints inside the walls, apart from each other.
  const auto place = [&](double sx, double sy, Footprint& out) {
    if (length - 2.0 * margin - sx <= 0.0 || width - 2.0 * margin - sy <= 0.0) return false;
    for (int attempt = 0; attempt < 200; ++attempt) {
      const double x = snap(uniform(margin, length - margin - sx));
      const double y = snap(uniform(margin, width - margin - sy));
      const Footprint f{{x, y}, {x + snap(sx), y + snap(sy)}};
      if (std::none_of(placed.begin(), placed.end(),
                       [&](const Footprint& p) { return f.overlaps(p, margin); })) {
        placed.push_back(f);
        out = f;
        return true;
      }
    }
    return false;
  };
  Footprint f;
  for (int k = 0; k < o.pillars; ++k) {
    const double side = uniform(0.3, 0.4);
    if (place(side, side, f))
      solids.push_back(Box(Eigen::Vector3d(f.min.x(), f.min.y(), 0.0),
                           Eigen::Vector3d(f.max.x(), f.max.y(), height)));
  }
  for (int k = 0; k < o.tables; ++k) {
    const bool along_x = uniform(0.0, 1.0) < 0.5;
    const double a = uniform(1.2, 1.8), b = uniform(0.6, 0.9);
    if (!place(along_x ? a : b, along_x ? b : a, f)) continue;
    const double top = snap(uniform(0.7, 0.76)), leg = snap(0.05), inset = snap(0.05);
    solids.push_back(Box(Eigen::Vector3d(f.min.x(), f.min.y(), top - snap(0.05)),
                         Eigen::Vector3d(f.max.x(), f.max.y(), top)));
    for (int c = 0; c < 4; ++c) {
      const double lx = (c & 1) ? f.max.x() - inset - leg : f.min.x() + inset;
      const double ly = (c & 2) ? f.max.y() - inset - leg : f.min.y() + inset;
      solids.push_back(Box(Eigen::Vector3d(lx, ly, 0.0), Eigen::Vector3d(lx + leg, ly + leg, top)));
    }
  }
  for (int k = 0; k < o.boxes; ++k) {
    if (!place(uniform(0.4, 1.2), uniform(0.4, 1.2), f)) continue;
    solids.push_back(Box(Eigen::Vector3d(f.min.x(), f.min.y(), 0.0),
                         Eigen::Vector3d(f.max.x(), f.max.y(), snap(uniform(0.4, 1.4)))));
  }

  for (const Box& b : solids) rasterise(room.occupancy, b);
  return room;
}

std::vector<Pose3> uneven_floor_poses(const Room3d& room, const UnevenFloorOptions& o) {
  VDTNAV_CHECK(o.count >= 0, "uneven_floor_poses: count must be >= 0");
  VDTNAV_CHECK(o.min_tilt >= 0.0 && o.max_tilt >= o.min_tilt && o.max_tilt < 0.5,
               "uneven_floor_poses: tilts must satisfy 0 <= min_tilt <= max_tilt < 0.5 rad");
  VDTNAV_CHECK(o.max_base_height >= 0.0 && o.clearance > 0.0 && o.clearance_height > 0.0 &&
                   o.min_separation >= 0.0,
               "uneven_floor_poses: heights, clearance and separation must be >= 0");
  const auto& grid = room.occupancy;
  const double r = grid.resolution();
  const Eigen::Vector3d lo = room.interior_min, hi = room.interior_max;
  VDTNAV_CHECK(hi.x() - lo.x() > 2.0 * o.clearance && hi.y() - lo.y() > 2.0 * o.clearance,
               "uneven_floor_poses: the room is smaller than the clearance");

  // Free iff no cell with its centre within `clearance` of the axis, from one cell above the floor
  // up to clearance_height, is occupied.
  const auto is_free = [&](const Eigen::Vector2d& c) {
    const Eigen::Vector3i a =
        grid.cell_of(Eigen::Vector3d(c.x() - o.clearance, c.y() - o.clearance, lo.z() + r));
    const Eigen::Vector3i b = grid.cell_of(
        Eigen::Vector3d(c.x() + o.clearance, c.y() + o.clearance, lo.z() + o.clearance_height));
    for (int k = a.z(); k <= b.z(); ++k)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int i = a.x(); i <= b.x(); ++i) {
          const Eigen::Vector3i idx(i, j, k);
          if (!grid.contains(idx)) return false;
          if ((grid.cell_center(idx).head<2>() - c).norm() > o.clearance) continue;
          if (grid(idx)) return false;
        }
    return true;
  };

  std::mt19937 rng(o.seed);
  auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  const auto signed_tilt = [&] {
    const double m = uniform(o.min_tilt, o.max_tilt);
    return uniform(0.0, 1.0) < 0.5 ? -m : m;
  };
  std::vector<Pose3> poses;
  std::vector<Eigen::Vector2d> places;
  for (int attempt = 0; static_cast<int>(poses.size()) < o.count; ++attempt) {
    if (attempt >= 2000 * std::max(1, o.count))
      throw ConfigError("uneven_floor_poses: could not find " + std::to_string(o.count) +
                        " free locations " + std::to_string(o.min_separation) + " m apart with " +
                        std::to_string(o.clearance) + " m clearance");
    const Eigen::Vector2d c(uniform(lo.x() + o.clearance, hi.x() - o.clearance),
                            uniform(lo.y() + o.clearance, hi.y() - o.clearance));
    if (std::any_of(places.begin(), places.end(),
                    [&](const Eigen::Vector2d& p) { return (p - c).norm() < o.min_separation; }))
      continue;
    if (!is_free(c)) continue;
    const double yaw = uniform(-3.14159265358979323846, 3.14159265358979323846);
    const double roll = signed_tilt(), pitch = signed_tilt();
    const double z = lo.z() + uniform(0.0, o.max_base_height);
    places.push_back(c);
    poses.push_back(pose3_from_xyz_rpy(c.x(), c.y(), z, roll, pitch, yaw));
  }
  return poses;
}

}  // namespace vdtnav::sim
