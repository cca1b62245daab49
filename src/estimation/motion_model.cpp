#include "vdtnav/estimation/motion_model.hpp"

#include <cmath>

namespace vdtnav {

void ekf_predict(MotionModelKind kind, const MotionNoise& noise, const OdometryStep& odo, Pose2& x,
                 Eigen::Matrix3d& p, Eigen::Matrix3d* jacobian) {
  const double c = std::cos(x[2]), s = std::sin(x[2]);
  if (kind == MotionModelKind::kVelocity) {
    const double dt = odo.dt;
    Eigen::Matrix3d gx = Eigen::Matrix3d::Identity();  // (3.9)
    gx(0, 2) = -dt * odo.v * s;
    gx(1, 2) = dt * odo.v * c;
    Eigen::Matrix<double, 3, 2> gu = Eigen::Matrix<double, 3, 2>::Zero();  // (3.10)
    gu(0, 0) = dt * c;
    gu(1, 0) = dt * s;
    gu(2, 1) = dt;
    const Eigen::Vector2d q(noise.sigma_v * noise.sigma_v, noise.sigma_w * noise.sigma_w);
    x = Pose2(x[0] + dt * odo.v * c, x[1] + dt * odo.v * s,
              wrap_angle(x[2] + dt * odo.w));                            // (3.7)
    p = gx * p * gx.transpose() + gu * q.asDiagonal() * gu.transpose();  // (3.8)
    if (jacobian != nullptr) *jacobian = gx;
    // Random-walk floor: variance grows linearly with time.
    p.diagonal() += dt * Eigen::Vector3d(noise.floor_xy_rate * noise.floor_xy_rate,
                                         noise.floor_xy_rate * noise.floor_xy_rate,
                                         noise.floor_yaw_rate * noise.floor_yaw_rate);
  } else {
    const Pose2& d = odo.delta;
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();  // d(x (+) d)/dx
    f(0, 2) = -s * d[0] - c * d[1];
    f(1, 2) = c * d[0] - s * d[1];
    Eigen::Matrix3d g = Eigen::Matrix3d::Identity();  // d(x (+) d)/dd
    g(0, 0) = c;
    g(0, 1) = -s;
    g(1, 0) = s;
    g(1, 1) = c;
    const double t = std::hypot(d[0], d[1]), rot = std::abs(d[2]);
    const double st = noise.a_tt * t + noise.a_tr * rot + noise.floor_t;
    const double sr = noise.a_rr * rot + noise.a_rt * t + noise.floor_r;
    const Eigen::Vector3d q(st * st, st * st, sr * sr);
    x = compose(x, d);
    p = f * p * f.transpose() + g * q.asDiagonal() * g.transpose();
    if (jacobian != nullptr) *jacobian = f;
  }
  p = 0.5 * (p + p.transpose());
}

}  // namespace vdtnav
