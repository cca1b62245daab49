#pragma once
/// \file
/// \brief One RGB-D frame: a colour image and a z-depth image of the same size, registered (the
/// depth of pixel (u, v) is along the optical axis of the colour camera), as a Kinect, RealSense
/// or the TUM RGB-D / ICL-NUIM datasets deliver them.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include <opencv2/core.hpp>

namespace vdtnav::rgbd_ground {

/// \brief Colour (CV_8UC3, BGR) and depth (CV_32F, metres along the optical axis, 0 = no
/// reading) of one instant.
struct RgbdFrame {
  cv::Mat colour;
  cv::Mat depth;
};

/// \brief A frame from images in memory. `depth` is CV_16U in raw units (`depth_scale` units per
/// metre: 5000 for TUM RGB-D and ICL-NUIM, 1000 for millimetres) or CV_32F/CV_64F in metres
/// (`depth_scale` ignored). NaN, inf and negative depths become 0 (no reading).
/// \throws ConfigError when the colour is not 8-bit with 1, 3 or 4 channels, the depth is of
/// another type, the sizes differ, depth_scale <= 0 for raw depth, or no pixel has a depth.
[[nodiscard]] RgbdFrame make_rgbd_frame(const cv::Mat& colour, const cv::Mat& depth,
                                        double depth_scale);

/// \brief Reads a colour image (any format OpenCV reads) and a 16-bit depth PNG/PGM.
/// \throws IoError when a file cannot be read; FormatError (naming the file) when the depth is
/// not 16-bit single-channel, the sizes differ or every depth is 0.
[[nodiscard]] RgbdFrame read_rgbd_frame(const std::string& colour_path,
                                        const std::string& depth_path, double depth_scale);

/// \brief Camera-to-world poses, one "tx ty tz qx qy qz qw" a line (a Hamilton quaternion with
/// the scalar last, as TUM's trajectories without the stamp); blank lines are skipped.
/// \throws IoError when the file cannot be read; FormatError `file:line: expected ...` on a line
/// without 7 finite numbers or with a zero quaternion.
[[nodiscard]] std::vector<Eigen::Isometry3d> read_camera_poses(const std::string& path);

}  // namespace vdtnav::rgbd_ground
