// The optimizer's two solvers, Ceres (the default) and the dense Levenberg-Marquardt on the
// fixed-size normal equations, on the same observations from the same guess: the same optimum (to a
// small share of its standard deviation) and the same covariance, in 2D with and without a robust
// loss, and in 3D with six and four degrees of freedom.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Cholesky>

#include "cloud_fixture.hpp"
#include "scan_fixture.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {
namespace {

/// Both solvers from `guess`: the Mahalanobis distance between their estimates (under the dense
/// solver's covariance) and the relative difference of their covariances (Frobenius norm).
struct Agreement {
  double mahalanobis = 0.0, covariance = 0.0;
  int dense_iterations = 0, ceres_iterations = 0;
};

template <int Dim>
Agreement compare(const VdtMap<Dim>& map, VdtOptimizerOptions o, const ObservationSet<Dim>& obs,
                  const typename PoseTraits<Dim>::Pose& guess) {
  using Traits = PoseTraits<Dim>;
  o.solver = ScanSolver::kDense;
  const LocalizationResultT<Dim> a = VdtOptimizerT<Dim>(map, o).solve(obs, guess);
  o.solver = ScanSolver::kCeres;
  const LocalizationResultT<Dim> b = VdtOptimizerT<Dim>(map, o).solve(obs, guess);
  EXPECT_EQ(a.status, LocalizationStatus::kConverged);
  EXPECT_EQ(b.status, LocalizationStatus::kConverged);
  EXPECT_TRUE(a.has_covariance && b.has_covariance);
  EXPECT_EQ(a.inliers, b.inliers);
  Agreement out;
  const typename Traits::Tangent e = Traits::minus(a.pose, b.pose);
  // Held components (4-DOF) have zero rows: compare on the estimated ones.
  typename Traits::Covariance c = a.covariance;
  for (int k = 0; k < Traits::kDoF; ++k) {
    if (c(k, k) == 0.0) c(k, k) = 1.0;
  }
  out.mahalanobis = std::sqrt(e.dot(c.ldlt().solve(e)));
  out.covariance = (a.covariance - b.covariance).norm() / b.covariance.norm();
  out.dense_iterations = a.iterations;
  out.ceres_iterations = b.iterations;
  return out;
}

/// A simulated scan at `truth` of the test world, with clutter (every 7th reading 0.25 m short)
/// when the loss is robust.
ScanPoints tour_scan(const Pose2& truth, RobustLoss loss, std::mt19937& rng) {
  LaserScan scan = test::simulate_scan(truth, 0.02, rng);
  if (loss == RobustLoss::kCauchy) {
    for (std::size_t i = 0; i < scan.ranges.size(); i += 7) scan.ranges[i] -= 0.25;
  }
  return scan_points(scan);
}

/// Both solvers on cluttered-or-clean tour scans at four poses, without and with the Cauchy loss
/// (options `base` otherwise), from the same guess; `check(k, loss, agreement)` for each.
template <class Check>
void compare_on_the_tour(std::mt19937& rng, VdtOptimizerOptions base, Check check) {
  for (const RobustLoss loss : {RobustLoss::kNone, RobustLoss::kCauchy}) {
    for (const std::size_t k : {2u, 7u, 12u, 18u}) {
      const Pose2 truth = test::tour_pose(k);
      const ScanPoints pts = tour_scan(truth, loss, rng);
      base.loss = loss;
      check(k, loss, compare<2>(test::world().map, base, pts, truth + Pose2(0.06, -0.04, 0.03)));
    }
  }
}

/// The readings the gate (3.3) keeps at `pose` (a solve with gate_rounds 1 uses these).
std::vector<int> gated_at(const VdtSensorModel& model, const ScanPoints& pts, const Pose2& pose) {
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(pose[2]).toRotationMatrix();
  std::vector<int> beams;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    bool inlier = false;
    (void)model.disparity_value(r, pose.head<2>(), pts.points[i], &inlier);
    if (inlier) beams.push_back(static_cast<int>(i));
  }
  return beams;
}

