// Calibration files and the Brown-Conrady camera: round trips, analytic Jacobian against finite
// differences, OpenCV's projectPoints as an independent oracle, and errors that name the file.
#include "vdtnav/camera/camera_model.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "../io/test_files.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::camera {
namespace {

/// A wide lens (~77 deg horizontal field) with the strong barrel distortion of action cameras.
CameraCalibration wide_lens() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 400.0, 0.0, 321.3, 0.0, 401.5, 238.7, 0.0, 0.0, 1.0;
  c.distortion = {-0.28, 0.09, 0.0012, -0.0007, -0.012};
  return c;
}

std::vector<Eigen::Vector2d> pixel_grid(int w, int h, int step) {
  std::vector<Eigen::Vector2d> px;
  for (int v = 0; v <= h - 1; v += step) {
    for (int u = 0; u <= w - 1; u += step) px.emplace_back(u, v);
  }
  px.emplace_back(w - 1, h - 1);
  return px;
}

TEST(PinholeCamera, UndistortThenDistortReturnsThePixelEverywhereInTheImage) {
  const PinholeCamera cam(wide_lens());
  const auto px = pixel_grid(640, 480, 16);
  const auto n = cam.undistort(px);
  ASSERT_EQ(n.size(), px.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < px.size(); ++i) {
    worst = std::max(worst, (cam.distort(n[i]) - px[i]).norm());
  }
  EXPECT_LT(worst, 1e-6) << "pixels";
}

TEST(PinholeCamera, DistortThenUndistortReturnsTheRay) {
  const PinholeCamera cam(wide_lens());
  std::vector<Eigen::Vector2d> normalized;
  std::vector<Eigen::Vector2d> px;
  for (double x = -0.78; x <= 0.78; x += 0.06) {
    for (double y = -0.58; y <= 0.58; y += 0.06) {
      normalized.emplace_back(x, y);
      px.push_back(cam.distort(normalized.back()));
    }
  }
  const auto back = cam.undistort(px);
  for (std::size_t i = 0; i < px.size(); ++i) {
    // In pixels: the error in normalized coordinates times the focal length.
    EXPECT_LT(400.0 * (back[i] - normalized[i]).norm(), 1e-6) << normalized[i].transpose();
  }
}

TEST(PinholeCamera, UndistortSurvivesPixelsBeyondTheLensModel) {
  // Far outside the image the polynomial folds back: Newton cannot settle, OpenCV's fallback
  // runs; the answer must still be the best found (never worse than the pinhole guess) or NaN.
  const PinholeCamera cam(wide_lens());
  const std::vector<Eigen::Vector2d> px{{-3000.0, -2500.0}, {320.0, 240.0}, {std::nan(""), 1.0}};
  const auto n = cam.undistort(px);
  ASSERT_EQ(n.size(), 3U);
  EXPECT_LT((cam.distort(n[1]) - px[1]).norm(), 1e-6);
  EXPECT_FALSE(n[2].allFinite());
}

TEST(PinholeCamera, DistortMatchesOpenCvProjectPoints) {
  const CameraCalibration c = wide_lens();
  const PinholeCamera cam(c);
  std::vector<cv::Point3d> rays;
  for (double x = -0.8; x <= 0.8; x += 0.2) {
    for (double y = -0.6; y <= 0.6; y += 0.2) rays.emplace_back(x, y, 1.0);
  }
  cv::Mat k(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col) k.at<double>(r, col) = c.camera_matrix(r, col);
  }
  std::vector<cv::Point2d> cv_px;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, c.distortion, cv_px);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector2d p = cam.distort({rays[i].x, rays[i].y});
    EXPECT_NEAR(p.x(), cv_px[i].x, 1e-9);
    EXPECT_NEAR(p.y(), cv_px[i].y, 1e-9);
  }
}

TEST(PinholeCamera, DistortJacobianMatchesCentralDifferences) {
  CameraCalibration c = wide_lens();
  c.camera_matrix(0, 1) = 0.7;  // skew, so that the intrinsic part is exercised too
  const PinholeCamera cam(c);
  const double eps = 1e-6;
  for (double x = -0.7; x <= 0.7; x += 0.35) {
    for (double y = -0.5; y <= 0.5; y += 0.25) {
      Eigen::Matrix2d j;
      (void)cam.distort({x, y}, &j);
      Eigen::Matrix2d fd;
      for (int k = 0; k < 2; ++k) {
        Eigen::Vector2d e = Eigen::Vector2d::Zero();
        e[k] = eps;
        fd.col(k) =
            (cam.distort(Eigen::Vector2d(x, y) + e) - cam.distort(Eigen::Vector2d(x, y) - e)) /
            (2 * eps);
      }
      EXPECT_LT((j - fd).norm(), 1e-6 * fd.norm()) << "at " << x << ", " << y;
    }
  }
}

