#pragma once
/// \file
/// \brief The observations the VDT estimators use, in any dimension (SPEC: points in the robot
/// frame with the range noise that produced them). A front end turns its readings into one: a
/// planar LiDAR scan (scan_points(), laser_scan.hpp), a pan-tilt point laser's sweep, ...

#include <cstddef>
#include <vector>

#include "vdtnav/core/traits.hpp"

namespace vdtnav {

/// \brief Range readings as robot-frame points, with the direction each moves along when its
/// range changes (aliases ScanPoints for 2D, ObservationSet3 for 3D).
///
/// Reading i with range r_i ends at p_i in the robot frame and dp_i/dr_i = directions[i]; for a
/// beam from a fixed origin o_i (after the mounting/calibration transform) along the unit
/// direction u_i, p_i = o_i + r_i u_i and dp_i/dr_i = u_i.
template <int Dim>
struct ObservationSet {
  using Vector = typename SpaceTraits<Dim>::Vector;

  std::vector<Vector> points;            ///< endpoints, robot frame
  std::vector<Vector> directions;        ///< dp/dr (unit beam directions), robot frame
  std::vector<double> ranges;            ///< the ranges kept
  std::vector<std::size_t> beam;         ///< index of each kept reading in the source
  double sigma_range = 0.0;              ///< range noise standard deviation, metres
  std::size_t dropped_not_finite = 0;    ///< NaN or inf readings
  std::size_t dropped_out_of_range = 0;  ///< outside the sensor's valid range interval

  [[nodiscard]] std::size_t size() const noexcept { return points.size(); }

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
    out.dropped_not_finite = dropped_not_finite;
    out.dropped_out_of_range = dropped_out_of_range;
    if (step == 0) step = 1;
    for (std::size_t i = 0; i < size(); i += step) {
      out.points.push_back(points[i]);
      out.directions.push_back(directions[i]);
      out.ranges.push_back(ranges[i]);
      out.beam.push_back(beam[i]);
    }
    return out;
  }
};

using ObservationSet2 = ObservationSet<2>;
using ObservationSet3 = ObservationSet<3>;

}  // namespace vdtnav