/// The robust VCD sum_i rho(|d_i|^2) over `beams` at `pose`, from the sensor model's value-only
/// lookup: the finite-difference oracle's cost (independent of the solver's Jacobians).
double robust_cost(const VdtSensorModel& model, const ScanPoints& pts,
                   const std::vector<int>& beams, RobustLoss loss, double scale,
                   const Pose2& pose) {
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(pose[2]).toRotationMatrix();
  double cost = 0.0;
  for (const int i : beams) {
    bool unused = false;
    const double s = model.disparity_value(r, pose.head<2>(), pts.points[i], &unused).squaredNorm();
    cost += loss == RobustLoss::kCauchy ? scale * scale * std::log1p(s / (scale * scale)) : s;
  }
  return cost;
}

/// The oracle of the convergence tests: Newton's step of the cost `f` at `pose`, from its gradient
/// and Hessian by central differences (steps 1e-4 m / rad), in sigmas (sigma2 H^-1); infinite
/// where that Hessian is not positive definite (not a minimum).
template <class Cost>
double newton_sigmas_by_differences(const Cost& f, const Pose2& pose, double sigma2) {
  const double e = 1e-4;
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  for (int a = 0; a < 3; ++a) {
    const Pose2 da = Pose2::Unit(a) * e;
    g[a] = (f(pose + da) - f(pose - da)) / (2 * e);
    for (int b = 0; b < 3; ++b) {
      const Pose2 db = Pose2::Unit(b) * e;
      h(a, b) = (f(pose + da + db) - f(pose + da - db) - f(pose - da + db) + f(pose - da - db)) /
                (4 * e * e);
    }
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(0.5 * (h + h.transpose()));
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return std::sqrt(g.dot(llt.solve(g)) / sigma2);
}

TEST(ScanSolvers, TheDenseCauchyCostIsTheSumOfTheReadingsLogTerms) {
  // The dense solver sums the Cauchy cost as b log prod_i (1 + s_i / b); here against the sum of
  // b log1p(s_i / b) over the solve's readings at its estimate. A loss scale of 2 mm makes the
  // factors large (up to ~6e4 within the 0.5 m gate), so the product must be flushed to its
  // logarithm many times within one scan or it would overflow.
  std::mt19937 rng(8);
  for (const double scale : {0.05, 0.002}) {
    const Pose2 truth = test::tour_pose(9);
    LaserScan scan = test::simulate_scan(truth, 0.02, rng);
    for (std::size_t i = 0; i < scan.ranges.size(); i += 5) scan.ranges[i] -= 0.2;  // clutter
    const ScanPoints pts = scan_points(scan);
    VdtOptimizerOptions o;
    o.solver = ScanSolver::kDense;
    o.loss = RobustLoss::kCauchy;
    o.loss_scale = scale;
    o.gate_rounds = 1;  // one solve over the readings gated at the guess
    const Pose2 guess = truth + Pose2(0.01, -0.01, 0.005);
    const VdtOptimizer opt(test::world().map, o);
    const LocalizationResult r = opt.solve(pts, guess);
    ASSERT_TRUE(r.status == LocalizationStatus::kConverged ||
                r.status == LocalizationStatus::kNotConverged);
    const VdtSensorModel& model = opt.sensor_model();
    const std::vector<int> beams = gated_at(model, pts, guess);
    const double expected = robust_cost(model, pts, beams, RobustLoss::kCauchy, scale, r.pose);
    ASSERT_EQ(static_cast<int>(beams.size()), r.inliers);
    // final_cost is the robust VCD sum rho (twice the solver's 1/2 sum rho).
    EXPECT_NEAR(r.final_cost, expected, 1e-9 * expected) << "loss scale " << scale;
  }
}

TEST(ScanSolvers, DenseAndCeresReachTheSameOptimumAndCovarianceIn2d) {
  std::mt19937 rng(3);
  compare_on_the_tour(rng, {}, [](std::size_t k, RobustLoss loss, const Agreement& g) {
    // The two stop at slightly different points of the same minimum: within a tenth of a
    // standard deviation; the covariance, evaluated there, within 1 %.
    EXPECT_LT(g.mahalanobis, 0.1) << "pose " << k << " loss " << static_cast<int>(loss);
    EXPECT_LT(g.covariance, 0.01) << "pose " << k << " loss " << static_cast<int>(loss);
    std::printf("2D pose %zu loss %d: %.3g sigma apart, covariance %.2g, iterations %d / %d\n", k,
                static_cast<int>(loss), g.mahalanobis, g.covariance, g.dense_iterations,
                g.ceres_iterations);
  });
}

TEST(ScanSolvers, DenseAndCeresReachTheSameOptimumAndCovarianceIn3dWithSixAndFourDof) {
  std::mt19937 rng(4);
  for (const bool four_dof : {false, true}) {
    for (int k = 0; k < 2; ++k) {
      const Pose3 truth = test::cloud_pose(k);
      const ObservationSet3 cloud = test::simulate_cloud(truth, 0.01, rng);
      VdtOptimizerOptions o;
      o.four_dof = four_dof;
      const Eigen::Vector3d rpy = rpy_of(truth.linear());
      const Eigen::Vector3d t = truth.translation() + Eigen::Vector3d(0.05, -0.05, 0.03);
      const Pose3 guess =
          four_dof ? pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0], rpy[1], rpy[2] + 0.03)
                   : pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0] + 0.02, rpy[1] - 0.02,
                                        rpy[2] + 0.03);
      const Agreement g = compare<3>(test::world3().map, o, cloud, guess);
      EXPECT_LT(g.mahalanobis, 0.1) << "pose " << k << " four_dof " << four_dof;
      EXPECT_LT(g.covariance, 0.01) << "pose " << k << " four_dof " << four_dof;
      std::printf("3D pose %d %s: %.3g sigma apart, covariance %.2g, iterations %d / %d\n", k,
                  four_dof ? "4-DOF" : "6-DOF", g.mahalanobis, g.covariance, g.dense_iterations,
                  g.ceres_iterations);
    }
  }
}

