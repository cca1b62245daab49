// The UDT baselines: beam derivatives against finite differences, tracking a short run, and
// the absence of a covariance for C-LOG-style optimization.
#include "vdtnav/estimation/udt_localizers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scan_fixture.hpp"

namespace vdtnav {
namespace {

TEST(UdtBeam, DerivativesMatchFiniteDifferences) {
  const DistanceFieldMap<2> udt(
      unsigned_distance_transform(nearest_occupied_cells(test::world().plan.occupancy)));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ua(-3.0, 3.0), ur(0.5, 2.0);
  int tested = 0;
  for (int k = 0; k < 400 && tested < 100; ++k) {
    const Pose2 x = test::tour_pose(static_cast<std::size_t>(k)) + Pose2(0.0, 0.0, ua(rng));
    const double a = ua(rng);
    const Eigen::Vector2d u(std::cos(a), std::sin(a)), p = ur(rng) * u;
    const auto at = [&](const Pose2& y, const Eigen::Vector2d& q) {
      return udt_beam(udt, y, std::cos(y[2]), std::sin(y[2]), q, u, 1e9);
    };
    const UdtBeam b = at(x, p);
    if (!b.inlier || b.e < 0.15) continue;  // away from the UDT's kink at obstacles
    const double h = 1e-4;
    for (int j = 0; j < 3; ++j) {
      const Pose2 e = Pose2::Unit(j) * h;
      ASSERT_NEAR(b.e_pose[j], (at(x + e, p).e - at(x - e, p).e) / (2 * h),
                  5e-3 * (1 + b.e_pose.norm()));
    }
    ASSERT_NEAR(b.e_range, (at(x, p + h * u).e - at(x, p - h * u).e) / (2 * h), 5e-3);
    ++tested;
  }
  EXPECT_GE(tested, 50);
}

template <typename Localizer>
LocalizationResult track(Localizer& loc, Pose2& truth) {
  std::mt19937 rng(11);
  truth = test::tour_pose(5);
  loc.reset(truth + Pose2(0.03, -0.03, 0.01), Eigen::Vector3d(1e-3, 1e-3, 3e-4).asDiagonal());
  OdometryStep odo;
  odo.dt = 0.025;
  odo.v = 0.4;
  odo.w = 0.1;
  LocalizationResult r;
  for (int k = 0; k < 40; ++k) {
    const Pose2 next(truth[0] + odo.dt * odo.v * std::cos(truth[2]),
                     truth[1] + odo.dt * odo.v * std::sin(truth[2]), truth[2] + odo.dt * odo.w);
    odo.delta = between(truth, next);
    truth = next;
    r = loc.update(odo, test::simulate_scan(truth, 0.02, rng, 541));
  }
  return r;
}

TEST(UdtLocalizers, BothTrackAShortRunAndOnlyTheEkfReportsACovariance) {
  Pose2 truth;
  UdtOptimizationLocalizer opt(test::world().plan.occupancy, UdtOptions{});
  const LocalizationResult a = track(opt, truth);
  EXPECT_EQ(opt.name(), "udt-opt");
  EXPECT_FALSE(a.has_covariance);
  EXPECT_LT(pose_error(a.pose, truth).head<2>().norm(), 0.03);
  UdtEkfLocalizer ekf(test::world().plan.occupancy, UdtOptions{});
  const LocalizationResult b = track(ekf, truth);
  EXPECT_EQ(ekf.name(), "udt-ekf");
  EXPECT_TRUE(b.has_covariance);
  EXPECT_LT(pose_error(b.pose, truth).head<2>().norm(), 0.03);
  EXPECT_EQ(opt.update(OdometryStep{}, LaserScan{}).status,
            LocalizationStatus::kTooFewObservations);
}

}  // namespace
}  // namespace vdtnav
