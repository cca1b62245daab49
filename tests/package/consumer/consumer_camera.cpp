// A user's program against the installed vdtnav::camera: a calibration written, read back, and a
// distorted pixel undistorted to the ray it came from.
#include <vdtnav/camera/camera_model.hpp>

#include <cmath>
#include <cstdio>

int main(int argc, char** argv) {
  using namespace vdtnav::camera;
  if (argc < 2) return 2;
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 500, 0, 319.5, 0, 500, 239.5, 0, 0, 1;
  c.distortion = {-0.2, 0.05, 0.001, -0.001, 0.0};
  write_opencv_calibration(argv[1], c);
  const PinholeCamera camera(read_calibration(argv[1]));
  const Eigen::Vector2d ray(0.3, -0.2);  // x/z, y/z
  const Eigen::Vector2d pixel = camera.distort(ray);
  const Eigen::Vector2d back = camera.undistort({pixel}).at(0);
  // Without distortion the pixel would be (469.5, 139.5); the barrel distortion pulls it in.
  const bool ok = (back - ray).norm() < 1e-6 && pixel.x() < 469.5 && pixel.x() > 400.0;
  std::printf("pixel (%g, %g), ray back (%g, %g): %s\n", pixel.x(), pixel.y(), back.x(), back.y(),
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