TEST(ScanSolvers, NewtonStepsReachTheMinimumInAFewIterationsAndSayWhenTheyDidNot) {
  // Issue 57: a solve is converged when Newton's step is at most step_sigma (0.01) of the pose's
  // standard deviations (scan_lm.hpp (C)). Oracle: the cost's gradient and Hessian by central
  // finite differences of the value-only lookups at the returned pose; the Newton step they give,
  // in sigmas (sigma^2 H^-1), must be within 0.02 (measured 0.003-0.010). From 6 cm / 0.03 rad
  // off (several sigma), with and without clutter under the Cauchy loss, a solve takes 6-15
  // evaluations (the safety net, 25, never met). With one iteration allowed the same solve is
  // reported not converged.
  std::mt19937 rng(5);
  for (const RobustLoss loss : {RobustLoss::kNone, RobustLoss::kCauchy}) {
    for (const std::size_t k : {2u, 7u, 12u, 18u}) {
      const Pose2 truth = test::tour_pose(k);
      const ScanPoints pts = tour_scan(truth, loss, rng);
      VdtOptimizerOptions o;
      o.solver = ScanSolver::kDense;
      o.loss = loss;
      o.gate_rounds = 1;  // one solve over the readings gated at the guess
      const Pose2 guess = truth + Pose2(0.06, -0.04, 0.03);
      const VdtOptimizer opt(test::world().map, o);
      const LocalizationResult r = opt.solve(pts, guess);
      ASSERT_EQ(r.status, LocalizationStatus::kConverged) << "pose " << k;
      EXPECT_LE(r.iterations, 16) << "pose " << k << " loss " << static_cast<int>(loss);
      const VdtSensorModel& model = opt.sensor_model();
      const std::vector<int> beams = gated_at(model, pts, guess);
      // F = 1/2 sum rho: gradient and Hessian by central differences (steps 1e-4 m / rad).
      const auto f = [&](const Pose2& x) {
        return 0.5 * robust_cost(model, pts, beams, loss, o.loss_scale, x);
      };
      const double sigma2 = model.map_sigma() * model.map_sigma() + 0.02 * 0.02 / 2;
      const double sigmas = newton_sigmas_by_differences(f, r.pose, sigma2);
      ASSERT_TRUE(std::isfinite(sigmas)) << "not a minimum: pose " << k;
      EXPECT_LT(sigmas, 0.02) << "pose " << k << " loss " << static_cast<int>(loss);
      std::printf("pose %zu loss %d: %d evaluations, Newton step %.2g sigma (finite differences)\n",
                  k, static_cast<int>(loss), r.iterations, sigmas);
      o.max_iterations = 1;
      EXPECT_EQ(VdtOptimizer(test::world().map, o).solve(pts, guess).status,
                LocalizationStatus::kNotConverged)
          << "pose " << k;
    }
  }
}

