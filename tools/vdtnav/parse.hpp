#pragma once
/// \file
/// \brief The text options of `vdtnav` that are not plain numbers: a pose `x,y,yaw` and the
/// standard deviations `sx,sy,syaw` of an initial pose.

#include <string>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"

namespace vdtnav::tools {

/// \brief Parses "x,y,yaw" (metres, metres, radians; finite); yaw is wrapped to (-pi, pi].
/// \throws ConfigError naming `what` and the text.
[[nodiscard]] Pose2 parse_pose(const std::string& text, const std::string& what);

/// \brief Parses "sx,sy,syaw", three standard deviations (metres, metres, radians): finite and
/// >= 0, and not wrapped (a yaw sigma of 2 pi stays 2 pi).
/// \throws ConfigError naming `what`, the text and what was expected.
[[nodiscard]] Eigen::Vector3d parse_sigmas(const std::string& text, const std::string& what);

}  // namespace vdtnav::tools
