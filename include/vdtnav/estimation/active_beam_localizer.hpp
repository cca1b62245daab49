#pragma once
/// \file
/// \brief The single rotating beam behind the Localizer2D interface (thesis ch. 4), for logs: of
/// every scan it keeps the one reading along the beam's current bearing, updates the VDT EKF with
/// it (n = 1: a 2-element innovation), turns the beam by its angular velocity over the scan
/// interval, and chooses the next goal segment (4.1) when the sweep reaches the current one.
/// `vdtnav localize --method active-ekf` / `passive-ekf` (settings: localizer_factory.hpp).

#include <memory>
#include <string>

#include "vdtnav/estimation/active_beam.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"

namespace vdtnav {

/// \brief Options of ActiveBeamLocalizer.
struct ActiveBeamLocalizerOptions {
  /// The filter: the VDT EKF with one reading per update (min_inliers 1, no window search).
  /// Its sensor.map_sigma, the per-reading floor, should be the map's wall roughness
  /// (measure_surface_roughness(occupancy).floor; make_localizer sets it when < 0).
  VdtEkfOptions ekf = one_reading_ekf();
  /// The sensor: Table 4.3's (270 degrees at 0.1745 rad/s, 23 segments, 0.5-30 m) by default;
  /// beam.gate refuses a reading the ray cast from the prediction disagrees with.
  RotatingBeamOptions beam = RotatingBeamOptions::table_4_3();
  BeamStrategy strategy = BeamStrategy::kActiveTrace;
  /// Radians: a scan's reading is kept when its bearing is within this of the beam's (the nearest
  /// one; 1 degree by default, a real scanner's spacing or finer); none, no update (prediction).
  double bearing_tolerance = 0.0175;

  [[nodiscard]] static VdtEkfOptions one_reading_ekf() {
    VdtEkfOptions o;
    o.min_inliers = 1;
    o.search.enabled = false;
    return o;
  }
};

/// \brief Localization with one reading per scan (see the file comment).
class ActiveBeamLocalizer final : public Localizer2D {
 public:
  /// \param map must outlive the localizer.
  ActiveBeamLocalizer(const VdtMap2& map, const ActiveBeamLocalizerOptions& options,
                      std::string name);
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return name_; }
  /// \brief The beam's bearing (robot frame) for the next scan.
  [[nodiscard]] double bearing() const noexcept { return beam_.bearing(); }

 private:
  ActiveBeamLocalizerOptions options_;
  VdtEkfLocalizer ekf_;
  ActiveBeamSelector selector_;
  RotatingBeamController beam_;
  std::string name_;
  Pose2 pose_ = Pose2::Zero();  ///< the last estimate and its covariance (the gate's prediction)
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Identity();
};

}  // namespace vdtnav