TEST(ScanSolvers, NearTheMinimumTheFloorFollowsAFlatCostIn2dAndTheSolveConverges) {
  // Issue 57: in 2D (K)'s floor stays at 1/4 away from the minimum, and where the cost is far
  // flatter than the IRLS matrix (most readings beyond the Cauchy loss's scale; the MIT corridor
  // along its length) each step covered a fraction of the way and (C), measured on the floored
  // matrix, understated the step left. Within one sigma the floor now follows the steps down as
  // far as keeps a step inside it (scan_lm.hpp (K)). 100 solves: the 20 tour poses, 5 draws
  // each, four readings in five pulled 0.1-0.4 m short along their beams (scale 0.05 m), from
  // 5 cm / 0.02 rad off. The oracle: Newton's step by central finite differences of the
  // value-only lookups at the returned pose, in sigmas. Measured: 97 converged, of which 63 with
  // the oracle's step within 0.01 sigma and 81 within 0.05; at the fixed floor 87 converged, 44
  // and 76 (and 16 with a step over 0.05 sigma: solves ending on a kink of the cost, a reading on
  // the medial axis between two walls, where central differences measure the kink — at tour pose
  // 18 a gradient of 0.07 in y and heading, yet the cost falls by 2e-4 of 2.33 along its step).
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> shift(0.1, 0.4);
  int converged = 0, within_001 = 0, within_005 = 0;
  double evaluations = 0.0;
  for (std::size_t k = 0; k < 100; ++k) {
    const Pose2 truth = test::tour_pose(k % 20);
    LaserScan scan = test::simulate_scan(truth, 0.01, rng);
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      if (i % 5 != 0) scan.ranges[i] -= shift(rng);
    }
    const ScanPoints pts = scan_points(scan);
    VdtOptimizerOptions o;
    o.solver = ScanSolver::kDense;
    o.loss = RobustLoss::kCauchy;
    o.loss_scale = 0.05;
    o.gate_rounds = 1;         // one solve over the readings gated at the guess (the oracle's)
    o.coarse_threshold = 1e9;  // no coarse alignment before it
    o.max_iterations = 50;     // the real-log settings' limit
    const Pose2 guess = truth + Pose2(0.04, -0.03, 0.02);
    const VdtOptimizer opt(test::world().map, o);
    const LocalizationResult r = opt.solve(pts, guess);
    if (r.status != LocalizationStatus::kConverged) continue;
    ++converged;
    evaluations += r.iterations;
    const VdtSensorModel& model = opt.sensor_model();
    const std::vector<int> beams = gated_at(model, pts, guess);
    const auto f = [&](const Pose2& x) {
      return 0.5 * robust_cost(model, pts, beams, o.loss, o.loss_scale, x);
    };
    const double sigma2 = model.map_sigma() * model.map_sigma() + 0.01 * 0.01 / 2;
    // Not a minimum by the oracle (infinite): counted as over both bounds.
    const double sigmas = newton_sigmas_by_differences(f, r.pose, sigma2);
    within_001 += sigmas <= 0.01;
    within_005 += sigmas <= 0.05;
  }
  std::printf(
      "2D, 4 readings in 5 beyond the loss scale: %d of 100 converged (%.1f evaluations "
      "mean), oracle's Newton step within 0.01 sigma %d, within 0.05 sigma %d\n",
      converged, evaluations / std::max(converged, 1), within_001, within_005);
  EXPECT_GE(converged, 95);
  EXPECT_GE(within_001, 60);
  EXPECT_GE(within_005, 80);
}

