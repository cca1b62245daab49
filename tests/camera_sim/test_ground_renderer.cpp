// Tests of the ground renderer against independent oracles: OpenCV's projectPoints of known world
// points through the same (distorted) camera pose, the ground sampling distance h / f of a level
// camera, and the statistics of exposure, blur and noise.

#include "vdtnav/camera_sim/ground_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

CameraCalibration distorted_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 520.0, 0.0, 321.3, 0.0, 518.0, 238.7, 0.0, 0.0, 1.0;
  c.distortion = {-0.25, 0.08, 0.0008, -0.0005, 0.0};
  return c;
}

CameraCalibration ideal_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 520.0, 0.0, 320.0, 0.0, 520.0, 240.0, 0.0, 0.0, 1.0;
  return c;
}

// A uniform texture of grey `level`, `size` metres square, centred at the origin.
GroundTexture uniform_texture(double level, double size = 60.0, double res = 0.02) {
  GroundTexture t;
  const int n = static_cast<int>(size / res);
  t.image = cv::Mat(n, n, CV_8UC1, cv::Scalar(level));
  t.resolution = res;
  t.origin = Eigen::Vector2d(-0.5 * size, -0.5 * size);
  t.background = level;
  return t;
}

// Paints the axis-aligned world square [centre +- half] with `level`.
void paint_square(GroundTexture* t, const Eigen::Vector2d& centre, double half, double level) {
  const int c0 =
      std::max(0, static_cast<int>((centre.x() - half - t->origin.x()) / t->resolution) - 1);
  const int c1 = std::min(
      t->image.cols, static_cast<int>((centre.x() + half - t->origin.x()) / t->resolution) + 2);
  const int r0 = std::max(
      0, t->image.rows - 2 - static_cast<int>((centre.y() + half - t->origin.y()) / t->resolution));
  const int r1 = std::min(
      t->image.rows,
      t->image.rows + 1 - static_cast<int>((centre.y() - half - t->origin.y()) / t->resolution));
  for (int r = r0; r < r1; ++r) {
    for (int c = c0; c < c1; ++c) {
      const Eigen::Vector2d p = t->pixel_center(c, r);
      if ((p - centre).cwiseAbs().maxCoeff() <= half) t->image.at<std::uint8_t>(r, c) = level;
    }
  }
}

// OpenCV's own projection of world point x through the camera on the rig at world_from_body.
Eigen::Vector2d project(const CameraCalibration& cal, const UavRig& rig,
                        const Eigen::Isometry3d& world_from_body, const Eigen::Vector3d& x) {
  const Eigen::Isometry3d camera_from_world = (world_from_body * rig.body_from_camera).inverse();
  cv::Mat r, rvec, tvec, k;
  cv::eigen2cv(Eigen::Matrix3d(camera_from_world.linear()), r);
  cv::Rodrigues(r, rvec);
  cv::eigen2cv(Eigen::Vector3d(camera_from_world.translation()), tvec);
  cv::eigen2cv(cal.camera_matrix, k);
  std::vector<cv::Point3d> object{{x.x(), x.y(), x.z()}};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, rvec, tvec, k, cal.distortion, image);
  return {image[0].x, image[0].y};
}

RenderOptions noiseless() {
  RenderOptions o;
  o.noise_sigma = 0.0;
  return o;
}

TEST(GroundRenderer, BrightSquaresLandWhereProjectPointsPutsThem) {
  const CameraCalibration cal = distorted_camera();
  const UavRig rig;
  const GroundRenderer renderer(cal, rig);
  const Eigen::Isometry3d pose = body_pose(1.0, -0.5, 11.0, 3.0 * kDeg, -4.0 * kDeg, 35.0 * kDeg);
  // Squares whose images fall at the centre and near two corners (strong distortion there):
  // their ground positions are found by bisection-free geometry, projectPoints is the oracle.
  GroundTexture texture = uniform_texture(40.0);
  const Eigen::Isometry3d world_from_camera = pose * rig.body_from_camera;
  std::vector<Eigen::Vector2d> squares;
  for (const auto& [u, v] : {std::pair{320, 240}, std::pair{70, 60}, std::pair{580, 430}}) {
    const Eigen::Vector2d n = renderer.ray(u, v);
    const Eigen::Vector3d r = world_from_camera.linear() * Eigen::Vector3d(n.x(), n.y(), 1.0);
    const Eigen::Vector3d c = world_from_camera.translation();
    const Eigen::Vector3d g = c - c.z() / r.z() * r;
    // Round to the texture grid so that the square is exactly centred there.
    squares.emplace_back(std::round(g.x() / 0.02) * 0.02, std::round(g.y() / 0.02) * 0.02);
    paint_square(&texture, squares.back(), 0.24, 240.0);  // edges between texture pixels
  }
  std::mt19937_64 rng(1);
  const cv::Mat image = renderer.render(texture, pose, noiseless(), rng);
  ASSERT_EQ(image.cols, 640);
  ASSERT_EQ(image.rows, 480);
  ASSERT_EQ(image.type(), CV_8UC1);
  for (const Eigen::Vector2d& sq : squares) {
    const Eigen::Vector2d expected = project(cal, rig, pose, Eigen::Vector3d(sq.x(), sq.y(), 0.0));
    double sw = 0.0, su = 0.0, sv = 0.0;
    for (int v = std::max(0, int(expected.y()) - 30); v < std::min(480, int(expected.y()) + 30);
         ++v) {
      for (int u = std::max(0, int(expected.x()) - 30); u < std::min(640, int(expected.x()) + 30);
           ++u) {
        const double w = image.at<std::uint8_t>(v, u) - 40.0;
        sw += w;
        su += w * u;
        sv += w * v;
      }
    }
    ASSERT_GT(sw, 100.0 * 200.0) << "square not rendered near " << expected.transpose();
    const Eigen::Vector2d centroid(su / sw, sv / sw);
    EXPECT_LT((centroid - expected).norm(), 0.5)
        << "centroid " << centroid.transpose() << " vs projectPoints " << expected.transpose();
  }
}

