// load_map (load_map.hpp): every map file vdtnav reads, by the extension. The point cloud and
// octree readers are vdtnav::pcl's and vdtnav::octomap's, compiled in when those front ends are
// built (VDTNAV_MAP_FILES_PCL, VDTNAV_MAP_FILES_OCTOMAP).
#include "vdtnav/map_files/load_map.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/file_extension.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#ifdef VDTNAV_MAP_FILES_OCTOMAP
#include "vdtnav/octomap/octree_map.hpp"
#endif
#ifdef VDTNAV_MAP_FILES_PCL
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#include "vdtnav/pcl/registered_scans.hpp"
#endif

namespace vdtnav {
namespace {

void say(const MapLoadOptions& options, const std::string& line) {
  if (options.say) options.say(line);
}

// format and say_grid serve the point cloud and octree readers (unused in a build without both).
[[maybe_unused]] std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0,
                                    double d = 0.0, double e = 0.0, double f = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d, e, f);
  return buf;
}

[[maybe_unused]] void say_grid(const OccupancyGrid<3>& g, const MapLoadOptions& options) {
  const double voxels = static_cast<double>(g.num_cells());
  say(options, format("dense grid %.0f x %.0f x %.0f voxels of %.3f m (%.1f M voxels, ~%.0f MB "
                      "as a VDT map)",
                      g.size().x(), g.size().y(), g.size().z(), g.resolution(), voxels * 1e-6,
                      voxels * 16.0 * 1e-6));
}

void check_options(const MapLoadOptions& options) {
  if (!(std::isfinite(options.resolution) && options.resolution >= 0.0))
    throw MapOptionError("--resolution must be finite and >= 0 (0: the source's default)");
  if (!(std::isfinite(options.margin) && options.margin >= 0.0))
    throw MapOptionError("--margin must be finite and >= 0");
}

/// A 2D map's occupancy as ROS cell values (100 occupied, 0 free), for what draws or publishes
/// it as a map_server map.
RosMap ros_map_of(const OccupancyGrid<2>& occ, const std::string& path) {
  RosMap ros;
  ros.cells = Grid<std::int8_t, 2>(occ.size(), occ.frame(), 0);
  for (std::size_t i = 0; i < occ.num_cells(); ++i) ros.cells[i] = occ[i] != 0 ? 100 : 0;
  ros.metadata.resolution = occ.resolution();
  ros.metadata.origin =
      Eigen::Vector3d(occ.frame().origin().x(), occ.frame().origin().y(), occ.frame().yaw());
  ros.image_path = path;
  return ros;
}

void load_uncertain(const std::string& path, LoadedMap& m) {
  m.uncertain =
      std::make_shared<const mapping::UncertainMapFile>(mapping::load_uncertain_map(path));
  m.ros.cells = m.uncertain->occupancy;
  m.ros.metadata.resolution = m.ros.cells.resolution();
  m.ros.metadata.origin =
      Eigen::Vector3d(m.ros.cells.frame().origin().x(), m.ros.cells.frame().origin().y(),
                      m.ros.cells.frame().yaw());
  m.ros.image_path = path;
  m.occupancy = occupancy(m.ros);
  m.vdt = std::make_unique<VdtMap2>(m.uncertain->map.to_vdt_map(m.ros.cells.resolution()));
  m.source = "uncertain map file";
}

/// A saved 2D VDT map: its occupancy is its features (the cells that are their own nearest
/// occupied cell), what the baselines and the global search need of it.
/// \return false when the file holds a 3D map (its header says so: nothing more is read).
bool load_vdt2(const std::string& path, LoadedMap& m) {
  VdtMap2 vdt;
  try {
    vdt = load_vdt_map<2>(path);
  } catch (const FormatError& e) {
    // load_vdt_map's message for a file of the other dimension (io/vdt_map_file.cpp)
    if (std::string(e.what()).find("3D map, but a 2D map was requested") == std::string::npos)
      throw;
    return false;
  }
  const Grid<std::int32_t, 2>& nearest = vdt.nearest_cells();
  m.occupancy = OccupancyGrid<2>(nearest.size(), nearest.frame(), 0);
  for (std::size_t i = 0; i < nearest.num_cells(); ++i)
    m.occupancy[i] = static_cast<std::uint8_t>(nearest[i] == static_cast<std::int32_t>(i));
  m.ros = ros_map_of(m.occupancy, path);
  m.vdt = std::make_unique<VdtMap2>(std::move(vdt));
  m.source = "vdt map file";
  return true;
}

