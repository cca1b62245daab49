#pragma once
/// \file
/// \brief The noise of an RGB-D reading: z-depth noise growing with the square of the depth, as
/// structured-light (triangulation: sigma_z ~ z^2 sigma_disparity / (f b)) and time-of-flight
/// sensors show it, and the pixel noise of an edge's location.

namespace vdtnav::rgbd_ground {

/// \brief sigma_z(z) = sigma_z0 + sigma_z2 z^2 (metres), pixel noise sigma_pixel (pixels).
/// Defaults: a Kinect-v1-class structured-light sensor, sigma_z2 = 1.4e-3 / m (Khoshelham and
/// Elberink 2012: 1.5 mm at 1 m, 4 cm at 5 m); an edge located to half a pixel.
struct DepthNoiseModel {
  double sigma_z0 = 0.0;
  double sigma_z2 = 1.4e-3;
  double sigma_pixel = 0.5;
  [[nodiscard]] double sigma_z(double z) const { return sigma_z0 + sigma_z2 * z * z; }
};

}  // namespace vdtnav::rgbd_ground
