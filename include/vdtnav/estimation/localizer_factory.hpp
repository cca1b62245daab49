#pragma once
/// \file
/// \brief Every 2D localizer by its table name ("vdt-opt", "vdt-ekf", "udt-opt", "udt-ekf",
/// "pf", "active-ekf", "passive-ekf"), so that command-line tools and studies run them side by
/// side on the same data.

#include <memory>
#include <string>
#include <vector>

#include "vdtnav/estimation/active_beam_localizer.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/particle_filter.hpp"
#include "vdtnav/estimation/recovering_localizer.hpp"
#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {

/// \brief The options of each method; a factory call uses the one its method needs. Its values
/// are vdtnav's one set of defaults, for maps drawn from real scans and clouds: those of the
/// localizers' constructors (vdt_opt_defaults(), vdt_ekf_defaults(), udt_defaults(),
/// vdt_localizer3_defaults()), of `vdtnav localize` and `localize3d` (what `--print-config`
/// prints), of the Python module and of the ROS node. exact_map_settings(): the thesis's solver
/// on an exact map (the generated studies').
struct LocalizerSettings {
  VdtOptimizerOptions vdt_opt = vdt_opt_defaults(2);
  VdtEkfOptions vdt_ekf = vdt_ekf_defaults();
  UdtOptions udt = udt_defaults();
  ParticleFilterOptions pf;
  /// One reading per scan along a rotating beam (thesis ch. 4): pointed by goal selection (4.1);
  /// the prediction from odometry increments.
  ActiveBeamLocalizerOptions active_ekf = on_odometry(ActiveBeamLocalizerOptions{});
  /// The same sensor kept at the robot's heading (or turning blindly: strategy passive-rotate).
  ActiveBeamLocalizerOptions passive_ekf = on_odometry(passive_beam());
  /// Global localization (`vdtnav localize --init global`); its refinement uses vdt_opt.
  GlobalLocalizationOptions global;
  /// Lost detection and re-acquisition (kidnapped robot) around vdt-opt and vdt-ekf; the
  /// acquisitions use `global` (refined with vdt_opt).
  RecoveryOptions recovery;
  /// The sequential 3D localizer of `vdtnav localize3d` (settings section localize3d:).
  VdtLocalizer3Options localize3d = vdt_localizer3_defaults();
  /// Threads of the work that runs in parallel (`threads:`, top level; 0: the machine's cores):
  /// the commands apply it with set_threads() (core/parallel.hpp) unless `--threads` is given.
  /// Results are the same for any count.
  int threads = 0;

  [[nodiscard]] static ActiveBeamLocalizerOptions passive_beam() {
    ActiveBeamLocalizerOptions o;
    o.strategy = BeamStrategy::kPassiveFixed;
    return o;
  }
  [[nodiscard]] static ActiveBeamLocalizerOptions on_odometry(ActiveBeamLocalizerOptions o) {
    o.ekf.motion = MotionModelKind::kOdometryIncrement;
    return o;
  }
};

/// \brief The defaults, LocalizerSettings{}, by name: real logs localized on a map built from
/// scans (`vdtnav localize`, the Intel study): odometry-increment motion models for the filters,
/// and for vdt-opt a Cauchy loss (scale 0.05 m) against what the map lacks or misplaces, the
/// window search on every scan explained below 95 %, and up to 50 solver iterations. On the Intel
/// log this takes the Kuemmerle error from 0.068 m / 1.4 deg (exact_map_settings()) to
/// 0.030 m / 0.48 deg. The map is one drawn from scans: vdt-opt and vdt-ekf consider the map
/// errors shared by the readings of each 2 m square, with the map builder's pose error at half a
/// cell (VdtSensorModelOptions::map_correlation_length, map_pose_sigma): relation NEES on the
/// Intel log 4.86 (mean), against 81 without. Lost detection and recovery keep their defaults:
/// they weigh what the map contradicts, not what it lacks (lost_detection.hpp), so that a map
/// drawn from part of a run needs no settings of its own; pass the map's unknown cells
/// (make_localizer's `knowledge`) so that scans into places it lacks are not held against it.
[[nodiscard]] LocalizerSettings log_settings();

/// \brief The thesis's localizers on an exact map (a generated floor plan or room, whose walls
/// are where the map says): each options struct's own values, no robust loss, 25 iterations, no
/// map-error correlation, the velocity motion model. The generated studies (Table 3.3, the
/// simulated runs) and the tests on generated maps use these.
[[nodiscard]] LocalizerSettings exact_map_settings();

/// \brief Settings for 3D LiDAR scans on a map drawn from real scans or clouds (the `vdtnav
/// localize3d` defaults; its --config keys go over them): vdt-opt with a Cauchy loss (scale
/// 0.05 m) against what the map lacks or misplaces, up to 50 iterations, and a covariance that
/// counts the map's own errors: shared by the readings of each 1 m cube, with the map builder's
/// pose error at half a voxel (map_correlation_length, map_pose_sigma), and scaled by the a
/// posteriori variance factor when the residuals are larger than that model says. On
/// libpointmatcher's real car pair (map of one scan, the other localized at 0.1 m) the pose lands
/// 0.8 cm / 0.16 deg and 1.6 cm / 0.15 deg from the reference, both ways, with NEES 13 and 14
/// against it (chi^2_6 95 %: 1.24-14.4); the plain defaults give 3 cm from a reference start
/// with NEES 223.
[[nodiscard]] LocalizerSettings cloud_settings();

/// \return the method names make_localizer() knows, in table order.
[[nodiscard]] const std::vector<std::string>& localizer_methods();

/// \brief A localizer by name. The VDT methods use `vdt`, the UDT methods and the particle filter
/// the occupancy grid it was built from; both must outlive the localizer. vdt-opt and vdt-ekf
/// come inside a RecoveringLocalizer (lost detection, re-acquisition) unless
/// settings.recovery.detect is off; the baselines (udt-*, pf) and the single-beam filters, whose
/// one reading per scan says nothing about being lost, do not. `knowledge`: the map's unknown
/// cells (MapKnowledge(ros_map.cells)), for the lost test; default: everything inside the map is
/// known (a floor plan). `settings` default: the defaults, those of `vdtnav localize`.
/// \throws ConfigError for an unknown method (the message lists the known ones).
[[nodiscard]] std::unique_ptr<Localizer2D> make_localizer(const std::string& method,
                                                          const VdtMap2& vdt,
                                                          const OccupancyGrid<2>& occupancy,
                                                          const LocalizerSettings& settings = {},
                                                          const MapKnowledge& knowledge = {});

}  // namespace vdtnav
