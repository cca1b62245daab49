#include "vdtnav/io/tum_trajectory.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

#include "text_fields.hpp"

namespace vdtnav {
namespace {

constexpr std::size_t kTumFields = 8;
constexpr std::array<const char*, kTumFields> kTumNames = {"t",  "x",  "y",  "z",
                                                           "qx", "qy", "qz", "qw"};

/// \return an empty string and the pose, or what was expected.
std::string parse_tum_line(std::string_view line, StampedPose3& out) {
  std::vector<std::string_view> f;
  std::array<double, kTumFields> v{};
  if (std::string error = io_text::parse_finite_fields(line, kTumNames, f, v); !error.empty()) {
    return error;
  }
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= kTumQuaternionNormTolerance)) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof(buf), norm);
    return "expected a unit quaternion qx qy qz qw (norm 1 within 1e-3), got norm " +
           std::string(buf, r.ptr);
  }
  out.t = v[0];
  out.pose = Pose3::Identity();
  q.coeffs() /= norm;
  out.pose.linear() = q.toRotationMatrix();
  out.pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
  return {};
}

std::string line_of(double t, const Eigen::Vector3d& p, Eigen::Quaterniond q) {
  VDTNAV_CHECK(std::isfinite(t) && p.allFinite() && q.coeffs().allFinite(),
               "tum_line: the time and pose must be finite");
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // q and -q are the same attitude; TUM uses qw >= 0
  std::string out;
  io_text::append_fixed(out, t);
  for (const double x : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()}) {
    out += ' ';
    io_text::append_fixed(out, x);
  }
  return out;
}

}  // namespace

TumTrajectory load_tum_trajectory(const std::string& path, const TumOptions& options) {
  TumTrajectory file;
  io_text::read_data_lines(path, "TUM trajectory", options.skip_malformed, parse_tum_line,
                           file.poses, file.malformed_lines);
  return file;
}

std::string tum_line(const StampedPose3& pose) {
  return line_of(pose.t, pose.pose.translation(), Eigen::Quaterniond(pose.pose.linear()));
}

std::string tum_line(double t, const Pose2& pose) {
  const double half = 0.5 * pose[2];
  return line_of(t, Eigen::Vector3d(pose[0], pose[1], 0.0),
                 Eigen::Quaterniond(std::cos(half), 0.0, 0.0, std::sin(half)));
}

void save_tum_trajectory(const std::string& path, const std::vector<StampedPose3>& poses) {
  std::string out;
  for (const StampedPose3& p : poses) {
    out += tum_line(p);
    out += '\n';
  }
  io_text::write_text_file(path, out);
}

Pose3 pose3_from_pose2(const Pose2& pose) {
  Pose3 p = Pose3::Identity();
  p.linear() = Eigen::AngleAxisd(pose[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(pose[0], pose[1], 0.0);
  return p;
}

Pose2 pose2_from_pose3(const Pose3& pose) {
  const Eigen::Matrix3d& r = pose.linear();
  return {pose.translation().x(), pose.translation().y(), std::atan2(r(1, 0), r(0, 0))};
}

}  // namespace vdtnav
