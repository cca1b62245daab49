#include "parse.hpp"

#include <cmath>
#include <cstdlib>

#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {

namespace {

/// Three comma-separated numbers (strtod, each consuming its whole field), or false.
bool parse_three(const std::string& text, Eigen::Vector3d& out) {
  std::size_t begin = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = text.find(',', begin);
    if ((k < 2) != (comma != std::string::npos)) return false;  // exactly two commas
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

}  // namespace

Pose2 parse_pose(const std::string& text, const std::string& what) {
  Pose2 p;
  if (!parse_three(text, p) || !p.allFinite()) {
    throw ConfigError(what + ": expected x,y,yaw (metres, metres, radians), got '" + text + "'");
  }
  p[2] = wrap_angle(p[2]);
  return p;
}

Eigen::Vector3d parse_sigmas(const std::string& text, const std::string& what) {
  Eigen::Vector3d s;
  if (!parse_three(text, s) || !s.allFinite() || (s.array() < 0.0).any()) {
    throw ConfigError(what +
                      ": expected three standard deviations sx,sy,syaw, finite and >= 0 "
                      "(metres, metres, radians), got '" +
                      text + "'");
  }
  return s;
}

}  // namespace vdtnav::tools
