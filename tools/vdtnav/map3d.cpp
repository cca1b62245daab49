#include "map3d.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "exit_status.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/file_extension.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#include "vdtnav/octomap/octree_map.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#include "vdtnav/pcl/registered_scans.hpp"

namespace vdtnav::tools {
namespace {

void say_grid(const OccupancyGrid<3>& g, bool quiet) {
  if (quiet) return;
  const double voxels = static_cast<double>(g.num_cells());
  std::fprintf(stderr,
               "[map3d] dense grid %d x %d x %d voxels of %.3f m (%.1f M voxels, ~%.0f MB as a "
               "VDT map)\n",
               g.size().x(), g.size().y(), g.size().z(), g.resolution(), voxels * 1e-6,
               voxels * 16.0 * 1e-6);
}

/// Voxelizes a map cloud (cropped to options.crop) into out.dense or out.sparse.
void map_of_cloud(pcl::PointCloud<pcl::PointXYZ> cloud, const std::string& what,
                  const Map3dOptions& options, Map3d& out) {
  const std::size_t read = cloud.size();
  if (options.crop) {
    const Eigen::Vector3f lo = options.crop->min.cast<float>(),
                          hi = options.crop->max.cast<float>();
    pcl::PointCloud<pcl::PointXYZ> kept;
    for (const pcl::PointXYZ& p : cloud) {
      const Eigen::Vector3f q = p.getVector3fMap();
      if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) kept.push_back(p);
    }
    if (kept.empty()) throw UsageError(what + ": --crop keeps none of the cloud's points");
    cloud.swap(kept);
  }
  PointCloudOccupancyOptions o;
  o.resolution = options.resolution > 0.0 ? options.resolution : 0.1;
  o.margin = options.margin;
  o.thin_surfaces = options.thin_surfaces;
  if (options.sparse) {
    if (!options.quiet)
      std::fprintf(stderr, "[map3d] %zu points read, %zu kept\n", read, cloud.size());
    out.sparse = std::make_unique<SparseVdtMap3>(sparse_vdt_map_from_point_cloud(cloud, o));
  } else {
    const PointCloudOccupancy occ = occupancy_from_point_cloud(cloud, o);
    if (!options.quiet) {
      std::fprintf(stderr, "[map3d] %zu points read, %zu kept, %zu occupied voxels\n", read,
                   cloud.size() - occ.num_dropped, occ.num_occupied);
    }
    say_grid(occ.occupancy, options.quiet);
    out.dense = std::make_unique<VdtMap3>(VdtMap3::build(occ.occupancy));
  }
  out.source = options.sparse ? "point cloud, sparse" : "point cloud";
}

void check_map_options(const Map3dOptions& options) {
  if (!(std::isfinite(options.resolution) && options.resolution >= 0.0))
    throw UsageError("--resolution must be finite and >= 0 (0: the source's default)");
  if (!(std::isfinite(options.margin) && options.margin >= 0.0))
    throw UsageError("--margin must be finite and >= 0");
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CropBox parse_crop(const std::string& text, const std::string& what) {
  CropBox box;
  double v[6];
  std::size_t begin = 0;
  for (int k = 0; k < 6; ++k) {
    const std::size_t comma = text.find(',', begin);
    const std::string field =
        text.substr(begin, comma == std::string::npos ? comma : comma - begin);
    char* end = nullptr;
    v[k] = std::strtod(field.c_str(), &end);
    if (field.empty() || *end != '\0' || !std::isfinite(v[k]) ||
        ((k < 5) != (comma != std::string::npos))) {
      throw UsageError(what + ": expected xmin,ymin,zmin,xmax,ymax,zmax (metres), got '" + text +
                       "'");
    }
    begin = comma + 1;
  }
  box.min = Eigen::Vector3d(v[0], v[1], v[2]);
  box.max = Eigen::Vector3d(v[3], v[4], v[5]);
  if (!(box.max.array() > box.min.array()).all())
    throw UsageError(what + ": expected max > min on every axis, got '" + text + "'");
  return box;
}

Map3d load_map3d(const std::string& path, const Map3dOptions& options) {
  check_map_options(options);
  const auto start = std::chrono::steady_clock::now();
  const std::string ext = lower_extension(path);
  Map3d out;
  const auto check_resolution = [&](double saved) {
    if (options.resolution > 0.0 && std::abs(options.resolution - saved) > 1e-9) {
      throw UsageError(path + ": the saved map has resolution " + std::to_string(saved) +
                       " m, not the --resolution " + std::to_string(options.resolution) +
                       " asked for (build it again)");
    }
  };
  if (ext == ".vdt" || ext == ".svdt") {
    if (options.crop) throw UsageError(path + ": --crop applies to point clouds, not a saved map");
    if (ext == ".vdt") {
      out.dense = std::make_unique<VdtMap3>(load_vdt_map<3>(path));
      out.source = "vdt map file";
    } else {
      out.sparse = std::make_unique<SparseVdtMap3>(load_sparse_vdt_map(path));
      out.source = "sparse vdt map file (memory-mapped)";
    }
    check_resolution(out.field().resolution());
  } else if (ext == ".bt" || ext == ".ot") {
    if (options.crop) throw UsageError(path + ": --crop applies to point clouds, not an octree");
    OctreeOccupancyOptions o;
    o.resolution = options.resolution;
    o.margin = options.margin;
    if (options.sparse) {
      out.sparse = std::make_unique<SparseVdtMap3>(load_octree_sparse_map(path, o));
    } else {
      const OctreeOccupancy occ = load_octree_occupancy(path, o);
      say_grid(occ.occupancy, options.quiet);
      out.dense = std::make_unique<VdtMap3>(VdtMap3::build(occ.occupancy));
    }
    out.source = options.sparse ? "octree, sparse" : "octree";
  } else {
    pcl::PointCloud<pcl::PointXYZ> cloud = read_point_cloud(path);
    map_of_cloud(std::move(cloud), path, options, out);
  }
  out.seconds = seconds_since(start);
  return out;
}

Map3d build_map3d_from_scans(const ScanRun& run, const Map3dOptions& options) {
  check_map_options(options);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> clouds = point_cloud_files_in(run.dir);
  const ScanPoseFile poses = load_scan_poses(run.poses);
  const std::vector<Pose3> pose_of = poses_of_scans(poses, clouds, run.stamp_tolerance);
  const std::vector<std::size_t> kept = select_scans(clouds.size(), run.selection);
  const double resolution = options.resolution > 0.0 ? options.resolution : 0.1;
  if (!options.quiet) {
    std::fprintf(stderr, "[map3d] %zu of the %zu clouds of %s, posed by %s (%s)\n", kept.size(),
                 clouds.size(), run.dir.c_str(), run.poses.c_str(),
                 poses.format == ScanPoseFormat::kKitti ? "KITTI" : "TUM");
  }
  std::vector<std::string> files;
  std::vector<Pose3> posed;
  for (const std::size_t k : kept) {
    files.push_back(clouds[k]);
    posed.push_back(pose_of[k] * run.lidar_pose);
  }
  const pcl::PointCloud<pcl::PointXYZ> merged = merge_scan_files(
      files, posed, resolution / 4.0, [&](std::size_t i, const RegisteredScans& m) {
        if (!options.quiet && (i + 1 == files.size() || (i + 1) % 100 == 0)) {
          std::fprintf(stderr, "[map3d] %zu / %zu clouds merged: %zu points, %zu cells of %.3f m\n",
                       i + 1, files.size(), m.points_added(), m.cells(), resolution / 4.0);
        }
      });
  Map3d out;
  map_of_cloud(merged, run.dir, options, out);
  out.source = options.sparse ? "mapping run, sparse" : "mapping run";
  out.seconds = seconds_since(start);
  return out;
}

std::size_t Map3d::memory_bytes() const {
  return dense ? dense->memory_bytes() : sparse->memory_bytes();
}

}  // namespace vdtnav::tools
