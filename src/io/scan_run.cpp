#include "vdtnav/io/scan_run.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>

#include <Eigen/Geometry>

#include "text_fields.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/file_extension.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kKittiFields = 12;
constexpr std::array<const char*, kKittiFields> kKittiNames = {
    "r00", "r01", "r02", "tx", "r10", "r11", "r12", "ty", "r20", "r21", "r22", "tz"};

/// \return an empty string and the pose of one KITTI line, or what was expected.
std::string parse_kitti_line(std::string_view line, Pose3& out) {
  std::vector<std::string_view> f;
  std::array<double, kKittiFields> v{};
  if (std::string error = io_text::parse_finite_fields(line, kKittiNames, f, v); !error.empty())
    return error;
  Eigen::Matrix3d r;
  r << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = r.determinant();
  if (!(off <= kKittiRotationTolerance && std::abs(det - 1.0) <= kKittiRotationTolerance)) {
    return "expected a rotation in the 3x3 part (R^T R = I and det R = 1 within 1e-3), got |R^T R "
           "- I| = " +
           std::to_string(off) + ", det R = " + std::to_string(det);
  }
  out = Pose3::Identity();
  out.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
  return {};
}

/// \return the number of whitespace-separated fields of the first data line, and its number.
std::pair<std::size_t, std::size_t> first_data_line_fields(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the pose file");
  std::string line;
  std::vector<std::string_view> fields;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    io_text::split_fields(line, fields);
    return {fields.size(), n};
  }
  if (in.bad()) throw IoError(path + ": cannot read the pose file");
  throw FormatError(path, 0, "no pose in the file (expected KITTI or TUM lines)");
}

}  // namespace

bool is_point_cloud_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".pcd" || ext == ".ply" || ext == ".vtk" || ext == ".csv" || ext == ".txt" ||
         ext == ".xyz";
}

std::vector<std::string> point_cloud_files_in(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw IoError(dir + ": expected a folder of point clouds");
  std::vector<std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && is_point_cloud_file(e.path().string()))
      files.push_back(e.path().string());
  if (ec) throw IoError(dir + ": cannot list the folder: " + ec.message());
  if (files.empty()) {
    throw ConfigError(dir +
                      ": no point cloud in the folder (expected .pcd, .ply, .vtk, .csv, .txt or "
                      ".xyz files)");
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::optional<double> stamp_of_name(const std::string& path) {
  const std::string stem = fs::path(path).stem().string();
  double t = 0.0;
  if (stem.empty() || !io_text::parse_double(stem, t) || !std::isfinite(t)) return std::nullopt;
  return t;
}

std::vector<Pose3> load_kitti_poses(const std::string& path) {
  std::vector<Pose3> poses;
  std::vector<std::size_t> unused;
  io_text::read_data_lines(path, "KITTI poses", false, parse_kitti_line, poses, unused);
  return poses;
}

std::vector<double> load_scan_times(const std::string& path) {
  static constexpr std::array<const char*, 1> kNames = {"t"};
  std::vector<double> times;
  std::vector<std::size_t> unused;
  double previous = -std::numeric_limits<double>::infinity();
  io_text::read_data_lines(
      path, "scan times", false,
      [&](std::string_view line, double& out) -> std::string {
        std::vector<std::string_view> f;
        std::array<double, 1> v{};
        if (std::string error = io_text::parse_finite_fields(line, kNames, f, v); !error.empty())
          return error;
        if (!(v[0] > previous)) {
          return "expected a stamp after the line before's (" + std::to_string(previous) +
                 " s), got " + std::to_string(v[0]);
        }
        previous = out = v[0];
        return {};
      },
      times, unused);
  return times;
}

ScanPoseFile load_scan_poses(const std::string& path) {
  ScanPoseFile file;
  file.path = path;
  const auto [fields, line] = first_data_line_fields(path);
  if (fields == kKittiFields) {
    file.format = ScanPoseFormat::kKitti;
    const std::vector<Pose3> poses = load_kitti_poses(path);
    for (std::size_t k = 0; k < poses.size(); ++k)
      file.poses.push_back({static_cast<double>(k), poses[k]});
  } else if (fields == 8) {
    file.format = ScanPoseFormat::kTum;
    file.poses = load_tum_trajectory(path).poses;
  } else {
    throw FormatError(path, line,
                      "expected a pose: 12 numbers (KITTI, a 3x4 matrix row by row) or 8 (TUM, t "
                      "x y z qx qy qz qw), found " +
                          std::to_string(fields) + " fields");
  }
  return file;
}

std::vector<Pose3> poses_of_scans(const ScanPoseFile& poses, const std::vector<std::string>& scans,
                                  double stamp_tolerance) {
  VDTNAV_CHECK(std::isfinite(stamp_tolerance) && stamp_tolerance >= 0.0,
               "poses_of_scans: the stamp tolerance must be finite and >= 0");
  std::vector<Pose3> out;
  out.reserve(scans.size());
  if (poses.format == ScanPoseFormat::kKitti) {
    if (poses.poses.size() != scans.size()) {
      throw ConfigError(poses.path + ": " + std::to_string(poses.poses.size()) +
                        " KITTI poses for " + std::to_string(scans.size()) +
                        " clouds (one pose a line, a line per cloud in name order)");
    }
    for (const StampedPose3& p : poses.poses) out.push_back(p.pose);
    return out;
  }
  std::vector<StampedPose3> sorted = poses.poses;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const StampedPose3& a, const StampedPose3& b) { return a.t < b.t; });
  for (const std::string& scan : scans) {
    const std::optional<double> t = stamp_of_name(scan);
    if (!t) {
      throw ConfigError(scan + ": TUM poses (" + poses.path +
                        ") are matched to clouds named by their time stamp, e.g. "
                        "1317357625.557814.pcd; this name is not a number");
    }
    const auto after = std::lower_bound(sorted.begin(), sorted.end(), *t,
                                        [](const StampedPose3& p, double s) { return p.t < s; });
    const StampedPose3* nearest = nullptr;
    if (after != sorted.end()) nearest = &*after;
    if (after != sorted.begin() &&
        (nearest == nullptr || *t - std::prev(after)->t < nearest->t - *t))
      nearest = &*std::prev(after);
    const double offset = nearest->t - *t;
    if (!(std::abs(offset) <= stamp_tolerance)) {
      throw ConfigError(scan + ": no pose of " + poses.path + " within " +
                        std::to_string(stamp_tolerance) + " s of its stamp " + std::to_string(*t) +
                        " (the nearest is " + std::to_string(offset) +
                        " s away; --stamp-tolerance)");
    }
    out.push_back(nearest->pose);
  }
  return out;
}

std::vector<std::size_t> select_scans(std::size_t count, const ScanSelection& s) {
  VDTNAV_CHECK(s.every >= 1, "scan selection: --every must be at least 1");
  VDTNAV_CHECK(!(s.skip_odd && s.skip_even),
               "scan selection: --skip-odd and --skip-even together leave no scan");
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < count; ++k) {
    if (k % static_cast<std::size_t>(s.every) != 0) continue;
    if ((k % 2 == 1 && s.skip_odd) || (k % 2 == 0 && s.skip_even)) continue;
    kept.push_back(k);
  }
  VDTNAV_CHECK(!kept.empty(), "scan selection: of " + std::to_string(count) + " scans, --every " +
                                  std::to_string(s.every) + (s.skip_odd ? " --skip-odd" : "") +
                                  (s.skip_even ? " --skip-even" : "") + " keeps none");
  return kept;
}

}  // namespace vdtnav
