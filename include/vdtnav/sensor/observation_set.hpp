#pragma once
/// \file
/// \brief The observations the VDT estimators use, in any dimension (SPEC: points in the robot
/// frame with the range noise that produced them). A front end turns its readings into one: a
/// planar LiDAR scan (scan_points(), laser_scan.hpp), a pan-tilt point laser's sweep, ...

#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/traits.hpp"

namespace vdtnav {

/// \brief Observations as robot-frame points with their noise (aliases ScanPoints for 2D,
/// ObservationSet3 for 3D).
///
/// Range readings: reading i with range r_i ends at p_i in the robot frame and
/// dp_i/dr_i = directions[i]; for a beam from a fixed origin o_i (after the mounting/calibration
/// transform) along the unit direction u_i, p_i = o_i + r_i u_i and dp_i/dr_i = u_i, and the
/// point's covariance is sigma_range^2 u_i u_i^T.
///
/// Points from other sensors (a camera's edge pixels projected to the ground) carry a full
/// covariance each (point_covariances) and may share errors: every point of a camera frame moves
/// with the same roll, pitch and altitude error theta, p_i(theta) ~ p_i + G_i theta with
/// G_i = shared_jacobians[i] and cov(theta) = shared_covariance. Such errors are not independent
/// per point; the estimators carry them as one common-mode term (vdt_optimizer.hpp, vdt_ekf.hpp).
template <int Dim>
struct ObservationSet {
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  /// Most shared error parameters a set can carry (fixed so that G_i needs no heap).
  static constexpr int kMaxShared = 6;
  using SharedJacobian = Eigen::Matrix<double, Dim, Eigen::Dynamic, 0, Dim, kMaxShared>;

  std::vector<Vector> points;      ///< endpoints, robot frame
  std::vector<Vector> directions;  ///< dp/dr (unit beam directions), robot frame
  std::vector<double> ranges;      ///< the ranges kept
  std::vector<std::size_t> beam;   ///< index of each kept reading in the source
  /// Seconds after the scan's stamp at which each reading was taken (a spinning LiDAR's sweep);
  /// empty: the readings are simultaneous (deskewing: sweep_motion.hpp).
  std::vector<double> times;
  double sigma_range = 0.0;  ///< range noise standard deviation, metres
  double range_max = std::numeric_limits<double>::infinity();  ///< sensor's no-return range, m
  std::size_t dropped_not_finite = 0;                          ///< NaN or inf readings
  std::size_t dropped_out_of_range = 0;  ///< outside the sensor's valid range interval
  /// Per-point covariance, robot frame; empty: sigma_range^2 u_i u_i^T (range readings).
  std::vector<Matrix> point_covariances;
  /// dp_i/dtheta of the errors theta every point shares; empty: none (see above).
  std::vector<SharedJacobian> shared_jacobians;
  Eigen::MatrixXd shared_covariance;  ///< cov(theta), k x k

  [[nodiscard]] std::size_t size() const noexcept { return points.size(); }
  /// \return the number k of shared error parameters (0: none).
  [[nodiscard]] int num_shared() const noexcept {
    return shared_jacobians.empty() ? 0 : static_cast<int>(shared_covariance.rows());
  }
  /// \return the covariance of point i (robot frame).
  [[nodiscard]] Matrix point_covariance(std::size_t i) const {
    if (!point_covariances.empty()) return point_covariances[i];
    return (sigma_range * sigma_range) * directions[i] * directions[i].transpose();
  }

  /// \brief Appends point `index` at p (robot frame) with covariance `cov` and, if the set has
  /// shared errors, its Jacobian g = dp/dtheta (no range: direction and range are zero).
  void add_point(const Vector& p, const Matrix& cov, std::size_t index,
                 const SharedJacobian* g = nullptr) {
    points.push_back(p);
    directions.push_back(Vector::Zero());
    ranges.push_back(0.0);
    beam.push_back(index);
    point_covariances.push_back(cov);
    if (g != nullptr) shared_jacobians.push_back(*g);
  }

  /// \brief Appends reading `index` of range r along the unit direction u from origin o (robot
  /// frame), after the caller checked that r is valid.
  void add(const Vector& origin, const Vector& u, double r, std::size_t index) {
    points.push_back(origin + r * u);
    directions.push_back(u);
    ranges.push_back(r);
    beam.push_back(index);
  }

  /// \brief Keeps every `step`-th observation (starting with the first), e.g. the thesis's
  /// downsampling of the 5700-point cloud by 2, 5, 10 and 100.
  [[nodiscard]] ObservationSet subsampled(std::size_t step) const {
    ObservationSet out;
    out.sigma_range = sigma_range;
    out.range_max = range_max;
    out.dropped_not_finite = dropped_not_finite;
    out.dropped_out_of_range = dropped_out_of_range;
    out.shared_covariance = shared_covariance;
    if (step == 0) step = 1;
    for (std::size_t i = 0; i < size(); i += step) {
      out.points.push_back(points[i]);
      out.directions.push_back(directions[i]);
      out.ranges.push_back(ranges[i]);
      out.beam.push_back(beam[i]);
      if (!times.empty()) out.times.push_back(times[i]);
      if (!point_covariances.empty()) out.point_covariances.push_back(point_covariances[i]);
      if (!shared_jacobians.empty()) out.shared_jacobians.push_back(shared_jacobians[i]);
    }
    return out;
  }
};

using ObservationSet2 = ObservationSet<2>;
using ObservationSet3 = ObservationSet<3>;

}  // namespace vdtnav
