// The sequential 3D localizer (VdtOptimizationLocalizer3) on a simulated VLP-16 drive through the
// generated 3D room: accuracy and covariance against the truth (NEES), the 4-DOF mode's held
// attitude, the prediction's covariance against Monte Carlo, and a teleport: the loss is reported,
// no wrong pose is reported converged, and recovery's template (RecoveringLocalizerT<3>) adopting
// what a 3D reacquisition finds.
#include "vdtnav/estimation/vdt_localizer3d.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace vdtnav {
namespace {

struct Drive {
  sim::Room3d room;
  std::unique_ptr<VdtMap3> map;
  std::vector<Pose3> truth;
};

/// The generated room at 0.1 m; a 6 m drive along x at 1.1 m height, 10 Hz at 1 m/s, rolling and
/// pitching a few degrees.
const Drive& drive() {
  static const Drive d = [] {
    Drive x;
    sim::Room3dOptions ro;
    ro.resolution = 0.1;
    ro.wall_thickness = 0.2;
    ro.boxes = 6;
    x.room = sim::generate_room3d(ro);
    x.map = std::make_unique<VdtMap3>(VdtMap3::build(x.room.occupancy));
    for (int k = 0; k < 50; ++k) {
      const double t = 0.1 * k;
      x.truth.push_back(pose3_from_xyz_rpy(1.2 + 0.1 * k, 2.5 + 0.3 * std::sin(t), 1.6,
                                           0.03 * std::sin(2 * kPi * t / 3.1),
                                           0.02 * std::sin(2 * kPi * t / 4.3), 0.2 + 0.05 * t));
    }
    return x;
  }();
  return d;
}

ObservationSet3 scan_at(const Pose3& pose, std::mt19937& rng) {
  sim::Lidar3dSpec spec;
  spec.azimuth_step = 2.0 * kPi / 360;  // 1 degree: 5760 rays
  return sim::lidar3d_observations(
             sim::simulate_lidar3d_scan(drive().room.occupancy, pose, spec, rng), spec)
      .subsampled(3);
}

Matrix6d start_covariance() {
  Matrix6d p = Matrix6d::Zero();
  p.diagonal() << 4e-4, 4e-4, 4e-4, 1e-4, 1e-4, 1e-4;
  return p;
}

TEST(VdtLocalizer3, TracksAVlp16DriveWithAConsistentCovarianceInBothModes) {
  const Drive& d = drive();
  VdtLocalizer3Options o6;
  VdtLocalizer3Options o4 = o6;
  o4.optimizer.four_dof = true;
  VdtOptimizationLocalizer3 loc6(*d.map, o6);
  VdtOptimizationLocalizer3 loc4(loc6.optimizer(), o4);
  EXPECT_EQ(loc6.name(), "vdt-opt-6dof");
  EXPECT_EQ(loc4.name(), "vdt-opt-4dof");
  std::mt19937 rng(3);
  loc6.reset(d.truth[0], start_covariance());
  loc4.reset(d.truth[0], start_covariance());
  std::vector<double> nees6, nees4;
  double max_pos6 = 0.0, max_att6 = 0.0, max_pos4 = 0.0;
  for (std::size_t k = 1; k < d.truth.size(); ++k) {
    const OdometryStep3 odo = o6.noisy_odometry(d.truth[k - 1], d.truth[k], 0.1, rng);
    const ObservationSet3 obs = scan_at(d.truth[k], rng);
    const LocalizationResult3 r6 = loc6.update(odo, obs);
    const LocalizationResult3 r4 = loc4.update(odo, obs);
    ASSERT_EQ(r6.status, LocalizationStatus::kConverged) << k;
    ASSERT_EQ(r4.status, LocalizationStatus::kConverged) << k;
    EXPECT_GT(r6.explained, 0.9);
    max_pos6 = std::max(max_pos6, (r6.pose.translation() - d.truth[k].translation()).norm());
    max_att6 = std::max(max_att6, attitude_error(r6.pose, d.truth[k]));
    max_pos4 = std::max(max_pos4, (r4.pose.translation() - d.truth[k].translation()).norm());
    int dof = 0;
    nees6.push_back(eval::nees(r6.pose, d.truth[k], r6.covariance, &dof));
    EXPECT_EQ(dof, 6);
    nees4.push_back(eval::nees(r4.pose, d.truth[k], r4.covariance, &dof));
    EXPECT_EQ(dof, 6);  // the held roll and pitch carry the IMU's variance
    // 4-DOF: roll and pitch are the IMU's, exactly.
    const Eigen::Vector3d rpy = rpy_of(r4.pose.linear());
    EXPECT_NEAR(rpy.x(), odo.roll, 1e-9);
    EXPECT_NEAR(rpy.y(), odo.pitch, 1e-9);
    EXPECT_NEAR(r4.covariance(3, 3), o4.sigma_imu_attitude * o4.sigma_imu_attitude, 1e-15);
  }
  const eval::AneesResult a6 = eval::anees(nees6, 6, 0.99), a4 = eval::anees(nees4, 6, 0.99);
  std::printf(
      "6-DOF: max %.4f m, %.4f rad, ANEES %.2f in [%.2f, %.2f]; 4-DOF: max %.4f m, ANEES "
      "%.2f\n",
      max_pos6, max_att6, a6.anees, a6.interval.lower, a6.interval.upper, max_pos4, a4.anees);
  EXPECT_LT(max_pos6, 0.05);
  EXPECT_LT(max_att6, 0.01);
  // Roll and pitch held at the IMU's (sigma 0.005 rad): 3 cm at 6 m, through x, y, z.
  EXPECT_LT(max_pos4, 0.08);
  // Not over-confident: the 99 % interval's upper end, as claimed (the map's correlated errors
  // off, map_correlation_length 0, the 6-DOF ANEES is 16.0; 1.5x over-confident fails). The
  // scans are cast in the map's own voxels, so its only error is the cell-centre surfaces'
  // quantisation, correlated over ~0.5 m here (cubes of 0.5 m: 5.56, inside; 0.3 m: 7.57): the
  // default 1 m cubes, sized for maps built from scans, are conservative on it, measured 3.11
  // (6-DOF) and 4.07 (4-DOF) - below the interval, held here to within 2.5x of the dimension.
  EXPECT_LE(a6.anees, a6.interval.upper);
  EXPECT_LE(a4.anees, a4.interval.upper);
  EXPECT_GT(a6.anees, 6.0 / 2.5);
  EXPECT_GT(a4.anees, 6.0 / 2.5);
}

TEST(VdtLocalizer3, DeskewingHalvesTheErrorOfASensorMovingAt2MetresPerSecondAnd30DegPerSecond) {
  // Issue 36's measurement: a VLP-16 (1 degree azimuth) sweeping for 0.1 s while it moves at
  // 2 m/s and 30 deg/s of yaw (simulate_lidar3d_sweep), its readings in the sensor's frame at
  // their own times; the same scans and odometry to two trackers, deskewing on and off.
  sim::Room3dOptions ro;
  ro.resolution = 0.1;
  ro.wall_thickness = 0.2;
  ro.pillars = 0;
  const sim::Room3d room = sim::generate_room3d(ro);
  const VdtMap3 map = VdtMap3::build(room.occupancy);
  SweepMotion motion;
  motion.velocity = Eigen::Vector3d(2.0, 0.0, 0.0);
  motion.rates = Eigen::Vector3d(0.0, 0.0, 30.0 * kPi / 180.0);
  std::vector<Pose3> truth = {pose3_from_xyz_rpy(2.0, 1.5, 1.6, 0.0, 0.0, 0.0)};
  for (int k = 1; k < 20; ++k) truth.push_back(truth.back() * motion.at(0.1));  // 4 m, 60 deg
  for (const Pose3& p : truth)
    ASSERT_EQ(room.occupancy(room.occupancy.frame().cell_of(p.translation())), 0);
  VdtLocalizer3Options on;
  VdtLocalizer3Options off = on;
  off.deskew = false;
  VdtOptimizationLocalizer3 with(map, on), without(map, off);
  Matrix6d p0 = Matrix6d::Identity() * 1e-4;
  with.reset(truth[0], p0);
  without.reset(truth[0], p0);
  sim::Lidar3dSpec spec;
  spec.azimuth_step = 2.0 * kPi / 360;
  std::mt19937 rng(4);
  double se[2] = {0.0, 0.0}, sa[2] = {0.0, 0.0};
  for (std::size_t k = 1; k < truth.size(); ++k) {
    const ObservationSet3 scan =
        sim::lidar3d_observations(
            sim::simulate_lidar3d_sweep(room.occupancy, truth[k], motion, spec, rng), spec)
            .subsampled(3);
    ASSERT_EQ(scan.times.size(), scan.size());
    const OdometryStep3 odo = on.noisy_odometry(truth[k - 1], truth[k], 0.1, rng);
    VdtOptimizationLocalizer3* locs[2] = {&with, &without};
    for (int m = 0; m < 2; ++m) {
      const LocalizationResult3 r = locs[m]->update(odo, scan);
      se[m] += (r.pose.translation() - truth[k].translation()).squaredNorm();
      sa[m] += std::pow(attitude_error(r.pose, truth[k]), 2);
    }
  }
  const double n = static_cast<double>(truth.size() - 1);
  std::printf(
      "2 m/s, 30 deg/s: position RMSE %.4f m deskewed, %.4f m not; attitude %.5f / %.5f rad\n",
      std::sqrt(se[0] / n), std::sqrt(se[1] / n), std::sqrt(sa[0] / n), std::sqrt(sa[1] / n));
  EXPECT_LE(std::sqrt(se[0] / n), 0.5 * std::sqrt(se[1] / n));  // the target
  EXPECT_LE(std::sqrt(sa[0] / n), 0.5 * std::sqrt(sa[1] / n));
  EXPECT_LT(std::sqrt(se[0] / n), 0.03);  // measured 0.0168 m (not deskewed: 0.130 m)
}

TEST(VdtLocalizer3, FourDofWithoutAnImuGivesTheHeldAttitudeNoInventedVariance) {
  // Odometry without roll and pitch (no IMU): the 4-DOF mode holds them at the prediction's (the
  // start's, moved by the odometry's rotations). Without a
  // held_attitude_sigma they are not estimated: NaN rows and columns, the free block finite and
  // positive definite, the next prediction not poisoned. With one, the IMU's treatment: sigma^2 in
  // the held rows and the free block grown by S sigma^2 S^T.
  const Drive& d = drive();
  VdtLocalizer3Options none;
  none.optimizer.four_dof = true;
  VdtLocalizer3Options given = none;
  given.held_attitude_sigma = 0.01;
  VdtOptimizationLocalizer3 loc_none(*d.map, none);
  VdtOptimizationLocalizer3 loc_given(loc_none.optimizer(), given);
  loc_none.reset(d.truth[0], start_covariance());
  loc_given.reset(d.truth[0], start_covariance());
  Pose3 last = d.truth[0];
  std::mt19937 rng(4);
  for (std::size_t k = 1; k < 12; ++k) {
    OdometryStep3 odo = none.noisy_odometry(d.truth[k - 1], d.truth[k], 0.1, rng);
    odo.roll = odo.pitch = std::nan("");  // no IMU
    const ObservationSet3 obs = scan_at(d.truth[k], rng);
    const LocalizationResult3 a = loc_none.update(odo, obs);
    const LocalizationResult3 b = loc_given.update(odo, obs);
    ASSERT_EQ(a.status, LocalizationStatus::kConverged) << k;
    ASSERT_EQ(b.status, LocalizationStatus::kConverged) << k;
    // Roll and pitch are the prediction's: the scan did not move them.
    const Eigen::Vector3d predicted = rpy_of((last * odo.delta).linear());
    EXPECT_NEAR(rpy_of(a.pose.linear()).x(), predicted.x(), 1e-9);
    EXPECT_NEAR(rpy_of(a.pose.linear()).y(), predicted.y(), 1e-9);
    last = a.pose;
    const int f[4] = {0, 1, 2, 5};
    Eigen::Matrix4d free_a, grown;
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        EXPECT_EQ(std::isnan(a.covariance(i, j)), i == 3 || i == 4 || j == 3 || j == 4);
      }
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        free_a(i, j) = a.covariance(f[i], f[j]);
        grown(i, j) = b.covariance(f[i], f[j]) - a.covariance(f[i], f[j]);
      }
    }
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(free_a).eigenvalues().minCoeff(), 0.0);
    EXPECT_TRUE(b.covariance.allFinite());
    EXPECT_NEAR(b.covariance(3, 3), 1e-4, 1e-15);
    EXPECT_NEAR(b.covariance(4, 4), 1e-4, 1e-15);
    // The same solve (both start from the same pose and scans): b's free block is a's plus a
    // positive semi-definite term that is not zero (a tilted scan moves z and x, y).
    EXPECT_TRUE(a.pose.isApprox(b.pose, 1e-9)) << k;
    EXPECT_GT(grown.trace(), 1e-3 * free_a.trace()) << k;
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(grown).eigenvalues().minCoeff(),
              -1e-9 * grown.trace());
  }
  // A held_attitude_sigma <= 0 is a configuration error.
  VdtLocalizer3Options bad = none;
  bad.held_attitude_sigma = 0.0;
  EXPECT_THROW(VdtOptimizationLocalizer3(*d.map, bad), ConfigError);
}

