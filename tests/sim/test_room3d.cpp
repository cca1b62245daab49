// The generated 3D room and the uneven-floor poses: deterministic per seed, closed, its cells are
// exactly the listed solids, ray casts stop where the solids say (floor z = 0, ...), the
// doorway is open, and the poses stand free, rolled and pitched by a few degrees.
#include "vdtnav/sim/room3d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"
#include "vdtnav/sim/point_laser_simulator.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {
namespace {

const Room3d& default_room() {
  static const Room3d room = generate_room3d({});
  return room;
}

/// Random free points strictly inside the room, away from the surfaces by a cell.
std::vector<Eigen::Vector3d> free_points(const Room3d& room, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  while (static_cast<int>(out.size()) < n) {
    const Eigen::Vector3d p = room.interior_min.array() + 0.1 +
                              (room.interior_max - room.interior_min).array() *
                                  Eigen::Array3d(u(rng), u(rng), u(rng)) * 0.97;
    const auto c = room.occupancy.cell_of(p);
    if (!room.occupancy(c)) out.push_back(p);
  }
  return out;
}

Eigen::Vector3d random_direction(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

TEST(Room3d, SameSeedSameRoomOtherSeedOtherRoom) {
  const Room3d& a = default_room();
  const Room3d b = generate_room3d({});
  Room3dOptions other;
  other.seed = 2;
  const Room3d c = generate_room3d(other);
  EXPECT_EQ(a.occupancy.values(), b.occupancy.values());
  EXPECT_NE(a.occupancy.values(), c.occupancy.values());
  // 12 m x 10 m x 3.5 m between the surfaces plus three 0.05 m layers beyond each.
  EXPECT_EQ(a.occupancy.size(), Eigen::Vector3i(245, 205, 75));
  EXPECT_EQ(a.occupancy.resolution(), 0.05);
  EXPECT_TRUE(a.interior_max.isApprox(Eigen::Vector3d(12.0, 10.0, 3.5)));
  // Walls, floor, ceiling, 3 partition pieces, and furniture: 2 pillars, 3 tables of 5 boxes
  // each, 4 crates when they all fit (they do for seed 1).
  EXPECT_EQ(a.solids.size(), 6u + 3u + 2u + 15u + 4u);
  EXPECT_FALSE(a.doorway.isEmpty());
}

TEST(Room3d, OccupiedCellsAreExactlyTheCellsInsideTheSolids) {
  const Room3d& room = default_room();
  const auto& g = room.occupancy;
  std::size_t occupied = 0;
  for (std::size_t l = 0; l < g.num_cells(); ++l) {
    const Eigen::Vector3i i = g.index_of(static_cast<std::ptrdiff_t>(l));
    const Eigen::Vector3d c = g.cell_center(i);
    bool inside = false;
    for (const auto& s : room.solids)
      inside |= (c.array() >= s.min().array() - 1e-9).all() &&
                (c.array() <= s.max().array() + 1e-9).all();
    ASSERT_EQ(g[l] != 0, inside) << "cell " << i.transpose();
    occupied += inside;
  }
  EXPECT_GT(occupied, g.num_cells() / 10);
  EXPECT_LT(occupied, g.num_cells() / 2);
}

TEST(Room3d, EmptyRoomSurfacesAreTheDocumentedPlanes) {
  Room3dOptions o;
  o.partition_x = 0.0;
  o.boxes = o.tables = o.pillars = 0;
  const Room3d room = generate_room3d(o);
  EXPECT_EQ(room.solids.size(), 6u);
  EXPECT_TRUE(room.doorway.isEmpty());
  for (const Eigen::Vector3d& p : free_points(room, 50, 3)) {
    const auto cast = [&](const Eigen::Vector3d& d) {
      return cast_ray<3>(room.occupancy, p, d, 100.0, RaySurface::kCellCentre);
    };
    EXPECT_NEAR(cast(-Eigen::Vector3d::UnitZ()), p.z(), 1e-9);  // floor z = 0
    EXPECT_NEAR(cast(Eigen::Vector3d::UnitZ()), 3.5 - p.z(), 1e-9);
    EXPECT_NEAR(cast(-Eigen::Vector3d::UnitX()), p.x(), 1e-9);
    EXPECT_NEAR(cast(Eigen::Vector3d::UnitX()), 12.0 - p.x(), 1e-9);
    EXPECT_NEAR(cast(-Eigen::Vector3d::UnitY()), p.y(), 1e-9);
    EXPECT_NEAR(cast(Eigen::Vector3d::UnitY()), 10.0 - p.y(), 1e-9);
  }
}

/// First entry t >= 0 of the ray o + t d into the closed box [lo, hi] (slab method), or +inf.
double slab_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi) {
  double t_near = 0.0, t_far = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return std::numeric_limits<double>::infinity();
      continue;
    }
    const double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    t_near = std::max(t_near, std::min(t0, t1));
    t_far = std::min(t_far, std::max(t0, t1));
  }
  return t_near <= t_far ? t_near : std::numeric_limits<double>::infinity();
}

