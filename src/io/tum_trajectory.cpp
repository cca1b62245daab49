#include "vdtnav/io/tum_trajectory.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>

namespace vdtnav {
namespace {

constexpr std::size_t kFields = 8;
constexpr std::array<const char*, kFields> kNames = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};

/// Splits on spaces and tabs (a '\r' counts as space); at most kFields + 1 fields.
std::size_t split(std::string_view line, std::array<std::string_view, kFields + 1>& out) {
  std::size_t n = 0, i = 0;
  while (i < line.size() && n < out.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out[n++] = line.substr(start, i - start);
  }
  return n;
}

bool parse_double(std::string_view s, double& v) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// \return an empty string and the pose, or what was expected.
std::string parse_line(std::string_view line, StampedPose3& out) {
  std::array<std::string_view, kFields + 1> f;
  const std::size_t n = split(line, f);
  if (n != kFields) {
    return "expected 8 fields (t x y z qx qy qz qw), found " +
           (n > kFields ? std::string("more than 8") : std::to_string(n));
  }
  std::array<double, kFields> v{};
  for (std::size_t k = 0; k < kFields; ++k) {
    if (!parse_double(f[k], v[k]) || !std::isfinite(v[k])) {
      return std::string(kNames[k]) + ": expected a finite number, got '" + std::string(f[k]) + "'";
    }
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

/// Shortest fixed-point text that reads back as exactly x.
void put(std::string& out, double x) {
  char buf[400];  // fixed notation of the largest double needs 309 digits
  const auto r = std::to_chars(buf, buf + sizeof(buf), x, std::chars_format::fixed);
  out.append(buf, r.ptr);
}

std::string line_of(double t, const Eigen::Vector3d& p, Eigen::Quaterniond q) {
  VDTNAV_CHECK(std::isfinite(t) && p.allFinite() && q.coeffs().allFinite(),
               "tum_line: the time and pose must be finite");
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // q and -q are the same attitude; TUM uses qw >= 0
  std::string out;
  put(out, t);
  for (const double x : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()}) {
    out += ' ';
    put(out, x);
  }
  return out;
}

}  // namespace

TumTrajectory load_tum_trajectory(const std::string& path, const TumOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open TUM trajectory: " + std::strerror(errno));
  TumTrajectory file;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    StampedPose3 pose;
    const std::string error = parse_line(line, pose);
    if (error.empty()) {
      file.poses.push_back(pose);
    } else if (options.skip_malformed) {
      file.malformed_lines.push_back(line_no);
    } else {
      throw FormatError(path, line_no, error);
    }
  }
  if (in.bad()) throw IoError(path + ": cannot read TUM trajectory");
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
  std::ofstream file(path, std::ios::binary);
  if (!file) throw IoError(path + ": cannot open for writing: " + std::strerror(errno));
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  if (!file.flush()) throw IoError(path + ": write failed");
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