TEST(VdtLocalizer3, ThePredictionsCovarianceMatchesMonteCarlo) {
  // No observations: the result is the prediction; its covariance against the spread of
  // X (+) e composed with the increment, e ~ N(0, P), plus the odometry noise Q.
  const Drive& d = drive();
  VdtLocalizer3Options o;  // an empty scan is judged by nothing: never a loss
  VdtOptimizationLocalizer3 loc(*d.map, o);
  const Pose3 x = pose3_from_xyz_rpy(2, 3, 1, 0.1, -0.05, 0.7);
  Matrix6d p = start_covariance();
  p(0, 5) = p(5, 0) = 1e-4;
  loc.reset(x, p);
  OdometryStep3 odo;
  odo.dt = 0.5;
  odo.delta = pose3_from_xyz_rpy(1.5, 0.3, 0.1, 0.0, 0.0, 0.2);
  const LocalizationResult3 r = loc.update(odo, ObservationSet3{});
  EXPECT_NE(r.status, LocalizationStatus::kConverged);
  const Eigen::LLT<Matrix6d> llt(p);
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0.0, 1.0);
  Matrix6d mc = Matrix6d::Zero();
  const int samples = 20000;
  for (int s = 0; s < samples; ++s) {
    Vector6d z;
    for (int k = 0; k < 6; ++k) z[k] = n(rng);
    const Vector6d e = ominus(oplus(x, llt.matrixL() * z) * odo.delta, x * odo.delta);
    mc += e * e.transpose() / samples;
  }
  const double st = o.sigma_translation_per_metre * odo.delta.translation().norm() +
                    o.sigma_translation_per_second * odo.dt;
  const double sr = o.sigma_rotation_per_radian * 0.2 + o.sigma_rotation_per_second * odo.dt;
  mc.topLeftCorner<3, 3>().diagonal().array() += st * st;
  mc.bottomRightCorner<3, 3>().diagonal().array() += sr * sr;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(r.covariance(i, j), mc(i, j), 0.05 * std::sqrt(mc(i, i) * mc(j, j)))
          << i << "," << j;
  EXPECT_LT((r.pose.matrix() - (x * odo.delta).matrix()).norm(), 1e-12);
}