TEST(Room3d, IsClosedAndRaysStopAtTheListedSolids) {
  // Cells whose centres lie in a solid cover the solid grown by half a cell, so the cell-boundary
  // ray cast must equal the first entry into one of the grown boxes.
  const Room3d& room = default_room();
  std::mt19937 rng(5);
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * room.occupancy.resolution());
  int missed = 0;
  for (const Eigen::Vector3d& p : free_points(room, 2000, 4)) {
    const Eigen::Vector3d d = random_direction(rng);
    const double r = cast_ray<3>(room.occupancy, p, d, 100.0, RaySurface::kCellBoundary);
    ASSERT_TRUE(std::isfinite(r)) << "a ray escapes the room from " << p.transpose();
    double expected = std::numeric_limits<double>::infinity();
    for (const auto& s : room.solids)
      expected = std::min(expected, slab_entry(p, d, s.min() - half, s.max() + half));
    EXPECT_NEAR(r, expected, 1e-9) << "from " << p.transpose() << " along " << d.transpose();
    // The cell-centre surface lies half a cell further along one axis, unless the ray leaves the
    // occupied cells before (grazing an edge): then it missed, and hits further on. Either way the
    // hit is on a plane through cell centres, at the end of a run of occupied cells.
    const double centre = cast_ray<3>(room.occupancy, p, d, 100.0, RaySurface::kCellCentre);
    ASSERT_TRUE(std::isfinite(centre));
    bool half_cell = false;
    for (int a = 0; a < 3; ++a) half_cell |= std::abs(centre - r - half[a] / std::abs(d[a])) < 1e-9;
    const Eigen::Vector3d u = room.occupancy.frame().continuous_index(p + centre * d);
    EXPECT_LT((u.array() - u.array().round()).abs().minCoeff(), 1e-6) << "not on a centre plane";
    EXPECT_NE(room.occupancy(room.occupancy.cell_of(p + (centre - 1e-6) * d)), 0);
    if (!half_cell) {
      ++missed;
      EXPECT_GT(centre, r);
      bool free_between = false;
      for (double s = r; s < centre && !free_between; s += 1e-3)
        free_between = room.occupancy(room.occupancy.cell_of(p + s * d)) == 0;
      EXPECT_TRUE(free_between) << "stopped short of the plane inside the solid";
    }
  }
  EXPECT_LT(missed, 100);  // grazing an edge is rare: 5 % of the rays at most
}

TEST(Room3d, DoorwayIsOpen) {
  const Room3d& room = default_room();
  const Eigen::Vector3d centre = room.doorway.center();
  // Level with the doorway's middle, 0.5 m in front of the partition, looking through it.
  const Eigen::Vector3d from(room.doorway.min().x() - 0.5, centre.y(), 1.0);
  const double r =
      cast_ray<3>(room.occupancy, from, Eigen::Vector3d::UnitX(), 100.0, RaySurface::kCellCentre);
  EXPECT_GT(r, 0.5 + room.doorway.sizes().x() + 0.1);
  // Above the lintel the partition is solid.
  const Eigen::Vector3d high(from.x(), centre.y(), room.doorway.max().z() + 0.3);
  EXPECT_NEAR(
      cast_ray<3>(room.occupancy, high, Eigen::Vector3d::UnitX(), 100.0, RaySurface::kCellCentre),
      0.5, 1e-9);
  EXPECT_NEAR(room.doorway.sizes().y(), 1.0, 1e-9);
  EXPECT_NEAR(room.doorway.sizes().z(), 2.1, 1e-9);
}

