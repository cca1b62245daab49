#pragma once
/// \file
/// \brief The text options of `vdtnav` that are not plain numbers: a pose `x,y,yaw` and the
/// standard deviations `sx,sy,syaw` of an initial pose; a 3D pose `x,y,z,roll,pitch,yaw` or a
/// 4x4 matrix file.

#include <string>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav::tools {

/// \brief Parses "x,y,yaw" (metres, metres, radians; finite); yaw is wrapped to (-pi, pi].
/// \throws UsageError naming `what` and the text.
[[nodiscard]] Pose2 parse_pose(const std::string& text, const std::string& what);

/// \brief Parses "sx,sy,syaw", three standard deviations (metres, metres, radians): finite and
/// >= 0, and not wrapped (a yaw sigma of 2 pi stays 2 pi).
/// \throws UsageError naming `what`, the text and what was expected.
[[nodiscard]] Eigen::Vector3d parse_sigmas(const std::string& text, const std::string& what);

/// \brief Parses "x,y,z,roll,pitch,yaw" (metres, radians; finite) as R = Rz(yaw) Ry(pitch)
/// Rx(roll). \throws UsageError naming `what` and the text.
[[nodiscard]] Pose3 parse_pose3(const std::string& text, const std::string& what);

/// \brief Reads a 4x4 rigid transform, 16 numbers row by row, separated by blanks, commas or
/// brackets ('#' starts a comment): [R t; 0 0 0 1] with R a rotation within 1e-4 (made exactly
/// one). \throws IoError (cannot open), FormatError (file:line: what was expected).
[[nodiscard]] Pose3 read_pose_matrix(const std::string& path);

}  // namespace vdtnav::tools
