// The 3D half of scan_agreement.hpp: a reading the map does not explain is contradicted when its
// segment passes through a surface of the map (a point-cloud map has no free space to end in).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "scan_scores.hpp"
#include "vdtnav/estimation/scan_agreement.hpp"

namespace vdtnav {

double first_surface_crossing(const VdtField3& field, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& dir, double from, double to, double out) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double h = field.resolution();
  // Within a voxel of a surface voxel's centre: a beam through a voxel passes within half its
  // diagonal of the centre.
  const double near = h;
  // |DT_v| interpolates the distance to the nearest surface voxel's centre to within about a
  // voxel's diagonal: a step of |DT_v| - sqrt(3) h - near never passes within `near` of one it did
  // not see. Half a voxel at least. (A sparse map's coarse level, far from every surface, may
  // overstate the distance by up to a brick's diagonal: a step there may then skip a surface, so
  // that a crossing is missed, never invented.)
  //
  // A crossing is a passage: the beam comes within `near` of a surface and then, still before
  // `to`, gets more than `out` from every surface — through the surface and out the other side
  // (or deep into a solid, or out of the map). A beam that grazes a surface and ends on or just
  // below it (a distant reading of the ground at a few degrees of incidence, near it for metres)
  // does not pass.
  const double slack = std::sqrt(3.0) * h + near, fine = 0.5 * h;
  double entered = kInf;
  for (double t = std::max(from, 0.0); t <= to;) {
    bool inside = false;
    const double d = field.value(origin + t * dir, &inside).norm();
    if (!inside) return entered;  // out of the map: through the surface it came near, if any
    if (std::isinf(entered)) {
      if (d < near) entered = t;
    } else if (d > out) {
      return entered;
    }
    t += std::isinf(entered) ? std::max(fine, d - slack) : fine;
  }
  return kInf;
}

ScanAgreement scan_agreement(const VdtSensorModel3& model, const ObservationSet3& scan,
                             const Pose3& pose, const ScanAgreementOptions& options) {
  ScanAgreement a;
  if (scan.size() == 0) return a;
  thread_local std::vector<int> subset;  // scratch: no allocation per scan
  thread_local std::vector<BeamDisparity3> ds;
  const Eigen::Matrix3d r = pose.linear();
  const Eigen::Vector3d t = pose.translation();
  detail::agreement_disparities(model, scan, r, t, options.max_readings, &subset, &ds);
  const std::size_t want = subset.size();
  const VdtField3& field = model.map();
  const double d2 = options.explained_distance * options.explained_distance;
  const double margin = options.margin >= 0.0
                            ? options.margin
                            : 2.0 * options.explained_distance + field.resolution();
  // Out the other side: twice as far from every surface as an explained reading may be (and
  // two voxels at least).
  const double out = 2.0 * std::max(options.explained_distance, field.resolution());
  for (std::size_t k = 0; k < want; ++k) {
    ++a.readings;
    const BeamDisparity3& b = ds[k];
    if (b.inlier && b.d.squaredNorm() < d2) {
      ++a.explained;
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(subset[k]);
    const double range = scan.ranges[i];
    if (!(range > 2.0 * margin)) {  // a point without a beam, or a beam too short to judge
      ++a.unknown;
      continue;
    }
    const Eigen::Vector3d dir = r * scan.directions[i];
    const Eigen::Vector3d origin = t + r * scan.points[i] - range * dir;
    // Through a surface: the map says the beam would have stopped before.
    if (std::isfinite(first_surface_crossing(field, origin, dir, margin, range - margin, out))) {
      ++a.contradicted;
    } else {
      ++a.unknown;
    }
  }
  return a;
}

}  // namespace vdtnav