TEST(VdtLocalizer3, ATeleportIsFlaggedUntilFoundAgainAndNoWrongPoseConverged) {
  // The tracker inside recovery (what `vdtnav localize3d` runs) flags every scan after the
  // teleport (refused, in doubt or lost) until recovery finds the robot again; the tracker alone
  // refuses the scans it cannot match but has no window test: never kLost, never found.
  const Drive& d = drive();
  VdtLocalizer3Options o;
  RecoveringLocalizer3 loc(*d.map, o);
  VdtOptimizationLocalizer3 alone(loc.tracker().optimizer(), o);
  std::mt19937 rng(4);
  loc.reset(d.truth[0], start_covariance());
  alone.reset(d.truth[0], start_covariance());
  // The robot is carried 5 m away (issue 57's case); odometry says nothing. The scans at the
  // prediction put beams through the room's walls and furniture: the window's contradiction
  // rises from the track's ~0 to ~0.5 of the readings the map judges (its floor and ceiling
  // explain 35 % of each scan wherever the robot is), in doubt on the first scan, and the doubt's
  // global search finds the robot (before issue 57's doubt search: lost 6 scans after, found the
  // next).
  const Eigen::Vector3d jump(0.0, 5.0, 0.0);
  int found_after = -1, flagged = 0, wrong_converged = 0, alone_lost = 0, alone_refused = 0;
  for (std::size_t k = 1; k < 36; ++k) {  // 16 scans after the teleport
    const bool moved = k >= 20;
    Pose3 where = d.truth[k];
    if (moved) where.translation() += jump;
    const OdometryStep3 odo = o.noisy_odometry(d.truth[k - 1], d.truth[k], 0.1, rng);
    const ObservationSet3 scan = scan_at(where, rng);
    const LocalizationResult3 r = loc.update(odo, scan);
    const LocalizationResult3 a = alone.update(odo, scan);
    if (!moved) {
      EXPECT_EQ(r.status, LocalizationStatus::kConverged) << k;
      EXPECT_EQ(a.status, LocalizationStatus::kConverged) << k;
      continue;
    }
    const double off = (r.pose.translation() - where.translation()).norm();
    if (r.status == LocalizationStatus::kConverged && off < 0.05 && found_after < 0)
      found_after = static_cast<int>(k) - 20;
    if (found_after < 0) {
      flagged += r.status == LocalizationStatus::kRefused || r.status == LocalizationStatus::kLost;
    }
    wrong_converged += r.status == LocalizationStatus::kConverged && off > 0.3;
    alone_lost += a.status == LocalizationStatus::kLost;
    alone_refused += a.status == LocalizationStatus::kRefused;
  }
  std::printf(
      "teleport: found again %d scans after, %d scans flagged before; wrong poses reported "
      "converged: %d; the tracker alone: %d lost, %d refused\n",
      found_after, flagged, wrong_converged, alone_lost, alone_refused);
  EXPECT_GE(found_after, 0);
  EXPECT_LE(found_after, 6);
  EXPECT_EQ(flagged, found_after);  // every scan before it
  EXPECT_EQ(wrong_converged, 0);
  EXPECT_EQ(alone_lost, 0);
  EXPECT_GE(alone_refused, 10);
}

