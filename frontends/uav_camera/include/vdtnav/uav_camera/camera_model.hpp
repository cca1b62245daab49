#pragma once
/// \file
/// \brief The camera model under its earlier name: it moved to vdtnav::camera
/// (vdtnav/camera/camera_model.hpp), shared by both camera front ends; these names stay for the
/// code written against vdtnav::uav_camera.

#include "vdtnav/camera/camera_model.hpp"

namespace vdtnav::uav_camera {
using camera::CameraCalibration;
using camera::PinholeCamera;
using camera::read_calibration;
using camera::write_opencv_calibration;
}  // namespace vdtnav::uav_camera
