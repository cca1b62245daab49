// The 3D estimators on a sparse map (SparseVdtMap3 through VdtField3) against the same estimators
// on the dense map of the same occupancy: the same solutions and covariances (the sparse map
// answers like the dense one within its band), and a tracked VLP-16 drive.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vdtnav/estimation/vdt_localizer3d.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace vdtnav {
namespace {

struct Maps {
  sim::Room3d room = [] {
    sim::Room3dOptions ro;
    ro.resolution = 0.1;
    ro.wall_thickness = 0.2;
    return sim::generate_room3d(ro);
  }();
  VdtMap3 dense = VdtMap3::build(room.occupancy);
  SparseVdtMap3 sparse = SparseVdtMap3::build(room.occupancy);
};

const Maps& maps() {
  static const Maps m;
  return m;
}

ObservationSet3 scan_at(const Pose3& pose, std::mt19937& rng) {
  sim::Lidar3dSpec spec;
  spec.azimuth_step = 2.0 * kPi / 360;
  return sim::lidar3d_observations(
             sim::simulate_lidar3d_scan(maps().room.occupancy, pose, spec, rng), spec)
      .subsampled(3);
}

TEST(SparseLocalization, TheOptimizerFindsTheDenseMapsSolutionAndCovariance) {
  VdtOptimizerOptions o;
  o.pyramid_levels = 0;  // the sparse map has no coarse levels: compare the fine solves
  const VdtOptimizer3 dense(maps().dense, o), sparse(maps().sparse, o);
  EXPECT_EQ(VdtOptimizer3(maps().sparse).options().pyramid_levels, 0);
  std::mt19937 rng(2);
  for (int k = 0; k < 3; ++k) {
    const Pose3 truth = pose3_from_xyz_rpy(2.0 + 1.5 * k, 3.0, 1.4, 0.02, -0.03, 0.5 * k);
    const ObservationSet3 obs = scan_at(truth, rng);
    Vector6d off;
    off << 0.05, -0.04, 0.03, 0.01, -0.01, 0.02;
    const LocalizationResult3 a = dense.solve(obs, oplus(truth, off));
    const LocalizationResult3 b = sparse.solve(obs, oplus(truth, off));
    ASSERT_EQ(a.status, LocalizationStatus::kConverged);
    ASSERT_EQ(b.status, LocalizationStatus::kConverged);
    EXPECT_LT(ominus(a.pose, b.pose).norm(), 1e-5) << k;
    EXPECT_EQ(a.inliers, b.inliers);
    ASSERT_TRUE(b.has_covariance);
    // Hessians by differences on the sparse map, analytic on the dense one: 1 % of the variances.
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(b.covariance(i, i), a.covariance(i, i), 0.01 * a.covariance(i, i)) << k;
  }
}

TEST(SparseLocalization, TheTrackerFollowsAVlp16DriveOnTheSparseMap) {
  // The tracker alone (no lost detection), with the exact-map options (a generated room).
  VdtOptimizationLocalizer3 loc(maps().sparse, VdtLocalizer3Options{});
  std::mt19937 rng(6);
  Pose3 prev = pose3_from_xyz_rpy(1.5, 2.5, 1.5, 0.0, 0.0, 0.2);
  Matrix6d p0 = Matrix6d::Identity() * 1e-4;
  loc.reset(prev, p0);
  double worst = 0.0;
  for (int k = 1; k < 30; ++k) {
    const Pose3 truth = pose3_from_xyz_rpy(1.5 + 0.1 * k, 2.5 + 0.2 * std::sin(0.1 * k), 1.5,
                                           0.02 * std::sin(k), 0.015 * std::cos(k), 0.2 + 0.01 * k);
    OdometryStep3 odo;
    odo.dt = 0.1;
    odo.delta = prev.inverse() * truth;
    const LocalizationResult3 r = loc.update(odo, scan_at(truth, rng));
    ASSERT_EQ(r.status, LocalizationStatus::kConverged) << k;
    worst = std::max(worst, (r.pose.translation() - truth.translation()).norm());
    prev = truth;
  }
  EXPECT_LT(worst, 0.05);
}

}  // namespace
}  // namespace vdtnav