TEST(RecoveringLocalizer3, ATeleportedRobotIsFoundAgainByGlobalLocalizationAndNotWithoutIt) {
  // Carried 3.5 m sideways and turned 90 degrees, beyond the attitude grid around the prediction:
  // recovery's global search (localize3d.global_recovery, the default) finds the robot on the
  // re-acquiring scans and the tracker goes on from there; without it the robot stays lost.
  const Drive& d = drive();
  VdtLocalizer3Options with;
  VdtLocalizer3Options without = with;
  without.global_recovery = false;
  RecoveringLocalizer3 a(*d.map, with);
  RecoveringLocalizer3 b(a.tracker().optimizer(), without);
  std::mt19937 rng(6);
  a.reset(d.truth[0], start_covariance());
  b.reset(d.truth[0], start_covariance());
  const Pose3 carry = pose3_from_xyz_rpy(0.0, 3.5, 0.0, 0.0, 0.0, kPi / 2);
  int found_after = -1, found_without = 0, wrong = 0;
  for (std::size_t k = 1; k < 32; ++k) {
    const bool moved = k >= 15;
    // The teleport: about the robot's own position (the room's free space holds both).
    Pose3 where = d.truth[k];
    if (moved) {
      where.translation() += carry.translation();
      where.linear() = carry.linear() * where.linear();
    }
    const OdometryStep3 odo = with.noisy_odometry(d.truth[k - 1], d.truth[k], 0.1, rng);
    const ObservationSet3 scan = scan_at(where, rng);
    const LocalizationResult3 ra = a.update(odo, scan);
    const LocalizationResult3 rb = b.update(odo, scan);
    const auto near = [&](const LocalizationResult3& r) {
      return r.status == LocalizationStatus::kConverged &&
             (r.pose.translation() - where.translation()).norm() < 0.05 &&
             attitude_error(r.pose, where) < 0.01;
    };
    if (!moved) continue;
    if (near(ra) && found_after < 0) found_after = static_cast<int>(k) - 15;
    wrong += ra.status == LocalizationStatus::kConverged && !near(ra);
    found_without += near(rb);
  }
  std::printf("teleport of 3.5 m and 90 deg: found again %d scans after (%d recoveries)\n",
              found_after, a.recoveries());
  EXPECT_GE(found_after, 0);
  EXPECT_LE(found_after, 12);  // in doubt, or lost after the window (5): the searching scans
  EXPECT_EQ(a.recoveries(), 1);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(found_without, 0);
  EXPECT_EQ(b.recoveries(), 0);
}

