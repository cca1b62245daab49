#include "vdtnav/camera/camera_model.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::camera {
namespace {

/// Most distortion coefficients the model supports: (k1, k2, p1, p2, k3).
constexpr std::size_t kMaxDistortion = 5;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open calibration file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError(path + ": cannot read calibration file");
  return ss.str();
}

/// Drops trailing zero coefficients beyond k3 (ROS's rational_polynomial writes 8 with zeros) and
/// checks that what is left is the (k1, k2, p1, p2[, k3]) model.
std::vector<double> checked_distortion(const std::string& path, std::vector<double> d,
                                       std::size_t line) {
  while (d.size() > kMaxDistortion && d.back() == 0.0) d.pop_back();
  for (double v : d) {
    if (!std::isfinite(v)) {
      throw FormatError(path, line, "key 'distortion_coefficients': expected finite numbers");
    }
  }
  if (d.size() > kMaxDistortion) {
    throw FormatError(path, line,
                      "key 'distortion_coefficients': " + std::to_string(d.size()) +
                          " non-zero coefficients: only the 4- or 5-coefficient Brown-Conrady "
                          "model (k1, k2, p1, p2[, k3]) is supported");
  }
  if (!d.empty() && d.size() < 4) {
    throw FormatError(path, line,
                      "key 'distortion_coefficients': expected 4 or 5 coefficients "
                      "(k1, k2, p1, p2[, k3]), got " +
                          std::to_string(d.size()));
  }
  return d;
}

/// The checks every reader applies (FormatError naming the file and the key).
void check_camera(const std::string& path, const CameraCalibration& c, std::size_t line_k) {
  if (c.width <= 0) {
    throw FormatError(path, 0, "key 'image_width': expected > 0, got " + std::to_string(c.width));
  }
  if (c.height <= 0) {
    throw FormatError(path, 0, "key 'image_height': expected > 0, got " + std::to_string(c.height));
  }
  const Eigen::Matrix3d& k = c.camera_matrix;
  if (!k.allFinite()) {
    throw FormatError(path, line_k, "key 'camera_matrix': expected finite numbers");
  }
  if (!(k(0, 0) > 0.0) || !(k(1, 1) > 0.0)) {
    std::ostringstream m;
    m << "key 'camera_matrix': expected fx > 0 and fy > 0, got fx = " << k(0, 0)
      << ", fy = " << k(1, 1);
    throw FormatError(path, line_k, m.str());
  }
  if (k(1, 0) != 0.0 || k(2, 0) != 0.0 || k(2, 1) != 0.0 || k(2, 2) != 1.0) {
    throw FormatError(path, line_k,
                      "key 'camera_matrix': expected [fx s cx; 0 fy cy; 0 0 1] (last row 0 0 1)");
  }
}

// --- OpenCV FileStorage ----------------------------------------------------------------------

CameraCalibration read_opencv(const std::string& path, const std::string& text) {
  // XML only: OpenCV's YAML files are read by yaml-cpp (read_calibration()).
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const std::exception& e) {
    // cv::Exception, and std::length_error from OpenCV's parser on some malformed keys (found
    // by fuzzing, fuzz/regressions/camera_calibration-opencv-length-error.yml).
    throw FormatError(path, 0, std::string("not a readable OpenCV XML file: ") + e.what());
  }
  if (!fs.isOpened()) throw FormatError(path, 0, "not a readable OpenCV XML file");
  if (!fs.root().isMap()) throw FormatError(path, 0, "expected a map of keys at the top level");

  CameraCalibration c;
  auto read_int = [&](const char* key) {
    const cv::FileNode n = fs[key];
    if (n.empty() || n.isNone())
      throw FormatError(path, 0, std::string("missing key '") + key + "'");
    if (!n.isInt() && !n.isReal()) {
      throw FormatError(path, 0, std::string("key '") + key + "': expected an integer");
    }
    const double v = n.real();
    if (v != std::floor(v) || std::abs(v) > 1e9) {
      throw FormatError(path, 0, std::string("key '") + key + "': expected an integer");
    }
    return static_cast<int>(v);
  };
  auto read_mat = [&](const char* key) {
    const cv::FileNode n = fs[key];
    if (n.empty() || n.isNone())
      throw FormatError(path, 0, std::string("missing key '") + key + "'");
    // OpenCV allocates rows x cols before it reads the data (fuzzing found 64 GB requests):
    // a calibration matrix is small, check its size first.
    const auto small = [&](const char* dim) {
      const cv::FileNode d = n.isMap() ? n[dim] : cv::FileNode();
      return !d.empty() && d.isInt() && d.real() >= 1.0 && d.real() <= 16.0;
    };
    if (!small("rows") || !small("cols")) {
      throw FormatError(path, 0,
                        std::string("key '") + key +
                            "': expected an opencv-matrix of 1..16 rows "
                            "and columns");
    }
    cv::Mat m;
    try {
      n >> m;
    } catch (const std::exception&) {
      m = cv::Mat();
    }
    if (m.empty()) {
      throw FormatError(path, 0, std::string("key '") + key + "': expected an opencv-matrix");
    }
    m.convertTo(m, CV_64F);
    return m;
  };

  c.width = read_int("image_width");
  c.height = read_int("image_height");
  const cv::Mat k = read_mat("camera_matrix");
  if (k.rows != 3 || k.cols != 3 || k.channels() != 1) {
    throw FormatError(path, 0,
                      "key 'camera_matrix': expected a 3x3 matrix, got " + std::to_string(k.rows) +
                          "x" + std::to_string(k.cols));
  }
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col) c.camera_matrix(r, col) = k.at<double>(r, col);
  }
  const cv::FileNode dn = fs["distortion_coefficients"];
  if (!dn.empty() && !dn.isNone()) {
    const cv::Mat d = read_mat("distortion_coefficients");
    if (d.rows != 1 && d.cols != 1) {
      throw FormatError(path, 0,
                        "key 'distortion_coefficients': expected a 1xN or Nx1 matrix, got " +
                            std::to_string(d.rows) + "x" + std::to_string(d.cols));
    }
    std::vector<double> v(d.begin<double>(), d.end<double>());
    c.distortion = checked_distortion(path, std::move(v), 0);
  }
  check_camera(path, c, 0);
  return c;
}