void load_octree(const std::string& path, const MapLoadOptions& options, LoadedMap& m) {
#ifdef VDTNAV_MAP_FILES_OCTOMAP
  if (options.crop) throw MapOptionError(path + ": --crop applies to point clouds, not an octree");
  OctreeOccupancyOptions o;
  o.resolution = options.resolution;
  o.margin = options.margin;
  if (options.sparse) {
    m.sparse = std::make_unique<SparseVdtMap3>(load_octree_sparse_map(path, o));
  } else {
    const OctreeOccupancy occ = load_octree_occupancy(path, o);
    say_grid(occ.occupancy, options);
    m.dense = std::make_unique<VdtMap3>(VdtMap3::build(occ.occupancy));
  }
  m.source = options.sparse ? "octree, sparse" : "octree";
#else
  (void)options;
  (void)m;
  throw ConfigError(path +
                    ": reading an OctoMap needs vdtnav::octomap, and this vdtnav was built "
                    "without it (install liboctomap-dev and rebuild)");
#endif
}

#ifdef VDTNAV_MAP_FILES_PCL
/// Voxelizes a map cloud (cropped to options.crop) into out.dense or out.sparse.
void voxelize_map_cloud(pcl::PointCloud<pcl::PointXYZ> cloud, const std::string& what,
                        const MapLoadOptions& options, LoadedMap& out) {
  const std::size_t read = cloud.size();
  if (options.crop) {
    const Eigen::Vector3f lo = options.crop->min.cast<float>(),
                          hi = options.crop->max.cast<float>();
    pcl::PointCloud<pcl::PointXYZ> kept;
    for (const pcl::PointXYZ& p : cloud) {
      const Eigen::Vector3f q = p.getVector3fMap();
      if ((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) kept.push_back(p);
    }
    if (kept.empty()) throw MapOptionError(what + ": --crop keeps none of the cloud's points");
    cloud.swap(kept);
  }
  PointCloudOccupancyOptions o;
  o.resolution = options.resolution > 0.0 ? options.resolution : 0.1;
  o.margin = options.margin;
  o.thin_surfaces = options.thin_surfaces;
  out.dimension = 3;
  if (options.sparse) {
    say(options, format("%.0f points read, %.0f kept", static_cast<double>(read),
                        static_cast<double>(cloud.size())));
    out.sparse = std::make_unique<SparseVdtMap3>(sparse_vdt_map_from_point_cloud(cloud, o));
  } else {
    const PointCloudOccupancy occ = occupancy_from_point_cloud(cloud, o);
    say(options,
        format("%.0f points read, %.0f kept, %.0f occupied voxels", static_cast<double>(read),
               static_cast<double>(cloud.size() - occ.num_dropped),
               static_cast<double>(occ.num_occupied)));
    say_grid(occ.occupancy, options);
    out.dense = std::make_unique<VdtMap3>(VdtMap3::build(occ.occupancy));
  }
  out.source = options.sparse ? "point cloud, sparse" : "point cloud";
}
#endif

void load_cloud(const std::string& path, const MapLoadOptions& options, LoadedMap& m) {
#ifdef VDTNAV_MAP_FILES_PCL
  voxelize_map_cloud(read_point_cloud(path), path, options, m);
#else
  (void)options;
  (void)m;
  throw ConfigError(path +
                    ": reading a point cloud needs vdtnav::pcl, and this vdtnav was built "
                    "without it (install libpcl-dev and rebuild)");
#endif
}

}  // namespace

CropBox parse_crop_box(const std::string& text, const std::string& what) {
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
      throw MapOptionError(what + ": expected xmin,ymin,zmin,xmax,ymax,zmax (metres), got '" +
                           text + "'");
    }
    begin = comma + 1;
  }
  box.min = Eigen::Vector3d(v[0], v[1], v[2]);
  box.max = Eigen::Vector3d(v[3], v[4], v[5]);
  if (!(box.max.array() > box.min.array()).all())
    throw MapOptionError(what + ": expected max > min on every axis, got '" + text + "'");
  return box;
}