TEST(GroundRenderer, ImageTopIsTheBodyFront) {
  const CameraCalibration cal = ideal_camera();
  const GroundRenderer renderer(cal, UavRig{});
  GroundTexture texture = uniform_texture(40.0);
  paint_square(&texture, {0.0, 3.0}, 0.3, 240.0);  // 3 m ahead of a UAV facing +y (yaw 90 deg)
  std::mt19937_64 rng(1);
  const cv::Mat image =
      renderer.render(texture, body_pose(0.0, 0.0, 10.0, 0.0, 0.0, 90.0 * kDeg), noiseless(), rng);
  const cv::Moments m = cv::moments(image > 128, true);
  ASSERT_GT(m.m00, 50.0);
  EXPECT_NEAR(m.m10 / m.m00, 320.0, 0.6);
  EXPECT_NEAR(m.m01 / m.m00, 240.0 - 3.0 * 520.0 / 10.0, 0.6);  // above the centre
}

TEST(GroundRenderer, LevelCameraSamplesTheGroundAtAltitudeOverFocalLength) {
  const CameraCalibration cal = ideal_camera();
  const GroundRenderer renderer(cal, UavRig{});
  // Checkerboard of 0.5 m squares.
  GroundTexture texture = uniform_texture(0.0);
  for (int r = 0; r < texture.image.rows; ++r) {
    for (int c = 0; c < texture.image.cols; ++c) {
      const Eigen::Vector2d p = texture.pixel_center(c, r);
      const bool odd =
          (static_cast<int>(std::floor(p.x() / 0.5)) + static_cast<int>(std::floor(p.y() / 0.5))) &
          1;
      texture.image.at<std::uint8_t>(r, c) = odd ? 200 : 50;
    }
  }
  const double h = 8.0, body_y = 0.13;
  std::mt19937_64 rng(1);
  const cv::Mat image =
      renderer.render(texture, body_pose(0.27, body_y, h, 0.0, 0.0, 0.0), noiseless(), rng);
  // Along row v = cy, u runs along world -y (camera x = -body y). Sub-pixel crossings of 125.
  std::vector<double> crossings;
  for (int u = 0; u + 1 < image.cols; ++u) {
    const double a = image.at<std::uint8_t>(240, u), b = image.at<std::uint8_t>(240, u + 1);
    if ((a - 125.0) * (b - 125.0) < 0.0) crossings.push_back(u + (125.0 - a) / (b - a));
  }
  ASSERT_GE(crossings.size(), 15u);
  // Least-squares line u_k = u_0 + k spacing.
  const double n = static_cast<double>(crossings.size());
  double sk = 0.0, su = 0.0, skk = 0.0, sku = 0.0;
  for (std::size_t k = 0; k < crossings.size(); ++k) {
    sk += k;
    su += crossings[k];
    skk += double(k) * k;
    sku += k * crossings[k];
  }
  const double spacing = (n * sku - sk * su) / (n * skk - sk * sk);
  const double gsd = 0.5 / spacing;  // metres per pixel
  EXPECT_NEAR(gsd, h / 520.0, 0.003 * h / 520.0);
  // Absolute position: the edge at world y = 0 is at u = cx + body_y f / h.
  const double u_zero = 320.0 + body_y * 520.0 / h;
  double nearest = 1e9;
  for (const double c : crossings) nearest = std::min(nearest, std::abs(c - u_zero));
  EXPECT_LT(nearest, 0.2);
}

TEST(GroundRenderer, ExposureAndNoiseHaveTheConfiguredStatistics) {
  const GroundRenderer renderer(distorted_camera(), UavRig{});
  const GroundTexture texture = uniform_texture(100.0);
  RenderOptions o;
  o.exposure_gain = 1.3;
  o.exposure_offset = -5.0;
  o.noise_sigma = 4.0;
  std::mt19937_64 rng(7);
  const cv::Mat image = renderer.render(texture, body_pose(0, 0, 12.0, 0.02, -0.03, 1.0), o, rng);
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_NEAR(mean[0], 1.3 * 100.0 - 5.0, 0.2);
  EXPECT_NEAR(stddev[0], 4.0, 0.4);  // rounding to integers adds only 1/12 to the variance
  // Gain saturates like an ADC.
  o.exposure_gain = 3.0;
  o.noise_sigma = 0.0;
  const cv::Mat saturated = renderer.render(texture, body_pose(0, 0, 12.0, 0, 0, 0), o, rng);
  EXPECT_EQ(cv::countNonZero(saturated != 255), 0);
}