// --- ROS camera_info --------------------------------------------------------------------------

std::size_t line_of(const YAML::Node& n) {
  const int l = n.Mark().line;
  return l >= 0 ? static_cast<std::size_t>(l + 1) : 0;
}

/// A {rows, cols, data} matrix of a camera_info file.
std::vector<double> ros_matrix(const std::string& path, const YAML::Node& root, const char* key,
                               int* rows, int* cols) {
  const YAML::Node n = root[key];
  if (!n) throw FormatError(path, 0, std::string("missing key '") + key + "'");
  const std::size_t line = line_of(n);
  if (!n.IsMap() || !n["rows"] || !n["cols"] || !n["data"] || !n["data"].IsSequence()) {
    throw FormatError(path, line,
                      std::string("key '") + key + "': expected a map {rows, cols, data: [...]}");
  }
  std::vector<double> data;
  try {
    *rows = n["rows"].as<int>();
    *cols = n["cols"].as<int>();
    for (const auto& v : n["data"]) data.push_back(v.as<double>());
  } catch (const YAML::Exception&) {
    throw FormatError(path, line, std::string("key '") + key + "': expected numbers");
  }
  if (*rows < 0 || *cols < 0 ||
      data.size() != static_cast<std::size_t>(*rows) * static_cast<std::size_t>(*cols)) {
    throw FormatError(path, line,
                      std::string("key '") + key + "': data has " + std::to_string(data.size()) +
                          " values, expected rows x cols = " + std::to_string(*rows) + " x " +
                          std::to_string(*cols));
  }
  return data;
}

/// A ROS camera_info file, or an OpenCV YAML file (the same keys; its matrices are tagged
/// !!opencv-matrix and carry a dt key, which are ignored).
CameraCalibration read_yaml(const std::string& path, const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw FormatError(path, e.mark.line >= 0 ? static_cast<std::size_t>(e.mark.line + 1) : 0,
                      "YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) {
    throw FormatError(path, line_of(root),
                      "expected a YAML map (OpenCV calibration or ROS camera_info)");
  }
  CameraCalibration c;
  auto read_int = [&](const char* key) {
    const YAML::Node n = root[key];
    if (!n) throw FormatError(path, 0, std::string("missing key '") + key + "'");
    try {
      return n.as<int>();
    } catch (const YAML::Exception&) {
      throw FormatError(path, line_of(n), std::string("key '") + key + "': expected an integer");
    }
  };
  c.width = read_int("image_width");
  c.height = read_int("image_height");
  int rows = 0;
  int cols = 0;
  const std::vector<double> k = ros_matrix(path, root, "camera_matrix", &rows, &cols);
  const std::size_t line_k = line_of(root["camera_matrix"]);
  if (rows != 3 || cols != 3) {
    throw FormatError(path, line_k,
                      "key 'camera_matrix': expected a 3x3 matrix, got " + std::to_string(rows) +
                          "x" + std::to_string(cols));
  }
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col)
      c.camera_matrix(r, col) = k[static_cast<std::size_t>(3 * r + col)];
  }
  if (const YAML::Node model = root["distortion_model"]) {
    std::string name;
    try {
      name = model.as<std::string>();
    } catch (const YAML::Exception&) {
      throw FormatError(path, line_of(model), "key 'distortion_model': expected a string");
    }
    if (name != "plumb_bob" && name != "rational_polynomial" && !name.empty()) {
      throw FormatError(path, line_of(model),
                        "key 'distortion_model': '" + name +
                            "' is not supported: expected plumb_bob (Brown-Conrady k1, k2, p1, "
                            "p2, k3)");
    }
  }
  if (root["distortion_coefficients"]) {
    std::vector<double> d = ros_matrix(path, root, "distortion_coefficients", &rows, &cols);
    if (rows > 1 && cols > 1) {
      throw FormatError(path, line_of(root["distortion_coefficients"]),
                        "key 'distortion_coefficients': expected a 1xN or Nx1 matrix");
    }
    c.distortion = checked_distortion(path, std::move(d), line_of(root["distortion_coefficients"]));
  }
  check_camera(path, c, line_k);
  return c;
}

}  // namespace