TEST(ScanSolvers, AFloorThatFollowsAFlatCostReachesAMinimumNoWorseThanTheFixedFloorIn3d) {
  // Issue 57: where most readings lie beyond the Cauchy loss's scale the cost is far flatter than
  // the IRLS matrix (a real 3D scan: 0.002-0.2 of it in every direction), and at (K)'s fixed
  // floor of 1/4 each step covers a fraction of the way. With the floor following the steps down
  // (newton_floor 1/64, the 3D default) the solve must still end at a minimum — Newton's step
  // there by central finite differences of the value-only lookups (the oracle) within 0.02
  // sigma — and at a cost no higher than the fixed floor's. Three readings in four are pulled
  // 0.1-0.4 m short along their beams (scale 0.05 m): the steps fall short (the floor moves),
  // and the longer steps reached a lower minimum on one pose (cost 15.77 against 15.98), the
  // same on the other.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> shift(0.1, 0.4);
  for (int k = 0; k < 2; ++k) {
    const Pose3 truth = test::cloud_pose(k);
    ObservationSet3 cloud = test::simulate_cloud(truth, 0.01, rng);
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      if (i % 4 == 0) continue;
      const double dr = shift(rng);
      cloud.points[i] -= dr * cloud.directions[i];
      cloud.ranges[i] -= dr;
    }
    VdtOptimizerOptions o;
    o.solver = ScanSolver::kDense;
    o.loss = RobustLoss::kCauchy;
    o.loss_scale = 0.05;
    o.gate_rounds = 1;
    o.max_iterations = 200;
    const Eigen::Vector3d rpy = rpy_of(truth.linear());
    const Eigen::Vector3d t = truth.translation() + Eigen::Vector3d(0.05, -0.05, 0.03);
    const Pose3 guess =
        pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0] + 0.02, rpy[1] - 0.02, rpy[2] + 0.03);
    o.newton_floor = 0.25;
    const LocalizationResult3 fixed = VdtOptimizer3(test::world3().map, o).solve(cloud, guess);
    o.newton_floor = 1.0 / 64.0;
    const VdtOptimizer3 opt(test::world3().map, o);
    const LocalizationResult3 following = opt.solve(cloud, guess);
    ASSERT_EQ(fixed.status, LocalizationStatus::kConverged) << "pose " << k;
    ASSERT_EQ(following.status, LocalizationStatus::kConverged) << "pose " << k;
    EXPECT_LE(following.final_cost, fixed.final_cost * (1.0 + 1e-9)) << "pose " << k;
    // The oracle: F = 1/2 sum rho(|d|^2) over the readings gated at the guess, by central
    // differences (steps 1e-4) in the pose perturbation at the returned pose.
    const VdtSensorModel3& model = opt.sensor_model();
    std::vector<int> beams;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      bool inlier = false;
      (void)model.disparity_value(guess.linear(), guess.translation(), cloud.points[i], &inlier);
      if (inlier) beams.push_back(static_cast<int>(i));
    }
    const double b = o.loss_scale * o.loss_scale;
    const auto f = [&](const Eigen::Matrix<double, 6, 1>& dx) {
      const Pose3 x = PoseTraits<3>::plus(following.pose, dx);
      double cost = 0.0;
      for (const int i : beams) {
        bool unused = false;
        const double s2 =
            model.disparity_value(x.linear(), x.translation(), cloud.points[i], &unused)
                .squaredNorm();
        cost += b * std::log1p(s2 / b);
      }
      return 0.5 * cost;
    };
    const double h = 1e-4;
    Eigen::Matrix<double, 6, 1> g;
    Eigen::Matrix<double, 6, 6> hess;
    for (int a = 0; a < 6; ++a) {
      const Eigen::Matrix<double, 6, 1> da = Eigen::Matrix<double, 6, 1>::Unit(a) * h;
      g[a] = (f(da) - f(-da)) / (2 * h);
      for (int c = 0; c < 6; ++c) {
        const Eigen::Matrix<double, 6, 1> dc = Eigen::Matrix<double, 6, 1>::Unit(c) * h;
        hess(a, c) = (f(da + dc) - f(da - dc) - f(dc - da) + f(-da - dc)) / (4 * h * h);
      }
    }
    const double sigma2 = model.map_sigma() * model.map_sigma() + 0.01 * 0.01 / 3;
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(0.5 * (hess + hess.transpose()));
    ASSERT_EQ(llt.info(), Eigen::Success) << "not a minimum: pose " << k;
    const double sigmas = std::sqrt(g.dot(llt.solve(g)) / sigma2);
    EXPECT_LT(sigmas, 0.02) << "pose " << k;
    std::printf(
        "3D pose %d, 3 readings in 4 beyond the loss scale: %d evaluations (cost %.6g) at "
        "the fixed floor, %d (cost %.6g) with the floor following; Newton step %.2g "
        "sigma (finite differences)\n",
        k, fixed.iterations, fixed.final_cost, following.iterations, following.final_cost, sigmas);
  }
}

}  // namespace
}  // namespace vdtnav
