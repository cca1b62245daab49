#pragma once
/// \file
/// \brief The pose of one 3D scan with no prior on a 3D VDT map, dense or sparse: branch and
/// bound over (x, y, z, yaw), roll and pitch from gravity (an IMU, or level), then the 3D
/// optimizer — the 2D search of global_localization.hpp in one more dimension.
///
/// The score of a pose is the truncated VCD  S = sum_i min(D(c + o_i)^2, tau^2)  of N readings,
/// D = |DT_v| at the centres of a search grid of edge h over the map (the map's cells, or coarser:
/// at least 0.1 m, since the readings' offsets are rounded to a cell anyway), c the sensor's cell,
/// o_i = round(R p_i / h) the reading's cell offset at R = Rz(yaw) Ry(pitch) Rx(roll). Headings
/// are taken in steps for which the scan's far readings (its 90th-percentile range r90) move by
/// about a cell. Over a cube of 2^k x 2^k x 2^k sensor cells the smallest D an endpoint can have
/// is the minimum of D over a 2^k window of the grid: a pyramid of min-pooled grids (one byte a
/// cell, min(D^2, tau^2) quantized downwards, so that a bound stays a bound), built once per map,
/// makes  LB = sum_i M_k(c + o_i)  an exact lower bound of S over the cube (D is 1-Lipschitz; the
/// pooling is its tightest form on the grid). Cubes are expanded best-first after a greedy descent
/// that gives an upper bound: the first leaf popped is the best cell-and-heading pose of the whole
/// map, and the leaves popped after it come in order of score — the distinct ones among them are
/// the alternatives. The best few are refined by the 6-DOF optimizer (its coarse levels); the
/// result is refused when the refined best leaves the scan unexplained or when a distinct
/// alternative explains it as well (a building with repeated rooms: the ambiguity is reported,
/// not guessed).
///
/// The sensor is placed where the map's surfaces are at least `clearance` away and, when given,
/// between min_z and max_z (a ground robot's sensor height: the search is then over a slab).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav {

struct GlobalLocalization3Options {
  /// tau, metres: a reading farther than this from the map counts tau^2 (unexplained).
  double truncation = 0.3;
  /// Readings scored, evenly over the scan's (the refinement uses them all).
  int max_readings = 200;
  /// The search grid's edge, metres; <= 0: the map's resolution, at least 0.1 m, and coarse
  /// enough for at most 2^25 cells over the map's box (a sparse map of a building).
  double resolution = 0.0;
  /// Radians between headings; <= 0: h / r90, clamped into [0.5, 3] degrees.
  double angular_step = -1.0;
  /// The coarsest cube is 2^levels cells on a side; < 0: about 3.2 m.
  int levels = -1;
  /// Metres: the sensor is not placed nearer the map's surfaces than this.
  double clearance = 0.2;
  /// The sensor heights searched (map frame, metres); NaN (the default): no bound.
  double min_z = std::numeric_limits<double>::quiet_NaN();
  double max_z = std::numeric_limits<double>::quiet_NaN();
  /// Distinct candidates refined by the optimizer (the best and its alternatives).
  int candidates = 6;
  /// Two poses are distinct when this far apart (metres) or this much turned in yaw (radians).
  double distinct_distance = 1.0;
  double distinct_angle = 0.5;
  /// Alternatives are looked for among leaves scoring at most best + this fraction of N tau^2.
  double alternative_margin = 0.1;
  /// Cubes scored at most; a search that reaches it stops with the leaves it has (the result
  /// says so: exhausted) and decides on them.
  std::size_t max_nodes = 4000000;
  /// A reading is explained when its disparity is below this (metres).
  double explained_distance = 0.1;
  /// The refined best must explain this fraction of the scan, else kRefused.
  double accept_fraction = 0.75;
  /// Ambiguous when a distinct refined alternative explains at least the best's fraction less
  /// this (and passes accept_fraction itself).
  double ambiguity_margin = 0.05;
  /// The refinement (6-DOF, with the coarse levels): the tracker's optimizer, whose map-error
  /// model makes the covariance (`vdtnav localize3d` passes its settings' vdt_opt).
  VdtOptimizerOptions optimizer;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief What a 3D global localization found.
struct GlobalLocalization3Result {
  /// The refined best pose and covariance; status kConverged when accepted (also when the
  /// refinement stopped at its iteration limit: it explains the scan), kRefused when the scan is
  /// unexplained or the pose ambiguous, kTooFewObservations for a scan without readings.
  LocalizationResult3 result;
  bool ambiguous = false;
  bool exhausted = false;           ///< the search stopped at max_nodes
  std::vector<Pose3> alternatives;  ///< distinct refined poses that explain the scan as well
  double explained = 0.0;           ///< fraction of the scan the best explains
  std::size_t nodes = 0;            ///< cubes scored
  std::size_t headings = 0;         ///< yaw steps over the turn
  /// The best cell-and-heading pose of the search (before refinement) and its score
  /// sum_i min(D_i^2, tau^2) over the scored readings (quantized as the pyramid is).
  Pose3 best_leaf = Pose3::Identity();
  double best_leaf_score = 0.0;
  double search_seconds = 0.0;  ///< wall time of the branch and bound
  double seconds = 0.0;         ///< wall time of the search and the refinement
};

/// \brief Global localization on one 3D map (see the file comment). Thread-compatible:
/// localize() is const.
class GlobalLocalizer3 {
 public:
  /// \param map must outlive the localizer.
  /// \throws ConfigError for bad options, or a search grid of more than 2^31 cells.
  explicit GlobalLocalizer3(const VdtField3& map, const GlobalLocalization3Options& options = {});

