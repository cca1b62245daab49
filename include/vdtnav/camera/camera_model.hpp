#pragma once
/// \file
/// \brief A calibrated pinhole camera with Brown-Conrady lens distortion (OpenCV's model and
/// conventions: pixel (u, v) with v down, camera frame x right, y down, z forward; integer pixel
/// coordinates are pixel centres), and the calibration files users have: the YAML that OpenCV's
/// calibration writes (`camera_matrix`, `distortion_coefficients`, `image_width`, `image_height`)
/// and ROS `camera_info` YAML.
///
/// Component vdtnav::camera: the camera sensor model that both camera front ends (uav_camera,
/// rgbd_ground) share, so that neither links the other. It is a component of its own rather than
/// part of vdtnav::sensor because it needs OpenCV (calib3d's undistortion as the fallback of
/// undistort(), FileStorage for OpenCV's XML calibrations), which the range sensor models and
/// everything that links them (estimation, mapping, io, sim) must not.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace vdtnav::camera {

/// \brief Intrinsics and distortion of one camera.
struct CameraCalibration {
  int width = 0;                                                ///< image width, pixels
  int height = 0;                                               ///< image height, pixels
  Eigen::Matrix3d camera_matrix = Eigen::Matrix3d::Identity();  ///< K = [fx 0 cx; 0 fy cy; 0 0 1]
  /// OpenCV order (k1, k2, p1, p2[, k3]); empty or all zero: no distortion.
  std::vector<double> distortion;
};

/// \brief Reads a calibration file: OpenCV's FileStorage YAML/XML (camera_matrix as an
/// opencv-matrix) or a ROS camera_info YAML (camera_matrix: {rows, cols, data}). The YAML files
/// of both kinds are read by yaml-cpp (the keys are the same; OpenCV's "%YAML:1.0" directive and
/// !!opencv-matrix tags are passed over), XML by OpenCV.
/// \throws IoError when the file cannot be read, FormatError (file and what was expected) when a
/// key is missing or malformed, or the values are not a usable camera (fx, fy <= 0, size <= 0).
[[nodiscard]] CameraCalibration read_calibration(const std::string& path);

/// \brief Writes `calibration` in OpenCV's FileStorage YAML (what read_calibration reads back).
void write_opencv_calibration(const std::string& path, const CameraCalibration& calibration);

/// \brief Projection and undistortion with one calibration.
class PinholeCamera {
 public:
  /// \throws ConfigError for an unusable calibration.
  explicit PinholeCamera(CameraCalibration calibration);

  [[nodiscard]] const CameraCalibration& calibration() const noexcept { return calibration_; }
  [[nodiscard]] int width() const noexcept { return calibration_.width; }
  [[nodiscard]] int height() const noexcept { return calibration_.height; }

  /// \brief Distorted pixels -> undistorted normalized coordinates (x/z, y/z) of their rays, by
  /// cv::undistortPoints (only these points, never the whole image).
  [[nodiscard]] std::vector<Eigen::Vector2d> undistort(
      const std::vector<Eigen::Vector2d>& pixels) const;

  /// \brief Normalized coordinates (x/z, y/z) -> distorted pixel; with `jacobian`, also
  /// d pixel / d normalized (2 x 2, analytic).
  [[nodiscard]] Eigen::Vector2d distort(const Eigen::Vector2d& normalized,
                                        Eigen::Matrix2d* jacobian = nullptr) const;

 private:
  CameraCalibration calibration_;
};

}  // namespace vdtnav::camera
