#pragma once
/// \file
/// \brief A bag's transforms (/tf, /tf_static, or an Odometry topic read as odom -> base), asked
/// for one frame in another at a stamp, interpolated — tf2's BufferCore behind a ROS-free
/// interface. Frame names lose a leading '/' (ROS 1's "/laser" is "laser"), as tf2 does.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

/// \brief Transforms over a time span, answered by interpolation (tf2::BufferCore).
class TransformBuffer {
 public:
  /// \param span_seconds how far back transforms are kept (a bag's duration, and more).
  explicit TransformBuffer(double span_seconds = 3600.0);
  ~TransformBuffer();
  TransformBuffer(TransformBuffer&&) noexcept;
  TransformBuffer& operator=(TransformBuffer&&) noexcept;

  /// \brief Adds a transform (static ones hold at every time).
  void add(const TransformStampedMsg& t, bool is_static);
  void add(const TfMsg& tf, bool is_static);
  /// \brief Adds an odometry message as header.frame_id -> child_frame_id.
  void add(const OdometryMsg& odom);

  /// \return whether `child`'s pose in `parent` is known at stamp_ns (interpolated; a static
  /// chain at any time).
  [[nodiscard]] bool can_lookup(const std::string& parent, const std::string& child,
                                std::int64_t stamp_ns) const;
  /// \return the pose of `child` in `parent` at stamp_ns; throws ConfigError naming both frames,
  /// the stamp and the frames the buffer holds (with their parents) when it is not known.
  [[nodiscard]] Pose3 lookup(const std::string& parent, const std::string& child,
                             std::int64_t stamp_ns) const;
  /// \return the latest stamp at which `child`'s pose in `parent` is known (a static chain: 0);
  /// none when the frames are not connected.
  [[nodiscard]] std::optional<std::int64_t> latest_stamp(const std::string& parent,
                                                         const std::string& child) const;
  /// \return whether the two frames are connected at all (at some time).
  [[nodiscard]] bool connected(const std::string& parent, const std::string& child) const;

  /// \return every frame with its parent ("" for a root), sorted by frame name.
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> frames() const;
  /// \return frames() as "child <- parent" lines, for error messages.
  [[nodiscard]] std::string describe() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// \return the frame id without a leading '/'.
[[nodiscard]] std::string strip_slash(const std::string& frame);

/// \return a transform message's pose as an isometry.
[[nodiscard]] Pose3 to_pose3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);

}  // namespace vdtnav::ros
