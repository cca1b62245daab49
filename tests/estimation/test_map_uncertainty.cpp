// A map that knows its own error (VdtSensorModelOptions::map_uncertainty, thesis ch. 5) in the
// optimizer's and the EKF's covariance: with a map whose errors are shared per 2 m square (the
// endpoints of a square moved by one N(0, sigma^2 I) draw, as a wall drawn a few centimetres off
// moves every reading that hits it), a MapUncertainty that knows exactly that covers the spread
// of the estimates over Monte Carlo trials; without it the covariance is many times too small.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "scan_fixture.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/map/map_uncertainty.hpp"

namespace vdtnav {
namespace {

using test::world;

constexpr double kLength = 2.0, kSigma = 0.02;

/// The error model of test::shift_by_shared_map_errors, as a map would know it: an endpoint
/// moved by e changes DT_v by J e, and the e of one square are one draw.
class SquaresUncertainty final : public MapUncertainty2 {
 public:
  explicit SquaresUncertainty(const VdtMap2& map) : map_(map) {}
  bool dt_covariance(const Eigen::Vector2d& p, Eigen::Matrix2d* cov) const override {
    const Eigen::Matrix2d j = map_.evaluate(p).jacobian;
    *cov = kSigma * kSigma * j * j.transpose();
    return true;
  }
  Eigen::Matrix3d propagate(const std::vector<Eigen::Vector2d>& q,
                            const std::vector<Sensitivity>& s,
                            std::vector<char>* known) const override {
    std::map<std::pair<long, long>, Sensitivity> groups;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const std::pair<long, long> key(static_cast<long>(std::floor(q[i].x() / kLength)),
                                      static_cast<long>(std::floor(q[i].y() / kLength)));
      auto [it, fresh] = groups.try_emplace(key);
      if (fresh) it->second.setZero();
      it->second += s[i] * map_.evaluate(q[i]).jacobian;
    }
    Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
    for (const auto& [key, g] : groups) out += kSigma * kSigma * g * g.transpose();
    if (known != nullptr) known->assign(q.size(), 1);
    return out;
  }

 private:
  const VdtMap2& map_;
};

/// ANEES over Monte Carlo trials of one pose: every trial a new map (new square errors) and new
/// range noise; `localize` returns the estimate of one scan.
template <typename Localize>
eval::AneesResult monte_carlo(const Pose2& truth, Localize localize) {
  std::mt19937 rng(91);
  std::vector<double> nees;
  for (int k = 0; k < 300; ++k) {
    ScanPoints scan = scan_points(test::simulate_scan(truth, 0.02, rng));
    test::shift_by_shared_map_errors(scan, truth, kLength, kSigma, rng);
    const LocalizationResult r = localize(scan);
    EXPECT_TRUE(r.has_covariance);
    nees.push_back(eval::nees(r.pose, truth, r.covariance));
  }
  return eval::anees(nees, 3, 0.99);
}

TEST(MapUncertainty, OptimizerCovarianceCoversTheMapsErrors) {
  const Pose2 truth = test::tour_pose(7);
  const SquaresUncertainty squares(world().map);
  for (const CovarianceMethod method :
       {CovarianceMethod::kGaussNewton, CovarianceMethod::kImplicitFunction}) {
    const auto anees = [&](const MapUncertainty2* u) {
      VdtOptimizerOptions o;
      o.covariance = method;
      o.sensor.map_sigma = 0.0;
      o.sensor.map_uncertainty = u;
      const VdtOptimizer opt(world().map, o);
      return monte_carlo(truth, [&](const ScanPoints& s) { return opt.solve(s, truth); });
    };
    const eval::AneesResult with = anees(&squares), without = anees(nullptr);
    std::printf("vdt-opt (%s): ANEES %.2f with the map's covariance, %.2f without\n",
                method == CovarianceMethod::kGaussNewton ? "Gauss-Newton" : "implicit function",
                with.anees, without.anees);
    // As the squares of map_correlation_length do (test_vdt_optimizer.cpp): within 1.5x; the
    // implicit-function covariance conservative, as there (measured 1.95: the map's curvature
    // at the moved endpoints). A check that the map's covariance enters, on errors drawn as the
    // map states them; Gauss-Newton measured 3.35, just over the 99 % interval [2.69, 3.32].
    // Calibration against errors no model draws: the rebuilt-map tests of test_vdt_optimizer.
    EXPECT_GT(with.anees, method == CovarianceMethod::kGaussNewton ? 3.0 / 1.5 : 3.0 / 1.8);
    EXPECT_LT(with.anees, 3.0 * 1.5);
    EXPECT_GT(without.anees, 3.0 * with.interval.upper);
  }
}

TEST(MapUncertainty, EkfReportsTheMapsShareOnTopOfItsCovariance) {
  const Pose2 truth = test::tour_pose(7);
  const SquaresUncertainty squares(world().map);
  const auto anees = [&](const MapUncertainty2* u) {
    VdtEkfOptions o;
    o.sensor.map_sigma = 1e-3;
    o.sensor.map_uncertainty = u;
    VdtEkfLocalizer ekf(world().map, o);
    // A weak prior at the truth: the scan alone decides, as in the optimizer.
    const Eigen::Matrix3d p0 = Eigen::Vector3d(1.0, 1.0, 0.1).asDiagonal();
    return monte_carlo(truth, [&](const ScanPoints& s) {
      ekf.reset(truth, p0);
      return ekf.update(OdometryStep{}, s);
    });
  };
  const eval::AneesResult with = anees(&squares), without = anees(nullptr);
  std::printf("vdt-ekf: ANEES %.2f with the map's covariance, %.2f without\n", with.anees,
              without.anees);
  EXPECT_GT(with.anees, 3.0 / 1.5);
  EXPECT_LT(with.anees, 3.0 * 1.5);
  EXPECT_GT(without.anees, 3.0 * with.interval.upper);
}

}  // namespace
}  // namespace vdtnav