TEST(GroundRenderer, MotionBlurPreservesTheMeanAndSmearsAlongTheMotion) {
  const GroundRenderer renderer(ideal_camera(), UavRig{});
  GroundTexture texture = uniform_texture(60.0);
  for (int k = -6; k <= 6; ++k) {
    for (int l = -6; l <= 6; ++l) paint_square(&texture, {2.5 * k, 2.5 * l}, 0.6, 220.0);
  }
  const Eigen::Isometry3d pose = body_pose(0.2, 0.1, 10.0, 0.0, 0.0, 0.0);  // squares upright
  std::mt19937_64 rng(3);
  const cv::Mat sharp = renderer.render(texture, pose, noiseless(), rng);
  RenderOptions o = noiseless();
  o.motion_blur_px = 15.0;
  o.blur_angle = 0.0;  // along +u
  const cv::Mat blurred = renderer.render(texture, pose, o, rng);
  EXPECT_NEAR(cv::mean(blurred)[0], cv::mean(sharp)[0], 0.5);
  cv::Mat gu_s, gv_s, gu_b, gv_b;
  cv::Sobel(sharp, gu_s, CV_32F, 1, 0);
  cv::Sobel(sharp, gv_s, CV_32F, 0, 1);
  cv::Sobel(blurred, gu_b, CV_32F, 1, 0);
  cv::Sobel(blurred, gv_b, CV_32F, 0, 1);
  // Gradient energy (L2; the L1 norm of a blurred step's gradient is its unchanged total
  // variation).
  const double along = cv::norm(gu_b, cv::NORM_L2) / cv::norm(gu_s, cv::NORM_L2);
  const double across = cv::norm(gv_b, cv::NORM_L2) / cv::norm(gv_s, cv::NORM_L2);
  EXPECT_LT(along, 0.5);   // edges across the motion are smeared
  EXPECT_GT(across, 0.8);  // edges along the motion are (almost) kept
}

TEST(GroundRenderer, SkyAndFarGroundAreBackgroundAndTheImageIsDeterministic) {
  const GroundRenderer renderer(ideal_camera(), UavRig{});
  GroundTexture texture = uniform_texture(30.0, 60.0);
  texture.background = 111.0;
  std::mt19937_64 rng(1);
  // Nose pitched up 80 deg: the camera looks forward 10 deg below the horizon, and the image top
  // (the body's front) sees the sky.
  const cv::Mat tilted =
      renderer.render(texture, body_pose(0, 0, 10.0, 0.0, -80.0 * kDeg, 0.0), noiseless(), rng);
  EXPECT_EQ(tilted.at<std::uint8_t>(0, 320), 111);
  EXPECT_EQ(tilted.at<std::uint8_t>(479, 320), 30);
  RenderOptions o;
  std::mt19937_64 a(42), b(42), c(43);
  const Eigen::Isometry3d pose = body_pose(1, 2, 9.0, 0.01, 0.02, 0.5);
  const cv::Mat ia = renderer.render(texture, pose, o, a);
  const cv::Mat ib = renderer.render(texture, pose, o, b);
  const cv::Mat ic = renderer.render(texture, pose, o, c);
  EXPECT_EQ(cv::norm(ia, ib, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(ia, ic, cv::NORM_L1), 0.0);
}

TEST(GroundRenderer, ARunwayFrameShowsPaintAndAsphalt) {
  RunwaySceneOptions so;
  so.grass_margin = 5.0;
  const RunwayScene scene = make_runway_scene(so);
  const GroundRenderer renderer(distorted_camera(), UavRig{});
  const Eigen::Isometry3d pose = body_pose(20.0, 8.0, 15.0, 0.03, -0.04, 0.7);
  std::mt19937_64 rng(1);
  RenderOptions o;
  o.motion_blur_px = 3.0;
  const cv::Mat image = renderer.render(scene.texture, pose, o, rng);
  // The view over the road shows white paint and dark asphalt (speed: BM in bench/frontends).
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(image, &lo, &hi);
  EXPECT_GT(hi, 190.0);
  EXPECT_LT(lo, 70.0);
}

TEST(GroundRenderer, RejectsBadConfiguration) {
  CameraCalibration bad = ideal_camera();
  bad.camera_matrix(0, 0) = 0.0;
  EXPECT_THROW(GroundRenderer(bad, UavRig{}), ConfigError);
  const GroundRenderer renderer(ideal_camera(), UavRig{});
  RenderOptions o;
  o.supersampling = 3;
  std::mt19937_64 rng(1);
  EXPECT_THROW(
      (void)renderer.render(uniform_texture(1.0, 2.0), Eigen::Isometry3d::Identity(), o, rng),
      ConfigError);
}

}  // namespace
}  // namespace vdtnav::uav_camera