LoadedMap load_map(const std::string& path, const MapLoadOptions& options, int dimension) {
  check_options(options);
  const auto start = std::chrono::steady_clock::now();
  const std::string ext = lower_extension(path);
  LoadedMap m;
  const auto check_resolution = [&](double saved) {
    if (options.resolution > 0.0 && std::abs(options.resolution - saved) > 1e-9) {
      throw MapOptionError(path + ": the saved map has resolution " + std::to_string(saved) +
                           " m, not the --resolution " + std::to_string(options.resolution) +
                           " asked for (build it again)");
    }
  };
  const auto saved_map = [&] {
    if (options.crop)
      throw MapOptionError(path + ": --crop applies to point clouds, not a saved map");
  };
  if (mapping::is_uncertain_map_file(path)) {  // by its magic, whatever its name
    load_uncertain(path, m);
  } else if (ext == ".yaml" || ext == ".yml") {
    m.ros = load_ros_map(path);
    m.occupancy = occupancy(m.ros);
    m.vdt = std::make_unique<VdtMap2>(VdtMap2::build(m.occupancy));
    m.source = "ros map";
  } else if (ext == ".vdt" && (saved_map(), load_vdt2(path, m))) {
    check_resolution(m.vdt->resolution());
  } else if (ext == ".vdt" || ext == ".svdt") {
    saved_map();
    m.dimension = 3;
    if (ext == ".vdt") {
      m.dense = std::make_unique<VdtMap3>(load_vdt_map<3>(path));
      m.source = "vdt map file";
    } else {
      m.sparse = std::make_unique<SparseVdtMap3>(load_sparse_vdt_map(path));
      m.source = "sparse vdt map file (memory-mapped)";
    }
    check_resolution(m.field3().resolution());
  } else if (ext == ".bt" || ext == ".ot") {
    m.dimension = 3;
    load_octree(path, options, m);
  } else {
    m.dimension = 3;
    load_cloud(path, options, m);
  }
  if (dimension != 0 && m.dimension != dimension) {
    throw ConfigError(path + ": a " + std::to_string(m.dimension) + "D map (" + m.source +
                      "), where a " + std::to_string(dimension) + "D map is expected");
  }
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

LoadedMap build_map_from_scans(const MapScanRun& run, const MapLoadOptions& options) {
  check_options(options);
#ifdef VDTNAV_MAP_FILES_PCL
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> clouds = point_cloud_files_in(run.dir);
  const ScanPoseFile poses = load_scan_poses(run.poses);
  const std::vector<Pose3> pose_of = poses_of_scans(poses, clouds, run.stamp_tolerance);
  const std::vector<std::size_t> kept = select_scans(clouds.size(), run.selection);
  const double resolution = options.resolution > 0.0 ? options.resolution : 0.1;
  say(options, std::to_string(kept.size()) + " of the " + std::to_string(clouds.size()) +
                   " clouds of " + run.dir + ", posed by " + run.poses + " (" +
                   (poses.format == ScanPoseFormat::kKitti ? "KITTI" : "TUM") + ")");
  std::vector<std::string> files;
  std::vector<Pose3> posed;
  for (const std::size_t k : kept) {
    files.push_back(clouds[k]);
    posed.push_back(pose_of[k] * run.lidar_pose);
  }
  const pcl::PointCloud<pcl::PointXYZ> merged = merge_scan_files(
      files, posed, resolution / 4.0, [&](std::size_t i, const RegisteredScans& m) {
        if (i + 1 == files.size() || (i + 1) % 100 == 0) {
          say(options, format("%.0f / %.0f clouds merged: %.0f points, %.0f cells of %.3f m",
                              static_cast<double>(i + 1), static_cast<double>(files.size()),
                              static_cast<double>(m.points_added()), static_cast<double>(m.cells()),
                              resolution / 4.0));
        }
      });
  LoadedMap out;
  voxelize_map_cloud(merged, run.dir, options, out);
  out.source = options.sparse ? "mapping run, sparse" : "mapping run";
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
#else
  throw ConfigError(run.dir +
                    ": building a map from point clouds needs vdtnav::pcl, and this vdtnav was "
                    "built without it (install libpcl-dev and rebuild)");
#endif
}

std::size_t LoadedMap::memory_bytes() const {
  if (dimension == 2) return vdt ? vdt->memory_bytes() : 0;
  return dense ? dense->memory_bytes() : sparse->memory_bytes();
}

}  // namespace vdtnav
