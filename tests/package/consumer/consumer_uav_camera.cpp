// A user's program against the installed vdtnav::uav_camera: a calibration file written and read
// back, and one image through the front end to ground points on the ground where they belong.
#include <vdtnav/uav_camera/camera_model.hpp>
#include <vdtnav/uav_camera/uav_camera_front_end.hpp>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>

int main(int argc, char** argv) {
  using namespace vdtnav;
  if (argc < 2) return 2;
  uav_camera::CameraCalibration c;
  c.width = 320;
  c.height = 240;
  c.camera_matrix << 300, 0, 159.5, 0, 300, 119.5, 0, 0, 1;
  uav_camera::write_opencv_calibration(argv[1], c);
  const uav_camera::UavCameraFrontEnd front(uav_camera::read_calibration(argv[1]),
                                            uav_camera::UavRig{});
  // A white vertical bar on grey: its two edges are image columns 100 and 140.
  cv::Mat img(240, 320, CV_8UC1, cv::Scalar(60));
  cv::rectangle(img, cv::Rect(100, 0, 40, 240), cv::Scalar(220), cv::FILLED);
  uav_camera::AttitudeReading level;
  level.laser_range = 10.0;
  const uav_camera::CameraFrame f = front.observe(img, level);
  // Level camera, default rig: column u lies at body y = -10 (u - 159.5) / 300 on the ground.
  int on_edges = 0;
  for (const auto& p : f.observations.points) {
    const double u = 159.5 - p.y() * 30.0;
    on_edges += (std::abs(u - 99.5) < 1.5 || std::abs(u - 139.5) < 1.5) ? 1 : 0;
  }
  const bool ok =
      f.observations.size() > 100 && on_edges == static_cast<int>(f.observations.size());
  std::printf("%zu ground points, %d on the bar's edges: %s\n", f.observations.size(), on_edges,
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
