#pragma once
/// \file
/// \brief The unsigned-distance-transform baselines of Table 3.3, behind the same interface as
/// the VDT methods: C-LOG-style optimization of the Chamfer cost sum_i DT_u(q_i)^2 (no
/// covariance, as C-LOG reports none) and an EKF whose per-beam observation is DT_u(q_i) = 0.
/// Both read the UDT through the same cubic B-spline as the VDT (DistanceFieldMap), so the
/// comparison isolates the representation.

#include <string>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// \brief One beam on the UDT: residual DT_u(q) and its derivatives.
struct UdtBeam {
  double e = 0.0;                                           ///< DT_u(q_i)
  Eigen::RowVector3d e_pose = Eigen::RowVector3d::Zero();   ///< d DT_u(q_i) / dX
  double e_range = 0.0;                                     ///< d DT_u(q_i) / dr_i
  Eigen::RowVector2d e_point = Eigen::RowVector2d::Zero();  ///< d DT_u(q_i) / dp_i (robot frame)
  bool inlier = false;                                      ///< inside the map and DT_u < gate
};

/// \brief Evaluates a beam (robot-frame point p, unit direction u) at pose X on a UDT.
[[nodiscard]] UdtBeam udt_beam(const DistanceFieldMap<2>& udt, const Pose2& pose, double cos_phi,
                               double sin_phi, const Eigen::Vector2d& p, const Eigen::Vector2d& u,
                               double gate);

/// \brief Options shared by the UDT baselines.
struct UdtOptions {
  double gate = 0.5;        ///< beams with DT_u >= gate are dropped
  double map_sigma = -1.0;  ///< map-noise floor (EKF); < 0: resolution / sqrt(12)
  int min_inliers = 10;
  int max_iterations = 25;
  MotionModelKind motion = MotionModelKind::kVelocity;  ///< EKF prediction
  MotionNoise noise;                                    ///< EKF prediction noise
};

/// \brief The UDT baselines' defaults (their constructors', LocalizerSettings{}'s, `vdtnav
/// localize`'s): odometry increments for the EKF's prediction. UdtOptions{}: the velocity model.
[[nodiscard]] UdtOptions udt_defaults();

/// \brief C-LOG-style optimization on the UDT ("udt-opt"): the guess is the last estimate
/// composed with odometry, then Ceres minimises sum_i DT_u(q_i)^2 over the gated beams.
class UdtOptimizationLocalizer final : public Localizer2D {
 public:
  UdtOptimizationLocalizer(const OccupancyGrid<2>& map, const UdtOptions& options = udt_defaults());
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return "udt-opt"; }

 private:
  DistanceFieldMap<2> udt_;
  UdtOptions options_;
  Pose2 pose_ = Pose2::Zero();
};

/// \brief EKF on the UDT ("udt-ekf"): innovation -DT_u(q_i) per beam, information-form update.
class UdtEkfLocalizer final : public Localizer2D {
 public:
  UdtEkfLocalizer(const OccupancyGrid<2>& map, const UdtOptions& options = udt_defaults());
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return "udt-ekf"; }

 private:
  DistanceFieldMap<2> udt_;
  UdtOptions options_;
  double map_sigma_;
  Pose2 x_ = Pose2::Zero();
  Eigen::Matrix3d p_ = Eigen::Matrix3d::Identity();
};

}  // namespace vdtnav
