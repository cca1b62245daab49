#pragma once
/// \file
/// \brief Lost detection and recovery around the sequential 3D localizer
/// (VdtOptimizationLocalizer3), the template 2D recovery uses (RecoveringLocalizerT<3>): the window
/// test of lost_detection.hpp reports kLost, and while lost the tracker re-acquires on lost scans
/// 1, 2, 4, 8 and then every 16th: first with the attitude grid of its multi-start around the
/// prediction (~0.5-1 s on a VLP-16 scan), then, while the scan is still unexplained there and
/// options.global_recovery is on, by global localization over the whole map
/// (global_localization3d.hpp, options.global; roll and pitch from the IMU when the odometry
/// carries them, else the track's; 0.1-0.3 s on CATEC, its pyramid built at the first loss). A
/// pose the search accepts (explained, not ambiguous) is adopted at once. The update time stays
/// bounded when the robot is lost for good.
///
/// Where it differs from 2D (recovering_localizer.hpp's Reacquisition says why): a scan is weighed
/// by scan_agreement.hpp's 3D classification — a reading the map does not explain contradicts
/// the pose only when its beam passed through a surface of the map (a point-cloud map says where
/// surfaces are, not where space is free), else it is unknown: on MulRan's Riverside (the map
/// from the odd keyframes) right poses are contradicted by 0.19-0.39 of the readings judged
/// (0.56 and 0.90 at the two scans the map lacks), poses 5 m off by 0.77 or more, where counting
/// every unexplained reading put right poses at 0.43-0.97 and flagged 43 % of the run lost
/// (issue 57); a found pose is adopted on one scan, not verified over several
/// (a VLP-16 scan of ~2000 readings decides what a 2D scan's window does, and the search refuses
/// ambiguous places itself); doubt comes from the rise above the track's own windows or from one
/// scan contradicted at the lost level (VdtLocalizer3Options::lost), not from 2D's absolute level;
/// a pose in doubt is refused as in 2D, and on doubted scans 1, 2, 4, 8, then every 16th the
/// global search runs, its pose adopted when it explains 0.2 more of the scan than the track (a
/// generated room's robot carried 5 m: found on the first scan after, where the window alone
/// reported it lost 6 scans after); and every scan enters the window (a voxelized 3D scan keeps
/// hundreds of readings).

#include <memory>

#include "vdtnav/estimation/recovering_localizer.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"

namespace vdtnav {

/// \brief A VdtOptimizationLocalizer3 with lost detection and recovery (names "vdt-opt-6dof",
/// "vdt-opt-4dof"); options.lost is the window test's.
class RecoveringLocalizer3 final : public RecoveringLocalizerT<3> {
 public:
  /// \throws ConfigError for invalid options. The map must outlive the localizer.
  RecoveringLocalizer3(const VdtField3& map,
                       const VdtLocalizer3Options& options = vdt_localizer3_defaults());
  /// \brief As above sharing `shared`'s coarse levels (same map): both modes built once.
  RecoveringLocalizer3(const VdtOptimizer3& shared, const VdtLocalizer3Options& options);

  /// \return the tracker (its optimizer, with_held_attitude()).
  [[nodiscard]] const VdtOptimizationLocalizer3& tracker() const noexcept { return *tracker_; }

 private:
  explicit RecoveringLocalizer3(VdtOptimizationLocalizer3* tracker);  // owns it
  const VdtOptimizationLocalizer3* tracker_;                          // owned by the base
};

}  // namespace vdtnav
