#pragma once
/// \file
/// \brief Trajectories in the TUM RGB-D benchmark format (Sturm et al., IROS 2012): one pose a
/// line, `t x y z qx qy qz qw` (time in seconds, position in metres, the attitude as a unit
/// quaternion, scalar last), `#` comments. The format the evo and TUM evaluation tools read.

#include <cstddef>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief A 3D pose with the time it holds at.
struct StampedPose3 {
  double t = 0.0;                  ///< seconds
  Pose3 pose = Pose3::Identity();  ///< attitude R and position t
};

/// \brief How a TUM trajectory is read.
struct TumOptions {
  /// false: a malformed line throws FormatError. true: it is skipped and its line number
  /// recorded in TumTrajectory::malformed_lines.
  bool skip_malformed = false;
};

/// \brief The content of a TUM trajectory file.
struct TumTrajectory {
  std::vector<StampedPose3> poses;           ///< in file order
  std::vector<std::size_t> malformed_lines;  ///< 1-based lines skipped with skip_malformed
};

/// \brief Tolerance on the norm of a quaternion read: |(qx, qy, qz, qw)| must be 1 within it
/// (files written with 6 decimals are that far off); the quaternion is then normalised.
inline constexpr double kTumQuaternionNormTolerance = 1e-3;

/// \brief Loads a TUM trajectory.
///
/// Blank lines and lines starting with `#` are ignored. A line is malformed unless it has
/// exactly 8 finite numbers with a quaternion whose norm is 1 within kTumQuaternionNormTolerance.
/// \throws IoError when the file cannot be read.
/// \throws FormatError (`file:line: what was expected`) for the first malformed line unless
///         options.skip_malformed.
[[nodiscard]] TumTrajectory load_tum_trajectory(const std::string& path,
                                                const TumOptions& options = {});

/// \brief One TUM line (without the newline) for a stamped pose: every number in the shortest
/// fixed-point form that reads back as the same double (time and position exactly; the
/// quaternion of R, with qw >= 0, to the last bit of its components).
/// \throws ConfigError when the time or the pose is not finite.
[[nodiscard]] std::string tum_line(const StampedPose3& pose);

/// \brief As tum_line(const StampedPose3&) for a planar pose: z = 0 and the yaw quaternion
/// (0, 0, sin(yaw/2), cos(yaw/2)), qw >= 0.
[[nodiscard]] std::string tum_line(double t, const Pose2& pose);

/// \brief Writes a trajectory, one tum_line() a line. load_tum_trajectory() returns the times and
/// positions bit for bit and each rotation matrix to within a few ulps (< 4e-15 per entry: the
/// matrix -> quaternion -> matrix rounding).
/// \throws ConfigError when a time or pose is not finite.
/// \throws IoError when the file cannot be written.
void save_tum_trajectory(const std::string& path, const std::vector<StampedPose3>& poses);

/// \return the 3D pose of a planar pose: (x, y, 0) and the rotation by yaw about z.
[[nodiscard]] Pose3 pose3_from_pose2(const Pose2& pose);

/// \return the planar pose (x, y, yaw) of a 3D pose, yaw = atan2(R10, R00) (the yaw of the ZYX
/// angles); z, roll and pitch are dropped.
[[nodiscard]] Pose2 pose2_from_pose3(const Pose3& pose);

}  // namespace vdtnav
