#include "vdtnav/pcl/registered_scans.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"

namespace vdtnav {
namespace {

constexpr double kHalfRange = 1 << 20;  // cells either side of the origin, per axis (21 bits)

}  // namespace

RegisteredScans::RegisteredScans(double cell) : cell_(cell) {
  VDTNAV_CHECK(std::isfinite(cell) && cell > 0.0,
               "RegisteredScans: the cell edge must be finite and > 0");
}

void RegisteredScans::add(const pcl::PointCloud<pcl::PointXYZ>& scan, const Pose3& pose) {
  VDTNAV_CHECK(pose.matrix().allFinite(), "RegisteredScans: the scan's pose must be finite");
  for (const pcl::PointXYZ& p : scan) {
    const Eigen::Vector3d q = p.getVector3fMap().cast<double>();
    if (!q.allFinite()) {
      ++dropped_;
      continue;
    }
    const Eigen::Vector3d m = pose * q;
    const Eigen::Vector3d c = (m / cell_).array().floor();
    if (!(c.cwiseAbs().maxCoeff() < kHalfRange)) {
      throw ConfigError("RegisteredScans: a point lands at (" + std::to_string(m.x()) + ", " +
                        std::to_string(m.y()) + ", " + std::to_string(m.z()) +
                        ") m in the map frame, beyond 2^20 cells of " + std::to_string(cell_) +
                        " m from its origin (are the poses and clouds in metres?)");
    }
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a)
      key = (key << 21) | static_cast<std::uint64_t>(static_cast<std::int64_t>(c[a] + kHalfRange));
    Sum& s = cells_[key];
    s.sum += m;
    s.n += 1.0;
    ++added_;
  }
  ++scans_;
}

pcl::PointCloud<pcl::PointXYZ> RegisteredScans::cloud() const {
  std::vector<std::pair<std::uint64_t, const Sum*>> sorted;
  sorted.reserve(cells_.size());
  for (const auto& [key, sum] : cells_) sorted.emplace_back(key, &sum);
  std::sort(sorted.begin(), sorted.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  pcl::PointCloud<pcl::PointXYZ> out;
  out.reserve(sorted.size());
  for (const auto& [key, s] : sorted) {
    const Eigen::Vector3f c = (s->sum / s->n).cast<float>();
    out.push_back(pcl::PointXYZ(c.x(), c.y(), c.z()));
  }
  return out;
}

pcl::PointCloud<pcl::PointXYZ> merge_scan_files(
    const std::vector<std::string>& files, const std::vector<Pose3>& poses, double cell,
    const std::function<void(std::size_t, const RegisteredScans&)>& on_scan) {
  VDTNAV_CHECK(files.size() == poses.size(), "merge_scan_files: " + std::to_string(files.size()) +
                                                 " files for " + std::to_string(poses.size()) +
                                                 " poses");
  RegisteredScans merged(cell);
  for (std::size_t k = 0; k < files.size(); ++k) {
    merged.add(read_point_cloud(files[k]), poses[k]);
    if (on_scan) on_scan(k, merged);
  }
  VDTNAV_CHECK(merged.points_added() > 0, "merge_scan_files: the " + std::to_string(files.size()) +
                                              " clouds hold no finite point");
  return merged.cloud();
}

}  // namespace vdtnav