TEST(PinholeCamera, NoDistortionIsThePlainPinhole) {
  CameraCalibration c = wide_lens();
  c.distortion.clear();
  const PinholeCamera cam(c);
  const Eigen::Vector2d p = cam.distort({0.1, -0.2});
  EXPECT_NEAR(p.x(), 400.0 * 0.1 + 321.3, 1e-12);
  EXPECT_NEAR(p.y(), 401.5 * -0.2 + 238.7, 1e-12);
  const auto n = cam.undistort({p});
  EXPECT_NEAR(n[0].x(), 0.1, 1e-12);
  EXPECT_NEAR(n[0].y(), -0.2, 1e-12);
}

TEST(PinholeCamera, RejectsUnsupportedDistortionModels) {
  CameraCalibration c = wide_lens();
  c.distortion = {0.1, 0.01, 0.0, 0.0, 0.0, 0.3, 0.0, 0.0};  // rational model: k4 != 0
  EXPECT_THROW(PinholeCamera{c}, ConfigError);
  c.distortion = {0.1, 0.01, 0.0, 0.0, 0.001, 0.0, 0.0, 0.0};  // trailing zeros: plain plumb_bob
  EXPECT_NO_THROW(PinholeCamera{c});
  c.distortion = {0.1, 0.01};
  EXPECT_THROW(PinholeCamera{c}, ConfigError);
  c = wide_lens();
  c.camera_matrix(0, 0) = -400.0;
  EXPECT_THROW(PinholeCamera{c}, ConfigError);
}

void expect_same(const CameraCalibration& a, const CameraCalibration& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_LT((a.camera_matrix - b.camera_matrix).norm(), 1e-12);
  ASSERT_EQ(a.distortion.size(), b.distortion.size());
  for (std::size_t i = 0; i < a.distortion.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.distortion[i], b.distortion[i]);
  }
}

TEST(CalibrationFiles, OpenCvRoundTrip) {
  const std::string dir = test::tmp_dir("camera");
  const CameraCalibration c = wide_lens();
  write_opencv_calibration(dir + "/cam.yaml", c);
  const auto text = test::lines_of(dir + "/cam.yaml");
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text[0], "%YAML:1.0");
  expect_same(read_calibration(dir + "/cam.yaml"), c);
}

TEST(CalibrationFiles, OpenCvFileWithoutDirectiveAndColumnDistortion) {
  const std::string dir = test::tmp_dir("camera");
  test::write_file(dir + "/cam.yml",
                   "image_width: 640\n"
                   "image_height: 480\n"
                   "camera_matrix: !!opencv-matrix\n"
                   "   rows: 3\n   cols: 3\n   dt: d\n"
                   "   data: [ 400., 0., 321.3, 0., 401.5, 238.7, 0., 0., 1. ]\n"
                   "distortion_coefficients: !!opencv-matrix\n"
                   "   rows: 5\n   cols: 1\n   dt: d\n"
                   "   data: [ -0.28, 0.09, 0.0012, -0.0007, -0.012 ]\n");
  expect_same(read_calibration(dir + "/cam.yml"), wide_lens());
}

TEST(CalibrationFiles, RosCameraInfo) {
  const std::string dir = test::tmp_dir("camera");
  test::write_file(
      dir + "/camera_info.yaml",
      "image_width: 640\n"
      "image_height: 480\n"
      "camera_name: downward\n"
      "camera_matrix:\n"
      "  rows: 3\n  cols: 3\n"
      "  data: [400.0, 0.0, 321.3, 0.0, 401.5, 238.7, 0.0, 0.0, 1.0]\n"
      "distortion_model: plumb_bob\n"
      "distortion_coefficients:\n"
      "  rows: 1\n  cols: 5\n"
      "  data: [-0.28, 0.09, 0.0012, -0.0007, -0.012]\n"
      "rectification_matrix:\n"
      "  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
      "projection_matrix:\n"
      "  rows: 3\n  cols: 4\n"
      "  data: [400.0, 0.0, 321.3, 0.0, 0.0, 401.5, 238.7, 0.0, 0.0, 0.0, 1.0, 0.0]\n");
  const CameraCalibration c = read_calibration(dir + "/camera_info.yaml");
  expect_same(c, wide_lens());
  // ...and it survives the trip through OpenCV's format.
  write_opencv_calibration(dir + "/cam.yaml", c);
  expect_same(read_calibration(dir + "/cam.yaml"), c);
}

