#pragma once
/// \file
/// \brief The UAV downward camera front end of Dataset 3 (thesis 3.4.3) in one call: an image and
/// the IMU/laser readings of its instant in, robot-frame ground points with their noise out
/// (edge_extraction.hpp, then ground_projection.hpp). The estimators never see the image.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/uav_camera/camera_model.hpp"
#include "vdtnav/uav_camera/edge_extraction.hpp"
#include "vdtnav/uav_camera/ground_projection.hpp"
#include "vdtnav/uav_camera/uav_rig.hpp"

namespace vdtnav::uav_camera {

/// \brief Settings of the front end.
struct UavCameraOptions {
  EdgeOptions edges;            ///< edge extraction and subsampling
  GroundProjectionNoise noise;  ///< pixel, IMU and laser noise
};

/// \brief What the front end makes of one frame.
struct CameraFrame {
  std::vector<Eigen::Vector2d> edges;  ///< edge pixels kept (distorted image coordinates)
  ObservationSet2 observations;        ///< their ground points, level frame (uav_rig.hpp)
  /// Empty, or why the frame gives no observation (an unusable attitude: check_attitude()).
  std::string rejected;
};

/// \brief Image + attitude -> ground observations.
class UavCameraFrontEnd {
 public:
  /// \throws ConfigError for an unusable calibration.
  UavCameraFrontEnd(const CameraCalibration& calibration, const UavRig& rig,
                    const UavCameraOptions& options = {});

  /// \brief Edges of `image`, projected to the ground with `attitude`. An unusable attitude
  /// (NaN, tilt beyond 80 degrees, non-positive laser range or altitude) gives no observation and
  /// says why in CameraFrame::rejected; the localizers then report kTooFewObservations.
  /// \throws ConfigError when the image's size is not the calibration's (the wrong camera or a
  /// resized stream: every projection would be silently wrong).
  [[nodiscard]] CameraFrame observe(const cv::Mat& image, const AttitudeReading& attitude) const;

  [[nodiscard]] const PinholeCamera& camera() const noexcept { return camera_; }
  [[nodiscard]] const UavRig& rig() const noexcept { return rig_; }
  [[nodiscard]] const UavCameraOptions& options() const noexcept { return options_; }

 private:
  PinholeCamera camera_;
  UavRig rig_;
  UavCameraOptions options_;
};

}  // namespace vdtnav::uav_camera