/// A tracker that never moves (an estimate stuck where it was reset), explaining nothing.
class StuckTracker3 final : public Localizer3D {
 public:
  void reset(const Pose3& pose, const Matrix6d& covariance) override {
    pose_ = pose;
    covariance_ = covariance;
  }
  LocalizationResult3 update(const OdometryStep3&, const ObservationSet3&) override {
    LocalizationResult3 r;
    r.status = LocalizationStatus::kConverged;
    r.pose = pose_;
    r.covariance = covariance_;
    r.has_covariance = true;
    r.explained = explained;
    return r;
  }
  std::string name() const override { return "stuck"; }
  double explained = 0.0;

 private:
  Pose3 pose_ = Pose3::Identity();
  Matrix6d covariance_ = Matrix6d::Identity();
};

/// A 3D reacquisition that finds `found` when asked (the test's stand-in for a search).
class FindsAPose3 final : public Reacquisition<3> {
 public:
  explicit FindsAPose3(const Pose3& found) : found_(found) {}
  ScanAgreement weigh(const ObservationSet3& observations, LocalizationResult3& r) override {
    return ScanAgreement::all_judged(static_cast<int>(observations.size()), r.explained);
  }
  std::optional<Adopted> reacquire(const OdometryStep3&, const ObservationSet3&,
                                   const LostDetector& detector, bool wrong,
                                   LocalizationResult3&) override {
    ++asked;
    if (!detector.lost() || !wrong) return std::nullopt;
    Adopted a;
    a.result.status = LocalizationStatus::kConverged;
    a.result.pose = found_;
    a.result.explained = 1.0;
    a.covariance = 1e-4 * Matrix6d::Identity();
    a.result.covariance = a.covariance;
    a.result.has_covariance = true;
    return a;
  }
  int asked = 0;