/// The message of the FormatError read_calibration throws for `text`.
std::string format_error(const std::string& path, const std::string& text) {
  test::write_file(path, text);
  try {
    (void)read_calibration(path);
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FormatError: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error for " << path;
  return {};
}

TEST(CalibrationFiles, ErrorsNameTheFileAndTheKey) {
  const std::string dir = test::tmp_dir("camera");
  const std::string ros_k =
      "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [400, 0, 320, 0, 400, 240, 0, 0, 1]\n";
  // Missing key.
  std::string msg = format_error(dir + "/no_width.yaml", "image_height: 480\n" + ros_k);
  EXPECT_NE(msg.find(dir + "/no_width.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing key 'image_width'"), std::string::npos) << msg;
  // A 2x2 camera matrix, both formats.
  msg = format_error(dir + "/k22.yaml",
                     "image_width: 640\nimage_height: 480\n"
                     "camera_matrix:\n  rows: 2\n  cols: 2\n  data: [400, 0, 0, 400]\n");
  EXPECT_EQ(msg.rfind(dir + "/k22.yaml:", 0), 0U) << msg;  // file:line: ...
  EXPECT_NE(msg.find("key 'camera_matrix': expected a 3x3 matrix, got 2x2"), std::string::npos)
      << msg;
  msg = format_error(dir + "/k22_cv.yaml",
                     "%YAML:1.0\nimage_width: 640\nimage_height: 480\n"
                     "camera_matrix: !!opencv-matrix\n  rows: 2\n  cols: 2\n  dt: d\n"
                     "  data: [400., 0., 0., 400.]\n");
  EXPECT_EQ(msg.rfind(dir + "/k22_cv.yaml:", 0), 0U) << msg;  // file:line: ...
  EXPECT_NE(msg.find("key 'camera_matrix': expected a 3x3 matrix, got 2x2"), std::string::npos)
      << msg;
  // Negative focal length.
  msg = format_error(dir + "/neg_fx.yaml",
                     "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                     "  data: [-400, 0, 320, 0, 400, 240, 0, 0, 1]\n");
  EXPECT_NE(msg.find("neg_fx.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("key 'camera_matrix': expected fx > 0"), std::string::npos) << msg;
  // Data that does not fill rows x cols.
  msg = format_error(dir + "/short.yaml",
                     "image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n"
                     "  data: [400, 0, 320]\n");
  EXPECT_NE(msg.find("key 'camera_matrix': data has 3 values"), std::string::npos) << msg;
  // An unsupported lens model.
  msg = format_error(dir + "/fisheye.yaml", "image_width: 640\nimage_height: 480\n" + ros_k +
                                                "distortion_model: equidistant\n");
  EXPECT_NE(msg.find("key 'distortion_model': 'equidistant' is not supported"), std::string::npos)
      << msg;
}

TEST(CalibrationFiles, MissingFileIsAnIoErrorNamingIt) {
  const std::string path = test::tmp_dir("camera") + "/nope.yaml";
  try {
    (void)read_calibration(path);
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(CalibrationFiles, FuzzFindingOpenCvLengthErrorIsAFormatError) {
  // fuzz_camera_calibration: OpenCV's FileStorage threw std::length_error on this file, which
  // escaped read_calibration and terminated the program.
  const std::string path =
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/camera_calibration-opencv-length-error.yml";
  try {
    (void)read_calibration(path);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_calibration-opencv-length-error.yml"),
              std::string::npos)
        << e.what();
  }
}

TEST(CalibrationFiles, FuzzFindingRootNotAMapIsAFormatError) {
  // fuzz_camera_calibration: OpenCV asserted (cv::Exception) reading a key of a root that is not
  // a map, which escaped read_calibration and terminated the program.
  const std::string path =
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/camera_calibration-opencv-root-not-a-map.yml";
  try {
    (void)read_calibration(path);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_calibration-opencv-root-not-a-map.yml"),
              std::string::npos)
        << e.what();
  }
}

TEST(CalibrationFiles, FuzzFindingHugeMatrixIsAFormatErrorNotAnAllocation) {
  // fuzz_camera_calibration: a matrix of absurd rows x cols made OpenCV allocate 64 GB.
  const std::string path =
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/camera_calibration-opencv-huge-matrix.yml";
  EXPECT_THROW((void)read_calibration(path), FormatError);
}

TEST(CalibrationFiles, FuzzFindingThatHungOpenCvsYamlParserIsAFormatError) {
  // fuzz_camera_calibration: OpenCV's YAML parser looped forever on these 22 bytes (a scalar
  // over three lines where a map was expected); yaml-cpp reads the YAML files now.
  const std::string path =
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/camera_calibration-opencv-hang.yml";
  try {
    (void)read_calibration(path);
    ADD_FAILURE() << "no error";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("expected a YAML map"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vdtnav::camera
