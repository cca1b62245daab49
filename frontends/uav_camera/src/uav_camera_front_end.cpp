#include "vdtnav/uav_camera/uav_camera_front_end.hpp"

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {

UavCameraFrontEnd::UavCameraFrontEnd(const CameraCalibration& calibration, const UavRig& rig,
                                     const UavCameraOptions& options)
    : camera_(calibration), rig_(rig), options_(options) {}

CameraFrame UavCameraFrontEnd::observe(const cv::Mat& image,
                                       const AttitudeReading& attitude) const {
  VDTNAV_CHECK(image.cols == camera_.width() && image.rows == camera_.height(),
               "UAV camera: image is " + std::to_string(image.cols) + "x" +
                   std::to_string(image.rows) + ", expected the calibration's " +
                   std::to_string(camera_.width()) + "x" + std::to_string(camera_.height()));
  CameraFrame frame;
  frame.rejected = check_attitude(attitude, rig_);
  frame.edges = extract_edges(image, options_.edges);
  frame.observations = ground_observations(frame.edges, camera_, rig_, attitude, options_.noise);
  return frame;
}

}  // namespace vdtnav::uav_camera