 private:
  Pose3 found_;
};

TEST(RecoveringLocalizer3, TheTemplateAdoptsWhatA3dReacquisitionFindsAndRestartsTheTracker) {
  // Lost detection and recovery over the pose traits: the same window test and adoption as in
  // 2D, around a 3D tracker. A stuck tracker explaining nothing is lost once the window fills
  // (W = 5 scans), and the pose the reacquisition then finds restarts it.
  auto tracker = std::make_unique<StuckTracker3>();
  StuckTracker3* stuck = tracker.get();
  const Pose3 found = pose3_from_xyz_rpy(4.0, -1.0, 0.5, 0.01, -0.02, 1.2);
  auto finder = std::make_unique<FindsAPose3>(found);
  FindsAPose3* f = finder.get();
  LostWatchOptions w;
  w.min_readings = 1;
  RecoveringLocalizerT<3> loc(std::move(tracker), std::move(finder), w);
  loc.reset(Pose3::Identity(), Matrix6d::Identity());
  ObservationSet3 scan;
  for (int i = 0; i < 50; ++i)
    scan.add(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 1.0 + 0.1 * i, i);
  int first_adopted = -1;
  for (int k = 0; k < 8 && first_adopted < 0; ++k) {
    const LocalizationResult3 r = loc.update(OdometryStep3{}, scan);
    if (loc.recoveries() == 1) {
      first_adopted = k;
      EXPECT_LT((r.pose.matrix() - found.matrix()).norm(), 1e-12);
      EXPECT_EQ(r.status, LocalizationStatus::kConverged);
    } else if (k < 4) {
      EXPECT_NE(r.status, LocalizationStatus::kLost) << k;  // the window is not full yet
    }
  }
  EXPECT_EQ(first_adopted, 4);          // the 5th scan fills the window: lost, and found at once
  EXPECT_FALSE(loc.detector().lost());  // a new start
  stuck->explained = 1.0;
  const LocalizationResult3 after = loc.update(OdometryStep3{}, scan);
  EXPECT_LT((after.pose.matrix() - found.matrix()).norm(), 1e-12);  // the tracker restarted there
  EXPECT_EQ(after.status, LocalizationStatus::kConverged);
  EXPECT_GE(f->asked, 1);
}

}  // namespace
}  // namespace vdtnav
