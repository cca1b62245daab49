#include "parse.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include <cerrno>
#include <cstring>

#include "exit_status.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {

namespace {

/// N comma-separated numbers (strtod, each consuming its whole field), or false.
template <int N>
bool parse_numbers(const std::string& text, Eigen::Matrix<double, N, 1>& out) {
  std::size_t begin = 0;
  for (int k = 0; k < N; ++k) {
    const std::size_t comma = text.find(',', begin);
    if ((k < N - 1) != (comma != std::string::npos)) return false;  // exactly N - 1 commas
    const std::string field =
        text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    char* end = nullptr;
    out[k] = std::strtod(field.c_str(), &end);
    if (field.empty() || end == field.c_str()) return false;
    while (*end == ' ' || *end == '\t') ++end;
    if (*end != '\0') return false;
    begin = comma + 1;
  }
  return true;
}

bool parse_three(const std::string& text, Eigen::Vector3d& out) {
  return parse_numbers<3>(text, out);
}

}  // namespace

Pose2 parse_pose(const std::string& text, const std::string& what) {
  Pose2 p;
  if (!parse_three(text, p) || !p.allFinite()) {
    throw UsageError(what + ": expected x,y,yaw (metres, metres, radians), got '" + text + "'");
  }
  p[2] = wrap_angle(p[2]);
  return p;
}

Eigen::Vector3d parse_sigmas(const std::string& text, const std::string& what) {
  Eigen::Vector3d s;
  if (!parse_three(text, s) || !s.allFinite() || (s.array() < 0.0).any()) {
    throw UsageError(what +
                     ": expected three standard deviations sx,sy,syaw, finite and >= 0 "
                     "(metres, metres, radians), got '" +
                     text + "'");
  }
  return s;
}

Pose3 parse_pose3(const std::string& text, const std::string& what) {
  Eigen::Matrix<double, 6, 1> v;
  if (!parse_numbers<6>(text, v) || !v.allFinite()) {
    throw UsageError(what +
                     ": expected x,y,z,roll,pitch,yaw (metres and radians, R = Rz(yaw) "
                     "Ry(pitch) Rx(roll)), got '" +
                     text + "'");
  }
  return pose3_from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5]);
}

Pose3 read_pose_matrix(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the 4x4 pose matrix: " + std::strerror(errno));
  std::vector<double> v;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    for (char& c : line) c = (c == ',' || c == ';' || c == '[' || c == ']') ? ' ' : c;
    std::istringstream fields(line);
    std::string field;
    while (fields >> field) {
      char* end = nullptr;
      const double x = std::strtod(field.c_str(), &end);
      if (end == field.c_str() || *end != '\0' || !std::isfinite(x)) {
        throw FormatError(
            path, line_no,
            "expected 16 finite numbers (a 4x4 matrix, row by row), got '" + field + "'");
      }
      if (v.size() == 16)
        throw FormatError(path, line_no, "expected 16 numbers (a 4x4 matrix), found more");
      v.push_back(x);
    }
  }
  if (v.size() != 16) {
    throw FormatError(
        path, line_no,
        "expected 16 numbers (a 4x4 matrix, row by row), found " + std::to_string(v.size()));
  }
  const Eigen::Matrix4d m =
      Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw FormatError(path, 0, "expected a last row 0 0 0 1 (a rigid transform)");
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (off > 1e-4 || r.determinant() < 0.0) {
    throw FormatError(path, 0,
                      "expected a rotation in the top-left 3x3 block (R^T R = I within 1e-4, "
                      "det R = +1); R^T R is off by " +
                          std::to_string(off));
  }
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();  // the nearest rotation
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

}  // namespace vdtnav::tools
