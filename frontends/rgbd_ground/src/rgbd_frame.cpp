#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::rgbd_ground {
namespace {

std::string size_of(const cv::Mat& m) {
  return std::to_string(m.cols) + " x " + std::to_string(m.rows);
}

}  // namespace

RgbdFrame make_rgbd_frame(const cv::Mat& colour, const cv::Mat& depth, double depth_scale) {
  VDTNAV_CHECK(!colour.empty() && !depth.empty(), "RGB-D frame: empty colour or depth image");
  VDTNAV_CHECK(colour.depth() == CV_8U &&
                   (colour.channels() == 1 || colour.channels() == 3 || colour.channels() == 4),
               "RGB-D frame: the colour image must be 8-bit with 1, 3 or 4 channels");
  VDTNAV_CHECK(colour.size() == depth.size(), "RGB-D frame: colour " + size_of(colour) +
                                                  " and depth " + size_of(depth) +
                                                  " differ in size (registered frames expected)");
  VDTNAV_CHECK(depth.channels() == 1 &&
                   (depth.depth() == CV_16U || depth.depth() == CV_32F || depth.depth() == CV_64F),
               "RGB-D frame: the depth image must be single-channel 16-bit (raw units) or "
               "floating point (metres)");
  RgbdFrame f;
  if (colour.channels() == 3) {
    f.colour = colour.clone();
  } else {
    cv::cvtColor(colour, f.colour,
                 colour.channels() == 1 ? cv::COLOR_GRAY2BGR : cv::COLOR_BGRA2BGR);
  }
  if (depth.depth() == CV_16U) {
    VDTNAV_CHECK(depth_scale > 0.0 && std::isfinite(depth_scale),
                 "RGB-D frame: depth_scale (raw units per metre) must be > 0");
    depth.convertTo(f.depth, CV_32F, 1.0 / depth_scale);
  } else {
    depth.convertTo(f.depth, CV_32F);
  }
  int valid = 0;
  for (int r = 0; r < f.depth.rows; ++r) {
    float* row = f.depth.ptr<float>(r);
    for (int c = 0; c < f.depth.cols; ++c) {
      if (!std::isfinite(row[c]) || row[c] < 0.0f) row[c] = 0.0f;  // no reading
      valid += row[c] > 0.0f;
    }
  }
  VDTNAV_CHECK(valid > 0, "RGB-D frame: no pixel has a depth reading (all zero)");
  return f;
}

RgbdFrame read_rgbd_frame(const std::string& colour_path, const std::string& depth_path,
                          double depth_scale) {
  const cv::Mat colour = cv::imread(colour_path, cv::IMREAD_COLOR);
  if (colour.empty()) throw IoError(colour_path + ": cannot read the colour image");
  const cv::Mat depth = cv::imread(depth_path, cv::IMREAD_UNCHANGED);
  if (depth.empty()) throw IoError(depth_path + ": cannot read the depth image");
  if (depth.channels() != 1 || depth.depth() != CV_16U) {
    throw FormatError(depth_path, 0,
                      "expected a single-channel 16-bit depth image (PNG or PGM), got " +
                          std::to_string(depth.channels()) + " channel(s) of another depth");
  }
  try {
    return make_rgbd_frame(colour, depth, depth_scale);
  } catch (const ConfigError& e) {
    throw FormatError(depth_path, 0, std::string(e.what()) + " (colour: " + colour_path + ")");
  }
}

std::vector<Eigen::Isometry3d> read_camera_poses(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the pose file");
  std::vector<Eigen::Isometry3d> out;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double v[7];
    for (double& x : v) {
      if (!(fields >> x) || !std::isfinite(x)) {
        throw FormatError(path, number,
                          "expected 7 numbers tx ty tz qx qy qz qw, got '" + line + "'");
      }
    }
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-9) throw FormatError(path, number, "the quaternion (qx qy qz qw) is zero");
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = q.normalized().toRotationMatrix();
    t.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    out.push_back(t);
  }
  return out;
}

}  // namespace vdtnav::rgbd_ground
