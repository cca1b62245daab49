#include "vdtnav/uav_camera/ground_projection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include <Eigen/LU>

namespace vdtnav::uav_camera {
namespace {

/// [v]x, the cross-product matrix.
Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

double altitude(const AttitudeReading& attitude, const UavRig& rig) {
  const Eigen::Vector3d hit = rig.laser_origin + attitude.laser_range * rig.laser_direction;
  return -(level_from_body(attitude.roll, attitude.pitch) * hit).z();
}

std::string check_attitude(const AttitudeReading& a, const UavRig& rig) {
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  const auto not_finite = [](const char* what, double v) {
    return std::string(what) + (std::isnan(v) ? " is NaN" : " is infinite");
  };
  if (!std::isfinite(a.roll)) return not_finite("roll", a.roll);
  if (!std::isfinite(a.pitch)) return not_finite("pitch", a.pitch);
  if (!std::isfinite(a.laser_range)) return not_finite("laser range", a.laser_range);
  if (std::abs(a.roll) >= kMaxTilt) {
    return "roll " + number(a.roll * kDeg) + " deg: expected |roll| < 80 deg";
  }
  if (std::abs(a.pitch) >= kMaxTilt) {
    return "pitch " + number(a.pitch * kDeg) + " deg: expected |pitch| < 80 deg";
  }
  if (!(a.laser_range > 0.0)) return "laser range " + number(a.laser_range) + " m: expected > 0";
  const double h = altitude(a, rig);
  if (!(h > 0.0)) return "altitude " + number(h) + " m: expected > 0";
  return {};
}

// Ground projection (replaces (3.22)). Level frame L: origin on the ground below the body, z up.
// With R = R_lb = Ry(pitch) Rx(roll), the camera pose in the body (R_bc, t_bc) and the laser
// (origin o, unit direction u, range r) hitting the ground:
//   altitude     h = -e_z^T R (o + r u)
//   camera       c = h e_z + R t_bc
//   ray          d = R m,  m = R_bc (x_n, y_n, 1)^T          (pinhole: K^-1 [u v 1]^T, undistorted)
//   ground hit   X = c + s d,  s = -c_z / d_z  (X_z = 0; valid for d_z < 0, s > 0)
//   point        p = X_xy = c_xy - (c_z / d_z) d_xy
// Derivatives: for any parameter a, with c' = dc/da and d' = dd/da, the hit moves by
// w = c' + s d' plus d ds/da, and ds/da keeps X_z = 0:  dp/da = w_xy - (w_z / d_z) d_xy.
//   x_n, y_n:   c' = 0,  d' = R R_bc e_{x,y}
//   roll:       R' = R [e_x]x,  h' = -e_z^T R' (o + r u),  c' = h' e_z + R' t_bc,  d' = R' m
//   pitch:      R' = [e_y]x R,  likewise
//   range:      h' = -e_z^T R u,  c' = h' e_z,  d' = 0
// Level camera at altitude h with the default rig: m = (-y_n, -x_n, -1), p = (-h y_n, -h x_n).
GroundPoint project_to_ground(const Eigen::Vector2d& normalized, const AttitudeReading& a,
                              const UavRig& rig) {
  GroundPoint g;
  const Eigen::Matrix3d r = level_from_body(a.roll, a.pitch);
  const Eigen::Matrix3d& r_bc = rig.body_from_camera.linear();
  const Eigen::Vector3d t_bc = rig.body_from_camera.translation();
  const Eigen::Vector3d laser = rig.laser_origin + a.laser_range * rig.laser_direction;
  const double h = -(r * laser).z();
  const Eigen::Vector3d c = h * Eigen::Vector3d::UnitZ() + r * t_bc;
  const Eigen::Vector3d m = r_bc * Eigen::Vector3d(normalized.x(), normalized.y(), 1.0);
  const Eigen::Vector3d d = r * m;
  if (!(d.z() < 0.0) || !(h > 0.0)) return g;
  const double s = -c.z() / d.z();
  if (!(s > 0.0) || !(s * d.norm() < kMaxRayLengthOverAltitude * h)) return g;
  g.p = (c + s * d).head<2>();
  g.valid = true;

  const auto dp = [&](const Eigen::Vector3d& dc, const Eigen::Vector3d& dd) -> Eigen::Vector2d {
    const Eigen::Vector3d w = dc + s * dd;
    return w.head<2>() - (w.z() / d.z()) * d.head<2>();
  };
  const Eigen::Matrix3d rr = r * r_bc;
  g.d_normalized.col(0) = dp(Eigen::Vector3d::Zero(), rr.col(0));
  g.d_normalized.col(1) = dp(Eigen::Vector3d::Zero(), rr.col(1));

  const Eigen::Matrix3d r_roll = r * skew(Eigen::Vector3d::UnitX());
  const Eigen::Matrix3d r_pitch = skew(Eigen::Vector3d::UnitY()) * r;
  const double h_roll = -(r_roll * laser).z();
  const double h_pitch = -(r_pitch * laser).z();
  const double h_range = -(r * rig.laser_direction).z();
  g.d_attitude.col(0) = dp(h_roll * Eigen::Vector3d::UnitZ() + r_roll * t_bc, r_roll * m);
  g.d_attitude.col(1) = dp(h_pitch * Eigen::Vector3d::UnitZ() + r_pitch * t_bc, r_pitch * m);
  g.d_attitude.col(2) = dp(h_range * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero());
  return g;
}

ObservationSet2 ground_observations(const std::vector<Eigen::Vector2d>& edge_pixels,
                                    const PinholeCamera& camera, const UavRig& rig,
                                    const AttitudeReading& attitude,
                                    const GroundProjectionNoise& noise) {
  ObservationSet2 out;
  out.sigma_range = 0.0;
  out.shared_covariance =
      Eigen::Vector3d(noise.sigma_roll * noise.sigma_roll, noise.sigma_pitch * noise.sigma_pitch,
                      noise.sigma_laser_range * noise.sigma_laser_range)
          .asDiagonal();
  if (!check_attitude(attitude, rig).empty()) {
    const bool nan = !std::isfinite(attitude.roll) || !std::isfinite(attitude.pitch) ||
                     !std::isfinite(attitude.laser_range);
    (nan ? out.dropped_not_finite : out.dropped_out_of_range) = edge_pixels.size();
    return out;
  }
  out.points.reserve(edge_pixels.size());
  out.directions.reserve(edge_pixels.size());
  out.ranges.reserve(edge_pixels.size());
  out.beam.reserve(edge_pixels.size());
  out.point_covariances.reserve(edge_pixels.size());
  out.shared_jacobians.reserve(edge_pixels.size());

  const std::vector<Eigen::Vector2d> normalized = camera.undistort(edge_pixels);
  const double var_pixel = noise.sigma_pixel * noise.sigma_pixel;
  for (std::size_t i = 0; i < edge_pixels.size(); ++i) {
    if (!edge_pixels[i].allFinite() || !normalized[i].allFinite()) {
      ++out.dropped_not_finite;
      continue;
    }
    const GroundPoint g = project_to_ground(normalized[i], attitude, rig);
    if (!g.valid) {
      ++out.dropped_out_of_range;
      continue;
    }
    // d normalized / d pixel is the inverse of the distortion's Jacobian at this point.
    Eigen::Matrix2d j_distort;
    (void)camera.distort(normalized[i], &j_distort);
    const Eigen::Matrix2d a = g.d_normalized * j_distort.inverse();
    const Eigen::Matrix2d cov = var_pixel * a * a.transpose();
    const ObservationSet2::SharedJacobian jac = g.d_attitude;
    out.add_point(g.p, cov, i, &jac);
  }
  if (noise.sigma_correlated > 0.0 && noise.correlation_length > 0.0 && out.size() > 0) {
    // Effective sample size of the correlated errors: n points in one square count as one.
    std::vector<std::int64_t> key(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto cx =
          static_cast<std::int64_t>(std::floor(out.points[i].x() / noise.correlation_length));
      const auto cy =
          static_cast<std::int64_t>(std::floor(out.points[i].y() / noise.correlation_length));
      key[i] = (cx + (1 << 20)) * (1 << 21) + (cy + (1 << 20));
    }
    std::vector<std::int64_t> sorted = key;
    std::sort(sorted.begin(), sorted.end());
    const double s2 = noise.sigma_correlated * noise.sigma_correlated;
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto range = std::equal_range(sorted.begin(), sorted.end(), key[i]);
      const double n = static_cast<double>(range.second - range.first);
      out.point_covariances[i].diagonal().array() += n * s2;
    }
  }
  return out;
}

}  // namespace vdtnav::uav_camera
