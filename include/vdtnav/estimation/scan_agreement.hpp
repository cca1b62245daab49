#pragma once
/// \file
/// \brief Whether a map agrees with a scan at a pose: each reading is explained, contradicted, or
/// about a place the map does not know — the evidence lost detection weighs.
///
/// A reading is
///  - **explained** when its disparity |d_i| (2.12) at the pose is below `explained_distance`
///    (an inlier of the gate (3.3)): the map has a surface where the beam ended;
///  - **contradicted** when the map says the beam cannot have ended there: its segment from the
///    sensor crosses an occupied cell more than `margin` before the endpoint (the map has a wall
///    the beam went through), or it ends in a cell the map knows to be free (nothing there);
///  - **unknown** otherwise: it ends where the map knows nothing (MapKnowledge: unknown cells,
///    outside the map) without crossing a wall.
///
/// The contradiction C / (E + C) of the readings the map can judge is what tells a wrong pose from
/// a map that lacks the place. Measured at the reference poses of real logs (Intel, its map from
/// the log's last third and from its odd scans; MIT Killian from its odd scans) a right pose's
/// five-scan window is contradicted by at most 0.22-0.39 (people, doors, clutter the map lacks;
/// p99 0.19-0.29), while the scan placed at another scan's pose is contradicted by 0.65 or more
/// in 99 % of windows — and the explained fraction alone cannot tell: in the rooms the Intel
/// study's map lacks, right poses explain as little as 27 % of a scan.
///
/// Walls are found on the VDT map's own cells (the stored nearest occupied cell of each cell: a
/// march along the beam in steps of the distance it may safely skip), so that the test sees the
/// surfaces the localizer matches against.

#include <cmath>
#include <cstddef>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief The thresholds of the classification.
struct ScanAgreementOptions {
  /// A reading whose disparity is below this is explained (metres).
  double explained_distance = 0.1;
  /// A wall crossed within this of the endpoint (or of the sensor) is not a contradiction: the
  /// beam grazes the surface it ends on, or the map has a mapping ghost under the robot (metres;
  /// < 0: 2 explained_distance + one map cell).
  double margin = -1.0;
  /// Readings classified, evenly over the scan (0: all).
  int max_readings = 0;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief The readings of one scan by class (see the file comment).
struct ScanAgreement {
  int readings = 0;      ///< classified
  int explained = 0;     ///< E
  int contradicted = 0;  ///< C
  int unknown = 0;       ///< readings - E - C

  /// \return E / readings (0 for no readings): the explained fraction.
  [[nodiscard]] double explained_fraction() const noexcept {
    return readings > 0 ? static_cast<double>(explained) / readings : 0.0;
  }
  /// \return E + C, the readings the map can judge.
  [[nodiscard]] int judged() const noexcept { return explained + contradicted; }
  /// \return C / (E + C) (0 when the map judges none).
  [[nodiscard]] double contradiction() const noexcept {
    return judged() > 0 ? static_cast<double>(contradicted) / judged() : 0.0;
  }
  /// \return `readings` readings of which the fraction `explained` is explained and every other
  /// one contradicted: a map without unknown space, where what the map does not explain it
  /// contradicts (how 3D scans were weighed until issue 57; tests' stand-ins still use it).
  [[nodiscard]] static ScanAgreement all_judged(int readings, double explained) noexcept {
    ScanAgreement a;
    a.readings = readings;
    a.explained = static_cast<int>(std::lround(explained * readings));
    a.contradicted = readings - a.explained;
    return a;
  }
  ScanAgreement& operator+=(const ScanAgreement& o) noexcept {
    readings += o.readings;
    explained += o.explained;
    contradicted += o.contradicted;
    unknown += o.unknown;
    return *this;
  }
  ScanAgreement& operator-=(const ScanAgreement& o) noexcept {
    readings -= o.readings;
    explained -= o.explained;
    contradicted -= o.contradicted;
    unknown -= o.unknown;
    return *this;
  }
};

/// \brief Classifies the readings of `scan` at `pose` (see the file comment).
/// \param model the sensor model on `map` (its disparities and gate decide "explained").
/// \param knowledge where `map` knows what is there (default-constructed: everywhere inside it).
[[nodiscard]] ScanAgreement scan_agreement(const VdtSensorModel& model, const VdtMap2& map,
                                           const MapKnowledge& knowledge, const ScanPoints& scan,
                                           const Pose2& pose,
                                           const ScanAgreementOptions& options = {});

/// \brief Classifies the readings of a 3D scan at `pose` on a 3D map (the file comment without
/// MapKnowledge: a point-cloud map says where surfaces are, not where space is free, so a reading
/// the map does not explain is contradicted only when its segment passes through a surface of the
/// map, else unknown — the map lacks the place, or the thing the beam hit). Readings without a
/// range (points, not beams) are explained or unknown.
[[nodiscard]] ScanAgreement scan_agreement(const VdtSensorModel3& model,
                                           const ObservationSet3& scan, const Pose3& pose,
                                           const ScanAgreementOptions& options = {});

/// \return the distance along the unit direction `dir` from `origin` at which the segment first
/// passes through a surface of `field` — comes within a voxel of a surface voxel's centre and
/// then, before `to`, more than `out` from every surface or out of the map — searched from
/// `from` by sphere tracing on |DT_v| (steps of |DT_v| less a voxel's diagonal and a voxel, at
/// least half a voxel); +inf when it passes through none (it grazes or ends on the surface it
/// reaches, or leaves the map without coming near one). scan_agreement() takes out = 2
/// max(explained_distance, a voxel).
[[nodiscard]] double first_surface_crossing(const VdtField3& field, const Eigen::Vector3d& origin,
                                            const Eigen::Vector3d& dir, double from, double to,
                                            double out);

/// \return the distance along the unit direction `dir` from `origin` at which the segment first
/// enters an occupied cell of `map`, searched over [from, to]; +inf when it enters none (or
/// leaves the map first).
[[nodiscard]] double first_occupied_crossing(const VdtMap2& map, const Eigen::Vector2d& origin,
                                             const Eigen::Vector2d& dir, double from, double to);

}  // namespace vdtnav