  /// \brief Branch and bound with the sensor's roll and pitch given (radians, R = Rz Ry Rx as
  /// pose3_from_xyz_rpy): from gravity, or 0 for a level sensor; the refinement frees them.
  [[nodiscard]] GlobalLocalization3Result localize(const ObservationSet3& scan, double roll = 0.0,
                                                   double pitch = 0.0) const;

  [[nodiscard]] const GlobalLocalization3Options& options() const noexcept { return options_; }
  [[nodiscard]] const VdtOptimizer3& optimizer() const noexcept { return optimizer_; }
  /// \return the search grid (edge h, cells per axis).
  [[nodiscard]] const GridFrame<3>& search_frame() const noexcept { return frame_; }
  [[nodiscard]] const Eigen::Vector3i& search_size() const noexcept { return size_; }
  /// \return the cells where the sensor may be placed.
  [[nodiscard]] std::size_t free_cells() const noexcept { return free_cells_; }
  /// \return the pyramid's levels above the finest (the coarsest cube has 2^levels() cells).
  [[nodiscard]] int levels() const noexcept { return levels_; }

 private:
  struct Node;
  /// The bound of cube (level, b) with the heading's offsets, quantized; stops summing (returning
  /// a value above it) once past stop_at.
  [[nodiscard]] std::uint32_t bound(int level, const Eigen::Vector3i& b,
                                    const std::vector<Eigen::Vector3i>& offsets,
                                    std::uint32_t stop_at) const;
  [[nodiscard]] bool free(int level, const Eigen::Vector3i& b) const;
  [[nodiscard]] std::size_t linear(const Eigen::Vector3i& c) const {
    return static_cast<std::size_t>(c.x()) +
           static_cast<std::size_t>(size_.x()) *
               (static_cast<std::size_t>(c.y()) +
                static_cast<std::size_t>(size_.y()) * static_cast<std::size_t>(c.z()));
  }

  const VdtField3* map_;
  GlobalLocalization3Options options_;
  VdtOptimizer3 optimizer_;
  GridFrame<3> frame_;
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  int levels_ = 0;
  /// pooled_[k](c) = min over the 2^k cube from c of q(D^2) = floor(255 min(D^2, tau^2) / tau^2)
  /// (cells outside the map: 255); free_[k](c) = whether the cube holds a cell the sensor may
  /// occupy.
  std::vector<std::vector<std::uint8_t>> pooled_;
  std::vector<std::vector<std::uint8_t>> free_;
  std::size_t free_cells_ = 0;
};

}  // namespace vdtnav