TEST(Room3d, RejectsLayoutsThatDoNotFit) {
  Room3dOptions o;
  o.wall_thickness = 0.05;
  EXPECT_THROW((void)generate_room3d(o), ConfigError);
  o = {};
  o.partition_x = 11.5;
  EXPECT_THROW((void)generate_room3d(o), ConfigError);
  o = {};
  o.door_height = 4.0;
  EXPECT_THROW((void)generate_room3d(o), ConfigError);
}

TEST(UnevenFloorPoses, ThreeFreeLocationsRolledAndPitchedAFewDegrees) {
  const Room3d& room = default_room();
  const UnevenFloorOptions o;
  const std::vector<Pose3> poses = uneven_floor_poses(room, o);
  ASSERT_EQ(poses.size(), 3u);
  const PanTiltCalibration unit = PanTiltCalibration::turtlebot_example();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector3d rpy = rpy_of(poses[k].linear());
    for (int a = 0; a < 2; ++a) {
      EXPECT_GE(std::abs(rpy[a]), 1.0 * kPi / 180 - 1e-12);
      EXPECT_LE(std::abs(rpy[a]), 5.0 * kPi / 180 + 1e-12);
    }
    const Eigen::Vector3d t = poses[k].translation();
    EXPECT_GE(t.z(), 0.0);
    EXPECT_LE(t.z(), 0.05);
    // The beam starts 0.3-0.5 m above the floor whatever the pan and tilt.
    for (double pan : {-2.0, 0.0, 1.5})
      for (double tilt : {-0.5, 0.0, 0.8}) {
        const double height = (poses[k] * pan_tilt_laser_pose(unit, pan, tilt)).translation().z();
        EXPECT_GT(height, 0.3);
        EXPECT_LT(height, 0.5);
      }
    // Free around the robot up to 1 m.
    for (double a = 0.0; a < 2 * kPi; a += 0.3)
      for (double rad : {0.0, 0.2, 0.45})
        for (double z : {0.1, 0.5, 0.95}) {
          const Eigen::Vector3d q(t.x() + rad * std::cos(a), t.y() + rad * std::sin(a), z);
          EXPECT_EQ(room.occupancy(room.occupancy.cell_of(q)), 0) << q.transpose();
        }
    for (std::size_t j = 0; j < k; ++j)
      EXPECT_GE((poses[j].translation() - t).head<2>().norm(), 2.0);
  }
  const std::vector<Pose3> again = uneven_floor_poses(room, o);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(again[k].isApprox(poses[k]));
  UnevenFloorOptions crowded;
  crowded.count = 200;
  crowded.min_separation = 3.0;
  EXPECT_THROW((void)uneven_floor_poses(room, crowded), ConfigError);
}

TEST(UnevenFloorPoses, DefaultSweepsInTheDefaultRoomReturnAlmostEverywhere) {
  const Room3d& room = default_room();
  const auto poses = uneven_floor_poses(room, {});
  const PointLaserSimOptions o;
  const auto sweeps = simulate_point_laser_sweeps(room.occupancy, poses, o, 1);
  ASSERT_EQ(sweeps.size(), 3u);
  for (const auto& s : sweeps) {
    ASSERT_EQ(s.readings.size(), 5700u);
    const ObservationSet3 obs = point_laser_observations(s.readings, o.calibration);
    EXPECT_EQ(obs.dropped_not_finite, 0u);  // a closed room: every beam returns
    EXPECT_GT(obs.size(), 5600u);
  }
}

}  // namespace
}  // namespace vdtnav::sim