CameraCalibration read_calibration(const std::string& path) {
  std::string text = read_text(path);
  const bool xml =
      text.compare(0, 5, "<?xml") == 0 || text.find("<opencv_storage>") != std::string::npos;
  if (!xml) {
    // OpenCV's YAML files (first line "%YAML:1.0", matrices tagged !!opencv-matrix) and ROS
    // camera_info files have the same keys: both are read by yaml-cpp. OpenCV's own YAML parser
    // hangs, throws std::length_error and allocates what a corrupt size claims on malformed input
    // (found by fuzzing: fuzz/regressions/camera_calibration-opencv-*.yml). Its non-standard
    // directive becomes a comment, so that line numbers stay those of the file.
    if (text.compare(0, 5, "%YAML") == 0) text.insert(0, "# ");
    return read_yaml(path, text);
  }
  try {
    return read_opencv(path, text);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    // OpenCV asserts as it reads nodes: any other exception is bad input too.
    throw FormatError(path, 0, std::string("not a readable OpenCV XML file: ") + e.what());
  }
}

void write_opencv_calibration(const std::string& path, const CameraCalibration& calibration) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    throw IoError(path + ": cannot write calibration file: " + e.what());
  }
  if (!fs.isOpened()) throw IoError(path + ": cannot write calibration file");
  cv::Mat k(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) k.at<double>(r, c) = calibration.camera_matrix(r, c);
  }
  std::vector<double> d = calibration.distortion;
  if (d.empty()) d.assign(5, 0.0);
  fs << "image_width" << calibration.width;
  fs << "image_height" << calibration.height;
  fs << "camera_matrix" << k;
  fs << "distortion_coefficients" << cv::Mat(1, static_cast<int>(d.size()), CV_64F, d.data());
  fs.release();
}

// --- PinholeCamera ----------------------------------------------------------------------------

PinholeCamera::PinholeCamera(CameraCalibration calibration) : calibration_(std::move(calibration)) {
  const Eigen::Matrix3d& k = calibration_.camera_matrix;
  VDTNAV_CHECK(calibration_.width > 0 && calibration_.height > 0,
               "PinholeCamera: image width and height must be > 0");
  VDTNAV_CHECK(k.allFinite() && k(0, 0) > 0.0 && k(1, 1) > 0.0,
               "PinholeCamera: camera_matrix must be finite with fx > 0 and fy > 0");
  VDTNAV_CHECK(k(1, 0) == 0.0 && k(2, 0) == 0.0 && k(2, 1) == 0.0 && k(2, 2) == 1.0,
               "PinholeCamera: camera_matrix must be [fx s cx; 0 fy cy; 0 0 1]");
  std::vector<double>& d = calibration_.distortion;
  while (d.size() > kMaxDistortion && d.back() == 0.0) d.pop_back();
  VDTNAV_CHECK(d.size() <= kMaxDistortion,
               "PinholeCamera: " + std::to_string(d.size()) +
                   " distortion coefficients: only (k1, k2, p1, p2[, k3]) are supported");
  VDTNAV_CHECK(d.empty() || d.size() >= 4,
               "PinholeCamera: expected 0, 4 or 5 distortion coefficients (k1, k2, p1, p2[, k3])");
  for (double v : d) VDTNAV_CHECK(std::isfinite(v), "PinholeCamera: distortion must be finite");
  d.resize(kMaxDistortion, 0.0);
}

