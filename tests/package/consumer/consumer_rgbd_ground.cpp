// A user's program against the installed vdtnav::rgbd_ground: a level camera 1 m above a grey
// floor with a green strip; the strip's two edges come back as ground points where they belong.
#include <vdtnav/rgbd_ground/ground_boundaries.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  camera::CameraCalibration c;
  c.width = 320;
  c.height = 240;
  c.camera_matrix << 300, 0, 159.5, 0, 300, 119.5, 0, 0, 1;
  // Camera looking straight down from 1 m (robot x forward = image up, y left = image left).
  Eigen::Isometry3d cam = Eigen::Isometry3d::Identity();
  cam.linear() << 0, -1, 0, -1, 0, 0, 0, 0, -1;
  cam.translation() = Eigen::Vector3d(0, 0, 1);
  cv::Mat colour(240, 320, CV_8UC3, cv::Scalar(128, 128, 128));
  colour.colRange(140, 180).setTo(cv::Scalar(50, 160, 60));  // a green strip, columns 140..179
  const cv::Mat depth(240, 320, CV_32F, cv::Scalar(1.0f));
  rgbd_ground::GroundBoundaryOptions o;
  o.plane.min_inliers = 100;
  const rgbd_ground::GroundBoundaryExtractor ex(camera::PinholeCamera(c), cam, o);
  const rgbd_ground::GroundBoundaries b =
      ex.extract(rgbd_ground::make_rgbd_frame(colour, depth, 1.0));
  // Column u at robot y = -(u - 159.5) / 300 on the ground 1 m below.
  int on_edges = 0;
  for (const auto& p : b.points) {
    const double u = 159.5 - 300.0 * p.robot.y();
    on_edges += (std::abs(u - 139.5) < 2.0 || std::abs(u - 179.5) < 2.0) ? 1 : 0;
  }
  const bool ok =
      b.plane.found && b.points.size() > 50 && on_edges == static_cast<int>(b.points.size());
  std::printf("%zu boundary points, %d on the strip's edges: %s\n", b.points.size(), on_edges,
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