Eigen::Vector2d PinholeCamera::distort(const Eigen::Vector2d& normalized,
                                       Eigen::Matrix2d* jacobian) const {
  const std::vector<double>& d = calibration_.distortion;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
  const double x = normalized.x();
  const double y = normalized.y();
  const double r2 = x * x + y * y;
  // Brown-Conrady (OpenCV): radial 1 + k1 r^2 + k2 r^4 + k3 r^6, tangential p1, p2.
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  const Eigen::Matrix3d& k = calibration_.camera_matrix;
  if (jacobian != nullptr) {
    // d radial / d r^2, and d r^2 / d(x, y) = 2 (x, y).
    const double dr = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);
    Eigen::Matrix2d jd;
    jd(0, 0) = radial + 2.0 * x * x * dr + 2.0 * p1 * y + 6.0 * p2 * x;
    jd(0, 1) = 2.0 * x * y * dr + 2.0 * p1 * x + 2.0 * p2 * y;
    jd(1, 0) = 2.0 * x * y * dr + 2.0 * p1 * x + 2.0 * p2 * y;
    jd(1, 1) = radial + 2.0 * y * y * dr + 6.0 * p1 * y + 2.0 * p2 * x;
    Eigen::Matrix2d kk;
    kk << k(0, 0), k(0, 1), 0.0, k(1, 1);
    *jacobian = kk * jd;
  }
  return {k(0, 0) * xd + k(0, 1) * yd + k(0, 2), k(1, 1) * yd + k(1, 2)};
}

std::vector<Eigen::Vector2d> PinholeCamera::undistort(
    const std::vector<Eigen::Vector2d>& pixels) const {
  constexpr double kTolerance2 = 1e-20;  // squared reprojection error, pixels^2 (1e-10 px)
  const Eigen::Matrix3d& k = calibration_.camera_matrix;
  std::vector<Eigen::Vector2d> out(pixels.size());
  std::vector<std::size_t> hard;  // points Newton did not settle: OpenCV's iteration, then polish
  // Newton on distort(x) = pixel with the analytic Jacobian, from the undistorted-lens guess
  // K^-1 pixel. It converges quadratically (3-4 steps to 1e-10 px), where OpenCV's fixed-point
  // iteration needs tens of steps near the corners of a wide lens.
  const auto newton = [&](const Eigen::Vector2d& pixel, Eigen::Vector2d x, int max_steps,
                          bool* converged) {
    Eigen::Matrix2d j;
    Eigen::Vector2d e = distort(x, &j) - pixel;
    for (int it = 0; it < max_steps && e.squaredNorm() > kTolerance2; ++it) {
      const Eigen::Vector2d x_new = x - j.inverse() * e;
      Eigen::Matrix2d j_new;
      const Eigen::Vector2d e_new = distort(x_new, &j_new) - pixel;
      if (!(e_new.squaredNorm() < e.squaredNorm())) break;  // keep only steps that help
      x = x_new;
      e = e_new;
      j = j_new;
    }
    *converged = e.squaredNorm() <= kTolerance2;
    return x;
  };
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (!pixels[i].allFinite()) {
      out[i] = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const double y0 = (pixels[i].y() - k(1, 2)) / k(1, 1);
    const double x0 = (pixels[i].x() - k(0, 2) - k(0, 1) * y0) / k(0, 0);
    bool converged = false;
    out[i] = newton(pixels[i], Eigen::Vector2d(x0, y0), 8, &converged);
    if (!converged) hard.push_back(i);
  }
  if (hard.empty()) return out;

  // Fallback: cv::undistortPoints (fixed point, stopped on reprojection error or iterations),
  // then Newton again from its answer.
  std::vector<cv::Point2d> src(hard.size());
  for (std::size_t h = 0; h < hard.size(); ++h) src[h] = {pixels[hard[h]].x(), pixels[hard[h]].y()};
  cv::Mat km(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) km.at<double>(r, c) = k(r, c);
  }
  const cv::Mat d(1, 5, CV_64F, const_cast<double*>(calibration_.distortion.data()));
  std::vector<cv::Point2d> dst;
  cv::undistortPoints(src, dst, km, d, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-10));
  for (std::size_t h = 0; h < hard.size(); ++h) {
    const Eigen::Vector2d x(dst[h].x, dst[h].y);
    if (!x.allFinite()) continue;  // keep Newton's best
    bool converged = false;
    const Eigen::Vector2d polished = newton(pixels[hard[h]], x, 8, &converged);
    const std::size_t i = hard[h];
    if ((distort(polished) - pixels[i]).squaredNorm() <
        (distort(out[i]) - pixels[i]).squaredNorm()) {
      out[i] = polished;
    }
  }
  return out;
}

}  // namespace vdtnav::camera
